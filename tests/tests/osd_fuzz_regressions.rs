//! The cages on which `cargo xtask fuzz-osd` once found subdiv disagreeing with OpenSubdiv,
//! kept with OpenSubdiv's limits so the disagreements stay fixed without libosd-dev
//! (`fixtures/osd_fuzz/`, see docs/testing.md). Each `<name>.obj` has references
//! `<name>.L<level>.txt` from `xtask/osd/ref_osd.cpp ... local` at the level where it failed;
//! the comparison is fuzz-osd's: counts, faces, positions within 1e-5 x diagonal and normals
//! within 0.05 degrees, through the whole-mesh path and (Catmull-Clark) the slate tessellator.
//! `fuzz13_16024_full` is the whole cage 16024 at levels 1-4, whose level-2 normal at valence-2
//! vertex 10 is undefined (parallel tangents; `ref_osd` writes 0 0 0 there since issue 13).

use subdiv_mesh::read_obj;
use subdiv_tests::osd_compare::{Tessellator, compare};
use subdiv_tests::{Reference, fixture_files, fixtures};

/// fuzz-osd's normal tolerance (degrees).
const NORMAL_DEG: f64 = 0.05;

#[test]
fn fuzz_osd_regressions_agree_with_opensubdiv() {
    let mut failures = Vec::new();
    let mut checked = 0;
    for file in fixture_files("osd_fuzz", "txt") {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        let (cage, lv) = name.rsplit_once(".L").unwrap();
        let level: subdiv_rules::Depth = lv.parse().unwrap();
        let path = fixtures().join("osd_fuzz").join(format!("{cage}.obj"));
        let text = std::fs::read_to_string(&path).unwrap();
        let loop_scheme = text.contains("scheme loop");
        let mesh = read_obj(&path).unwrap_or_else(|e| panic!("{cage}: {e}"));
        let reference = Reference::read(&file);
        let mut paths = vec![Tessellator::Uniform];
        if !loop_scheme {
            paths.push(Tessellator::Slate);
        }
        for which in paths {
            checked += 1;
            if let Err(e) = compare(&mesh, level, &reference, which, NORMAL_DEG) {
                failures.push(format!("{name} ({which:?}): {e}"));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {checked} checks disagree with OpenSubdiv:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(checked >= 10, "only {checked} checks");
}
