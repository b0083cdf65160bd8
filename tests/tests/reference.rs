//! Uniform limit tessellations against OpenSubdiv 3.5 reference limit surfaces, for every
//! reference shape at levels 1-3: equal vertex and face counts, the same faces, positions within
//! 1e-5 of the cage's bounding-box diagonal, normals within 0.5 degrees where the surface is
//! smooth (no infinitely sharp edge or vertex at the point).

use subdiv_mesh::read_obj;
use subdiv_tests::osd_compare::{Outcome, Tessellator, compare};
use subdiv_tests::{Reference, fixture_files, fixtures};

fn check(shape: &str, level: subdiv_rules::Depth) -> Result<Outcome, String> {
    check_with(shape, level, Tessellator::Uniform)
}

/// Catmull-Clark and Loop shapes again, through the slate tessellators.
fn check_slate(shape: &str, level: subdiv_rules::Depth) -> Result<Outcome, String> {
    check_with(shape, level, Tessellator::Slate)
}

fn check_with(
    shape: &str,
    level: subdiv_rules::Depth,
    which: Tessellator,
) -> Result<Outcome, String> {
    // Bilinear references are computed on the Catmull-Clark shapes.
    let cage = match shape.strip_prefix("bilinear_") {
        Some(rest) => format!("catmark_{rest}"),
        None => shape.to_string(),
    };
    let cage_path = fixtures()
        .join("reference/shapes")
        .join(format!("{cage}.obj"));
    let reference =
        Reference::read(&fixtures().join(format!("reference/limit/{shape}.L{level}.txt")));
    let mesh = read_obj(&cage_path).map_err(|e| e.to_string())?;
    compare(&mesh, level, &reference, which, 0.5)
}

#[test]
fn every_reference_shape_matches_opensubdiv() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for file in fixture_files("reference/limit", "txt") {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        let (shape, lv) = name.rsplit_once(".L").unwrap();
        let level: subdiv_rules::Depth = lv.parse().unwrap();
        match check(shape, level) {
            Ok(o) => {
                checked += 1;
                eprintln!(
                    "{name}: max position error {:.2e} x diag, {} smooth normals within {:.4} deg",
                    o.max_pos_err, o.smooth_normals, o.max_normal_deg
                );
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} reference checks failed:\n{}",
        failures.len(),
        checked + failures.len(),
        failures.join("\n")
    );
    assert!(checked >= 90, "only {checked} reference files checked");
}

#[test]
fn slate_tessellation_matches_opensubdiv() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for file in fixture_files("reference/limit", "txt") {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        if !name.starts_with("catmark_") {
            continue;
        }
        let (shape, lv) = name.rsplit_once(".L").unwrap();
        match check_slate(shape, lv.parse().unwrap()) {
            Ok(o) => {
                checked += 1;
                eprintln!(
                    "slate {name}: max position error {:.2e} x diag, normals within {:.4} deg",
                    o.max_pos_err, o.max_normal_deg
                );
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(checked >= 60, "only {checked} checked");
}

/// Every Loop reference shape at levels 1-3 through the triangular slates.
#[test]
fn loop_slate_tessellation_matches_opensubdiv() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for file in fixture_files("reference/limit", "txt") {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        if !name.starts_with("loop_") {
            continue;
        }
        let (shape, lv) = name.rsplit_once(".L").unwrap();
        match check_slate(shape, lv.parse().unwrap()) {
            Ok(o) => {
                checked += 1;
                eprintln!(
                    "loop slate {name}: max position error {:.2e} x diag, normals within {:.4} deg",
                    o.max_pos_err, o.max_normal_deg
                );
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(checked >= 27, "only {checked} checked");
}

/// Every bilinear reference (OpenSubdiv's `SCHEME_BILINEAR` on the Catmull-Clark shapes) at
/// levels 1-3 through the bilinear patches of `subdiv_slate::tessellate_bilinear`.
#[test]
fn bilinear_patches_match_opensubdiv() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for file in fixture_files("reference/limit", "txt") {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        if !name.starts_with("bilinear_") {
            continue;
        }
        let (shape, lv) = name.rsplit_once(".L").unwrap();
        match check_slate(shape, lv.parse().unwrap()) {
            Ok(o) => {
                checked += 1;
                eprintln!(
                    "bilinear {name}: max position error {:.2e} x diag, {} smooth normals within {:.4} deg",
                    o.max_pos_err, o.smooth_normals, o.max_normal_deg
                );
                assert!(o.smooth_normals > 0, "{name}: no normal compared");
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(checked >= 18, "only {checked} checked");
}
