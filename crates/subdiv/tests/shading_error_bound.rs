//! The shading bound of the pixel-error mode against the true surface (issue 12): with
//! `--pixel-error P --shading-error DEG` the 99th percentile over the image's pixels of the angle
//! between drawn and true normals (`shading_deg_p99`) stays within `DEG + MARGIN_DEG`, and the
//! silhouette within `P + 0.5` pixels, for every fixture cage seen from four cameras (three
//! around it, one from a random direction), against a uniform tessellation one level deeper
//! than the deepest adaptive depth. Rendered with the real renderer (lavapipe in CI); without a
//! Vulkan driver the test prints a note and passes unless `SUBDIV_VK_REQUIRE_DRIVER=1`.
//!
//! **Ignored: the shading bound does not hold yet** (2026-11-30): the silhouette bound holds on
//! every cage, but `shading_deg_p99` exceeds `DEG + MARGIN_DEG` on 14 of 39 cages at 2° and 7
//! of 39 at 5° with the contour term of the model (17 and 8 before it; up to 23.4°,
//! catmark_cube_creases1; docs/figures/quality_shading_bound_test.txt). The model now counts
//! the pixels straddling silhouettes (`subdiv_depth::contour`) but not those straddling sharp
//! crease lines, which dominate at this size (see docs/performance.md, "Line pixels").
//! `cargo test -p subdiv --test shading_error_bound -- --ignored` (about 4 minutes here).

mod common;

use common::{cages, renderer};
use glam::Vec3;
use subdiv::mesh::{Camera, ReadOptions, read_obj_with};
use subdiv::quality::{Config, QualityParams, QualityRun, orbit_cameras};

/// Shading tolerances checked (degrees): the default and a looser one.
const TOLERANCES: [f32; 2] = [2.0, 5.0];
/// The pixel error of the checked runs.
const PIXEL_ERROR: f32 = 1.0;
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
#[ignore = "the shading bound does not hold yet on 14 of 39 fixtures at 2° (crease and silhouette pixels); see the module documentation"]
fn shading_error_bounds_the_image_p99_on_every_fixture() {
    let Some(mut renderer) = renderer() else {
        return;
    };
    let mut checked = 0;
    let mut failures = Vec::new();
    let mut worst = vec![(f32::NEG_INFINITY, String::new()); TOLERANCES.len()];
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
                max_depth: 4,
                reference_depth: Some(5),
                timing_runs: 1,
                shading_error_deg: deg,
            };
            let run = QualityRun::new(&mut renderer, &cage, &cameras, params).unwrap();
            let q = run
                .measure(&mut renderer, Config::PixelError(PIXEL_ERROR))
                .unwrap();
            eprintln!("{name} at {deg}°: {q}");
            let excess = q.shading_deg_p99 - deg;
            if excess >= worst.0 {
                *worst = (excess, format!("{name}: {q}"));
            }
            if excess > MARGIN_DEG || q.silhouette_px_max > PIXEL_ERROR + 0.5 {
                failures.push(format!("{name} at {deg}°: {q}"));
            }
            checked += 1;
        }
    }
    for (deg, (_, at)) in TOLERANCES.iter().zip(&worst) {
        eprintln!("largest p99 over the tolerance at {deg}°: {at}");
    }
    assert!(checked >= TOLERANCES.len() * 30, "only {checked} runs");
    assert!(
        failures.is_empty(),
        "shading beyond DEG + {MARGIN_DEG}° or silhouette beyond P + 0.5:\n{}",
        failures.join("\n")
    );
}
