//! Shared fixtures of the unit tests: small cages, a one-call frame and watertightness checks.

use subdiv_mesh::{Mesh, parse_obj};

use super::{AdaptiveFrame, Assembler, FanMethod};

/// The unit cube, outward counter-clockwise faces (6 quads, closed).
pub(super) fn cube() -> Mesh {
    Mesh::from_soup(&parse_obj(&subdiv_test_support::cube().obj()).unwrap()).unwrap()
}

/// A flat `k x k` grid of quads in the `z = 0` plane (open: `4k` boundary edges).
pub(super) fn grid(k: usize) -> Mesh {
    let soup = subdiv_test_support::height_grid(k as u32, false, 0.0, |_, _| 0.0);
    Mesh::from_soup(&parse_obj(&soup.obj()).unwrap()).unwrap()
}

/// A closed triangular prism: faces 0 and 1 are triangles, 2..=4 quads (all level-1 units:
/// every quad touches a triangle).
pub(super) fn prism() -> Mesh {
    Mesh::from_soup(&parse_obj(&subdiv_test_support::prism().obj()).unwrap()).unwrap()
}

/// The unit cube with its top split into two triangles: face 0 (the bottom, away from the
/// triangles) is a regular patch, faces 1..=6 are level-1 units.
pub(super) fn split_cube() -> Mesh {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
               f 1 3 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    Mesh::from_soup(&parse_obj(obj).unwrap()).unwrap()
}

/// One frame of a fresh assembler.
pub(super) fn frame(
    mesh: &Mesh,
    max_depth: subdiv_slate::Depth,
    depth: &[u8],
    active: &[bool],
    method: FanMethod,
) -> AdaptiveFrame {
    let mut asm = Assembler::new(mesh, max_depth).unwrap();
    asm.set_method(method);
    let mut g = AdaptiveFrame::default();
    asm.frame(mesh, depth, active, &mut g).unwrap();
    g
}

/// Checks that no directed edge is used twice and no triangle is degenerate, first by index,
/// then after welding vertices with bitwise equal positions; returns the number of open
/// (unpaired) edges after welding, which both passes must agree on.
pub(crate) fn open_edges(g: &AdaptiveFrame) -> usize {
    subdiv_test_support::open_edges("frame", g.surface().positions(), g.surface().face_indices())
}

/// The generator of the unit tests (their seeds are xorshift64 seeds: `Rng::xorshift`).
pub(crate) use subdiv_test_support::Rng;

/// The unit cube with its bottom face replaced by two quads around a new vertex 9 that share
/// the two consecutive edges 1-9 and 9-4: vertex 9 is interior with valence 2. `rot` rotates the
/// vertex lists of the two quads (by `rot[0]` and `rot[1]` places), which moves vertex 9 to a
/// different corner of each patch.
pub(super) fn valence2_cube(rot: [usize; 2]) -> Mesh {
    let mut quads = [[1, 2, 4, 9], [1, 9, 4, 3]];
    quads[0].rotate_left(rot[0] % 4);
    quads[1].rotate_left(rot[1] % 4);
    let mut obj = String::from(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\nv 0.6 0.4 -0.1\n",
    );
    for q in quads {
        obj += &format!("f {} {} {} {}\n", q[3], q[2], q[1], q[0]);
    }
    obj += "f 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    Mesh::from_soup(&parse_obj(&obj).unwrap()).unwrap()
}

/// A pillow: two 2x2 quad sheets glued along their border ring; the four ring corners are
/// interior vertices of valence 2, each at a different patch corner in its two faces.
pub(super) fn pillow() -> Mesh {
    let obj = "v -1 -1 0.1\nv 0 -1 0\nv 1 -1 -0.1\nv 1 0 0.05\nv 1 1 0.1\nv 0 1 0\nv -1 1 -0.05\n\
               v -1 0 0\nv 0.1 0 0.8\nv 0 -0.1 -0.6\n\
               f 1 2 9 8\nf 2 3 4 9\nf 9 4 5 6\nf 8 9 6 7\n\
               f 8 10 2 1\nf 10 4 3 2\nf 6 5 4 10\nf 7 6 10 8\n";
    Mesh::from_soup(&parse_obj(obj).unwrap()).unwrap()
}

