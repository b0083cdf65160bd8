//! UVs through DoI-driven adaptive Loop refinement (`subdiv-redgreen`, what `subdiv refine` runs),
//! on the UV cages (`fixtures/meshes/fvar/tri_seam.obj`, and `cube_uv`,
//! `grid_seam`, `grid_seam_crease` triangulated) under every face-varying option:
//! - with every face selected at every step the channel is exactly uniform Loop face-varying
//!   refinement's (`refine_uniform`), and OpenSubdiv's (`fixtures/reference/fvar`, levels 1-3);
//! - with partial selections (balanced or the paper's plain closure) two faces sharing an edge
//!   agree on the values at its ends unless the edge lies on a seam of the cage, where they
//!   differ; balanced, every corner carries the uniform refinement's value at its point at its
//!   vertex's level (one of them at a seam).

use std::collections::HashMap;

use glam::{DVec3, Vec2, Vec3};
use subdiv_mesh::{FVarLinearInterpolation, FaceId, Mesh, VertexId, parse_obj, triangulate};
use subdiv_redgreen::{AdaptiveMesh, Balance, loop_step_with};
use subdiv_rules::{Scheme, refine_uniform};
use subdiv_tests::osd_fvar::{compare_fvar, parse_fvar};
use subdiv_tests::{PointGrid, fixtures};

/// The Loop UV cages under every option, each face in its own face group (groups follow
/// refinement: every refined face names the cage face it lies in).
fn cages() -> Vec<(String, Mesh)> {
    let mut out = Vec::new();
    for shape in [
        "tri_seam",
        "cube_uv",
        "grid_seam",
        "grid_seam_crease",
        "grid_seam_semi",
        "grid_seam_decay",
        "fan_inf_span",
    ] {
        let text =
            std::fs::read_to_string(fixtures().join(format!("meshes/fvar/{shape}.obj"))).unwrap();
        for option in FVarLinearInterpolation::ALL {
            let mut soup = parse_obj(&text).unwrap();
            soup.options.fvar = option;
            let mut m = triangulate(&Mesh::from_soup(&soup).unwrap()).unwrap();
            let n = m.num_faces() as u32;
            m.set_groups((0..n).map(|f| format!("f{f}")).collect(), (0..n).collect());
            out.push((format!("{shape} {}", option.name()), m));
        }
    }
    out
}

/// Per pair of cage faces sharing an edge (smaller first): whether that edge is a seam.
fn cage_seams(cage: &Mesh) -> HashMap<(u32, u32), bool> {
    let mut out = HashMap::new();
    for e in cage.edges() {
        let h = e.halfedge(0);
        let (f, g) = (cage.face(h), cage.face(h.twin()));
        if f.is_some() && g.is_some() {
            out.insert((f.0.min(g.0), f.0.max(g.0)), seam(cage, h));
        }
    }
    out
}

/// The value of face `f`'s corner at `v`.
fn corner(m: &Mesh, f: FaceId, v: VertexId) -> (u32, Vec2) {
    let fv = m.uv().unwrap();
    let (offsets, _) = m.face_lists();
    let k = m.face_vertices(f).iter().position(|&x| x == v).unwrap();
    let i = fv.indices[offsets[f.idx()] as usize + k];
    (i, fv.values[i as usize])
}

/// Whether the interior edge of `h` has different values at an end on its two sides.
fn seam(m: &Mesh, h: subdiv_mesh::HalfedgeId) -> bool {
    let (f, g) = (m.face(h), m.face(h.twin()));
    [m.from(h), m.to(h)]
        .iter()
        .any(|&v| corner(m, f, v).1 != corner(m, g, v).1)
}

#[test]
fn every_face_selected_is_uniform_face_varying_refinement() {
    for (name, cage) in cages() {
        for balance in [Balance::Vertex, Balance::None] {
            let mut a = AdaptiveMesh::new(cage.clone()).unwrap();
            let mut u = cage.clone();
            for level in 1..=3 {
                let all = vec![true; a.mesh.num_faces()];
                a = loop_step_with(&a, &all, balance).unwrap().0;
                u = refine_uniform(&u, Scheme::Loop).unwrap();
                assert_eq!(a.mesh.uv(), u.uv(), "{name} {balance:?} level {level}");
                assert_eq!(a.previous_uv.len(), u.uv().unwrap().values.len());
            }
        }
    }
}

#[test]
fn every_face_selected_matches_opensubdiv() {
    let text = std::fs::read_to_string(fixtures().join("meshes/fvar/tri_seam.obj")).unwrap();
    let mut compared = 0;
    for option in FVarLinearInterpolation::ALL {
        let mut soup = parse_obj(&text).unwrap();
        soup.options.fvar = option;
        let cage = Mesh::from_soup(&soup).unwrap();
        let mut a = AdaptiveMesh::new(cage.clone()).unwrap();
        for level in 1..=3u8 {
            let all = vec![true; a.mesh.num_faces()];
            a = subdiv_redgreen::loop_step(&a, &all).unwrap().0;
            let file = format!(
                "reference/fvar/tri_seam.loop.o{}.L{level}.txt",
                option.tag()
            );
            let faces = parse_fvar(&std::fs::read_to_string(fixtures().join(file)).unwrap());
            compared += compare_fvar(&cage, Scheme::Loop, level, &a.mesh, &faces)
                .unwrap_or_else(|e| panic!("{} L{level}: {e}", option.name()));
        }
    }
    assert!(compared > 6 * 3 * 8 * 64, "{compared}");
}

