//! The cages on which `cargo xtask fuzz-osd` once found subdiv disagreeing with OpenSubdiv,
//! kept with OpenSubdiv's limits so the disagreements stay fixed without libosd-dev
//! (`fixtures/osd_fuzz/`, see docs/testing.md). Each `<name>.obj` has references
//! `<name>.L<level>.txt` from `xtask/osd/ref_osd.cpp ... local` at the level where it failed;
//! the comparison is fuzz-osd's: counts, faces, positions within 1e-5 x diagonal and normals
//! within 0.05 degrees, through the whole-mesh path and the slate tessellator of the cage's
//! scheme.
//! `fuzz13_16024_full` is the whole cage 16024 at levels 1-4, whose level-2 normal at valence-2
//! vertex 10 is undefined (parallel tangents; `ref_osd` writes 0 0 0 there).

use subdiv_tests::osd_compare::{Tessellator, assert_fixture_dir_agrees};

/// fuzz-osd's normal tolerance (degrees).
const NORMAL_DEG: f64 = 0.05;

#[test]
fn fuzz_osd_regressions_agree_with_opensubdiv() {
    assert_fixture_dir_agrees("osd_fuzz", NORMAL_DEG, 10, |_| {
        vec![Tessellator::Uniform, Tessellator::Slate]
    });
}
