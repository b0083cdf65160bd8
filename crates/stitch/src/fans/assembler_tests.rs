//! Tests of `assembler.rs`.

use super::super::test_util::{
    Emitted, Rng, assert_emitted, bent_once, cube, depth_walk, grid, open_edges, prism, split_cube,
    uv_grid,
};
use super::*;

/// Test access to an assembler's frame data.
impl Assembler {
    /// Test access: the last frame's triangles, one-sided corner normals and face-varying
    /// corner values emitted afresh (every run, nothing kept) over the blocks as cached.
    pub(in crate::fans) fn emitted_afresh(
        &self,
        mesh: &Mesh,
        depth: &[Depth],
        active: &[bool],
    ) -> Emitted {
        let depth: Vec<Depth> = (0..depth.len())
            .map(|u| depth[u].clamp(self.min_depth(u), self.max_depth))
            .collect();
        let drawn = active.iter().any(|&a| a);
        let uvs = self.uvs.as_ref().filter(|_| mesh.uv().is_some() && drawn);
        let (mut chunks, mut tris, mut sided, mut corners) = Default::default();
        self.with_frame(mesh, &depth, active, |fr| {
            fr.emit_frame(
                active,
                self.method,
                uvs,
                None,
                &mut chunks,
                &mut tris,
                &mut sided,
                &mut corners,
            )
        });
        (tris, sided, corners)
    }

    /// Test access: the frame data (edge resolutions, owners, point ids) for `depth` and
    /// `active`, over the blocks as currently cached.
    pub(in crate::fans) fn with_frame<R>(
        &self,
        mesh: &Mesh,
        depth: &[Depth],
        active: &[bool],
        f: impl FnOnce(&Frame) -> R,
    ) -> R {
        let fr = self.frame_data(mesh, depth, active);
        f(&fr)
    }
}

#[test]
fn quads_per_depth_counts_grid_quads_of_drawn_units() {
    // Split cube: face 0 a regular patch, faces 1 and 2 triangles (3 level-1 quads each),
    // faces 3..=6 quads next to them (4 level-1 quads each).
    let mesh = split_cube();
    let mut asm = Assembler::new(&mesh, 4).unwrap();
    let mut g = AdaptiveFrame::default();
    let depth = [0, 1, 2, 1, 3, 2, 1];
    let mut active = [true; 7];
    active[6] = false;
    asm.frame(&mesh, &depth, &active, &mut g).unwrap();
    // depth 0: face 0 (1 quad); depth 1: face 1 (3) + face 3 (4); depth 2: face 2 (3 * 4)
    // + face 5 (4 * 4); depth 3: face 4 (4 * 16); face 6 not drawn.
    assert_eq!(asm.quads_per_depth(&g), vec![1, 7, 28, 64]);
    // Every drawn quad is two triangles unless it was replaced by a fan.
    let quads: u64 = asm.quads_per_depth(&g).iter().sum();
    assert!(quads * 2 <= g.num_triangles() as u64 + 4 * 64);
}

#[test]
fn cache_recomputes_only_patches_whose_depth_rose() {
    let mesh = cube();
    let mut asm = Assembler::new(&mesh, 4).unwrap();
    let mut g = AdaptiveFrame::default();
    asm.frame(&mesh, &[2; 6], &[true; 6], &mut g).unwrap();
    assert_eq!(g.patches_recomputed, 6);
    let v0 = g.vertex_version;
    let pos0 = g.surface().positions().to_vec();
    // Lower every depth: blocks reused, vertex buffer untouched.
    asm.frame(&mesh, &[1; 6], &[true; 6], &mut g).unwrap();
    assert_eq!(g.patches_recomputed, 0);
    assert_eq!(g.vertex_version, v0);
    assert_eq!(g.surface().positions(), pos0);
    assert_eq!(g.num_triangles(), 6 * 8);
    assert_eq!(open_edges(&g), 0);
    // Raise face 0 above the cache: face 0 and its four fanning neighbours, not face 1.
    let mut depth = [2u8; 6];
    depth[0] = 3;
    asm.frame(&mesh, &depth, &[true; 6], &mut g).unwrap();
    assert_eq!(g.patches_recomputed, 5);
    assert!(g.vertex_version > v0);
    assert_eq!(open_edges(&g), 0);
    let v1 = g.vertex_version;
    // Back down and up again: all cached.
    asm.frame(&mesh, &[2; 6], &[true; 6], &mut g).unwrap();
    asm.frame(&mesh, &depth, &[true; 6], &mut g).unwrap();
    assert_eq!(g.patches_recomputed, 0);
    assert_eq!(g.vertex_version, v1);
    // Invalidating drops every block.
    asm.invalidate();
    asm.frame(&mesh, &depth, &[true; 6], &mut g).unwrap();
    assert_eq!(g.patches_recomputed, 6);
    assert!(g.vertex_version > v1);
}

