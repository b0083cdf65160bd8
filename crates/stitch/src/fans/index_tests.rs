//! Tests of `index.rs`.

use super::super::test_util::{
    Rng, cube, frame, grid, open_edges, pillow, prism, split_cube, valence2_cube,
};
use super::FanMethod;

const METHODS: [FanMethod; 2] = [FanMethod::Subdivided, FanMethod::Simple];

#[test]
fn uniform_depths_give_two_triangles_per_quad_and_no_fans() {
    for (name, mesh, open_per_level) in [("cube", cube(), 0), ("grid", grid(3), 12)] {
        let nf = mesh.num_faces();
        for d in 0..=3u8 {
            for method in METHODS {
                let g = frame(&mesh, 3, &vec![d; nf], &vec![true; nf], method);
                assert_eq!(
                    g.num_triangles(),
                    nf * 2 * 4usize.pow(d as u32),
                    "{name} depth {d} {method:?}"
                );
                // No fan centres: only the grid points of the uniform tessellation.
                let (pos, _, idx) = g.compact();
                let n = (1usize << d) + 1;
                let want = if name == "cube" {
                    6 * (n - 1) * (n - 1) + 2
                } else {
                    (3 * (n - 1) + 1).pow(2)
                };
                assert_eq!(pos.len(), want, "{name} depth {d}: vertices");
                assert_eq!(idx.len(), g.surface().face_indices().len());
                assert_eq!(open_edges(&g), open_per_level << d, "{name} depth {d}");
            }
        }
    }
}

/// Triangles of a quad patch at depth `a` with one side next to a depth-`b` unit (`b > a`):
/// the `2^a` quads along that side become fans through the `2^(b-a) - 1` deeper points,
/// plus (subdivided method) the midpoint of each inner edge between two of them.
fn fanned_patch_triangles(a: u32, b: u32, method: FanMethod) -> usize {
    let n = 1usize << a;
    let plain = 2 * (n * n - n);
    let fans = n * (4 + (1usize << (b - a)) - 1);
    let extra = match method {
        FanMethod::Subdivided => 2 * (n - 1),
        FanMethod::Simple => 0,
    };
    plain + fans + extra
}

#[test]
fn one_deeper_face_turns_neighbour_border_quads_into_watertight_fans() {
    let mesh = cube();
    // Face 0 (z = 0) borders faces 2..=5; face 1 is opposite.
    for a in 0..=2u32 {
        for b in a + 1..=3 {
            let mut depth = vec![a as u8; 6];
            depth[0] = b as u8;
            for method in METHODS {
                let g = frame(&mesh, 3, &depth, &[true; 6], method);
                let want = 2 * 4usize.pow(b)
                    + 2 * 4usize.pow(a)
                    + 4 * fanned_patch_triangles(a, b, method);
                assert_eq!(g.num_triangles(), want, "depths {a}/{b} {method:?}");
                assert_eq!(open_edges(&g), 0, "depths {a}/{b} {method:?}");
            }
        }
    }
}

#[test]
fn subdivided_method_adds_the_inner_edge_points() {
    let mesh = cube();
    let mut depth = vec![1u8; 6];
    depth[0] = 2;
    let sub = frame(&mesh, 2, &depth, &[true; 6], FanMethod::Subdivided);
    let simple = frame(&mesh, 2, &depth, &[true; 6], FanMethod::Simple);
    // Four neighbours, each with one inner edge between two fans: one more point, two
    // more triangles each.
    assert_eq!(sub.num_triangles(), simple.num_triangles() + 4 * 2);
    assert_eq!(sub.compact().0.len(), simple.compact().0.len() + 4);
    // Same vertex buffer: the method changes only the index buffer.
    assert_eq!(sub.surface().positions(), simple.surface().positions());
}

#[test]
fn fans_on_a_grid_stay_closed_inside() {
    // The centre face of a 3x3 grid two levels deeper than the rest: its four neighbours
    // fan, the outer boundary stays open with 2^d segments per boundary edge.
    let mesh = grid(3);
    let mut depth = vec![1u8; 9];
    depth[4] = 3;
    for method in METHODS {
        let g = frame(&mesh, 3, &depth, &[true; 9], method);
        assert_eq!(open_edges(&g), 12 * 2, "{method:?}");
        let want = 2 * 64 + 4 * 8 + 4 * fanned_patch_triangles(1, 3, method);
        assert_eq!(g.num_triangles(), want, "{method:?}");
    }
}

