//! The budget controller and its model on a simulated machine: frame time a known linear cost
//! of the work plus noise (and an occasional hiccup), the faces' errors falling with depth.

use subdiv_test_support::Rng;

use super::*;
use crate::frame_model::FrameTimeModel;

/// A scene of `n` faces: every eighth a back face with geometric depth 0 or 1, the rest front
/// or silhouette faces; errors fall by a factor 3-5 per level from a face-dependent start.
struct Scene {
    a: Assignment,
    errors: Vec<f32>,
    min_depth: Vec<Depth>,
    weight: Vec<f32>,
    max_depth: Depth,
}

fn scene(n: usize, rng: &mut Rng) -> Scene {
    let max_depth = 5;
    let levels = max_depth as usize + 1;
    let mut a = Assignment::default();
    let mut errors = vec![0.0; n * levels];
    for f in 0..n {
        let back = f % 8 == 3;
        a.class.push(if back {
            Class::Back
        } else if f % 5 == 0 {
            Class::Silhouette
        } else {
            Class::Front
        });
        a.depth.push(if back { (f % 2) as Depth } else { 3 });
        a.active.push(true);
        a.radius.push(20.0);
        a.curvature.push(2);
        let start = 50.0 + 400.0 * rng.next_f32();
        let fall = 3.0 + 2.0 * rng.next_f32();
        // A back face is hidden (a closed surface): it shows no error.
        let start = if back { 0.0 } else { start };
        for d in 0..levels {
            errors[f * levels + d] = start / fall.powi(d as i32);
        }
    }
    let weight = (0..n)
        .map(|f| if f % 17 == 0 { 1.25 } else { 1.0 })
        .collect();
    Scene {
        a,
        errors,
        min_depth: (0..n).map(|f| (f % 17 == 0) as Depth).collect(),
        weight,
        max_depth,
    }
}

/// The simulated machine: 3 ms a frame, 25 ms per 10^5 triangles, 6 ms per 10^5 points, 1 ms
/// per 10^5 uploaded vertices; ±4 % noise and one frame in 50 two and a half times as slow.
fn machine(w: &FrameWork, rng: &mut Rng) -> f64 {
    let t = 3e-3 + 25e-3 * w.triangles * 1e-5 + 6e-3 * w.points * 1e-5 + 1e-3 * w.uploaded * 1e-5;
    let noise = 1.0 + 0.04 * rng.unit() as f64;
    let hiccup = if rng.chance(2) { 2.5 } else { 1.0 };
    t * noise * hiccup
}

/// Runs `frames` frames at the targets `fps(i)`; returns per frame (measured seconds, depths).
fn run(
    s: &Scene,
    frames: usize,
    fps: impl Fn(usize) -> f32,
    rng: &mut Rng,
) -> Vec<(f64, Vec<Depth>)> {
    let n = s.a.depth.len();
    let mut model = FrameTimeModel::with_default_prior();
    let mut c = BudgetController::new(fps(0));
    let mut cached: Vec<Option<Depth>> = vec![None; n];
    let mut depth = vec![0; n];
    let mut out = Vec::new();
    for i in 0..frames {
        c.set_target_fps(fps(i));
        let costs: Vec<FaceCost> = (0..n)
            .map(|f| FaceCost {
                weight: s.weight[f],
                cached: cached[f],
            })
            .collect();
        let capped: Vec<bool> = s.a.class.iter().map(|&c| c == Class::Back).collect();
        let choice = Choice {
            errors: &s.errors,
            costs: &costs,
            assignment: &s.a,
            capped: &capped,
            min_depth: &s.min_depth,
            first: &[],
            max_depth: s.max_depth,
            fixed: FrameWork::default(),
        };
        let work = c.choose(&choice, &model, &mut depth);
        let predicted = model.predict(&work);
        let measured = machine(&work, rng);
        if std::env::var_os("BUDGET_DEBUG").is_some() {
            eprintln!(
                "{i} target {:.1} ms measured {:.1} predicted {:.1} budget {:.1} tris {:.0} pts {:.0}",
                1e3 / f64::from(fps(i)),
                measured * 1e3,
                predicted * 1e3,
                c.budget() * 1e3,
                work.triangles,
                work.points
            );
        }
        model.observe(&work, measured);
        c.observe(measured, predicted);
        for (k, &d) in cached.iter_mut().zip(&depth) {
            *k = Some(k.map_or(d, |c| c.max(d)));
        }
        out.push((measured, depth.clone()));
    }
    out
}