#[test]
fn vertices_outside_the_dirty_ranges_keep_their_bits() {
    // Random depths frame after frame: whatever a frame recomputes, every vertex outside
    // its dirty ranges is the previous frame's, and a frame that recomputes nothing
    // rewrites nothing.
    let mut rng = super::super::test_util::Rng::xorshift(0x51a7_5eed);
    for mesh in [cube(), split_cube(), prism()] {
        let nf = mesh.num_faces();
        let mut asm = Assembler::new(&mesh, 4).unwrap();
        let mut g = AdaptiveFrame::default();
        asm.frame(&mesh, &vec![1; nf], &vec![true; nf], &mut g)
            .unwrap();
        let all = 0..g.surface().num_vertices() as u32;
        assert_eq!(g.dirty_vertices().to_vec(), vec![all]);
        for round in 0..40 {
            let before = g.surface().positions().to_vec();
            let depth: Vec<u8> = (0..nf).map(|_| rng.below(5) as u8).collect();
            asm.frame(&mesh, &depth, &vec![true; nf], &mut g).unwrap();
            let now = g.surface().positions();
            let dirty = g.dirty_vertices();
            if g.patches_recomputed == 0 {
                assert!(dirty.is_empty(), "round {round}");
            }
            for (v, p) in before.iter().enumerate().take(now.len()) {
                if !dirty.iter().any(|r| r.contains(&(v as u32))) {
                    assert_eq!(now[v], *p, "round {round} vertex {v}");
                }
            }
            assert_eq!(open_edges(&g), 0, "round {round}");
        }
    }
}

#[test]
fn cached_frame_matches_fresh_frame() {
    // A frame sampled from deeper cached blocks has the same triangles as a fresh one, and
    // the same points up to rounding (blocks of different depths evaluate the limit
    // through different paths, so the last bit may differ).
    let mesh = prism();
    let mut depth = [1u8, 2, 1, 3, 2];
    let mut asm = Assembler::new(&mesh, 3).unwrap();
    let mut g = AdaptiveFrame::default();
    asm.frame(&mesh, &[3; 5], &[true; 5], &mut g).unwrap();
    asm.frame(&mesh, &depth, &[true; 5], &mut g).unwrap();
    assert_eq!(g.patches_recomputed, 0);
    assert_eq!(open_edges(&g), 0);
    let mut fresh_asm = Assembler::new(&mesh, 3).unwrap();
    let mut fresh = AdaptiveFrame::default();
    fresh_asm
        .frame(&mesh, &depth, &[true; 5], &mut fresh)
        .unwrap();
    let (p_cached, _, i_cached) = g.compact();
    let (p_fresh, _, i_fresh) = fresh.compact();
    assert_eq!(i_cached, i_fresh);
    for (a, b) in p_cached.iter().zip(&p_fresh) {
        let d = (glam::Vec3::from(*a) - glam::Vec3::from(*b)).length();
        assert!(d < 1e-5, "{a:?} vs {b:?}");
    }
    // Depth 0 is clamped to the triangle's minimum depth 1: the same frame.
    depth[0] = 0;
    let mut clamped = AdaptiveFrame::default();
    fresh_asm
        .frame(&mesh, &depth, &[true; 5], &mut clamped)
        .unwrap();
    assert_eq!(clamped.compact(), fresh.compact());
}

#[test]
fn vertex_depth_and_unit_depth_follow_the_frame() {
    let mesh = cube();
    let depth = [0u8, 1, 2, 0, 1, 2];
    let g = super::super::test_util::frame(&mesh, 2, &depth, &[true; 6], FanMethod::Subdivided);
    assert_eq!(g.unit_depth, depth);
    assert_eq!(g.units_per_depth(), vec![2, 2, 2]);
    assert_eq!(g.vertex_depth().len(), g.surface().positions().len());
    assert_eq!(g.surface().normals().len(), g.surface().positions().len());
    for &i in g.surface().face_indices() {
        let d = g.vertex_depth()[i as usize];
        assert!((0.0..=2.0).contains(&d) && d.fract() == 0.0);
    }
}

#[test]
fn depths_are_clamped_to_the_unit_range() {
    let asm = Assembler::new(&split_cube(), 2).unwrap();
    assert_eq!(
        (0..7).map(|u| asm.min_depth(u)).collect::<Vec<_>>(),
        vec![0, 1, 1, 1, 1, 1, 1]
    );
    let mesh = prism();
    let deep =
        super::super::test_util::frame(&mesh, 2, &[200; 5], &[true; 5], FanMethod::Subdivided);
    let two = super::super::test_util::frame(&mesh, 2, &[2; 5], &[true; 5], FanMethod::Subdivided);
    assert_eq!(deep.surface().face_indices(), two.surface().face_indices());
    assert_eq!(deep.unit_depth, vec![2; 5]);
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let mesh = cube();
    let max = subdiv_slate::MAX_DEPTH - 1;
    assert!(matches!(
        Assembler::new(&mesh, max + 1),
        Err(AssemblyError::TooDeep { depth, max: m }) if depth == max + 1 && m == max
    ));
    assert!(Assembler::with_budget(&mesh, max, &Budget::unlimited()).is_ok());
    let mut asm = Assembler::new(&mesh, 2).unwrap();
    let mut g = AdaptiveFrame::default();
    let err = asm.frame(&mesh, &[1; 5], &[true; 6], &mut g).unwrap_err();
    assert!(matches!(
        err,
        AssemblyError::Length {
            got: 5,
            want: 6,
            ..
        }
    ));
    assert!(err.to_string().contains("5 entries"), "{err}");
    let err = asm.frame(&mesh, &[1; 6], &[true; 7], &mut g).unwrap_err();
    assert!(matches!(err, AssemblyError::Length { want: 6, .. }));
    assert!(g.surface().face_indices().is_empty());
    // The assembler stays usable.
    asm.frame(&mesh, &[1; 6], &[true; 6], &mut g).unwrap();
    assert_eq!(g.num_triangles(), 48);
}

