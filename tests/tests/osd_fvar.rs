//! Face-varying refinement (UVs) against OpenSubdiv 3.5: for every cage in
//! `fixtures/meshes/fvar` (UV seams, darts, junctions, semi-sharp creases and vertices on and
//! beside the seams, dependent sharpness, infinitely sharp edges inside a span that wraps round
//! the walk's start, a non-manifold cage read as the readers read it), every face-varying
//! linear interpolation option and levels 1-3, uniform Catmull-Clark and Loop refinement give
//! the values of `PrimvarRefiner::InterpolateFaceVarying` at every corner of every refined
//! face, within `value_tolerance`. References: `fixtures/reference/fvar/
//! <shape>.<scheme>.o<option>.L<level>.txt`, printed by `xtask/osd/ref_fvar.cpp`.
//! The face-varying limit values of the refined meshes (`limit_face_varying`) against
//! `PrimvarRefiner::LimitFaceVarying` at levels 1-2: `fixtures/reference/fvar_limit/`, printed
//! by `ref_fvar ... limit`.

use subdiv_mesh::{FVarLinearInterpolation, Mesh, parse_obj};
use subdiv_rules::{Scheme, limit_face_varying, refine_uniform_levels};

use subdiv_tests::osd_fvar::{compare_fvar, compare_fvar_values, parse_fvar};
use subdiv_tests::{fixture_files, fixtures};

/// Compares one reference file (refined values, or with `limit` their limits); returns the
/// number of corners compared.
fn check(path: &std::path::Path, limit: bool) -> Result<usize, String> {
    let name = path.file_name().unwrap().to_string_lossy().to_string();
    let parts: Vec<&str> = name.split('.').collect();
    let [shape, scheme, option, level, "txt"] = parts[..] else {
        return Err(format!("{name}: not <shape>.<scheme>.o<k>.L<l>.txt"));
    };
    let scheme = match scheme {
        "catmark" => Scheme::CatmullClark,
        "loop" => Scheme::Loop,
        s => return Err(format!("{name}: scheme {s}")),
    };
    let option = FVarLinearInterpolation::from_tag(option[1..].parse().unwrap()).unwrap();
    let level: u8 = level[1..].parse().unwrap();
    let text =
        std::fs::read_to_string(fixtures().join(format!("meshes/fvar/{shape}.obj"))).unwrap();
    let mut soup = parse_obj(&text).map_err(|e| e.to_string())?;
    soup.options.fvar = option;
    // As the readers take a cage: non-manifold ones in manifold pieces.
    soup.split_nonmanifold().map_err(|e| e.to_string())?;
    let mesh = Mesh::from_soup(&soup).map_err(|e| e.to_string())?;
    let refined = refine_uniform_levels(&mesh, scheme, level).map_err(|e| e.to_string())?;
    let faces = parse_fvar(&std::fs::read_to_string(path).unwrap());
    if limit {
        let uvs = limit_face_varying(&refined, scheme).ok_or("no UVs")?;
        compare_fvar_values(&mesh, scheme, level, &refined, &uvs, &faces)
    } else {
        compare_fvar(&mesh, scheme, level, &refined, &faces)
    }
    .map_err(|e| format!("{name}: {e}"))
}

#[test]
fn face_varying_refinement_matches_opensubdiv() {
    let files = fixture_files("reference/fvar", "txt");
    assert_eq!(
        files.len(),
        198,
        "11 shape/scheme pairs x 6 options x 3 levels"
    );
    let mut failures = Vec::new();
    let mut corners = 0;
    for path in &files {
        match check(path, false) {
            Ok(n) => corners += n,
            Err(e) => failures.push(e),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} differ:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
    assert!(corners > 10_000, "{corners}");
}

#[test]
fn face_varying_limit_matches_opensubdiv() {
    let files = fixture_files("reference/fvar_limit", "txt");
    assert_eq!(
        files.len(),
        132,
        "11 shape/scheme pairs x 6 options x 2 levels"
    );
    let mut failures = Vec::new();
    let mut corners = 0;
    for path in &files {
        match check(path, true) {
            Ok(n) => corners += n,
            Err(e) => failures.push(e),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} differ:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
    assert!(corners > 2_000, "{corners}");
}
