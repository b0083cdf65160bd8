//! Watertightness of the triangle fans, ownership, caching and the bitwise agreement of the
//! patch lattices with the uniform Loop tessellation.

use glam::Vec3;
use subdiv_mesh::{Mesh, parse_obj};
use subdiv_slate::{TriLayout, tessellate_tri};

use super::*;
use crate::fans::test_util::{
    Emitted, Rng, assert_emitted, bent_once, depth_walk, open_edges, uv_grid,
};

fn fixture(name: &str) -> Mesh {
    let path = subdiv_test_support::shape(&format!("{name}.obj"));
    let text = std::fs::read_to_string(&path).unwrap();
    Mesh::from_soup(&parse_obj(&text).unwrap()).unwrap()
}

const FIXTURES: [&str; 9] = [
    "loop_cube",
    "loop_cube_creases0",
    "loop_cubes_semisharp",
    "loop_icosahedron",
    "loop_pole8",
    "loop_saddle_edgecorner",
    "loop_tetrahedron",
    "loop_triangle_edgeonly",
    "loop_xord_interior",
];

/// Open edges the frame must have: the drawn cage edges with one drawn side, each in
/// `2^resolution` segments.
fn expected_open(mesh: &Mesh, asm: &TriAssembler, g: &AdaptiveFrame) -> usize {
    let mut sides = vec![(0u32, 0u8); mesh.num_edges()];
    for (f, p) in asm.layout().patches().iter().enumerate() {
        let d = g.unit_depth[f];
        if d == u8::MAX {
            continue;
        }
        for e in p.edges {
            let s = &mut sides[e.idx()];
            s.0 += 1;
            s.1 = s.1.max(d);
        }
    }
    sides
        .iter()
        .filter(|s| s.0 == 1)
        .map(|s| 1usize << s.1)
        .sum()
}

fn frame(mesh: &Mesh, depth: &[Depth], active: &[bool]) -> (TriAssembler, AdaptiveFrame) {
    let mut asm = TriAssembler::new(mesh, 5).unwrap();
    let mut g = AdaptiveFrame::default();
    asm.frame(mesh, depth, active, &mut g).unwrap();
    (asm, g)
}

#[test]
fn random_depths_are_watertight_on_every_loop_fixture() {
    let mut rng = Rng::xorshift(0x9e37_79b9_7f4a_7c15);
    for name in FIXTURES {
        let mesh = fixture(name);
        let nf = mesh.num_faces();
        for round in 0..12 {
            let depth: Vec<Depth> = (0..nf).map(|_| rng.below(5) as Depth).collect();
            // Every third round leaves some faces out (culled).
            let active: Vec<bool> = (0..nf)
                .map(|_| round % 3 != 2 || rng.below(4) > 0)
                .collect();
            let (asm, g) = frame(&mesh, &depth, &active);
            let open = open_edges(&g);
            assert_eq!(
                open,
                expected_open(&mesh, &asm, &g),
                "{name} {depth:?} {active:?}"
            );
            // Inside every patch the lattice triangles are kept: at least 4^d per drawn face.
            let lattice: u64 = asm.triangles_per_depth(&g).iter().sum();
            assert!(g.num_triangles() as u64 >= lattice, "{name}");
        }
    }
}

#[test]
fn every_depth_pair_across_an_edge_is_watertight() {
    // Two triangles sharing an edge, and a closed tetrahedron: every combination of depths,
    // including a depth-0 face with three deeper sides (split at its side midpoints).
    let two = Mesh::from_soup(
        &parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0.3\nf 1 2 3\nf 2 4 3\n").unwrap(),
    )
    .unwrap();
    for a in 0..=4 {
        for b in 0..=4 {
            let (asm, g) = frame(&two, &[a, b], &[true; 2]);
            assert_eq!(open_edges(&g), expected_open(&two, &asm, &g), "{a} {b}");
        }
    }
    let tet = fixture("loop_tetrahedron");
    for code in 0..5u32.pow(4) {
        let depth: Vec<Depth> = (0..4).map(|k| (code / 5u32.pow(k) % 5) as Depth).collect();
        let (_, g) = frame(&tet, &depth, &[true; 4]);
        assert_eq!(open_edges(&g), 0, "{depth:?}");
        // Euler: a closed triangulated sphere has V - E + F = 2 with E = 3F / 2.
        let (p, _, idx) = g.compact();
        assert_eq!(
            p.len() as i64 - (idx.len() / 2) as i64 + (idx.len() / 3) as i64,
            2
        );
    }
}

/// Every drawn point is the point of some patch's lattice at the patch's depth: bitwise the
/// uniform Loop tessellation's at that depth where that patch owns it in the uniform layout,
/// within rounding where a finer (or the only drawn) neighbour writes a shared point instead.
#[test]
fn drawn_points_are_the_uniform_tessellation_at_the_patch_depth() {
    let mut rng = Rng::xorshift(77);
    for name in [
        "loop_cubes_semisharp",
        "loop_saddle_edgecorner",
        "loop_pole8",
    ] {
        let mesh = fixture(name);
        let nf = mesh.num_faces();
        let uniform: Vec<_> = (0..=4).map(|d| tessellate_tri(&mesh, d).unwrap()).collect();
        let layouts: Vec<_> = (1..=4).map(|d| TriLayout::new(&mesh, d).unwrap()).collect();
        let (mut exact, mut shared) = (0, 0);
        for _ in 0..4 {
            let depth: Vec<Depth> = (0..nf).map(|_| 1 + rng.below(4) as Depth).collect();
            let (asm, g) = frame(&mesh, &depth, &vec![true; nf]);
            for &v in g.surface().face_indices() {
                let (f, c, k) = asm.vertex_source(v).unwrap();
                let n = 1u32 << c;
                let j = (0..=n)
                    .rev()
                    .find(|&j| subdiv_slate::tri_lattice_index(n, 0, j) <= k);
                let j = j.unwrap();
                let i = k - subdiv_slate::tri_lattice_index(n, 0, j);
                let p = &layouts[c as usize - 1].patches()[f];
                let (id, owned) = TriLayout::point_id(p, n, i, j);
                let want = uniform[c as usize].positions()[id as usize];
                let got = g.surface().positions()[v as usize];
                if owned {
                    assert_eq!(got, want, "{name} face {f} ({i}, {j}) at depth {c}");
                    assert_eq!(
                        g.surface().normals()[v as usize],
                        uniform[c as usize].normals()[id as usize]
                    );
                    exact += 1;
                } else {
                    let d = (Vec3::from(got) - Vec3::from(want)).length();
                    assert!(d < 1e-5, "{name} face {f} ({i}, {j}): {d}");
                    shared += 1;
                }
            }
        }
        assert!(exact > 4 * shared, "{name}: {exact} exact, {shared} shared");
    }
}