/// Share of `times` within ±10 % of `1 / fps`.
fn within(times: &[(f64, Vec<Depth>)], fps: f32) -> f64 {
    let t = 1.0 / f64::from(fps);
    let ok = times
        .iter()
        .filter(|(m, _)| (m / t - 1.0).abs() <= 0.1)
        .count();
    ok as f64 / times.len().max(1) as f64
}

#[test]
fn control_converges_and_holds_the_band() {
    for seed in [0xb0d9e7, 1, 2, 3] {
        let mut rng = Rng::splitmix(seed);
        let s = scene(600, &mut rng);
        let frames = run(&s, 150, |_| 20.0, &mut rng);
        let share = within(&frames[30..], 20.0);
        // The machine's own ceiling: about 97 % of its frames lie within ±10 % of their median
        // (one in 50 is a hiccup); control must keep at least 0.9 of that.
        assert!(
            share >= 0.9 * 0.97,
            "seed {seed}: share within ±10 %: {share}"
        );
    }
}

#[test]
fn a_change_of_target_is_met_within_ten_frames() {
    for (seed, (from, to)) in [(15.0f32, 40.0f32), (40.0, 15.0)]
        .into_iter()
        .flat_map(|p| [(0x5ee5, p), (17, p), (18, p)])
    {
        let mut rng = Rng::splitmix(seed);
        let s = scene(600, &mut rng);
        let switch = 100;
        let frames = run(&s, 200, |i| if i < switch { from } else { to }, &mut rng);
        let t = 1.0 / f64::from(to);
        let first = frames[switch..]
            .iter()
            .position(|(m, _)| (m / t - 1.0).abs() <= 0.1)
            .expect("reaches the new target");
        assert!(
            first < 10,
            "seed {seed}, {from} -> {to} fps: first in the band after {first}"
        );
        let share = within(&frames[switch + 10..], to);
        assert!(
            share >= 0.85,
            "seed {seed}, {from} -> {to} fps: share {share}"
        );
    }
}

#[test]
fn back_faces_are_never_raised() {
    let mut rng = Rng::splitmix(42);
    let s = scene(300, &mut rng);
    // A generous budget: every front face goes to the deepest depth, back faces stay.
    for (_, depth) in run(&s, 60, |_| 5.0, &mut rng) {
        for (f, &d) in depth.iter().enumerate() {
            if s.a.class[f] == Class::Back {
                assert!(d <= s.a.depth[f].max(s.min_depth[f]), "face {f}");
            }
        }
    }
}

#[test]
fn a_still_camera_gives_a_still_picture() {
    for seed in [99, 100, 101] {
        still(seed);
    }
}

fn still(seed: u64) {
    let mut rng = Rng::splitmix(seed);
    let s = scene(600, &mut rng);
    let frames = run(&s, 200, |_| 25.0, &mut rng);
    // After convergence, noise and hiccups move no depth.
    let settled = &frames[60..];
    for (i, w) in settled.windows(2).enumerate() {
        if w[0].1 != w[1].1 && std::env::var_os("BUDGET_DEBUG").is_some() {
            let moved = (0..w[0].1.len())
                .filter(|&f| w[0].1[f] != w[1].1[f])
                .count();
            eprintln!("frame {}: {moved} faces moved", i + 61);
        }
    }
    let changes = settled.windows(2).filter(|w| w[0].1 != w[1].1).count();
    assert_eq!(changes, 0, "seed {seed}: depth changes after settling");
}