#[test]
fn frames_too_large_for_memory_are_refused_before_any_work() {
    // 36 patches at depth 11 need 36 * 2049^2 > MAX_POINTS cached points.
    let mesh = grid(6);
    let max = subdiv_slate::MAX_DEPTH - 1;
    let mut asm = Assembler::with_budget(&mesh, max, &Budget::unlimited()).unwrap();
    let mut g = AdaptiveFrame::default();
    let err = asm
        .frame(&mesh, &[max; 36], &[true; 36], &mut g)
        .unwrap_err();
    let want = 36 * ((1u64 << max) + 1).pow(2);
    assert!(want > subdiv_slate::MAX_POINTS);
    assert!(matches!(err, AssemblyError::TooLarge { points } if points == want));
    assert!(g.surface().positions().is_empty());
    asm.frame(&mesh, &[1; 36], &[true; 36], &mut g).unwrap();
    assert_eq!(g.patches_recomputed, 36);
    assert_eq!(open_edges(&g), 24 * 2);
}

#[test]
fn runs_kept_from_the_last_frame_are_what_emitting_them_again_gives() {
    // A moving camera changes a few depths a frame: the runs of patches whose state stayed
    // keep their triangles, and the frame is bit for bit the one emitted afresh.
    let pawn = subdiv_mesh::read_obj(subdiv_test_support::shape("catmark_pawn.obj")).unwrap();
    let mut rng = Rng::xorshift(0x6b65_7074);
    for (name, mut mesh) in [("pawn", pawn), ("uv grid", uv_grid(14, true, false))] {
        let mut asm = Assembler::new(&mesh, 4).unwrap();
        let mut g = AdaptiveFrame::default();
        let kept = depth_walk(&mut mesh, &mut rng, |mesh, depth, active, bent, i| {
            if bent {
                asm.move_to(mesh);
            }
            asm.frame(mesh, depth, active, &mut g).unwrap();
            let afresh = asm.emitted_afresh(mesh, depth, active);
            assert_emitted(&g, &afresh, &format!("{name} frame {i}"));
            asm.runs_kept
        });
        assert!(kept > 80, "{name}: {kept} runs kept");
        if name == "uv grid" {
            let s = g.surface();
            assert!(!s.uv_indices().is_empty() && !s.corner_normals().is_empty());
        }
    }
}

#[test]
fn a_moved_cage_gives_its_runs_their_new_one_sided_normals() {
    let mesh = uv_grid(12, true, false);
    let mut asm = Assembler::new(&mesh, 3).unwrap();
    let mut g = AdaptiveFrame::default();
    bent_once(false, |mesh, depth, active, bent| {
        if bent {
            asm.move_to(mesh);
        }
        asm.frame(mesh, depth, active, &mut g).unwrap();
        let afresh = asm.emitted_afresh(mesh, depth, active);
        assert_emitted(&g, &afresh, "bent");
        (afresh.1, asm.runs_kept, asm.deps.len())
    });
}

#[test]
fn a_deeper_face_varying_level_leaves_every_run_its_values() {
    // One face drawn deeper than any before: the face-varying values are made again at a
    // deeper level; the runs far from the face, kept or not, name the same values.
    let mesh = uv_grid(14, false, false);
    let nf = mesh.num_faces();
    let mut asm = Assembler::new(&mesh, 4).unwrap();
    let mut g = AdaptiveFrame::default();
    let (mut depth, active) = (vec![1u8; nf], vec![true; nf]);
    asm.frame(&mesh, &depth, &active, &mut g).unwrap();
    let uvs_before = g.surface().uvs().len();
    assert_eq!(asm.uvs.as_ref().map(|u| u.level()), Some(2));
    depth[nf - 1] = 3;
    asm.frame(&mesh, &depth, &active, &mut g).unwrap();
    let (_, _, uv) = asm.emitted_afresh(&mesh, &depth, &active);
    assert!(g.surface().uv_indices() == uv);
    assert_eq!(asm.uvs.as_ref().map(|u| u.level()), Some(4));
    assert!(g.surface().uvs().len() > 10 * uvs_before);
}
