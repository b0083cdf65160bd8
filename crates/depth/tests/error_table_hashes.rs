//! The pixel-error mode's per-face error tables (`patch_errors`, `patch_errors_tri`), bit for
//! bit: a hash of every face's chord errors, area elements, outlier areas and normal cone, for
//! Catmull-Clark (quads, creases, n-gons) and Loop (semi-sharp creases, a valence-8 pole)
//! cages, against `error_table_hashes.txt`. The adaptive frames' hashes see these tables only
//! through the depths they choose; this sees every value.
//!
//! `ERROR_TABLE_HASHES_BLESS=1 cargo test -p subdiv-depth --test error_table_hashes` rewrites
//! the file (see `subdiv_test_support::check_recorded`).

use std::fmt::Write as _;
use std::path::Path;

use subdiv_depth::{PatchErrors, patch_errors, patch_errors_tri};
use subdiv_mesh::{Mesh, parse_obj};
use subdiv_slate::{PatchSet, TriLayout};
use subdiv_test_support::{Fnv, shape};

fn hash(e: &PatchErrors) -> u64 {
    let mut h = Fnv::new();
    for f in &e.faces {
        h.f32s(&f.deviation);
        let sh = &f.shading;
        h.u32(sh.elements.len() as u32);
        for el in &sh.elements {
            h.f32s(&el.centre.to_array());
            h.f32s(&el.normal.to_array());
            h.f32s(&[el.area, el.cell]);
        }
        h.f32s(&sh.outlier_area);
        h.u32(sh.scales as u32);
        h.f32s(&[sh.weight, f.normals.cos]);
        h.f32s(&f.normals.axis.to_array());
        h.u32(u32::from(f.outline));
    }
    h.0
}

/// One line per cage: `name scheme faces hash`.
fn lines() -> String {
    let mut out = String::new();
    let tolerance = 10f32.to_radians();
    for (name, loop_scheme) in [
        ("catmark_helmet", false),
        ("catmark_pawn", false),
        ("catmark_nonquads", false),
        ("loop_cubes_semisharp", true),
        ("loop_pole8", true),
    ] {
        let path = shape(&format!("{name}.obj"));
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let mesh = Mesh::from_soup(&parse_obj(&text).unwrap()).unwrap();
        let e = if loop_scheme {
            let layout = TriLayout::new(&mesh, 1).unwrap();
            patch_errors_tri(&mesh, &layout, 3, tolerance)
        } else {
            let set = PatchSet::new(&mesh).unwrap();
            patch_errors(&mesh, &set, 3, tolerance)
        };
        let scheme = if loop_scheme { "loop" } else { "catmark" };
        writeln!(out, "{name} {scheme} {} {:016x}", e.faces.len(), hash(&e)).unwrap();
    }
    out
}

#[test]
fn error_tables_are_bit_identical_to_the_recorded_hashes() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/error_table_hashes.txt");
    subdiv_test_support::check_recorded(&path, &lines(), "ERROR_TABLE_HASHES_BLESS");
}
