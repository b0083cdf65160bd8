//! Tests of [`subdiv::DynamicSubdivision`], the per-frame adaptive node: depths, fans,
//! frame-rate control, given depths, moving positions and non-manifold seams.

use std::collections::HashMap;

use glam::Vec3;

use subdiv_depth::Class;
use subdiv_mesh::parse_obj;

use subdiv::{Control, DynamicSubdivision};
use subdiv_depth::{DepthParams, FrameTimeModel};
use subdiv_mesh::{Camera, Mesh};
use subdiv_rules::Scheme;
use subdiv_slate::Depth;
use subdiv_stitch::{AdaptiveFrame, AssemblyError};

/// The unit cube: face 0 is `z = 0`, face 1 is `z = 1`, faces 2..=5 the sides.
fn cube() -> Mesh {
    Mesh::from_soup(&parse_obj(&subdiv_test_support::cube().obj()).unwrap()).unwrap()
}

/// A closed triangular prism (two triangles, three quads).
fn prism() -> Mesh {
    Mesh::from_soup(&parse_obj(&subdiv_test_support::prism().obj()).unwrap()).unwrap()
}

fn params(max_depth: Depth) -> DepthParams {
    DepthParams {
        max_depth,
        projected_size: None,
        ..DepthParams::default()
    }
}

/// A camera on the `+z` axis at distance `dist` from the cube's centre, looking at it.
fn camera_on_z(dist: f32) -> Camera {
    let c = Vec3::splat(0.5);
    Camera::new(c + Vec3::Z * dist, c, Vec3::Y, 45.0, 800, 600)
}

/// After welding bitwise equal positions, every edge of a closed surface has exactly two
/// triangles, in opposite directions.
fn assert_closed(g: &AdaptiveFrame) {
    let open = subdiv_test_support::welded_open_edges(
        "frame",
        g.surface().positions(),
        g.surface().face_indices(),
    );
    assert_eq!(open, 0, "open edges");
}

#[test]
fn back_faces_stay_at_depth_zero_front_faces_go_deeper() {
    let mut node = DynamicSubdivision::new(cube(), params(3)).unwrap();
    let g = node.update(&camera_on_z(20.0), None).unwrap().clone();
    let a = node.assignment();
    assert_eq!(a.class[0], Class::Back);
    assert_eq!(a.class[1], Class::Front);
    assert_eq!(a.depth[0], 0);
    assert!(a.depth[1] > 0, "front face depth {}", a.depth[1]);
    for f in 2..6 {
        assert_eq!(a.class[f], Class::Silhouette, "side face {f}");
        assert!(a.depth[f] > 0);
    }
    assert_eq!(g.unit_depth(), a.depth);
    assert!(g.num_triangles() < node.uniform_triangles_at(3));
    assert_closed(&g);
    // From the other side the roles swap.
    node.update(&camera_on_z(-20.0), None).unwrap();
    let a = node.assignment();
    assert_eq!((a.class[0], a.class[1]), (Class::Front, Class::Back));
    assert_eq!(a.depth[1], 0);
    assert!(a.depth[0] > 0);
}

#[test]
fn culled_back_faces_are_not_drawn() {
    let p = DepthParams {
        cull_back: true,
        ..params(3)
    };
    let mut node = DynamicSubdivision::new(cube(), p).unwrap();
    let g = node.update(&camera_on_z(20.0), None).unwrap();
    assert_eq!(g.unit_depth()[0], u8::MAX);
    assert!(!node.assignment().active[0]);
    assert!(node.assignment().active[1..].iter().all(|&x| x));
}

