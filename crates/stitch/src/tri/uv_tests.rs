//! Face-varying limit UVs of adaptive Loop frames against the uniform Loop
//! slates: equal at uniform depth; at mixed depths every triangle takes, at each corner, the
//! deepest uniform tessellation's value at that point on one cage face's side (seams keep both
//! sides, no jump elsewhere).

use subdiv_mesh::{Mesh, parse_obj};
use subdiv_slate::tessellate_tri;

use super::*;
use crate::fans::test_util::{Rng, open_edges};

fn fvar(name: &str) -> String {
    let path = subdiv_test_support::fixture(&format!("meshes/fvar/{name}.obj"));
    std::fs::read_to_string(path).unwrap()
}

/// The Loop cages with UVs: the octahedron with a seam loop, and the cube's cross unwrap with
/// every quad split on its first diagonal (a cage not in the fixtures as such).
fn cages() -> Vec<(&'static str, Mesh)> {
    let mut cube = String::new();
    for line in fvar("cube_uv").lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            ["f", a, b, c, d] => cube += &format!("f {a} {b} {c}\nf {a} {c} {d}\n"),
            _ => cube += &format!("{line}\n"),
        }
    }
    [("tri_seam", fvar("tri_seam")), ("cube_uv_split", cube)]
        .into_iter()
        .map(|(n, t)| (n, Mesh::from_soup(&parse_obj(&t).unwrap()).unwrap()))
        .collect()
}

fn close(a: [f32; 3], b: [f32; 3]) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= 1e-5)
}

#[test]
fn uniform_depth_frames_have_the_loop_slates_uvs() {
    for (name, mesh) in cages() {
        let nf = mesh.num_faces();
        let mut asm = TriAssembler::new(&mesh, 4).unwrap();
        let mut g = AdaptiveFrame::default();
        for d in 1..=3 {
            asm.frame(&mesh, &vec![d; nf], &vec![true; nf], &mut g)
                .unwrap();
            let s = tessellate_tri(&mesh, d).unwrap();
            assert_eq!(
                g.surface().face_indices().len(),
                s.face_indices().len(),
                "{name} {d}"
            );
            assert_eq!(
                g.surface().uv_indices().len(),
                g.surface().face_indices().len(),
                "{name} {d}"
            );
            for c in 0..g.surface().face_indices().len() {
                let p = g.surface().positions()[g.surface().face_indices()[c] as usize];
                assert!(
                    close(p, s.positions()[s.face_indices()[c] as usize]),
                    "{name} {d}"
                );
                assert_eq!(
                    g.surface().uvs()[g.surface().uv_indices()[c] as usize],
                    s.uvs()[s.uv_indices()[c] as usize],
                    "{name} depth {d} corner {c}"
                );
            }
        }
    }
}

/// Corners of the uniform depth-`d` Loop tessellation: (cage face, position, UV).
fn reference(mesh: &Mesh, d: Depth) -> Vec<(usize, [f32; 3], [f32; 2])> {
    let s = tessellate_tri(mesh, d).unwrap();
    let per_face = 3usize << (2 * d);
    (0..s.face_indices().len())
        .map(|c| {
            let p = s.positions()[s.face_indices()[c] as usize];
            (c / per_face, p, s.uvs()[s.uv_indices()[c] as usize])
        })
        .collect()
}

#[test]
fn mixed_depth_corners_take_the_deepest_uniform_uvs_on_one_side() {
    let mut rng = Rng::xorshift(0x5eed_0016);
    for (name, mesh) in cages() {
        let nf = mesh.num_faces();
        let top: Depth = 3;
        let refs = reference(&mesh, top);
        let mut asm = TriAssembler::new(&mesh, top).unwrap();
        let mut g = AdaptiveFrame::default();
        for round in 0..6 {
            // The first frames are shallow: the values are refined again when a frame needs a
            // deeper level. Face 0 is always at the top depth, the level of the reference.
            let mut depth: Vec<Depth> = (0..nf).map(|_| rng.below(4) as Depth).collect();
            if round == 0 {
                depth.fill(1);
                asm.frame(&mesh, &depth, &vec![true; nf], &mut g).unwrap();
            }
            depth[0] = top;
            asm.frame(&mesh, &depth, &vec![true; nf], &mut g).unwrap();
            assert_eq!(open_edges(&g), 0, "{name}");
            assert_eq!(
                g.surface().uv_indices().len(),
                g.surface().face_indices().len(),
                "{name}"
            );
            let mut pairs = std::collections::HashSet::new();
            for t in 0..g.surface().face_indices().len() / 3 {
                let corners: Vec<([f32; 3], [f32; 2])> = (3 * t..3 * t + 3)
                    .map(|c| {
                        let p = g.surface().positions()[g.surface().face_indices()[c] as usize];
                        (p, g.surface().uvs()[g.surface().uv_indices()[c] as usize])
                    })
                    .collect();
                for &(p, uv) in &corners {
                    let at: Vec<[f32; 2]> =
                        refs.iter().filter(|r| close(r.1, p)).map(|r| r.2).collect();
                    assert!(
                        !at.is_empty(),
                        "{name}: a corner off the depth-{top} lattice"
                    );
                    assert!(at.contains(&uv), "{name} {depth:?}: {uv:?} not in {at:?}");
                    pairs.insert((p.map(f32::to_bits), uv.map(f32::to_bits)));
                }
                // All three corners on one face's side: no jump inside a triangle.
                let side = (0..nf).any(|f| {
                    corners
                        .iter()
                        .all(|&(p, uv)| refs.iter().any(|r| r.0 == f && r.2 == uv && close(r.1, p)))
                });
                assert!(
                    side,
                    "{name} {depth:?}: triangle {t} mixes seam sides {corners:?}"
                );
            }
            // Seams keep both sides: some points carry two values.
            let (points, _, _) = g.compact();
            assert!(
                pairs.len() > points.len(),
                "{name}: {} {}",
                pairs.len(),
                points.len()
            );
        }
    }
}

#[test]
fn cages_without_uvs_get_none() {
    let mesh =
        Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap()).unwrap();
    let mut asm = TriAssembler::new(&mesh, 2).unwrap();
    let mut g = AdaptiveFrame::default();
    asm.frame(&mesh, &[2], &[true], &mut g).unwrap();
    assert!(!g.surface().face_indices().is_empty());
    assert!(g.surface().uvs().is_empty() && g.surface().uv_indices().is_empty());
}
