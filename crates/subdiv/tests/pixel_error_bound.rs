//! The pixel-error bound against the true surface (issue 12): with `--pixel-error P` the
//! silhouette of the adaptive tessellation lies within `P + 0.5` pixels of the silhouette of a
//! uniform tessellation one level deeper than the deepest adaptive depth, for every fixture cage
//! seen from five cameras around it. Rendered with the real renderer (lavapipe in CI); without a
//! Vulkan driver the test prints a note and passes unless `SUBDIV_VK_REQUIRE_DRIVER=1`.

use std::path::{Path, PathBuf};

use glam::Vec3;
use subdiv::mesh::{Camera, ReadOptions, read_obj_with};
use subdiv::quality::{Config, QualityParams, QualityRun, orbit_cameras};
use subdiv::vk::{ContextOptions, Renderer, Validation, VkError};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn cages() -> Vec<PathBuf> {
    let mut out = Vec::new();
    for dir in ["fixtures/reference/shapes", "fixtures/scenes"] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "obj"))
            .collect();
        files.sort();
        out.extend(files);
    }
    out
}

fn renderer() -> Option<Renderer> {
    let options = ContextOptions {
        validation: Validation::IfAvailable,
        ..Default::default()
    };
    match Renderer::with_options(&options) {
        Ok(r) => Some(r),
        Err(e @ (VkError::LoaderMissing { .. } | VkError::NoDriver { .. }))
            if std::env::var("SUBDIV_VK_REQUIRE_DRIVER").as_deref() != Ok("1") =>
        {
            eprintln!("skipping: {e}");
            None
        }
        Err(e) => panic!("cannot create renderer: {e}"),
    }
}

#[test]
#[ignore = "open (issue 12): at pixel error 2, loop_triangle_edgeonly (triangles with semi-sharp \
            corners, read as Catmull-Clark) is 3.5 px off; every other fixture holds at 1 and 2; \
            run with --ignored"]
fn pixel_error_bounds_the_silhouette_on_every_fixture() {
    let Some(mut renderer) = renderer() else {
        return;
    };
    let params = QualityParams {
        size: [320, 240],
        max_depth: 4,
        reference_depth: Some(5),
        timing_runs: 1,
    };
    let mut checked = 0;
    let mut failures = Vec::new();
    for path in cages() {
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
        // Five cameras around the cage, slightly above it, and one from below in the set.
        let base = Camera::eye_relative(lo, hi, Vec3::new(0.9, 0.45, 2.0), 45.0, 320, 240);
        let mut cameras = orbit_cameras(&base, 4);
        cameras.push(Camera::eye_relative(
            lo,
            hi,
            Vec3::new(0.4, -1.6, 1.2),
            45.0,
            320,
            240,
        ));
        let run = QualityRun::new(&mut renderer, &cage, &cameras, params).unwrap();
        for px in [2.0f32, 1.0] {
            let q = run.measure(&mut renderer, Config::PixelError(px)).unwrap();
            if q.silhouette_px_max > px + 0.5 {
                failures.push(format!("{name} at pixel error {px}: {q}"));
            }
            checked += 1;
        }
    }
    assert!(checked >= 2 * 30, "only {checked} runs");
    assert!(
        failures.is_empty(),
        "silhouette beyond P + 0.5:\n{}",
        failures.join("\n")
    );
}
