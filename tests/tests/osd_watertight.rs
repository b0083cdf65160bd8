//! Adaptive watertightness on random cages (issue 13 item 6): the random cages of
//! `cargo xtask fuzz-osd` (`subdiv_tests::osd_gen`, read as Catmull-Clark cages, and the Loop
//! ones as adaptive Loop too, issue 14 item 4) under random
//! cameras, through `subdiv::DynamicSubdivision` in curvature mode (with and without the
//! projected-size rule, sometimes culling back faces) and in pixel-error mode. After welding
//! identical coordinates, every edge of the frame's triangles is used by exactly two triangles,
//! except the edges along the boundary of the drawn surface (the cage's boundary, holes, faces
//! not drawn), which are used by one: as many as the drawn faces' depths put on those cage edges
//! (2^depth each).
//!
//! `SUBDIV_WATERTIGHT_CAGES` (default 40) and `SUBDIV_WATERTIGHT_SEED` (default 1) scale a run.

use std::collections::HashMap;

use glam::Vec3;
use subdiv::DynamicSubdivision;
use subdiv_depth::DepthParams;
use subdiv_mesh::{Camera, Mesh};
use subdiv_rules::Scheme;
use subdiv_stitch::FrameGeometry;
use subdiv_tests::fuzz::Rng;
use subdiv_tests::osd_gen::random_cage;

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Open edges the frame must have: along every cage edge with exactly one drawn face, 2^depth
/// of that face.
fn expected_open_edges(mesh: &Mesh, g: &FrameGeometry) -> usize {
    let drawn = |h| {
        let f = mesh.face(h);
        f.is_some() && g.unit_depth[f.idx()] != u8::MAX
    };
    mesh.edges()
        .map(|e| {
            let (a, b) = (drawn(e.halfedge(0)), drawn(e.halfedge(1)));
            match (a, b) {
                (true, false) => 1usize << g.unit_depth[mesh.face(e.halfedge(0)).idx()],
                (false, true) => 1usize << g.unit_depth[mesh.face(e.halfedge(1)).idx()],
                _ => 0,
            }
        })
        .sum()
}

/// Welds identical coordinates and counts the triangles on every edge: `Err` unless each edge
/// has one or two (two in opposite directions) and exactly `want_open` have one. Triangles that
/// welding makes degenerate are left out (they cover nothing).
fn check_watertight(g: &FrameGeometry, want_open: usize) -> Result<(), String> {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let weld: Vec<u32> = g
        .positions
        .iter()
        .map(|p| {
            let key = p.map(|x| if x == 0.0 { 0 } else { x.to_bits() });
            let n = ids.len() as u32;
            *ids.entry(key).or_insert(n)
        })
        .collect();
    let mut uses: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
    for t in g.indices.chunks(3) {
        let w = [
            weld[t[0] as usize],
            weld[t[1] as usize],
            weld[t[2] as usize],
        ];
        if w[0] == w[1] || w[1] == w[2] || w[0] == w[2] {
            continue;
        }
        for k in 0..3 {
            let (a, b) = (w[k], w[(k + 1) % 3]);
            let e = uses.entry((a.min(b), a.max(b))).or_default();
            if a < b { e.0 += 1 } else { e.1 += 1 }
        }
    }
    let mut open = 0;
    for (&(a, b), &(fw, bw)) in &uses {
        match (fw, bw) {
            (1, 1) => {}
            (1, 0) | (0, 1) => open += 1,
            _ => {
                let p = g.positions[weld.iter().position(|&w| w == a).unwrap_or(0)];
                return Err(format!(
                    "edge {a}-{b} at {p:?} is used {fw} times one way and {bw} the other"
                ));
            }
        }
    }
    if open != want_open {
        return Err(format!(
            "{open} open edges, want {want_open} (the drawn surface's boundary)"
        ));
    }
    Ok(())
}

fn params(rng: &mut Rng, pixel: bool) -> DepthParams {
    DepthParams {
        max_depth: rng.range(2, 4) as u8,
        projected_size: rng.chance(50).then_some((2.0, 8.0)),
        pixel_error: pixel.then(|| [0.5, 1.0, 3.0][rng.below(3)]),
        cull_back: rng.chance(25),
        ..DepthParams::default()
    }
}

fn camera(rng: &mut Rng, mesh: &Mesh) -> Camera {
    let (lo, hi) = mesh.bounds();
    let dir = Vec3::new(rng.unit(), rng.unit(), rng.unit()).normalize_or(Vec3::Z);
    let dist = [0.6, 1.5, 3.0, 8.0][rng.below(4)];
    let (w, h) = [(320, 240), (800, 600), (64, 64)][rng.below(3)];
    Camera::eye_relative(lo, hi, dir * dist, 45.0, w, h)
}

#[test]
fn random_cages_are_watertight_under_random_cameras() {
    let seed = env_u64("SUBDIV_WATERTIGHT_SEED", 1);
    let cages = env_u64("SUBDIV_WATERTIGHT_CAGES", 40);
    let mut failures = Vec::new();
    let mut frames = 0;
    let mut loops = 0;
    for index in 0..cages {
        let cage = random_cage(seed, index);
        let mesh = cage.mesh().expect("generated cages are valid");
        let mut rng = Rng::for_case(seed ^ 0xCA3E, index);
        loops += usize::from(cage.loop_scheme);
        let schemes: &[Scheme] = if cage.loop_scheme {
            &[Scheme::CatmullClark, Scheme::Loop]
        } else {
            &[Scheme::CatmullClark]
        };
        for (&scheme, pixel) in schemes.iter().flat_map(|s| [(s, false), (s, true)]) {
            let mut node =
                DynamicSubdivision::with_scheme(mesh.clone(), scheme, params(&mut rng, pixel))
                    .unwrap_or_else(|e| panic!("seed {seed} cage {index} {scheme:?}: {e}"));
            for shot in 0..3 {
                let cam = camera(&mut rng, &mesh);
                let g = node
                    .update(&cam, None)
                    .unwrap_or_else(|e| panic!("seed {seed} cage {index}: {e}"));
                frames += 1;
                if let Err(e) = check_watertight(g, expected_open_edges(&mesh, g)) {
                    let mode = if pixel { "pixel-error" } else { "curvature" };
                    failures.push(format!(
                        "seed {seed} cage {index} ({}) {scheme:?} {mode} camera {shot}: {e}",
                        cage.features()
                    ));
                }
            }
        }
    }
    assert!(loops > 0, "no Loop cage among {cages}");
    assert!(
        failures.is_empty(),
        "{} of {frames} frames are not watertight:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The check sees a missing triangle and a duplicated one.
#[test]
fn the_check_finds_cracks() {
    let cage = random_cage(1, 0);
    let mesh = cage.mesh().expect("valid");
    let params = DepthParams {
        max_depth: 2,
        ..DepthParams::default()
    };
    let mut node = DynamicSubdivision::new(mesh.clone(), params).expect("assembles");
    let (lo, hi) = mesh.bounds();
    let cam = Camera::eye_relative(lo, hi, Vec3::new(0.3, 0.4, 2.0), 45.0, 320, 240);
    let g = node.update(&cam, None).expect("frame").clone();
    let want = expected_open_edges(&mesh, &g);
    check_watertight(&g, want).expect("the real frame is watertight");
    let mut cracked = g.clone();
    cracked.indices.truncate(cracked.indices.len() - 3);
    assert!(check_watertight(&cracked, want).is_err());
    let mut doubled = g.clone();
    doubled.indices.extend_from_slice(&g.indices[..3]);
    assert!(check_watertight(&doubled, want).is_err());
}
