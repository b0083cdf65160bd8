//! The predictive control's choice for a budget of triangles against uniform tessellation: at
//! uniform depth d's triangle count (d = 2, 3), the budgeted picture's silhouette is within
//! half a pixel (the metric's resolution) of uniform depth d's, on every Catmull-Clark fixture
//! cage and the 3-torus from two cameras, against uniform depth 5. A budget spent on a few faces
//! drawn finely while the rest stay at depth 0 fails it (a coarse 3-torus then shows outlines
//! pixels off), and so does a back face holding part of the outline left at depth 0 (the
//! pyramid). Not claimed at uniform depth 1's count (8 triangles a face): there the budget
//! draws the pillow at depth 1 everywhere, uniform's depths, yet its outline is 6.3 px off
//! against uniform's 2.9 px: at that depth the pillow's quads are far from planar, and the
//! adaptive frame splits them into triangles along other diagonals than the uniform render.
//! Rendered with the real renderer; without a Vulkan driver the test prints a note and passes
//! unless `SUBDIV_VK_REQUIRE_DRIVER=1`.

mod common;

use common::{cages, renderer};
use glam::Vec3;
use subdiv::mesh::{Camera, ReadOptions, read_obj_with};
use subdiv_quality::{Config, QualityParams, QualityRun, orbit_cameras};

const SIZE: [u32; 2] = [240, 180];

#[test]
fn a_triangle_budget_draws_silhouettes_no_worse_than_uniform() {
    let Some(mut renderer) = renderer() else {
        return;
    };
    let params = QualityParams {
        size: SIZE,
        max_depth: 4,
        reference_depth: Some(5),
        timing_runs: 1,
        shading_error_deg: 10.0,
    };
    let mut checked = 0;
    let mut failures = Vec::new();
    let mut paths = cages();
    paths.push(subdiv_test_support::fixture("meshes/cc_3torus.obj"));
    for path in paths {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if name.starts_with("loop_") {
            continue;
        }
        let Ok(cage) = read_obj_with(
            &path,
            ReadOptions {
                split_nonmanifold_vertices: true,
            },
        ) else {
            continue; // Cages the reader refuses are tested elsewhere.
        };
        let (lo, hi) = cage.bounds();
        let [w, h] = SIZE;
        let base = Camera::eye_relative(lo, hi, Vec3::new(0.9, 0.45, 2.0), 45.0, w, h);
        let cameras: Vec<Camera> = orbit_cameras(&base, 4).into_iter().step_by(2).collect();
        let run = QualityRun::new(&mut renderer, &cage, &cameras, params)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        for d in 2..=3u8 {
            let uniform = run.measure(&mut renderer, Config::Uniform(d)).unwrap();
            let n = u32::try_from(uniform.triangles).unwrap();
            let budget = run.measure(&mut renderer, Config::Budget(n)).unwrap();
            if budget.silhouette_px_max > uniform.silhouette_px_max + 0.5 {
                failures.push(format!("{name}:\n  {uniform}\n  {budget}"));
            }
            checked += 1;
        }
    }
    assert!(checked >= 2 * 20, "only {checked} runs");
    assert!(
        failures.is_empty(),
        "budgeted silhouettes worse than uniform's by more than 0.5 px:\n{}",
        failures.join("\n")
    );
}
