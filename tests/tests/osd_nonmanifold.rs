//! Non-manifold cages as OpenSubdiv refines them: the hand-made cages of
//! `fixtures/nonmanifold/` (a fin of three quads, two cubes sharing an edge, two pyramids
//! touching at their apex, a cube with a bare vertex; for Loop a fin with a tetrahedron on an
//! edge and two tetrahedra touching at a vertex; both schemes, `chain_semi_corner*`: a vertex
//! with exactly two non-manifold edges, OpenSubdiv's crease rule, after a semi-sharp vertex
//! sharpness has run out; `chain_semi_crease*`, `chain_chaikin_*`: semi-sharp creases at such a
//! vertex, in two of its copies or, with Chaikin's decay, in one or two, and at a corner;
//! `chain_one_face_copy*`: a copy of it with one face under edge-and-corner), read as
//! `read_obj` reads them (cut into manifold pieces, `PolygonSoup::split_nonmanifold`), against
//! OpenSubdiv's limits from `xtask/osd/ref_osd.cpp ... local` at levels 1-3, which takes the
//! cages as they are. The comparison is fuzz-osd's (coincident copies welded): counts, faces,
//! positions within 1e-5 x diagonal, normals within 0.05 degrees where smooth; whole-mesh path
//! and slate.

use std::collections::HashMap;

use subdiv_mesh::{PolygonSoup, read_obj, read_obj_soup};
use subdiv_tests::osd_compare::{Tessellator, assert_fixture_dir_agrees};
use subdiv_tests::{fixture_files, fixtures};

/// fuzz-osd's normal tolerance (degrees).
const NORMAL_DEG: f64 = 0.05;

#[test]
fn nonmanifold_cages_agree_with_opensubdiv() {
    assert_fixture_dir_agrees("nonmanifold", NORMAL_DEG, 204, |_| {
        vec![Tessellator::Uniform, Tessellator::Slate]
    });
}

/// What the split reports on each cage, and that a manifold cage is left alone.
#[test]
fn the_split_names_what_is_non_manifold() {
    let soup = |name: &str| -> PolygonSoup {
        read_obj_soup(fixtures().join("nonmanifold").join(name)).unwrap()
    };
    let mut fin = soup("fin3_quads.obj");
    let found = fin.split_nonmanifold().unwrap();
    assert_eq!(found.edges, vec![(0, 1, 3)]);
    assert_eq!(found.vertices, vec![(0, 3), (1, 3)]);
    assert_eq!(found.copies.len(), 4);
    let mut cubes = soup("cubes_edge.obj");
    let found = cubes.split_nonmanifold().unwrap();
    assert_eq!(found.edges, vec![(0, 1, 4)]);
    assert_eq!(found.vertices, vec![(0, 2), (1, 2)]);
    let mut bowtie = soup("bowtie_pyramids.obj");
    let found = bowtie.split_nonmanifold().unwrap();
    assert!(found.edges.is_empty());
    assert_eq!(found.vertices, vec![(0, 2)]);
    let mut bare = soup("bare_vertex.obj");
    let before = bare.clone();
    let found = bare.split_nonmanifold().unwrap();
    assert!(found.is_empty());
    assert_eq!(found.bare, vec![8]);
    assert_eq!(bare.face_indices, before.face_indices);
    assert_eq!(bare.creases, before.creases);
}

/// The uniform slates write the copies of a non-manifold edge with the same bits: every point
/// `SeamCurves` gives on a seam is in the output once per copy (both schemes, depths 0-4).
#[test]
fn seam_copies_agree_to_the_bit_in_the_uniform_slates() {
    let mut checked = 0;
    for file in fixture_files("nonmanifold", "obj") {
        let name = file.file_stem().unwrap().to_string_lossy().to_string();
        let mesh = read_obj(&file).unwrap_or_else(|e| panic!("{name}: {e}"));
        let seams = subdiv_rules::SeamCurves::new(&mesh);
        if seams.is_empty() {
            continue;
        }
        for depth in 0..=4u8 {
            let t = if name.contains("loop") {
                subdiv_slate::tessellate_tri(&mesh, depth)
            } else {
                subdiv_slate::tessellate(&mesh, depth)
            }
            .unwrap();
            let mut count: HashMap<[u32; 3], usize> = HashMap::new();
            for p in t.positions() {
                *count.entry(p.map(f32::to_bits)).or_default() += 1;
            }
            for group in seams.groups() {
                let h = group[0].halfedge(0);
                // An end vertex's copies: one may hold two copies of the edge (a fan leaving
                // and returning through it).
                let ends = |end: glam::Vec3| {
                    let mut vs: Vec<u32> = group
                        .iter()
                        .flat_map(|e| mesh.edge_vertices(*e))
                        .filter(|&v| mesh.position(v) == end)
                        .map(|v| v.0)
                        .collect();
                    vs.sort_unstable();
                    vs.dedup();
                    vs.len()
                };
                let last = 1u32 << depth;
                for s in 0..=last {
                    let p = seams.point(&mesh, h, s, depth).unwrap().to_array();
                    let n = count.get(&p.map(f32::to_bits)).copied().unwrap_or(0);
                    let copies = match s {
                        0 => ends(mesh.position(mesh.from(h))),
                        _ if s == last => ends(mesh.position(mesh.to(h))),
                        _ => group.len(),
                    };
                    assert!(
                        n >= copies,
                        "{name} depth {depth}: point {s} of {copies} copies is in the output {n} times",
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 100, "only {checked} points");
}