#[test]
fn fixed_face_depths_are_checked_and_used() {
    let mut node = DynamicSubdivision::new(cube(), params(3)).unwrap();
    let err = node.set_face_depths(Some(vec![1; 5])).unwrap_err();
    assert!(matches!(
        err,
        AssemblyError::Length {
            got: 5,
            want: 6,
            ..
        }
    ));
    let depths = vec![0u8, 3, 1, 2, 1, 2];
    node.set_face_depths(Some(depths.clone())).unwrap();
    // The camera sees face 0 from behind, but the fixed depths win.
    let g = node.update(&camera_on_z(20.0), None).unwrap().clone();
    assert_eq!(g.unit_depth(), depths);
    assert_eq!(node.assignment().depth, depths);
    assert_closed(&g);
    // Back to view-dependent depths.
    node.set_face_depths(None).unwrap();
    node.update(&camera_on_z(-20.0), None).unwrap();
    assert_eq!(node.assignment().depth[1], 0);
}

#[test]
fn positions_are_checked_and_name_the_bad_vertex() {
    let mut node = DynamicSubdivision::new(cube(), params(2)).unwrap();
    let mut pos = node.mesh().positions().to_vec();
    pos[3].y = f32::NAN;
    let err = node.set_positions(&pos).unwrap_err();
    assert!(matches!(err, AssemblyError::NonFinite { vertex: 3 }));
    assert!(err.to_string().contains("vertex 3"), "{err}");
    pos[3].y = f32::INFINITY;
    assert!(matches!(
        node.set_positions(&pos),
        Err(AssemblyError::NonFinite { vertex: 3 })
    ));
    assert!(matches!(
        node.set_positions(&pos[..7]),
        Err(AssemblyError::Length {
            got: 7,
            want: 8,
            ..
        })
    ));
    // The cage is unchanged by the refused calls; good positions move it.
    assert_eq!(node.mesh().position(subdiv_mesh::VertexId(3)).y, 1.0);
    let doubled: Vec<Vec3> = cube().positions().iter().map(|p| *p * 2.0).collect();
    node.set_positions(&doubled).unwrap();
    assert_eq!(node.mesh().bounds().1, Vec3::splat(2.0));
    let g = node.update(&camera_on_z(20.0), None).unwrap();
    assert_closed(g);
}

#[test]
fn uniform_triangle_count_matches_a_uniform_frame() {
    // Depth 0 is left out for the prism: its quads touch triangles, so they are level-1
    // units whose depth is clamped to 1 in the frame, while `uniform_triangles_at(0)`
    // counts them as 2 triangles each.
    for (mesh, depths) in [(cube(), 0..=3u8), (prism(), 1..=3)] {
        let nf = mesh.num_faces();
        let mut node = DynamicSubdivision::new(mesh, params(3)).unwrap();
        for d in depths {
            node.set_face_depths(Some(vec![d; nf])).unwrap();
            let g = node.update(&camera_on_z(20.0), None).unwrap();
            assert_eq!(g.num_triangles(), node.uniform_triangles_at(d), "depth {d}");
        }
        assert_eq!(node.uniform_triangles(), node.uniform_triangles_at(3));
    }
}

#[test]
fn frame_rate_control_toggles() {
    let mut node = DynamicSubdivision::new(cube(), params(3)).unwrap();
    assert_eq!((node.control(), node.target_fps()), (Control::Off, None));
    // A target turns the default, predictive control on.
    node.set_frame_rate_control(Some(30.0));
    assert_eq!(node.control(), Control::Budget);
    let fps = node.budget_controller().map(|c| c.target_fps()).unwrap();
    assert!((fps - 30.0).abs() < 1e-3, "{fps}");
    node.update(&camera_on_z(20.0), Some(0.1)).unwrap();
    assert!(node.budget_controller().is_some());
    node.set_frame_rate_control(None);
    assert!(node.budget_controller().is_none() && node.paper_controller().is_none());
    node.set_target_fps(60.0);
    assert_eq!(node.target_fps(), Some(60.0));
    // The paper's controller on request; changing the target keeps the controller.
    node.set_control(Control::Paper, 20.0);
    node.update(&camera_on_z(20.0), Some(0.1)).unwrap();
    node.set_target_fps(25.0);
    let fps = node.paper_controller().map(|c| c.target_fps()).unwrap();
    assert!((fps - 25.0).abs() < 1e-3, "{fps}");
    // Every mode fits the frame-time model and predicts each frame; the frames that measured
    // the pixel-error data (the first budget frame) are not fitted.
    node.update(&camera_on_z(20.0), Some(0.1)).unwrap();
    let (work, predicted) = node.last_frame().unwrap();
    assert!(work.triangles > 0.0 && predicted > 0.0);
    assert_eq!(node.frame_model().frames(), 1);
}