#[test]
fn cache_recomputes_only_patches_whose_depth_rose() {
    let mesh = fixture("loop_icosahedron");
    let nf = mesh.num_faces();
    let mut asm = TriAssembler::new(&mesh, 4).unwrap();
    let mut g = AdaptiveFrame::default();
    asm.frame(&mesh, &vec![3; nf], &vec![true; nf], &mut g)
        .unwrap();
    assert_eq!(g.patches_recomputed, nf);
    let v0 = g.vertex_version;
    asm.frame(&mesh, &vec![1; nf], &vec![true; nf], &mut g)
        .unwrap();
    assert_eq!((g.patches_recomputed, g.vertex_version), (0, v0));
    assert_eq!(g.num_triangles(), nf * 4);
    assert_eq!(open_edges(&g), 0);
    let mut depth = vec![2; nf];
    depth[0] = 4;
    asm.frame(&mesh, &depth, &vec![true; nf], &mut g).unwrap();
    assert_eq!(g.patches_recomputed, 1);
    assert!(g.vertex_version > v0);
    assert_eq!(open_edges(&g), 0);
    asm.invalidate();
    asm.frame(&mesh, &depth, &vec![true; nf], &mut g).unwrap();
    assert_eq!(g.patches_recomputed, nf);
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let quad =
        Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap())
            .unwrap();
    let err = TriAssembler::new(&quad, 3).unwrap_err();
    assert!(matches!(err, AssemblyError::Rules(_)), "{err}");
    let tet = fixture("loop_tetrahedron");
    assert!(matches!(
        TriAssembler::new(&tet, MAX_DEPTH + 1),
        Err(AssemblyError::TooDeep { .. })
    ));
    let mut asm = TriAssembler::new(&tet, 3).unwrap();
    let mut g = AdaptiveFrame::default();
    let err = asm.frame(&tet, &[1; 3], &[true; 4], &mut g).unwrap_err();
    assert!(matches!(
        err,
        AssemblyError::Length {
            got: 3,
            want: 4,
            ..
        }
    ));
    asm.frame(&tet, &[9; 4], &[true; 4], &mut g).unwrap();
    assert_eq!(
        g.unit_depth,
        vec![3; 4],
        "depths are clamped to the maximum"
    );
}

impl TriAssembler {
    /// The last frame's triangles, one-sided corner normals and face-varying corner values
    /// emitted afresh (every run, nothing kept) over the lattices as cached.
    fn emitted_afresh(&self, mesh: &Mesh, depth: &[Depth], active: &[bool]) -> Emitted {
        let depth: Vec<Depth> = depth.iter().map(|&d| d.min(self.max_depth)).collect();
        let active: Vec<bool> = (0..active.len())
            .map(|f| active[f] && self.layout.patches()[f].visible)
            .collect();
        let drawn = active.iter().any(|&a| a);
        let uvs = self.uvs.as_ref().filter(|_| mesh.uv().is_some() && drawn);
        self.emit_afresh(mesh, &depth, &active, uvs)
    }
}

#[test]
fn runs_kept_from_the_last_frame_are_what_emitting_them_again_gives() {
    // A few depths change a frame, then the cage moves: the runs whose state stayed keep
    // their triangles, and every frame is bit for bit the one emitted afresh.
    let mut rng = Rng::xorshift(0x7472_6973);
    for (name, mut mesh) in [
        ("uv grid", uv_grid(12, true, true)),
        ("semi-sharp cubes", fixture("loop_cubes_semisharp")),
    ] {
        let mut asm = TriAssembler::new(&mesh, 4).unwrap();
        let mut g = AdaptiveFrame::default();
        let kept = depth_walk(&mut mesh, &mut rng, |mesh, depth, active, bent, i| {
            if bent {
                asm.invalidate();
            }
            asm.frame(mesh, depth, active, &mut g).unwrap();
            let afresh = asm.emitted_afresh(mesh, depth, active);
            assert_emitted(&g, &afresh, &format!("{name} frame {i}"));
            asm.runs_kept
        });
        assert!(kept > 40, "{name}: {kept} runs kept");
    }
}

#[test]
fn a_moved_cage_gives_its_runs_their_new_one_sided_normals() {
    let mesh = uv_grid(12, true, true);
    let mut asm = TriAssembler::new(&mesh, 3).unwrap();
    let mut g = AdaptiveFrame::default();
    bent_once(true, |mesh, depth, active, bent| {
        if bent {
            asm.invalidate();
        }
        asm.frame(mesh, depth, active, &mut g).unwrap();
        let afresh = asm.emitted_afresh(mesh, depth, active);
        assert_emitted(&g, &afresh, "bent");
        (afresh.1, asm.runs_kept, asm.deps.len())
    });
}
