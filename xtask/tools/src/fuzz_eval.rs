//! The evaluation part of `cargo xtask fuzz-osd`: each random cage's limit surface at 16
//! random points and the same snapped to the level-3 lattice, subdiv's exact evaluation
//! against OpenSubdiv's `Bfr::Surface` (`xtask/osd/ref_eval.cpp`), with the tolerances and the
//! deep-refinement explanation of `subdiv_tests::eval_compare` (as `tests/tests/eval_bfr.rs`
//! on the fixtures). A difference that the snapped points leave unexplained is looked at again
//! with the corners of the random points' lattice cells too.

use std::path::Path;

use subdiv::eval::Evaluator;
use subdiv::eval::Query;
use subdiv_tests::eval_compare::{
    BfrValue, agree_or_explain, bfr_points, lattice_cell_corners, parse_bfr,
};
use subdiv_tests::osd_cage::OsdCage;

use crate::eval_refs::run_ref_eval;

/// Random points per cage (each also snapped to the lattice).
const POINTS: usize = 16;

/// What one cage's evaluation check found.
pub enum Outcome {
    /// Within the tolerances.
    Agrees,
    /// Bfr is off the limit surface (the explanation).
    BfrOff(String),
    /// OpenSubdiv's harness failed (Bfr 3.5.0 crashes on a few degenerate cages).
    BfrFailed(String),
}

/// Checks `cage` (named `name`, written to `dir`): `Err` is a disagreement.
pub fn check(exe: &Path, dir: &Path, cage: &OsdCage, name: &str) -> Result<Outcome, String> {
    let mesh = cage
        .mesh()
        .map_err(|e| format!("subdiv refuses the cage: {e}"))?;
    let scheme = if cage.loop_scheme {
        subdiv_rules::Scheme::Loop
    } else {
        subdiv_rules::Scheme::CatmullClark
    };
    let eval =
        Evaluator::new(&mesh, scheme).map_err(|e| format!("evaluation refuses the cage: {e}"))?;
    let text = cage.to_obj();
    let seed = text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
    });
    let points = bfr_points(&eval, POINTS, seed);
    if points.is_empty() {
        return Ok(Outcome::Agrees);
    }
    let bfr = |points: &[Query]| -> Result<Vec<Option<BfrValue>>, String> {
        let lines = run_ref_eval(exe, dir, &format!("{name}.eval"), &text, scheme, points, 10)
            .map_err(|e| format!("{e:#}"))?;
        lines.iter().map(|l| parse_bfr(l)).collect()
    };
    let values = match bfr(&points) {
        Ok(values) => values,
        Err(e) => return Ok(Outcome::BfrFailed(e)),
    };
    let disagreement = match agree_or_explain(&mesh, scheme, &points, &values) {
        Ok(None) => return Ok(Outcome::Agrees),
        Ok(Some(why)) => return Ok(Outcome::BfrOff(why)),
        Err(e) => e,
    };
    // Unexplained: the corners of the random points' lattice cells may lie nearer to what
    // makes the difference than their snapped points do (a second run, so that Bfr failing
    // on them costs nothing).
    let mut more = points.clone();
    more.extend(lattice_cell_corners(
        &eval,
        &points[..POINTS.min(points.len())],
    ));
    match bfr(&more).map(|values| agree_or_explain(&mesh, scheme, &more, &values)) {
        Ok(Ok(Some(why))) => Ok(Outcome::BfrOff(why)),
        _ => Err(disagreement),
    }
}