#[test]
fn a_given_frame_model_prices_the_first_frame() {
    // A model with known coefficients (one second per 10^5 triangles) needs no warm-up frames:
    // the first frame already draws the budget's choice, here far fewer triangles than the
    // geometric depths.
    let camera = camera_on_z(20.0);
    let mut free = DynamicSubdivision::new(cube(), params(3)).unwrap();
    let geometric = free.update(&camera, None).unwrap().num_triangles();
    let mut node = DynamicSubdivision::new(cube(), params(3)).unwrap();
    node.set_frame_model(FrameTimeModel::new([0.0, 1.0, 0.0, 0.0, 0.0]));
    node.set_control(Control::Budget, 1e5 / 24.0);
    node.patch_errors();
    let budgeted = node.update(&camera, None).unwrap().num_triangles();
    assert!(budgeted < geometric / 2, "{budgeted} against {geometric}");
}

/// The Loop icosahedron.
fn icosahedron() -> Mesh {
    let path = subdiv_test_support::fixture("reference/shapes/loop_icosahedron.obj");
    Mesh::from_soup(&parse_obj(&std::fs::read_to_string(path).unwrap()).unwrap()).unwrap()
}

#[test]
fn loop_node_runs_every_adaptive_mode_watertight() {
    let mesh = icosahedron();
    let nf = mesh.num_faces();
    let (lo, hi) = mesh.bounds();
    let camera = Camera::eye_relative(lo, hi, Vec3::new(0.3, 0.2, 2.5), 45.0, 800, 600);
    let mut node = DynamicSubdivision::with_scheme(mesh, Scheme::Loop, params(4)).unwrap();
    assert_eq!(node.scheme(), Scheme::Loop);
    // Curvature and classification: back faces at depth 0, front ones deeper.
    let g = node.update(&camera, None).unwrap().clone();
    assert_closed(&g);
    let a = node.assignment().clone();
    assert!(a.class.contains(&Class::Back) && a.class.contains(&Class::Front));
    for f in 0..nf {
        if a.class[f] == Class::Back {
            assert_eq!(a.depth[f], 0);
        }
    }
    assert!(a.depth.iter().any(|&d| d > 0));
    let lattice: u64 = node.quads_per_depth().iter().sum();
    assert!(g.num_triangles() as u64 >= lattice);
    assert!(g.num_triangles() < node.uniform_triangles());
    // Pixel error, projected size, frame-rate control, fixed (DoI) depths, culling.
    node.set_params(DepthParams {
        pixel_error: Some(0.5),
        ..params(4)
    })
    .unwrap();
    assert_closed(&node.update(&camera, None).unwrap().clone());
    assert_eq!(node.patch_errors().faces.len(), nf);
    node.set_params(DepthParams {
        projected_size: Some((2.0, 8.0)),
        ..params(4)
    })
    .unwrap();
    node.set_frame_rate_control(Some(60.0));
    for _ in 0..5 {
        assert_closed(&node.update(&camera, Some(0.5)).unwrap().clone());
    }
    node.set_frame_rate_control(None);
    let depths: Vec<Depth> = (0..nf).map(|f| (f % 5) as Depth).collect();
    node.set_face_depths(Some(depths.clone())).unwrap();
    let g = node.update(&camera, None).unwrap().clone();
    assert_eq!(g.unit_depth(), depths);
    assert_closed(&g);
    node.set_face_depths(Some(vec![2; nf])).unwrap();
    let g = node.update(&camera, None).unwrap();
    assert_eq!(g.num_triangles(), node.uniform_triangles_at(2));
}

