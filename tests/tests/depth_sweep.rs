//! Projected-size depth rules end to end (Settgast et al. 2004, Section 3.1): as the eye
//! recedes from the pawn the tessellation gets coarser, over any number of levels, down to
//! depth 0 once the whole model covers a few pixels.

use glam::Vec3;
use subdiv::DynamicSubdivision;
use subdiv_depth::DepthParams;
use subdiv_mesh::{Camera, read_obj};

/// The CLI's `--eye-relative 0,0.3,D --up 0,0,1` camera for the Z-up pawn.
fn camera(lo: Vec3, hi: Vec3, d: f32) -> Camera {
    let mut c = Camera::eye_relative(lo, hi, Vec3::new(0.0, 0.3, d), 45.0, 800, 600);
    if c.forward().cross(Vec3::Z).length_squared() > 1e-6 {
        c.up = Vec3::Z;
    }
    c
}

#[test]
fn receding_eye_coarsens_down_to_depth_zero() {
    let path = subdiv_tests::fixtures().join("reference/shapes/catmark_pawn.obj");
    let mesh = read_obj(path).unwrap();
    let (lo, hi) = mesh.bounds();
    let mut node = DynamicSubdivision::new(mesh, DepthParams::default()).unwrap();
    let mut counts = Vec::new();
    for d in [2.0f32, 10.0, 40.0, 160.0] {
        let tris = node
            .update(&camera(lo, hi, d), None)
            .unwrap()
            .num_triangles();
        let depths = &node.assignment().depth;
        let mut hist = [0usize; 6];
        for &x in depths {
            hist[x as usize] += 1;
        }
        eprintln!("D = {d}: {tris} triangles, patches per depth {hist:?}");
        counts.push((d, tris, depths.iter().copied().max().unwrap_or(0)));
    }
    // Strictly fewer triangles at each step, unless the previous distance already had every
    // patch at depth 0 (nothing left to coarsen: then the count stays).
    for w in counts.windows(2) {
        let floor = w[0].2 == 0 && w[1].1 == w[0].1;
        assert!(
            w[1].1 < w[0].1 || floor,
            "triangles must fall as the eye recedes: {counts:?}"
        );
    }
    assert!(
        counts[2].1 < counts[1].1 && counts[1].1 < counts[0].1,
        "{counts:?}"
    );
    let (_, _, deepest) = counts[3];
    assert_eq!(
        deepest, 0,
        "at 160 half-diagonals every patch is at depth 0: {counts:?}"
    );
}
