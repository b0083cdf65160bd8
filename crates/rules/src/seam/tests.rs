use glam::Vec3;
use subdiv_mesh::{Mesh, PolygonSoup, parse_obj};

use super::*;
use crate::{Scheme, tessellate_uniform};

/// A non-manifold cage split into its manifold pieces (`PolygonSoup::split_nonmanifold`).
fn split(text: &str) -> Mesh {
    let mut soup: PolygonSoup = parse_obj(text).unwrap();
    soup.split_nonmanifold().unwrap();
    Mesh::from_soup(&soup).unwrap()
}

/// Three quads on the edge 1-2 and a fourth on the edge 2-3 beside it: a chain of two
/// non-manifold edges through vertex 2 (a crease there: exactly two non-manifold edges), ending
/// at corners. Off-axis coordinates so that rounding differs between orientations.
const FINS: &str = "v 0.1 0.013 0.007\nv 1.3 0.021 -0.011\nv 2.7 0.05 0.031\n\
    v 0.12 1.1 0.05\nv 1.31 1.2 0.02\nv 2.71 1.07 0.04\n\
    v 0.09 -0.07 1.13\nv 1.29 0.03 1.21\nv 2.69 0.02 1.17\n\
    v 0.11 -1.03 0.02\nv 1.33 -1.11 -0.03\nv 2.73 -0.97 0.01\n\
    f 1 2 5 4\nf 2 3 6 5\nf 2 1 7 8\nf 3 2 8 9\nf 1 2 11 10\nf 2 3 12 11\n";

#[test]
fn copies_give_the_same_bits_from_either_side_at_any_depth() {
    same_bits(FINS);
    same_bits(&format!("{FINS}t corner 1/1/0 1 1.5\n"));
}

fn same_bits(text: &str) {
    let mesh = split(text);
    let seams = SeamCurves::new(&mesh);
    assert!(!seams.is_empty());
    // Two non-manifold edges, three copies each.
    assert_eq!(seams.groups().len(), 2);
    assert!(seams.groups().iter().all(|g| g.len() == 3));
    for g in seams.groups() {
        for log2 in 0..=5u8 {
            let n = 1u32 << log2;
            // Every copy, both half-edges, every parameter: one value per point of the edge,
            // oriented by the first copy's even half-edge.
            let e0 = g[0].halfedge(0);
            let (a0, b0) = (mesh.position(mesh.from(e0)), mesh.position(mesh.to(e0)));
            for s in 0..=n {
                let want = seams.point(&mesh, e0, s, log2).unwrap();
                for &e in g {
                    for side in 0..2 {
                        let h = e.halfedge(side);
                        let same = mesh.position(mesh.from(h)) == a0;
                        assert!(same || mesh.position(mesh.from(h)) == b0);
                        let t = if same { s } else { n - s };
                        let got = seams.point(&mesh, h, t, log2).unwrap();
                        assert_eq!(got.to_array(), want.to_array(), "{e:?} side {side} {s}/{n}");
                    }
                }
                // The same point at the next depth (parameter 2s / 2n).
                assert_eq!(seams.point(&mesh, e0, 2 * s, log2 + 1), Some(want));
            }
        }
    }
}

/// Every seam point of `text` at depth 3 is a limit point of the whole-mesh reference path.
fn check_limit(text: &str) {
    let mesh = split(text);
    let seams = SeamCurves::new(&mesh);
    assert!(!seams.is_empty());
    let depth = 3u8;
    let reference = tessellate_uniform(&mesh, Scheme::CatmullClark, depth).unwrap();
    let (lo, hi) = mesh.bounds();
    let tol = 1e-6 * (hi - lo).length();
    let n = 1u32 << depth;
    for g in seams.groups() {
        let h = g[0].halfedge(0);
        for s in 0..=n {
            let p = seams.point(&mesh, h, s, depth).unwrap();
            let nearest = reference
                .positions()
                .iter()
                .map(|q| (Vec3::from(*q) - p).length())
                .fold(f32::INFINITY, f32::min);
            assert!(nearest < tol, "{s}/{n}: {nearest}");
        }
    }
}

#[test]
fn seam_points_are_the_limit_surface() {
    check_limit(FINS);
    // A semi-sharp vertex sharpness at the crease vertex: a corner, then blended (1.5: one
    // level as a corner, then the weight 0.5; 2.25: two levels, then 0.25).
    check_limit(&format!("{FINS}t corner 1/1/0 1 1.5\n"));
    check_limit(&format!("{FINS}t corner 1/1/0 1 2.25\n"));
    let mesh = split(FINS);
    let seams = SeamCurves::new(&mesh);
    // The corners stay where they are; the crease vertex (cage vertex 2, 0-based 1) is not.
    let v = |i: u32| VertexId(i);
    assert_eq!(seams.vertex_point(&mesh, v(0)), Some(mesh.position(v(0))));
    assert_ne!(seams.vertex_point(&mesh, v(1)), Some(mesh.position(v(1))));
    assert_eq!(seams.vertex_point(&mesh, v(3)), None);
}

#[test]
fn manifold_cages_and_semi_sharp_chains_are_left_alone() {
    let cube = &subdiv_test_support::cube().obj();
    let mesh = split(cube);
    let seams = SeamCurves::new(&mesh);
    assert!(seams.is_empty() && seams.groups().is_empty());
    assert_eq!(seams.point(&mesh, HalfedgeId(0), 1, 1), None);
    // Two coincident boundary edges (a seam of duplicated vertices) whose chains differ beyond
    // one end: a group, not evaluated here.
    let open = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 0\nv 1 0 0\nv 1 -1 0\nv 0 -2 0\n\
                v 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 6 5 8 7\nf 2 9 10 3\n";
    let mesh = split(open);
    let seams = SeamCurves::new(&mesh);
    assert_eq!(seams.groups().len(), 1);
    assert!(seams.is_empty());
}
