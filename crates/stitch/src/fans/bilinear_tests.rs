//! The bilinear assembler measured against the uniform bilinear tessellation
//! (`subdiv_slate::tessellate_bilinear`, which agrees with OpenSubdiv's bilinear refinement).

use std::collections::HashSet;

use subdiv_mesh::{Mesh, parse_obj};
use subdiv_slate::tessellate_bilinear;

use super::test_util::{Rng, open_edges, prism};
use super::{AdaptiveFrame, Assembler};

/// A bent cage of quads, a triangle and a pentagon (non-planar faces: their bilinear patches
/// are twisted, so a wrong corner order or parameter moves points off the uniform lattice).
fn bent() -> Mesh {
    let obj = "v 0 0 0\nv 1 0 0.2\nv 2 0 0\nv 0 1 0.1\nv 1 1 -0.3\nv 2 1 0.4\nv 0 2 0\n\
               v 1 2 0.5\nv 2 2 -0.1\nv 3 1.5 0.3\nv 2.5 2.8 0.2\nv 3 0.5 -0.2\n\
               f 1 2 5 4\nf 2 3 6 5\nf 4 5 8 7\nf 5 6 9 8\nf 6 10 11 9\nf 3 12 6\n";
    Mesh::from_soup(&parse_obj(obj).unwrap()).unwrap()
}

fn bilinear_frame(mesh: &Mesh, max_depth: u8, depth: &[u8]) -> AdaptiveFrame {
    let mut asm = Assembler::bilinear(mesh, max_depth).unwrap();
    let mut g = AdaptiveFrame::default();
    asm.frame(mesh, depth, &vec![true; depth.len()], &mut g)
        .unwrap();
    g
}

/// The bits of the points the frame's triangles use.
fn used_points(g: &AdaptiveFrame) -> HashSet<[u32; 3]> {
    let s = g.surface();
    s.face_indices()
        .iter()
        .map(|&i| s.positions()[i as usize].map(f32::to_bits))
        .collect()
}

fn uniform_points(mesh: &Mesh, depth: u8) -> HashSet<[u32; 3]> {
    let t = tessellate_bilinear(mesh, depth).unwrap();
    t.positions().iter().map(|p| p.map(f32::to_bits)).collect()
}

/// Every triangle faces the way its corners' normals do (each corner on a patch border has
/// its own patch's normal: on a bent cage the mean of two patches' would not always).
fn check_normals(g: &AdaptiveFrame, what: &str) {
    let s = g.surface();
    let p = |i: u32| glam::Vec3::from(s.positions()[i as usize]);
    for (t, tri) in s.face_indices().chunks(3).enumerate() {
        let n = (p(tri[1]) - p(tri[0])).cross(p(tri[2]) - p(tri[0]));
        for c in 0..3 {
            let cn = glam::Vec3::from(s.corner_normal(3 * t + c));
            assert!(
                n.dot(cn) > 0.0,
                "{what}: triangle {t} corner {c}: {n} against {cn}"
            );
        }
    }
}

/// The open edges a frame at `depth` per face has: `2^depth` along each boundary edge.
fn boundary_points(mesh: &Mesh, depth: &[u8]) -> usize {
    mesh.edges()
        .filter(|&e| mesh.is_boundary_edge(e))
        .map(|e| {
            let face = [e.halfedge(0), e.halfedge(1)]
                .into_iter()
                .map(|h| mesh.face(h))
                .find(|f| f.is_some())
                .expect("a boundary edge has a face");
            1usize << depth[face.idx()]
        })
        .sum()
}

/// At one depth everywhere the frame's points are the uniform tessellation's, bit for bit.
#[test]
fn a_uniform_frame_has_the_uniform_points() {
    for (name, mesh) in [("bent", bent()), ("prism", prism())] {
        for d in 1..=4u8 {
            let g = bilinear_frame(&mesh, 5, &vec![d; mesh.num_faces()]);
            assert_eq!(
                used_points(&g),
                uniform_points(&mesh, d),
                "{name} depth {d}"
            );
            let boundary = boundary_points(&mesh, &vec![d; mesh.num_faces()]);
            assert_eq!(open_edges(&g), boundary, "{name} depth {d}");
            check_normals(&g, name);
        }
    }
}

