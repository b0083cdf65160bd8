//! The shading bound of the pixel-error mode against the true surface: with
//! `--pixel-error P --shading-error DEG`, over the pixels off the reference's *line pixels*
//! (where the true normal turns by more than DEG to a neighbouring pixel: crease lines, folds
//! and strips narrower than a pixel, `subdiv_quality::line_pixels`), the 99th percentile of
//! the angle between drawn and true normals (`shading_deg_p99_off_lines`) stays within
//! `DEG + MARGIN_DEG` — or, where even the deepest depth drawn everywhere leaves more, within
//! what that uniform tessellation reaches plus `MARGIN_DEG` — and the silhouette within
//! `P + 0.5` pixels, for every fixture cage seen
//! from four cameras (three around it, one from a random direction), against a uniform
//! tessellation one level deeper than the deepest adaptive depth, at the default tolerance and
//! at 5°. Rendered with the real renderer (lavapipe in CI); without a Vulkan driver the test
//! prints a note and passes unless `SUBDIV_VK_REQUIRE_DRIVER=1`.
//!
//! The line pixels are left out because there no depth resolves the normal at pixel scale: a
//! pixel shows the mean normal of its footprint, which turns with where the line falls in it,
//! in the reference as in any tessellation. Over all pixels (`shading_deg_p99`) the bound does
//! not hold on creased cages at this size (up to 23.4° at 10° on catmark_cube_creases1, drawn
//! at the deepest depth everywhere); the test prints the largest such figure per tolerance.

mod common;

use common::{cages, renderer};
use glam::Vec3;
use subdiv::mesh::{Camera, ReadOptions, read_obj_with};
use subdiv_quality::{Config, QualityParams, QualityRun, orbit_cameras};

/// Shading tolerances checked (degrees): the default and a stricter one.
const TOLERANCES: [f32; 2] = [subdiv::depth::DEFAULT_SHADING_ERROR_DEG, 5.0];
/// The pixel error of the checked runs.
const PIXEL_ERROR: f32 = 1.0;
/// The deepest depth of the checked runs (`--max-depth`).
const MAX_DEPTH: subdiv::rules::Depth = 4;
/// What the measurement adds to the tolerance, in degrees: the reference (uniform depth
/// `maxsd + 1`) is itself not the limit surface, and a pixel's normal is the mean of its 3 × 3
/// samples, so a pixel across a crease strip narrower than a pixel reads a blend of both sides
/// in either render.
const MARGIN_DEG: f32 = 0.5;
const SIZE: [u32; 2] = [240, 180];

/// A camera from a random direction (a fixed seed per cage, so failures repeat) at 1.6–2.6
/// half-diagonals from the centre.
fn random_camera(lo: Vec3, hi: Vec3, seed: u32) -> Camera {
    let mut state = seed.wrapping_mul(2654435761) | 1;
    let mut rnd = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f32 / u32::MAX as f32
    };
    let z = rnd() * 2.0 - 1.0;
    let a = rnd() * std::f32::consts::TAU;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let dir = Vec3::new(r * a.cos(), z, r * a.sin());
    Camera::eye_relative(lo, hi, dir * (1.6 + rnd()), 45.0, SIZE[0], SIZE[1])
}

#[test]
fn shading_error_bounds_the_image_p99_on_every_fixture() {
    let Some(mut renderer) = renderer() else {
        return;
    };
    let mut checked = 0;
    let mut failures = Vec::new();
    let mut worst = vec![(f32::NEG_INFINITY, String::new()); TOLERANCES.len()];
    let mut worst_all = (f32::NEG_INFINITY, String::new());
    for (k, path) in cages().into_iter().enumerate() {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let Ok(cage) = read_obj_with(
            &path,
            ReadOptions {
                split_nonmanifold_vertices: true,
            },
        ) else {
            continue; // Cages the reader refuses are tested elsewhere.
        };
        let (lo, hi) = cage.bounds();
        let base = Camera::eye_relative(lo, hi, Vec3::new(0.9, 0.45, 2.0), 45.0, SIZE[0], SIZE[1]);
        let mut cameras = orbit_cameras(&base, 3);
        cameras.push(random_camera(lo, hi, 1000 + k as u32));
        for (deg, worst) in TOLERANCES.into_iter().zip(&mut worst) {
            let params = QualityParams {
                size: SIZE,
                max_depth: MAX_DEPTH,
                reference_depth: Some(MAX_DEPTH + 1),
                timing_runs: 1,
                shading_error_deg: deg,
            };
            let run = QualityRun::new(&mut renderer, &cage, &cameras, params).unwrap();
            let q = run
                .measure(&mut renderer, Config::PixelError(PIXEL_ERROR))
                .unwrap();
            // The deepest depth allowed, everywhere: where even it leaves more than DEG, the
            // bound is what it reaches.
            let deepest = run
                .measure(&mut renderer, Config::Uniform(MAX_DEPTH))
                .unwrap();
            eprintln!("{name} at {deg}°: {q}\n    {deepest}");
            let bound = deg.max(deepest.shading_deg_p99_off_lines);
            let excess = q.shading_deg_p99_off_lines - bound;
            if excess >= worst.0 {
                *worst = (excess, format!("{name}: {q}"));
            }
            if q.shading_deg_p99 - deg >= worst_all.0 {
                worst_all = (q.shading_deg_p99 - deg, format!("{name} at {deg}°: {q}"));
            }
            if excess > MARGIN_DEG || q.silhouette_px_max > PIXEL_ERROR + 0.5 {
                failures.push(format!("{name} at {deg}°: {q}"));
            }
            checked += 1;
        }
    }
    for (deg, (_, at)) in TOLERANCES.iter().zip(&worst) {
        eprintln!("largest p99 off the lines over its bound at {deg}°: {at}");
    }
    eprintln!(
        "largest p99 over all pixels over the tolerance: {}",
        worst_all.1
    );
    assert!(checked >= TOLERANCES.len() * 30, "only {checked} runs");
    assert!(
        failures.is_empty(),
        "shading off the lines beyond max(DEG, uniform depth {MAX_DEPTH}'s) + {MARGIN_DEG}° or silhouette beyond P + 0.5:\n{}",
        failures.join("\n")
    );
}
