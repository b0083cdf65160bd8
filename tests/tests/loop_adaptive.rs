//! Adaptive Loop tessellation: watertight to the bit over every
//! triangle fixture × random cameras × random depths, in every depth mode.

use glam::Vec3;
use subdiv::DynamicSubdivision;
use subdiv_depth::DepthParams;
use subdiv_mesh::{Camera, Mesh};
use subdiv_rules::Scheme;
use subdiv_stitch::AdaptiveFrame;
use subdiv_test_support::Rng;

/// Uniform in `[0, 1)` in steps of 1e-6.
fn unit(rng: &mut Rng) -> f32 {
    rng.below(1_000_000) as f32 / 1_000_000.0
}

/// After welding bitwise equal positions: no degenerate triangle, every directed edge used
/// once, and the same open edges as by index (shared points are one vertex). Returns the open
/// edges.
fn open_edges(name: &str, g: &AdaptiveFrame) -> usize {
    subdiv_test_support::open_edges(name, g.surface().positions(), g.surface().face_indices())
}

/// The open edges a frame must have: cage edges with one drawn face (the boundary, holes,
/// culled neighbours), each in `2^depth` segments of its deeper drawn side.
fn expected_open(mesh: &Mesh, g: &AdaptiveFrame) -> usize {
    let mut sides = vec![(0u32, 0u8); mesh.num_edges()];
    for f in mesh.faces() {
        let d = g.unit_depth()[f.idx()];
        if d == u8::MAX {
            continue;
        }
        let h0 = mesh.face_halfedge(f);
        let mut h = h0;
        loop {
            let s = &mut sides[h.edge().idx()];
            s.0 += 1;
            s.1 = s.1.max(d);
            h = mesh.next(h);
            if h == h0 {
                break;
            }
        }
    }
    sides
        .iter()
        .filter(|s| s.0 == 1)
        .map(|s| 1usize << s.1)
        .sum()
}

fn random_camera(rng: &mut Rng, mesh: &Mesh) -> Camera {
    let (lo, hi) = mesh.bounds();
    let dir = Vec3::new(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5).normalize_or(Vec3::Z);
    // From close up (parts of the cage behind the eye or beside the view) to far away.
    let dist = 0.6 + 4.0 * unit(rng);
    Camera::eye_relative(lo, hi, dir * dist, 30.0 + 40.0 * unit(rng), 640, 480)
}

#[test]
fn adaptive_loop_is_watertight_on_every_triangle_fixture() {
    let mut rng = Rng::xorshift(0x2545_f491_4f6c_dd1d);
    let cages = subdiv_tests::loop_cages();
    assert!(cages.len() >= 11, "{} loop cages", cages.len());
    for (name, mesh) in cages {
        let nf = mesh.num_faces();
        let max_depth = if nf > 1000 { 3 } else { 4 };
        let params = DepthParams {
            max_depth,
            ..DepthParams::default()
        };
        let mut node = DynamicSubdivision::with_scheme(mesh.clone(), Scheme::Loop, params)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let modes = [
            params,
            DepthParams {
                pixel_error: Some(0.5 + 2.0 * unit(&mut rng)),
                ..params
            },
            DepthParams {
                cull_back: true,
                projected_size: Some((1.0, 4.0)),
                cone_aperture_deg: 5.0,
                ..params
            },
        ];
        for (m, mode) in modes.iter().enumerate() {
            node.set_params(*mode).unwrap();
            for _ in 0..2 {
                let camera = random_camera(&mut rng, &mesh);
                let g = node.update(&camera, None).unwrap().clone();
                let label = format!("{name} mode {m} from {}", camera.eye);
                assert_eq!(open_edges(&label, &g), expected_open(&mesh, &g), "{label}");
            }
        }
        // Depths given from outside (a DoI, a user): random per face, some faces not drawn.
        node.set_params(params).unwrap();
        for round in 0..3 {
            let depths: Vec<u8> = (0..nf)
                .map(|_| (rng.next_u64() % (max_depth as u64 + 1)) as u8)
                .collect();
            node.set_face_depths(Some(depths.clone())).unwrap();
            let camera = random_camera(&mut rng, &mesh);
            let g = node.update(&camera, None).unwrap().clone();
            let label = format!("{name} random depths round {round}");
            assert_eq!(open_edges(&label, &g), expected_open(&mesh, &g), "{label}");
            for (drawn, given) in g.unit_depth().iter().zip(&depths) {
                assert!(drawn == given || *drawn == u8::MAX, "{label}");
            }
        }
        node.set_face_depths(None).unwrap();
        // Frame-rate control moving depths frame by frame: always watertight.
        node.set_frame_rate_control(Some(1000.0));
        let camera = random_camera(&mut rng, &mesh);
        for frame in 0..6 {
            let g = node.update(&camera, Some(0.05)).unwrap().clone();
            let label = format!("{name} frame-rate frame {frame}");
            assert_eq!(open_edges(&label, &g), expected_open(&mesh, &g), "{label}");
        }
    }
}
