//! Adaptive assembly: crack-free (bitwise) for random per-face depths, on every fixture cage.

use glam::DVec3;
use subdiv_mesh::{Mesh, MeshStats, ReadOptions, VertexId, read_obj_with};
use subdiv_rules::{Scheme, refine_uniform_levels};
use subdiv_stitch::{AdaptiveFrame, Assembler, FanMethod};
use subdiv_test_support::{Rng, indexed_open_edges, shape};
use subdiv_tests::PointGrid;

fn cages() -> Vec<(String, Mesh)> {
    subdiv_tests::catmull_clark_cages()
}

/// Every edge of the triangle mesh has two triangles using it in opposite directions, except
/// the cage's own boundary; returns the number of open edges.
fn check_closed(name: &str, g: &AdaptiveFrame) -> usize {
    indexed_open_edges(name, g.surface().face_indices())
}

/// An interior vertex of valence 2 with the smooth or dart rule and no semi-sharpness left (as in
/// `invariants.rs`).
fn valence2_smooth(mesh: &Mesh, v: VertexId) -> bool {
    let s: Vec<f32> = mesh
        .outgoing(v)
        .map(|h| mesh.edge_sharpness(h.edge()))
        .collect();
    mesh.valence(v) == 2
        && !mesh.is_boundary_vertex(v)
        && mesh.vertex_sharpness(v) == 0.0
        && s.iter().all(|&x| x == 0.0 || x >= 10.0)
        && s.iter().filter(|&&x| x >= 10.0).count() < 2
}

/// OpenSubdiv gives the vertices of [`valence2_smooth`] the corner masks: their "limit" is their
/// position at the level their patch was evaluated at (levels `0..=depth`), not a point of the
/// limit surface. Those positions, for every such vertex and level.
fn corner_mask_points(mesh: &Mesh, depth: u8) -> Vec<DVec3> {
    let vs: Vec<VertexId> = mesh
        .vertices()
        .filter(|&v| valence2_smooth(mesh, v))
        .collect();
    if vs.is_empty() {
        return Vec::new();
    }
    (0..=depth)
        .flat_map(|k| {
            let m = refine_uniform_levels(mesh, Scheme::CatmullClark, k).unwrap();
            vs.iter()
                .map(|&v| m.position(v).as_dvec3())
                .collect::<Vec<_>>()
        })
        .collect()
}

#[test]
fn random_depths_are_watertight() {
    let mut rng = Rng::xorshift(0x9e3779b97f4a7c15);
    for (name, mesh) in cages() {
        let stats = MeshStats::of(&mesh);
        let maxd = if mesh.num_faces() > 500 { 3 } else { 4 };
        let mut asm = Assembler::new(&mesh, maxd).unwrap();
        let nu = mesh.num_faces();
        let (lo, hi) = mesh.bounds();
        let tol = 1e-5 * (hi - lo).length() as f64;
        // Reference points: the uniform tessellation one level deeper than any patch.
        let uni = subdiv_slate::tessellate(&mesh, maxd + 1).unwrap();
        let pts: Vec<DVec3> = uni
            .positions()
            .iter()
            .map(|p| glam::Vec3::from(*p).as_dvec3())
            .collect();
        let grid = PointGrid::new(&pts, tol * 10.0);
        // Blocks are evaluated at most one level below the deepest face.
        let corner_masked = corner_mask_points(&mesh, maxd + 1);
        let mut g = AdaptiveFrame::default();
        for round in 0..12 {
            let depth: Vec<u8> = (0..nu)
                .map(|_| (rng.next_u64() % (maxd as u64 + 1)) as u8)
                .collect();
            let method = if round % 3 == 2 {
                FanMethod::Simple
            } else {
                FanMethod::Subdivided
            };
            asm.set_method(method);
            asm.frame(&mesh, &depth, &vec![true; nu], &mut g).unwrap();
            let open = check_closed(&name, &g);
            let holes = mesh.faces().filter(|&f| mesh.is_hole(f)).count();
            if holes == 0 {
                // Open edges only along the cage boundary: 2^d segments per boundary edge of a
                // face at depth d (clamped to the face's minimum depth).
                let want: usize = mesh
                    .edges()
                    .filter(|&e| mesh.is_boundary_edge(e))
                    .map(|e| {
                        let h = if mesh.face(e.halfedge(0)).is_some() {
                            e.halfedge(0)
                        } else {
                            e.halfedge(1)
                        };
                        let f = mesh.face(h).idx();
                        1usize << depth[f].max(asm.min_depth(f))
                    })
                    .sum();
                assert_eq!(
                    open, want,
                    "{name} round {round}: open edges ({} cage boundary edges)",
                    stats.boundary_edges
                );
            }
            // Every referenced vertex is a limit point of the surface.
            for &i in g.surface().face_indices().iter().step_by(7) {
                let p = glam::Vec3::from(g.surface().positions()[i as usize]).as_dvec3();
                let (_, d) = grid.nearest(p);
                let masked = || corner_masked.iter().any(|q| (*q - p).length() <= tol);
                assert!(
                    d <= tol || masked(),
                    "{name} round {round}: vertex {i} at {p:?} is {d:.2e} off the limit surface"
                );
            }
        }
    }
}