/// At mixed depths the frame is watertight and every point lies on the bilinear surface: it is
/// a point of the uniform tessellation one level below the deepest face (fan centres and
/// subdivided edges are one level deeper than their patch).
#[test]
fn a_mixed_frame_is_watertight_and_on_the_surface() {
    let mut rng = Rng::xorshift(0x5eed_b11e);
    for (name, mesh) in [("bent", bent()), ("prism", prism())] {
        for _ in 0..12 {
            let depth: Vec<u8> = (0..mesh.num_faces())
                .map(|_| 1 + (rng.next_u64() % 4) as u8)
                .collect();
            let g = bilinear_frame(&mesh, 5, &depth);
            let deepest = *depth.iter().max().unwrap();
            let lattice = uniform_points(&mesh, deepest + 1);
            let off: Vec<_> = used_points(&g).difference(&lattice).copied().collect();
            assert!(
                off.is_empty(),
                "{name} {depth:?}: {} points off the surface",
                off.len()
            );
            assert_eq!(
                open_edges(&g),
                boundary_points(&mesh, &depth),
                "{name} {depth:?}"
            );
            check_normals(&g, name);
        }
    }
}

/// UVs follow the bilinear rules (linear: every option the same) through fans at mixed depths:
/// each corner's UV is the uniform tessellation's at that point, on a cage whose UVs have no
/// seams (one value per point).
#[test]
fn uvs_are_the_uniform_uvs_at_mixed_depths() {
    let mut obj = String::from(
        "v 0 0 0\nv 1 0 0.2\nv 2 0 0\nv 0 1 0.1\nv 1 1 -0.3\nv 2 1 0.4\nv 0 2 0\nv 1 2 0.5\n\
         v 2 2 -0.1\nv 3 1.5 0.3\n",
    );
    let uv = [
        (0.0, 0.0),
        (0.4, 0.0),
        (1.0, 0.1),
        (0.0, 0.5),
        (0.6, 0.4),
        (0.9, 0.6),
    ];
    let uv2 = [(0.1, 1.0), (0.5, 0.9), (1.0, 1.0), (1.3, 0.8)];
    for (u, v) in uv.iter().chain(&uv2) {
        obj += &format!("vt {u} {v}\n");
    }
    obj += "f 1/1 2/2 5/5 4/4\nf 2/2 3/3 6/6 5/5\nf 4/4 5/5 8/8 7/7\nf 5/5 6/6 10/10 9/9 8/8\n";
    let mesh = Mesh::from_soup(&parse_obj(&obj).unwrap()).unwrap();
    let mut rng = Rng::xorshift(0x0b11_10a7);
    for _ in 0..8 {
        let depth: Vec<u8> = (0..mesh.num_faces())
            .map(|_| 1 + (rng.next_u64() % 3) as u8)
            .collect();
        let g = bilinear_frame(&mesh, 4, &depth);
        let deepest = *depth.iter().max().unwrap();
        let t = tessellate_bilinear(&mesh, deepest + 1).unwrap();
        let mut at = std::collections::HashMap::new();
        for (c, &v) in t.face_indices().iter().enumerate() {
            let value = t.uvs()[t.uv_indices()[c] as usize];
            at.insert(t.positions()[v as usize].map(f32::to_bits), value);
        }
        let s = g.surface();
        assert_eq!(s.uv_indices().len(), s.face_indices().len());
        for (c, &v) in s.face_indices().iter().enumerate() {
            let p = s.positions()[v as usize];
            let want = at[&p.map(f32::to_bits)];
            let got = s.uvs()[s.uv_indices()[c] as usize];
            let d = (got[0] - want[0]).abs().max((got[1] - want[1]).abs());
            assert!(
                d < 1e-6,
                "{depth:?} corner {c} at {p:?}: {got:?} against {want:?}"
            );
        }
    }
}