/// Selections for step `s` of a mesh: faces near a point, and pseudo-random faces.
fn selection(a: &AdaptiveMesh, kind: usize, s: u32) -> Vec<bool> {
    let (lo, hi) = a.mesh.bounds();
    let target = lo + (hi - lo) * Vec3::new(0.8, 0.3, 0.6);
    let radius = (hi - lo).length() * 0.35;
    let mut seed = 0x9e37_79b9u32 ^ (s * 7919 + kind as u32);
    a.mesh
        .faces()
        .map(|f| match kind {
            0 => a.mesh.face_centroid(f).distance(target) < radius,
            _ => {
                seed ^= seed << 13;
                seed ^= seed >> 17;
                seed ^= seed << 5;
                seed.is_multiple_of(5)
            }
        })
        .collect()
}

#[test]
fn partial_selections_keep_uvs_continuous_off_seams() {
    let mut checked = [0usize; 3];
    for (name, cage) in cages() {
        let seams = cage_seams(&cage);
        let mut uniform = vec![cage.clone()];
        for l in 0..4 {
            uniform.push(refine_uniform(&uniform[l], Scheme::Loop).unwrap());
        }
        let grids: Vec<PointGrid> = uniform
            .iter()
            .map(|u| {
                let p: Vec<DVec3> = u.positions().iter().map(|p| p.as_dvec3()).collect();
                PointGrid::new(&p, 0.05)
            })
            .collect();
        // Per level and vertex: the values of its corners.
        let values: Vec<Vec<Vec<Vec2>>> = uniform
            .iter()
            .map(|u| {
                let mut at = vec![Vec::new(); u.num_vertices()];
                for f in u.faces() {
                    for &v in u.face_vertices(f) {
                        at[v.idx()].push(corner(u, f, v).1);
                    }
                }
                at
            })
            .collect();
        for balance in [Balance::Vertex, Balance::None] {
            for kind in 0..2 {
                let mut a = AdaptiveMesh::new(cage.clone()).unwrap();
                for s in 0..4 {
                    let sel = selection(&a, kind, s);
                    a = loop_step_with(&a, &sel, balance).unwrap().0;
                }
                let what = format!("{name} {balance:?} selection {kind}");
                checked[0] += check_edges(&a.mesh, &seams, &what);
                if balance == Balance::Vertex {
                    checked[1] += check_values(&a, &values, &grids, &what);
                }
                checked[2] += a.green.num_green_faces();
            }
        }
    }
    // Edges, corners and green triangles (the closures are exercised).
    assert!(
        checked[0] > 10_000 && checked[1] > 10_000 && checked[2] > 100,
        "{checked:?}"
    );
}

/// Two faces sharing an edge agree on its ends' values unless the edge lies on a seam of the
/// cage (`seams`, by the cage faces the two faces lie in, their face groups), where they do
/// not. Returns the edges checked.
fn check_edges(m: &Mesh, seams: &HashMap<(u32, u32), bool>, what: &str) -> usize {
    let fv = m.uv().expect("UVs carried");
    assert_eq!(fv.indices.len(), 3 * m.num_faces(), "{what}");
    let mut n = 0;
    for e in m.edges() {
        let h = e.halfedge(0);
        let (f, g) = (m.face(h), m.face(h.twin()));
        if !f.is_some() || !g.is_some() {
            continue;
        }
        let (cf, cg) = (m.face_groups()[f.idx()], m.face_groups()[g.idx()]);
        let want = cf != cg && seams[&(cf.min(cg), cf.max(cg))];
        assert_eq!(
            seam(m, h),
            want,
            "{what}: edge {e:?} between cage faces {cf} {cg}"
        );
        if !want {
            for v in [m.from(h), m.to(h)] {
                assert_eq!(corner(m, f, v).0, corner(m, g, v).0, "{what}: one value");
            }
        }
        n += 1;
    }
    n
}

/// Every corner's value is one of the values of the uniform refinement at its vertex's level
/// at the same point (`values`: per level and vertex, its corners' values). Returns the corners
/// checked.
fn check_values(
    a: &AdaptiveMesh,
    values: &[Vec<Vec<Vec2>>],
    grids: &[PointGrid],
    what: &str,
) -> usize {
    let m = &a.mesh;
    let mut top = vec![0u8; m.num_vertices()];
    for f in m.faces() {
        for v in m.face_vertices(f) {
            top[v.idx()] = top[v.idx()].max(a.level[f.idx()]);
        }
    }
    let mut n = 0;
    for f in m.faces() {
        for &v in m.face_vertices(f) {
            let l = top[v.idx()] as usize;
            let (w, d) = grids[l].nearest(m.position(v).as_dvec3());
            assert!(d < 1e-4, "{what}: vertex {v:?} is no level-{l} point ({d})");
            let got = corner(m, f, v).1;
            let near = values[l][w]
                .iter()
                .map(|t| t.distance(got))
                .fold(f32::INFINITY, f32::min);
            assert!(near < 1e-5, "{what}: {v:?} level {l}: {got} off by {near}");
            n += 1;
        }
    }
    n
}
