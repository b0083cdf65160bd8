//! Small cages shared by the unit tests.

use subdiv_mesh::{Mesh, parse_obj};

fn mesh(obj: &str) -> Mesh {
    Mesh::from_soup(&parse_obj(obj).expect("test OBJ parses")).expect("test mesh is manifold")
}

/// One quad (4 boundary vertices).
pub(crate) fn single_quad() -> Mesh {
    mesh("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
}

/// The unit cube: 6 quads, closed, every vertex of valence 3.
pub(crate) fn cube() -> Mesh {
    mesh(&subdiv_test_support::cube().obj())
}

/// A `k x k` grid of quads in the plane (open, interior vertices of valence 4).
pub(crate) fn grid(k: usize) -> Mesh {
    mesh(&subdiv_test_support::height_grid(k as u32, false, 0.0, |_, _| 0.0).obj())
}

/// A pentagon with two rings of quads around it (an open disc): face 0 is the pentagon, faces
/// 1..=5 the quads on its edges, faces 6..=10 the outer quads (no vertex on the pentagon).
pub(crate) fn pentagon_flower() -> Mesh {
    let mut obj = String::new();
    for r in [1.0f64, 2.0, 3.0] {
        for i in 0..5 {
            let a = std::f64::consts::TAU * i as f64 / 5.0;
            obj += &format!("v {} {} 0\n", r * a.cos(), r * a.sin());
        }
    }
    // Vertices 1..=5 on the pentagon, 6..=10 on the first ring, 11..=15 on the second.
    obj += "f 1 2 3 4 5\n";
    for ring in 0..2 {
        for i in 0..5 {
            let (a, b) = (ring * 5 + i + 1, ring * 5 + (i + 1) % 5 + 1);
            obj += &format!("f {} {} {} {}\n", b, a, a + 5, b + 5);
        }
    }
    mesh(&obj)
}

/// A pentagonal prism: two pentagons and five quads, closed.
pub(crate) fn pentagonal_prism() -> Mesh {
    let mut obj = String::new();
    for z in [0.0f64, 1.0] {
        for i in 0..5 {
            let a = std::f64::consts::TAU * i as f64 / 5.0;
            obj += &format!("v {} {} {z}\n", a.cos(), a.sin());
        }
    }
    obj += "f 5 4 3 2 1\nf 6 7 8 9 10\n";
    for i in 0..5 {
        let (a, b) = (i + 1, (i + 1) % 5 + 1);
        obj += &format!("f {} {} {} {}\n", a, b, b + 5, a + 5);
    }
    mesh(&obj)
}
