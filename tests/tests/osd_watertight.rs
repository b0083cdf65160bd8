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
//! Non-manifold cages (a share of the generator's, refined as manifold pieces whose copies of
//! a vertex coincide, `PolygonSoup::split_nonmanifold`): welding joins the pieces' copies of a
//! non-manifold edge, so an edge there may be used by up to as many triangles as the cage has
//! faces on it, in any directions. The uses on open and non-manifold edges must then make up
//! the drawn pieces' boundary plus at most the segments of the copies that lie inside a piece
//! (counted only where welding joins them with another copy).
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
use subdiv_tests::osd_cage::OsdCage;
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

/// A cage's non-manifold edges (`PolygonSoup::split_nonmanifold`): the most faces on one of
/// them (0 for a manifold cage) and, per edge of the split mesh, whether it is a copy of one.
fn nonmanifold_edges(cage: &OsdCage, mesh: &Mesh) -> (u32, Vec<bool>) {
    let mut soup = subdiv_mesh::parse_obj(&cage.to_obj()).expect("generated cages parse");
    let nv = soup.positions.len();
    let found = soup.split_nonmanifold().expect("generated cages are valid");
    let orig = |v: usize| {
        if v < nv {
            v
        } else {
            found.copies[v - nv].0 as usize
        }
    };
    let on = mesh
        .edges()
        .map(|e| {
            let (a, b) = (mesh.from(e.halfedge(0)), mesh.to(e.halfedge(0)));
            let (a, b) = (orig(a.idx()) as u32, orig(b.idx()) as u32);
            found
                .edges
                .iter()
                .any(|x| (x.0, x.1) == (a.min(b), a.max(b)))
        })
        .collect();
    (found.edges.iter().map(|e| e.2).max().unwrap_or(0), on)
}

/// Drawn-face segments on the split mesh's copies of non-manifold edges (2^depth per drawn
/// face on each).
fn seam_uses(mesh: &Mesh, g: &FrameGeometry, on: &[bool]) -> usize {
    mesh.edges()
        .filter(|e| on[e.idx()])
        .map(|e| {
            [e.halfedge(0), e.halfedge(1)]
                .iter()
                .map(|&h| mesh.face(h))
                .filter(|f| f.is_some() && g.unit_depth[f.idx()] != u8::MAX)
                .map(|f| 1usize << g.unit_depth[f.idx()])
                .sum::<usize>()
        })
        .sum()
}

/// Welds identical coordinates and counts the triangles on every edge: `Err` unless each edge
/// has one or two (two in opposite directions), or (on a non-manifold cage, whose manifold
/// pieces' copies of a non-manifold edge weld together) up to `most` in any directions; and
/// unless the uses on open and non-manifold edges plus two per welded pair of piece borders
/// (an edge used once each way by triangles that name it with different vertices, which only
/// welding joins) make up `want_open`, the drawn pieces' boundary. Triangles that welding
/// makes degenerate are left out (they cover nothing).
fn check_watertight(
    g: &FrameGeometry,
    want_open: usize,
    most: u32,
    seams: usize,
) -> Result<(), String> {
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
    // Per welded edge: uses each way and the first use's own (unwelded) vertices.
    type Uses = (u32, u32, Option<(u32, u32)>, bool);
    let mut uses: HashMap<(u32, u32), Uses> = HashMap::new();
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
            let (ra, rb) = (t[k], t[(k + 1) % 3]);
            let raw = (ra.min(rb), ra.max(rb));
            let e = uses.entry((a.min(b), a.max(b))).or_default();
            if a < b {
                e.0 += 1
            } else {
                e.1 += 1
            }
            match e.2 {
                None => e.2 = Some(raw),
                Some(r) if r != raw => e.3 = true,
                _ => {}
            }
        }
    }
    let mut open = 0;
    for (&(a, b), &(fw, bw, _, joined)) in &uses {
        match (fw, bw) {
            (1, 1) if !joined => {}
            (1, 1) if most > 0 => open += 2,
            (1, 0) | (0, 1) => open += 1,
            _ if most > 0 && fw + bw <= most => open += (fw + bw) as usize,
            _ => {
                let p = g.positions[weld.iter().position(|&w| w == a).unwrap_or(0)];
                return Err(format!(
                    "edge {a}-{b} at {p:?} is used {fw} times one way and {bw} the other"
                ));
            }
        }
    }
    // A copy of a non-manifold edge inside its piece (two drawn faces) is counted only where
    // welding joins it with another copy, so with seams the count lies in a range.
    if open < want_open || open > want_open + seams {
        return Err(format!(
            "{open} open or non-manifold edge uses, want {want_open} (the drawn pieces' \
             boundary, {seams} of it on non-manifold edges, each counted once or more)"
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
        let (most, on) = nonmanifold_edges(&cage, &mesh);
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
                let (open, seams) = (expected_open_edges(&mesh, g), seam_uses(&mesh, g, &on));
                if let Err(e) = check_watertight(g, open, most, seams) {
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
    check_watertight(&g, want, 0, 0).expect("the real frame is watertight");
    let mut cracked = g.clone();
    cracked.indices.truncate(cracked.indices.len() - 3);
    assert!(check_watertight(&cracked, want, 0, 0).is_err());
    let mut doubled = g.clone();
    doubled.indices.extend_from_slice(&g.indices[..3]);
    assert!(check_watertight(&doubled, want, 0, 0).is_err());
}
