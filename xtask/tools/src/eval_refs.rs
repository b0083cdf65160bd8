//! `cargo xtask eval-refs [LEVEL]`: the OpenSubdiv references of the evaluation tests
//! (`tests/tests/eval_bfr.rs`), written to `fixtures/reference/eval/`.
//!
//! For every fixture cage of `subdiv_tests::eval_compare::eval_fixtures` it draws 32 random
//! points and the same snapped to the level-3 lattice (`bfr_points`, seeded by the file
//! name), evaluates them with
//! `xtask/osd/ref_eval.cpp` (OpenSubdiv 3.5 `Bfr::Surface<double>`, approximation levels LEVEL,
//! default 10) on the cage with its coordinates rounded to `f32` as subdiv reads them, and
//! writes one file a cage: a header line `bfr-eval source=<fixture> scheme=<s> level=<L>
//! points=<n>`, then `FACE U V` and `ref_eval`'s line for each point.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result, bail};
use subdiv::eval::Evaluator;
use subdiv_mesh::{CageOptions, read_cage};
use subdiv_rules::Scheme;
use subdiv_tests::eval_compare::{
    bfr_points, eval_fixtures, eval_reference_name, obj_rounded_to_f32,
};

use xtask::osd::{INSTALL, osd_present};

/// Random points per cage (each also snapped to the level-3 lattice: twice as many points).
const RANDOM: usize = 32;

/// The scheme as `ref_eval` names it.
pub fn scheme_arg(s: Scheme) -> &'static str {
    match s {
        Scheme::CatmullClark => "catmark",
        Scheme::Loop => "loop",
        Scheme::Bilinear => "bilinear",
    }
}

/// Runs `ref_eval` on the cage `obj` (written to `dir`) at `points`: one output line a point.
pub fn run_ref_eval(
    exe: &Path,
    dir: &Path,
    name: &str,
    obj: &str,
    scheme: Scheme,
    points: &[subdiv::eval::Query],
    level: u32,
) -> Result<Vec<String>> {
    let cage = dir.join(format!("{name}.obj"));
    let pts = dir.join(format!("{name}.points.txt"));
    std::fs::write(&cage, obj_rounded_to_f32(obj))?;
    let mut text = String::new();
    for q in points {
        writeln!(text, "{} {} {}", q.face, q.u, q.v)?;
    }
    std::fs::write(&pts, text)?;
    let out = crate::bench_osd::output(
        Command::new(exe)
            .arg(&cage)
            .arg(scheme_arg(scheme))
            .arg(&pts)
            .arg(level.to_string()),
    )
    .with_context(|| format!("ref_eval on {name}"))?;
    // OpenSubdiv prints its topology warnings to stdout too.
    let lines: Vec<String> = out
        .lines()
        .filter(|l| l.starts_with("p ") || *l == "hole")
        .map(str::to_string)
        .collect();
    if lines.len() != points.len() {
        bail!(
            "ref_eval on {name}: {} lines for {} points",
            lines.len(),
            points.len()
        );
    }
    let _ = std::fs::remove_file(&pts);
    let _ = std::fs::remove_file(&cage);
    Ok(lines)
}

pub fn run(root: &Path, args: &[String]) -> Result<()> {
    if !osd_present() {
        bail!("eval-refs needs OpenSubdiv 3.5 (Debian libosd-dev): sudo {INSTALL}");
    }
    let level: u32 = args
        .first()
        .map_or(Ok(10), |a| a.parse())
        .context("eval-refs [LEVEL]")?;
    let exe = crate::fuzz_osd::build_harness(root, "ref_eval")?;
    let fixtures = root.join("fixtures");
    let out_dir = fixtures.join("reference/eval");
    let work = xtask::target_dir().join("eval-refs");
    std::fs::create_dir_all(&out_dir)?;
    std::fs::create_dir_all(&work)?;
    let list = eval_fixtures(&fixtures);
    let mut skipped = Vec::new();
    for (rel, scheme) in &list {
        let path = fixtures.join(rel);
        let cage = read_cage(&path, &CageOptions::default())
            .with_context(|| format!("reading {}", path.display()))?;
        let eval = Evaluator::new(&cage.mesh, *scheme)
            .with_context(|| format!("{}: subdiv refuses it", path.display()))?;
        let seed = rel.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
        });
        let points = bfr_points(&eval, RANDOM, seed);
        if points.is_empty() {
            continue;
        }
        let name = eval_reference_name(rel);
        let obj = std::fs::read_to_string(&path)?;
        let stem = name.trim_end_matches(".txt");
        let lines = match run_ref_eval(&exe, &work, stem, &obj, *scheme, &points, level) {
            Ok(lines) => lines,
            Err(e) => {
                // OpenSubdiv itself fails on a few degenerate fuzz cages (a crash in Bfr).
                println!("eval-refs: {rel}: skipped, ref_eval fails: {e:#}");
                skipped.push(rel.clone());
                let _ = std::fs::remove_file(out_dir.join(&name));
                continue;
            }
        };
        let mut text = format!(
            "bfr-eval source={rel} scheme={} level={level} points={} osd=3.5\n",
            scheme_arg(*scheme),
            points.len()
        );
        for (q, l) in points.iter().zip(&lines) {
            writeln!(text, "{} {} {} {l}", q.face, q.u, q.v)?;
        }
        std::fs::write(out_dir.join(&name), text)?;
    }
    println!(
        "eval-refs: references of {} cages in {} ({} skipped: {})",
        list.len() - skipped.len(),
        out_dir.display(),
        skipped.len(),
        skipped.join(", ")
    );
    Ok(())
}
