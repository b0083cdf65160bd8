//! Face-varying limit values (UVs) of adaptive Catmull-Clark frames (`subdiv-stitch`): on every
//! UV cage of `fixtures/meshes/fvar` under every face-varying option,
//! - a frame of one depth carries, corner by corner, the UVs of the uniform slates;
//! - frames of random mixed depths give every triangle corner one of the values the uniform
//!   tessellation one level deeper has at that point (one per side of a seam), and two
//!   triangles sharing an edge (plain quads or fans) disagree at its ends only at seams.

use std::collections::HashMap;

use glam::DVec3;
use subdiv_mesh::{FVarLinearInterpolation, Mesh, parse_obj};
use subdiv_rules::{LimitMesh, Scheme, tessellate_uniform};
use subdiv_stitch::{AdaptiveFrame, Assembler};
use subdiv_tests::{PointGrid, fixtures};

fn uv_cages() -> Vec<(String, Mesh)> {
    let mut out = Vec::new();
    for shape in ["cube_uv", "grid_seam", "grid_seam_crease", "tri_seam"] {
        let path = fixtures().join(format!("meshes/fvar/{shape}.obj"));
        let text = std::fs::read_to_string(path).unwrap();
        for option in FVarLinearInterpolation::ALL {
            let mut soup = parse_obj(&text).unwrap();
            soup.options.fvar = option;
            out.push((
                format!("{shape} {}", option.name()),
                Mesh::from_soup(&soup).unwrap(),
            ));
        }
    }
    out
}

fn dv(p: &[f32; 3]) -> DVec3 {
    glam::Vec3::from(*p).as_dvec3()
}

fn uv_of(uvs: &[[f32; 2]], i: u32) -> [f32; 2] {
    uvs[i as usize]
}

fn close(a: [f32; 2], b: [f32; 2]) -> bool {
    (a[0] - b[0]).abs() <= 1e-5 && (a[1] - b[1]).abs() <= 1e-5
}

/// The distinct UVs of the reference at each of its points.
fn values_at_points(r: &LimitMesh) -> Vec<Vec<[f32; 2]>> {
    let mut at = vec![Vec::<[f32; 2]>::new(); r.positions().len()];
    for (c, &v) in r.face_indices().iter().enumerate() {
        let uv = uv_of(r.uvs(), r.uv_indices()[c]);
        let list = &mut at[v as usize];
        if !list.iter().any(|&x| close(x, uv)) {
            list.push(uv);
        }
    }
    at
}

fn frame(mesh: &Mesh, depths: &[u8]) -> AdaptiveFrame {
    let mut asm = Assembler::new(mesh, 4).unwrap();
    let mut g = AdaptiveFrame::default();
    asm.frame(mesh, depths, &vec![true; depths.len()], &mut g)
        .unwrap();
    g
}