#[test]
fn random_depths_are_watertight_with_n_gons() {
    let mut rng = Rng::xorshift(0x9e37_79b9_7f4a_7c15);
    for (name, mesh) in [
        ("cube", cube()),
        ("prism", prism()),
        ("split", split_cube()),
    ] {
        let nf = mesh.num_faces();
        for round in 0..24 {
            let depth: Vec<u8> = (0..nf).map(|_| rng.below(5) as u8).collect();
            let method = METHODS[round % 2];
            let g = frame(&mesh, 4, &depth, &vec![true; nf], method);
            assert_eq!(
                open_edges(&g),
                0,
                "{name} round {round} depths {depth:?} {method:?}"
            );
        }
    }
}

#[test]
fn valence_2_vertices_are_watertight_at_any_depth_pair() {
    // Two quads sharing the two edges of an interior valence-2 vertex, the vertex at every
    // pair of patch corners: at equal depths their corner quads have the same three border
    // points, at different depths the shallower one fans; every depth pair must be closed.
    let mut rng = Rng::xorshift(0x2545_f491_4f6c_dd1d);
    for rot in (0..16).map(|r| [r % 4, r / 4]) {
        let mesh = valence2_cube(rot);
        let nf = mesh.num_faces();
        for a in 0..=3u8 {
            for b in 0..=3u8 {
                let mut depth: Vec<u8> = (0..nf).map(|_| rng.below(4) as u8).collect();
                depth[0] = a;
                depth[1] = b;
                for method in METHODS {
                    let g = frame(&mesh, 3, &depth, &vec![true; nf], method);
                    assert_eq!(
                        open_edges(&g),
                        0,
                        "rotation {rot:?} depths {depth:?} {method:?}"
                    );
                }
            }
        }
    }
    // The pillow: four valence-2 ring corners, uniform and random depths.
    let mesh = pillow();
    let nf = mesh.num_faces();
    for round in 0..32 {
        let depth: Vec<u8> = if round < 4 {
            vec![round as u8; nf]
        } else {
            (0..nf).map(|_| rng.below(5) as u8).collect()
        };
        for method in METHODS {
            let g = frame(&mesh, 4, &depth, &vec![true; nf], method);
            assert_eq!(open_edges(&g), 0, "pillow depths {depth:?} {method:?}");
        }
    }
}

#[test]
fn inactive_faces_emit_nothing_and_cause_no_fans() {
    let mesh = cube();
    // Face 0 culled, at a deeper depth that would otherwise make its neighbours fan.
    let mut depth = vec![1u8; 6];
    depth[0] = 3;
    let mut active = [true; 6];
    active[0] = false;
    let g = frame(&mesh, 3, &depth, &active, FanMethod::Subdivided);
    assert_eq!(g.num_triangles(), 5 * 8);
    assert_eq!(g.unit_depth, vec![u8::MAX, 1, 1, 1, 1, 1]);
    assert_eq!(g.units_per_depth(), vec![0, 5]);
    // The culled face leaves a square hole of 4 * 2 segments.
    assert_eq!(open_edges(&g), 8);
    // Nothing active: nothing drawn.
    let g = frame(&mesh, 3, &depth, &[false; 6], FanMethod::Subdivided);
    assert_eq!(g.num_triangles(), 0);
    assert_eq!(g.units_per_depth(), Vec::<usize>::new());
}

#[test]
fn n_gon_units_have_two_triangles_per_level_one_quad() {
    let mesh = prism();
    for d in 1..=3u32 {
        let g = frame(&mesh, 3, &[d as u8; 5], &[true; 5], FanMethod::Subdivided);
        // Two triangles of three level-1 quads each, three quads.
        let want = 2 * 3 * 2 * 4usize.pow(d - 1) + 3 * 2 * 4usize.pow(d);
        assert_eq!(g.num_triangles(), want, "depth {d}");
        assert_eq!(open_edges(&g), 0);
    }
}
