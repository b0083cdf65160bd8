//! Face-varying limit values (UVs) of adaptive Loop frames (`subdiv_stitch::TriAssembler`):
//! on the Loop UV cages (`fixtures/meshes/fvar/tri_seam.obj`, and
//! `cube_uv.obj` with each quad split on a diagonal) under every face-varying option,
//! - a frame of one depth carries, corner by corner, the UVs of the uniform Loop slates;
//! - frames of random mixed depths give every triangle corner one of the values the uniform
//!   Loop tessellation at the deepest drawn depth (`tessellate_uniform`) has at that point (one
//!   per side of a seam), and two triangles sharing an edge (lattice triangles or fans)
//!   disagree at its ends only at seams.

use std::collections::HashMap;

use glam::DVec3;
use subdiv_mesh::{FVarLinearInterpolation, Mesh, parse_obj};
use subdiv_rules::{Scheme, tessellate_uniform};
use subdiv_stitch::{AdaptiveFrame, TriAssembler};
use subdiv_tests::{PointGrid, fixtures};

fn loop_uv_cages() -> Vec<(String, Mesh)> {
    let read = |s: &str| std::fs::read_to_string(fixtures().join(s)).unwrap();
    let mut split = String::new();
    for line in read("meshes/fvar/cube_uv.obj").lines() {
        match line.split_whitespace().collect::<Vec<_>>().as_slice() {
            ["f", a, b, c, d] => split += &format!("f {a} {b} {c}\nf {a} {c} {d}\n"),
            _ => split += &format!("{line}\n"),
        }
    }
    let mut out = Vec::new();
    for (shape, text) in [
        ("tri_seam", read("meshes/fvar/tri_seam.obj")),
        ("cube_uv split", split),
    ] {
        for option in FVarLinearInterpolation::ALL {
            let mut soup = parse_obj(&text).unwrap();
            soup.options.fvar = option;
            let name = format!("{shape} {}", option.name());
            out.push((name, Mesh::from_soup(&soup).unwrap()));
        }
    }
    out
}

fn dv(p: &[f32; 3]) -> DVec3 {
    glam::Vec3::from(*p).as_dvec3()
}

fn close(a: [f32; 2], b: [f32; 2]) -> bool {
    (a[0] - b[0]).abs() <= 1e-5 && (a[1] - b[1]).abs() <= 1e-5
}

fn frame(asm: &mut TriAssembler, mesh: &Mesh, depths: &[u8]) -> AdaptiveFrame {
    let mut g = AdaptiveFrame::default();
    asm.frame(mesh, depths, &vec![true; depths.len()], &mut g)
        .unwrap();
    assert_eq!(
        g.surface().uv_indices().len(),
        g.surface().face_indices().len()
    );
    g
}

#[test]
fn uniform_loop_frames_carry_the_slate_uvs() {
    for (name, mesh) in loop_uv_cages() {
        let mut asm = TriAssembler::new(&mesh, 3).unwrap();
        for d in 1..=3u8 {
            let g = frame(&mut asm, &mesh, &vec![d; mesh.num_faces()]);
            let s = subdiv_slate::tessellate_tri(&mesh, d).unwrap();
            // Same triangles in the same order (face by face, lattice rows).
            assert_eq!(
                g.surface().face_indices().len(),
                s.face_indices().len(),
                "{name} {d}"
            );
            for c in 0..g.surface().face_indices().len() {
                let got = g.surface().uvs()[g.surface().uv_indices()[c] as usize];
                let want = s.uvs()[s.uv_indices()[c] as usize];
                assert_eq!(got, want, "{name} depth {d} corner {c}");
            }
        }
    }
}

#[test]
fn mixed_depth_loop_frames_keep_seams_and_do_not_jump_elsewhere() {
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut ends_checked = 0;
    for (name, mesh) in loop_uv_cages() {
        let top = 3u8;
        let r = tessellate_uniform(&mesh, Scheme::Loop, top).unwrap();
        let mut at = vec![Vec::<[f32; 2]>::new(); r.positions().len()];
        for (c, &v) in r.face_indices().iter().enumerate() {
            let uv = r.uvs()[r.uv_indices()[c] as usize];
            if !at[v as usize].iter().any(|&x| close(x, uv)) {
                at[v as usize].push(uv);
            }
        }
        let pr: Vec<DVec3> = r.positions().iter().map(dv).collect();
        let grid = PointGrid::new(&pr, 1e-3);
        let mut asm = TriAssembler::new(&mesh, top).unwrap();
        for _ in 0..4 {
            let mut depths: Vec<u8> = (0..mesh.num_faces())
                .map(|_| {
                    seed ^= seed << 13;
                    seed ^= seed >> 7;
                    seed ^= seed << 17;
                    (seed % 4) as u8
                })
                .collect();
            depths[0] = top;
            let g = frame(&mut asm, &mesh, &depths);
            let map: Vec<usize> = g
                .surface()
                .positions()
                .iter()
                .map(|p| grid.nearest(dv(p)).0)
                .collect();
            for (c, &v) in g.surface().face_indices().iter().enumerate() {
                let uv = g.surface().uvs()[g.surface().uv_indices()[c] as usize];
                let options = &at[map[v as usize]];
                assert!(
                    options.iter().any(|&x| close(x, uv)),
                    "{name} {depths:?} corner {c}: {uv:?} not among {options:?}"
                );
            }
            // Two triangles across an edge agree at its ends unless the point is on a seam.
            let mut edges: HashMap<(u32, u32), Vec<[usize; 2]>> = HashMap::new();
            for t in 0..g.num_triangles() {
                for k in 0..3 {
                    let (c0, c1) = (3 * t + k, 3 * t + (k + 1) % 3);
                    let (a, b) = (
                        g.surface().face_indices()[c0],
                        g.surface().face_indices()[c1],
                    );
                    let key = (a.min(b), a.max(b));
                    edges
                        .entry(key)
                        .or_default()
                        .push(if a < b { [c0, c1] } else { [c1, c0] });
                }
            }
            for ((a, b), sides) in &edges {
                assert_eq!(
                    sides.len(),
                    2,
                    "{name} {depths:?}: an open or non-manifold edge"
                );
                for (end, v) in [(0, *a), (1, *b)] {
                    let u0 = g.surface().uvs()[g.surface().uv_indices()[sides[0][end]] as usize];
                    let u1 = g.surface().uvs()[g.surface().uv_indices()[sides[1][end]] as usize];
                    if !close(u0, u1) {
                        assert!(
                            at[map[v as usize]].len() > 1,
                            "{name} {depths:?}: UV jump {u0:?} / {u1:?} off a seam"
                        );
                    }
                    ends_checked += 1;
                }
            }
        }
    }
    assert!(ends_checked > 10_000, "{ends_checked}");
}