#[test]
fn uniform_frames_carry_the_slate_uvs() {
    for (name, mesh) in uv_cages() {
        let min = if mesh.faces().any(|f| mesh.face_size(f) != 4) {
            1
        } else {
            0
        };
        for d in min..=3u8 {
            let g = frame(&mesh, &vec![d; mesh.num_faces()]);
            assert_eq!(
                g.surface().uv_indices().len(),
                g.surface().face_indices().len(),
                "{name}"
            );
            let s = subdiv_slate::tessellate(&mesh, d).unwrap();
            let ps: Vec<DVec3> = s.positions().iter().map(dv).collect();
            let grid = PointGrid::new(&ps, 1e-3);
            let near = |p| grid.nearest(dv(p)).0;
            let map: Vec<usize> = g.surface().positions().iter().map(near).collect();
            // Every three corners of a slate quad name it.
            let mut quads: HashMap<[usize; 3], usize> = HashMap::new();
            for q in 0..s.num_faces() {
                let f = s.face(q);
                for skip in 0..4 {
                    let mut key: Vec<usize> = (0..4)
                        .filter(|&k| k != skip)
                        .map(|k| f[k] as usize)
                        .collect();
                    key.sort_unstable();
                    quads.insert([key[0], key[1], key[2]], q);
                }
            }
            for t in 0..g.num_triangles() {
                let ids: Vec<usize> = (0..3)
                    .map(|k| map[g.surface().face_indices()[3 * t + k] as usize])
                    .collect();
                let mut key = ids.clone();
                key.sort_unstable();
                let q = quads[&[key[0], key[1], key[2]]];
                for (k, &v) in ids.iter().enumerate() {
                    let c = s.face(q).iter().position(|&x| x as usize == v).unwrap();
                    let want = uv_of(s.uvs(), s.uv_indices()[s.face_offsets()[q] as usize + c]);
                    let got = uv_of(g.surface().uvs(), g.surface().uv_indices()[3 * t + k]);
                    assert!(
                        close(got, want),
                        "{name} depth {d} triangle {t}: {got:?} vs {want:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn mixed_depth_frames_keep_seams_and_do_not_jump_elsewhere() {
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut fans_checked = 0;
    for (name, mesh) in uv_cages() {
        let r = tessellate_uniform(&mesh, Scheme::CatmullClark, 4).unwrap();
        let at = values_at_points(&r);
        let pr: Vec<DVec3> = r.positions().iter().map(dv).collect();
        let grid = PointGrid::new(&pr, 1e-3);
        for _ in 0..4 {
            let depths: Vec<u8> = (0..mesh.num_faces())
                .map(|_| {
                    seed ^= seed << 13;
                    seed ^= seed >> 7;
                    seed ^= seed << 17;
                    (seed % 4) as u8
                })
                .collect();
            let g = frame(&mesh, &depths);
            let s = g.surface();
            assert_eq!(s.uv_indices().len(), s.face_indices().len(), "{name}");
            let near = |p| grid.nearest(dv(p)).0;
            let map: Vec<usize> = s.positions().iter().map(near).collect();
            // Each corner: one of the reference's values at its point.
            for (c, &v) in s.face_indices().iter().enumerate() {
                let uv = uv_of(s.uvs(), s.uv_indices()[c]);
                let options = &at[map[v as usize]];
                assert!(
                    options.iter().any(|&x| close(x, uv)),
                    "{name} {depths:?} corner {c}: {uv:?} not among {options:?}"
                );
            }
            // Two triangles across an edge agree at its ends unless the point is on a seam.
            let mut edges: HashMap<(u32, u32), Vec<(usize, usize)>> = HashMap::new();
            for t in 0..g.num_triangles() {
                for k in 0..3 {
                    let (a, b) = (
                        g.surface().face_indices()[3 * t + k],
                        g.surface().face_indices()[3 * t + (k + 1) % 3],
                    );
                    edges
                        .entry((a.min(b), a.max(b)))
                        .or_default()
                        .push((3 * t + k, 3 * t + (k + 1) % 3));
                }
            }
            for ((a, b), sides) in &edges {
                if sides.len() != 2 {
                    continue;
                }
                let (s0, s1) = (sides[0], sides[1]);
                for (v, c0, c1) in [
                    (*a, corner_of(&g, s0, *a), corner_of(&g, s1, *a)),
                    (*b, corner_of(&g, s0, *b), corner_of(&g, s1, *b)),
                ] {
                    let (u0, u1) = (
                        uv_of(g.surface().uvs(), g.surface().uv_indices()[c0]),
                        uv_of(g.surface().uvs(), g.surface().uv_indices()[c1]),
                    );
                    if !close(u0, u1) {
                        assert!(
                            at[map[v as usize]].len() > 1,
                            "{name} {depths:?}: UV jump {u0:?} / {u1:?} off a seam"
                        );
                    }
                    fans_checked += 1;
                }
            }
        }
    }
    assert!(fans_checked > 10_000, "{fans_checked}");
}

/// The corner (of the two in `side`) that references vertex `v`.
fn corner_of(g: &AdaptiveFrame, side: (usize, usize), v: u32) -> usize {
    if g.surface().face_indices()[side.0] == v {
        side.0
    } else {
        side.1
    }
}

#[test]
fn frames_of_a_cage_without_uvs_carry_none() {
    let (_, mut mesh) = uv_cages().swap_remove(0);
    mesh.clear_uv();
    let g = frame(&mesh, &[0, 1, 2, 3, 2, 1]);
    assert!(g.num_triangles() > 0);
    assert!(g.surface().uvs().is_empty() && g.surface().uv_indices().is_empty());
    let s = subdiv_slate::tessellate(&mesh, 2).unwrap();
    assert!(s.uvs().is_empty() && s.uv_indices().is_empty());
}