#[test]
fn loop_node_refuses_quads() {
    let err = DynamicSubdivision::with_scheme(cube(), Scheme::Loop, params(3)).unwrap_err();
    assert!(matches!(err, AssemblyError::Rules(_)), "{err}");
}

#[test]
fn pixel_error_mode_is_watertight() {
    let p = DepthParams {
        pixel_error: Some(0.5),
        ..params(3)
    };
    let mut node = DynamicSubdivision::new(cube(), p).unwrap();
    let g = node.update(&camera_on_z(3.0), None).unwrap().clone();
    assert!(g.num_triangles() > 0);
    assert_closed(&g);
    assert_eq!(node.assignment().depth[0], 0, "back face");
    // Deviations shrink with depth on every face.
    let errors = node.patch_errors().clone();
    assert_eq!(errors.faces.len(), 6);
    assert!(errors.closed);
    for f in &errors.faces {
        let d = &f.deviation;
        assert_eq!(d.len(), 4);
        assert!(d.windows(2).all(|w| w[1] <= w[0]), "{d:?}");
    }
}

/// Three quads on one edge (a fin), cut into manifold pieces as OpenSubdiv refines it.
fn fin() -> Mesh {
    fin_from(
        "v 0 0 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\nv 0 0 1\nv 0 1 1\nv -1 0 0\nv -1 1 0\n\
              f 1 3 4 2\nf 1 2 6 5\nf 1 2 8 7\n",
    )
}

/// A cage with three faces on the edge 0-1, cut into its manifold pieces.
fn fin_from(obj: &str) -> Mesh {
    let mut soup = parse_obj(obj).unwrap();
    let found = soup.split_nonmanifold().unwrap();
    assert_eq!(found.edges, vec![(0, 1, 3)]);
    Mesh::from_soup(&soup).unwrap()
}

/// The segments of a frame used by three triangles after welding bitwise equal positions (on
/// a fin, its non-manifold edge), checking that no edge has more than three.
fn fin_segments(g: &subdiv_stitch::AdaptiveFrame) -> usize {
    let id = subdiv_test_support::weld(g.surface().positions());
    let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
    for t in g.surface().face_indices().chunks(3) {
        for k in 0..3 {
            let (a, b) = (id[t[k] as usize], id[t[(k + 1) % 3] as usize]);
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    assert!(uses.values().all(|&n| (1..=3).contains(&n)));
    uses.values().filter(|&&n| n == 3).count()
}

#[test]
fn faces_on_a_nonmanifold_edge_share_one_depth_and_its_points() {
    let mut node = DynamicSubdivision::new(fin(), params(3)).unwrap();
    node.set_face_depths(Some(vec![1, 2, 3])).unwrap();
    let g = node.update(&camera_on_z(5.0), None).unwrap().clone();
    assert_eq!(g.unit_depth(), vec![3, 3, 3]);
    // After welding, the fin edge has 2^3 segments of three triangles each.
    assert_eq!(
        fin_segments(&g),
        8,
        "segments on the fin edge with three triangles"
    );
}

/// A triangle on the fin is drawn through its level-1 quads, at depth 1 at least: the quads
/// on the other copies follow it, so the copies keep one depth after the stitcher's clamp.
#[test]
fn a_level1_face_on_a_nonmanifold_edge_lifts_its_copies() {
    let mesh = fin_from(
        "v 0 0 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\nv 0 0 1\nv 0 1 1\nv -1 0.5 0\n\
         f 1 3 4 2\nf 1 2 6 5\nf 1 2 7\n",
    );
    let mut node = DynamicSubdivision::new(mesh, params(3)).unwrap();
    node.set_face_depths(Some(vec![0, 0, 0])).unwrap();
    let g = node.update(&camera_on_z(5.0), None).unwrap().clone();
    assert_eq!(g.unit_depth(), vec![1, 1, 1]);
    assert_eq!(
        fin_segments(&g),
        2,
        "segments on the fin edge with three triangles"
    );
}

/// A node whose cage moved draws what a node made for the moved cage draws, bit for bit: the
/// level-1 points of the prism's triangles and their neighbours follow the cage, and no cached
/// patch of the old positions survives (Catmull-Clark and Loop).
#[test]
fn moved_positions_give_a_fresh_nodes_frame() {
    let tri_prism =
        Mesh::from_soup(&parse_obj(&subdiv_test_support::prism().triangulated().obj()).unwrap())
            .unwrap();
    for (mesh, scheme) in [(prism(), Scheme::CatmullClark), (tri_prism, Scheme::Loop)] {
        let camera = camera_on_z(4.0);
        let mut node = DynamicSubdivision::with_scheme(mesh.clone(), scheme, params(3)).unwrap();
        node.update(&camera, None).unwrap();
        for frame in 1..4 {
            let moved: Vec<Vec3> = mesh
                .positions()
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let a = frame as f32 * 0.7 + i as f32;
                    *p + Vec3::new(a.sin(), a.cos(), (2.0 * a).sin()) * 0.15
                })
                .collect();
            node.set_positions(&moved).unwrap();
            let mut fresh_mesh = mesh.clone();
            fresh_mesh.positions_mut().copy_from_slice(&moved);
            let mut fresh = DynamicSubdivision::with_scheme(fresh_mesh, scheme, params(3)).unwrap();
            let want = fresh.update(&camera, None).unwrap().surface().clone();
            let got = node.update(&camera, None).unwrap().surface();
            assert!(*got == want, "{scheme:?} frame {frame}");
        }
    }
}