/// A `k x k` grid over a bump with a UV per vertex: quads with the corner one split into two
/// triangles (level-1 units around it), or with `triangles` all split; with `crease` an
/// infinitely sharp crease across it.
pub(crate) fn uv_grid(k: usize, crease: bool, triangles: bool) -> Mesh {
    let mut obj = String::new();
    for j in 0..=k {
        for i in 0..=k {
            let (x, y) = (i as f32 / k as f32, j as f32 / k as f32);
            let z = 0.3 * (x * 3.0).sin() * (y * 2.0).cos();
            obj += &format!("v {x} {y} {z}\nvt {x} {y}\n");
        }
    }
    let id = |i: usize, j: usize| j * (k + 1) + i + 1;
    for j in 0..k {
        for i in 0..k {
            let [a, b, c, d] = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if triangles || (i == 0 && j == 0) {
                obj += &format!("f {a}/{a} {b}/{b} {c}/{c}\nf {a}/{a} {c}/{c} {d}/{d}\n");
            } else {
                obj += &format!("f {a}/{a} {b}/{b} {c}/{c} {d}/{d}\n");
            }
        }
    }
    let m = k / 2;
    for i in (0..k).filter(|_| crease) {
        obj += &format!("t crease 2/1/0 {} {} 10\n", id(i, m) - 1, id(i + 1, m) - 1);
    }
    Mesh::from_soup(&parse_obj(&obj).unwrap()).unwrap()
}

pub(crate) use crate::runs::Emitted;

/// Asserts that frame `g` has the triangles, one-sided corner normals and face-varying corner
/// values `afresh` (a frame emitted again, nothing kept).
pub(crate) fn assert_emitted(g: &AdaptiveFrame, afresh: &Emitted, what: &str) {
    let s = g.surface();
    assert!(s.face_indices() == afresh.0, "{what}: triangles");
    assert!(s.corner_normals() == afresh.1, "{what}: one-sided normals");
    assert!(s.uv_indices() == afresh.2, "{what}: face-varying values");
}

/// Moves the cage: `z += 0.2 x y` (other normals along a crease across a [`uv_grid`]).
pub(crate) fn bend(mesh: &mut Mesh) {
    for p in mesh.positions_mut() {
        p.z += 0.2 * p.x * p.y;
    }
}

/// A moving camera over a moving cage: 80 frames from depth 1 everywhere, each changing a few
/// faces' depths (now and then their activity), the cage bent at frame 50.
/// `frame(mesh, depth, active, bent, i)` builds frame `i` (`bent`: the cage moved since the
/// last) and returns how many runs it kept; returns the sum.
pub(crate) fn depth_walk(
    mesh: &mut Mesh,
    rng: &mut Rng,
    mut frame: impl FnMut(&Mesh, &[u8], &[bool], bool, usize) -> usize,
) -> usize {
    let nf = mesh.num_faces();
    let (mut depth, mut active) = (vec![1u8; nf], vec![true; nf]);
    let mut kept = 0;
    for i in 0..80 {
        for _ in 0..rng.below(4) {
            let f = rng.below(nf);
            depth[f] = rng.below(5) as u8;
            if rng.chance(15) {
                active[f] = !active[f];
            }
        }
        if i == 50 {
            bend(mesh);
        }
        kept += frame(mesh, &depth, &active, i == 50, i);
    }
    kept
}

/// A still camera over a cage that moves once: two frames of [`uv_grid`] (`triangles` as
/// there, with the crease) at depth 2 everywhere, the cage bent between them.
/// `frame(mesh, depth, active, bent)` builds one, checks it against a frame emitted afresh and
/// returns the frame's one-sided corner normals, the runs it kept and the runs in all.
/// Asserts that the crease's normals moved and that the bent frame kept some runs, not all:
/// blocks computed again into the slots they had leave the runs without one-sided normals.
pub(crate) fn bent_once(
    triangles: bool,
    mut frame: impl FnMut(&Mesh, &[u8], &[bool], bool) -> (Vec<(u32, [f32; 3])>, usize, usize),
) {
    let mut mesh = uv_grid(12, true, triangles);
    let nf = mesh.num_faces();
    let (depth, active) = (vec![2u8; nf], vec![true; nf]);
    let (before, _, _) = frame(&mesh, &depth, &active, false);
    bend(&mut mesh);
    let (after, kept, runs) = frame(&mesh, &depth, &active, true);
    assert!(
        after.len() > 50 && after != before,
        "the crease's normals moved"
    );
    assert!(kept > 0 && kept < runs, "{kept} of {runs} runs kept");
}