#[test]
fn uniform_depths_equal_uniform_tessellation() {
    for (name, mesh) in cages().into_iter().take(8) {
        let nu = mesh.num_faces();
        let mut asm = Assembler::new(&mesh, 3).unwrap();
        let mut g = AdaptiveFrame::default();
        for d in 1..=3u8 {
            asm.frame(&mesh, &vec![d; nu], &vec![true; nu], &mut g)
                .unwrap();
            let uni = subdiv_slate::tessellate(&mesh, d).unwrap();
            let quads = uni.num_faces();
            assert_eq!(g.num_triangles(), 2 * quads, "{name} depth {d}");
            let (p, _, idx) = g.compact();
            assert_eq!(
                p.len(),
                uni.positions().len(),
                "{name} depth {d}: vertex count"
            );
            assert_eq!(idx.len(), 6 * quads);
        }
    }
}

#[test]
fn cache_reuses_blocks_while_depths_do_not_rise() {
    let mesh = read_obj_with(fixtures_shape("catmark_helmet"), ReadOptions::default()).unwrap();
    let nu = mesh.num_faces();
    let mut asm = Assembler::new(&mesh, 4).unwrap();
    let mut g = AdaptiveFrame::default();
    asm.frame(&mesh, &vec![3; nu], &vec![true; nu], &mut g)
        .unwrap();
    assert_eq!(g.patches_recomputed(), asm.patch_set().patches().len());
    let v0 = g.vertex_version();
    // Lower every depth: nothing recomputed, vertices unchanged.
    asm.frame(&mesh, &vec![2; nu], &vec![true; nu], &mut g)
        .unwrap();
    assert_eq!(g.patches_recomputed(), 0);
    assert_eq!(g.vertex_version(), v0);
    // Raise one face: only the patches that need more detail are recomputed.
    let mut d = vec![2u8; nu];
    d[0] = 4;
    asm.frame(&mesh, &d, &vec![true; nu], &mut g).unwrap();
    assert!(
        g.patches_recomputed() >= 1 && g.patches_recomputed() < asm.patch_set().patches().len() / 2
    );
    assert_ne!(g.vertex_version(), v0);
    assert!(check_closed("helmet", &g) > 0); // the helmet is open
}

fn fixtures_shape(n: &str) -> std::path::PathBuf {
    shape(&format!("{n}.obj"))
}

/// Welds identical coordinates, then checks every edge has two triangles in opposite
/// directions; returns the number of open (boundary) edges.
fn welded_open_edges(name: &str, g: &AdaptiveFrame) -> usize {
    subdiv_test_support::welded_open_edges(
        name,
        g.surface().positions(),
        g.surface().face_indices(),
    )
}

#[test]
fn random_cameras_are_watertight() {
    use subdiv::DynamicSubdivision;
    use subdiv_depth::DepthParams;
    use subdiv_mesh::Camera;
    let mut rng = Rng::xorshift(0x2545F4914F6CDD1D);
    let mut unit = || (rng.next_u64() % 2001) as f32 / 1000.0 - 1.0;
    for (name, mesh) in cages() {
        let stats = MeshStats::of(&mesh);
        let holes = mesh.faces().filter(|&f| mesh.is_hole(f)).count();
        let big = mesh.num_faces() > 200;
        // At least 200 cameras for every closed cage (the property); fewer for big open ones.
        let closed = stats.boundary_edges == 0 && holes == 0;
        let cameras = if closed || !big { 200 } else { 40 };
        for pixel_mode in [false, true] {
            let params = DepthParams {
                max_depth: if big { 2 } else { 3 },
                pixel_error: pixel_mode.then_some(1.0),
                ..DepthParams::default()
            };
            let mut node = DynamicSubdivision::new(mesh.clone(), params).unwrap();
            let (lo, hi) = mesh.bounds();
            for c in 0..cameras {
                let dir = glam::Vec3::new(unit(), unit(), unit()).normalize_or_zero();
                let dist = 1.2 + 4.0 * (unit() + 1.0);
                let cam = Camera::eye_relative(
                    lo,
                    hi,
                    dir * dist,
                    30.0 + 30.0 * (unit() + 1.0),
                    640,
                    480,
                );
                let g = node.update(&cam, None).unwrap();
                let open = welded_open_edges(&name, g);
                if stats.boundary_edges == 0 && holes == 0 {
                    assert_eq!(
                        open, 0,
                        "{name} camera {c} (pixel mode {pixel_mode}): closed cage has open edges"
                    );
                }
            }
        }
    }
}

#[test]
fn moving_the_cage_updates_the_surface() {
    use subdiv::DynamicSubdivision;
    use subdiv_depth::DepthParams;
    use subdiv_mesh::Camera;
    let mesh = read_obj_with(fixtures_shape("catmark_cube"), ReadOptions::default()).unwrap();
    let (lo, hi) = mesh.bounds();
    let cam = Camera::eye_relative(lo, hi, glam::Vec3::new(0.5, 0.7, 3.0), 45.0, 640, 480);
    let mut node = DynamicSubdivision::new(
        mesh.clone(),
        DepthParams {
            max_depth: 3,
            ..Default::default()
        },
    )
    .unwrap();
    let before = node.update(&cam, None).unwrap().clone();
    let moved: Vec<glam::Vec3> = mesh.positions().iter().map(|p| *p * 2.0).collect();
    node.set_positions(&moved).unwrap();
    let after = node.update(&cam, None).unwrap();
    // Twice the cage, twice the limit surface (the same camera sees it bigger, depths may differ).
    let max = |g: &AdaptiveFrame| {
        g.surface()
            .face_indices()
            .iter()
            .map(|&i| glam::Vec3::from(g.surface().positions()[i as usize]).length())
            .fold(0.0f32, f32::max)
    };
    assert!((max(after) / max(&before) - 2.0).abs() < 1e-3);
    assert!(node.set_positions(&moved[..3]).is_err());
    let mut bad = moved.clone();
    bad[2].x = f32::NAN;
    assert!(node.set_positions(&bad).is_err());
}