/// Bilinear: the curvature mode refines a patch only while its own normals spread past the
/// cone. A cage of twisted quads (a saddle, `z = x y / 4`) goes as deep as each face needs
/// and no deeper, near or far, with the projected-size rule on; the cube's flat quads stay
/// at depth 0 even at the silhouette.
#[test]
fn bilinear_curvature_mode_refines_twisted_patches_only() {
    let saddle = subdiv_test_support::height_grid(6, false, -3.0, |x, y| 0.25 * x * y);
    let saddle = Mesh::from_soup(&parse_obj(&saddle.obj()).unwrap()).unwrap();
    let p = DepthParams {
        max_depth: 5,
        ..DepthParams::default()
    };
    assert!(p.projected_size.is_some());
    let most = subdiv_depth::bilinear_face_depths(&saddle, p.cone_aperture_deg, p.max_depth);
    assert!(
        most.iter().any(|&d| d > 0) && most.iter().all(|&d| d < 5),
        "{most:?}"
    );
    let mut node = DynamicSubdivision::with_scheme(saddle, Scheme::Bilinear, p).unwrap();
    for dist in [2.0f32, 6.0, 40.0] {
        let cam = Camera::new(
            Vec3::new(0.5, -1.0, dist),
            Vec3::ZERO,
            Vec3::Y,
            45.0,
            800,
            600,
        );
        let depths = node.update(&cam, None).unwrap().unit_depth().to_vec();
        assert!(
            depths.iter().zip(&most).all(|(d, m)| d <= m),
            "{dist}: {depths:?}"
        );
        if dist == 2.0 {
            assert_eq!(depths, most, "close up, every face as deep as it needs");
        }
    }
    let mut node = DynamicSubdivision::with_scheme(cube(), Scheme::Bilinear, p).unwrap();
    for eye in [Vec3::new(0.5, 0.5, 3.0), Vec3::new(2.0, 1.5, 2.0)] {
        let cam = Camera::new(eye, Vec3::splat(0.5), Vec3::Y, 45.0, 800, 600);
        let g = node.update(&cam, None).unwrap();
        assert!(
            g.unit_depth().iter().all(|&d| d == 0),
            "{:?}",
            g.unit_depth()
        );
        assert_closed(g);
    }
}