#[test]
fn more_time_buys_less_error() {
    let mut rng = Rng::splitmix(5);
    let s = scene(400, &mut rng);
    let error = |depth: &[Depth]| -> f64 {
        let levels = s.max_depth as usize + 1;
        (0..depth.len())
            .map(|f| s.errors[f * levels + depth[f] as usize] as f64)
            .sum()
    };
    let fast = run(&s, 80, |_| 60.0, &mut rng);
    let slow = run(&s, 80, |_| 15.0, &mut rng);
    let (ef, es) = (error(&fast[79].1), error(&slow[79].1));
    assert!(es < 0.5 * ef, "15 fps error {es} vs 60 fps {ef}");
}

#[test]
fn face_errors_fall_with_depth_and_vanish_where_nothing_is_seen() {
    use crate::{VertexData, assign, face_spheres, patch_errors};
    use subdiv_mesh::{Camera, Mesh, glam::Vec3, parse_obj};
    use subdiv_rules::Scheme;
    let mesh = Mesh::from_soup(&parse_obj(&subdiv_test_support::cube().obj()).unwrap()).unwrap();
    let set = subdiv_slate::PatchSet::new(&mesh).unwrap();
    let max_depth = 3;
    let errors = patch_errors(&mesh, &set, max_depth, 10f32.to_radians());
    let spheres = face_spheres(&mesh, Scheme::CatmullClark);
    let p = crate::DepthParams {
        max_depth,
        ..crate::DepthParams::default()
    };
    let vd = VertexData::compute(&mesh, Scheme::CatmullClark, p.cone_aperture_deg, max_depth);
    let camera = Camera::new(
        Vec3::new(1.6, 1.3, 2.5),
        Vec3::splat(0.5),
        Vec3::Y,
        45.0,
        320,
        240,
    );
    let mut a = assign(&mesh, &vd, &spheres, None, &camera, &p);
    let levels = max_depth as usize + 1;
    let e = face_errors(&camera, &errors, &spheres, &a, max_depth);
    assert_eq!(e.len(), 6 * levels);
    let capped = crate::capped_back_faces(&camera, &errors, &spheres, &a);
    let mut seen = 0;
    for f in 0..6 {
        let row = &e[f * levels..(f + 1) * levels];
        if capped[f] {
            // A closed cube hides the faces turned away from the eye: nothing of them shows.
            assert!(row.iter().all(|&x| x == 0.0), "face {f}: {row:?}");
            continue;
        }
        seen += 1;
        // A visible face, or a back face whose limit surface may still turn to the eye (it may
        // hold the outline), shows errors at depth 0 that the deepest depth all but removes.
        assert!(row[0] > 0.0, "face {f}: {row:?}");
        assert!(row[levels - 1] < 0.25 * row[0], "face {f}: {row:?}");
    }
    assert!(seen >= 3, "a corner view sees three faces");
    // Head-on from far away, the face opposite the eye is provably turned away.
    let far = Camera::new(
        Vec3::new(0.5, 0.5, 40.0),
        Vec3::splat(0.5),
        Vec3::Y,
        10.0,
        320,
        240,
    );
    let a_far = assign(&mesh, &vd, &spheres, None, &far, &p);
    let capped_far = crate::capped_back_faces(&far, &errors, &spheres, &a_far);
    let e_far = face_errors(&far, &errors, &spheres, &a_far, max_depth);
    let hidden: Vec<usize> = (0..6).filter(|&f| capped_far[f]).collect();
    assert!(!hidden.is_empty(), "{:?}", a_far.class);
    for f in hidden {
        assert_eq!(a_far.class[f], Class::Back);
        assert!(
            e_far[f * levels..(f + 1) * levels]
                .iter()
                .all(|&x| x == 0.0)
        );
    }
    // An inactive face has no error at any depth.
    let f = (0..6).find(|&f| a.class[f] != Class::Back).unwrap();
    a.active[f] = false;
    let e = face_errors(&camera, &errors, &spheres, &a, max_depth);
    assert!(e[f * levels..(f + 1) * levels].iter().all(|&x| x == 0.0));
}
