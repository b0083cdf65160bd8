//! A quality run on a cube at 64x48 (needs a Vulkan driver; skipped without one unless
//! `SUBDIV_VK_REQUIRE_DRIVER=1`), and the parameter checks (no driver needed).

use glam::Vec3;
use subdiv::mesh::{Camera, Mesh, parse_obj};
use subdiv::vk::{ContextOptions, Renderer, Validation, VkError};

use super::*;

fn cube() -> Mesh {
    Mesh::from_soup(&parse_obj(&subdiv_test_support::cube().obj()).unwrap()).unwrap()
}

/// A renderer (validation when installed); `None` without a driver unless one is required.
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
fn configurations_and_parameter_checks() {
    let names: Vec<String> = Config::all(2).iter().map(Config::name).collect();
    assert_eq!(
        names,
        [
            "uniform-0",
            "uniform-1",
            "uniform-2",
            "curvature",
            "pixel-error-2",
            "pixel-error-1",
            "pixel-error-0.5",
            "dicing-2",
            "dicing-1",
            "dicing-0.5"
        ]
    );
    let p = QualityParams::default();
    assert_eq!((p.max_depth, p.reference_depth()), (5, 6));
    p.check().unwrap();
    let same = QualityParams {
        reference_depth: Some(5),
        ..p
    };
    let e = same.check().unwrap_err();
    assert!(matches!(
        e,
        QualityError::ReferenceNotDeeper {
            reference: 5,
            max_depth: 5
        }
    ));
    assert!(e.to_string().contains("not deeper"), "{e}");
    let deep = QualityParams { max_depth: 12, ..p };
    assert!(matches!(
        deep.check(),
        Err(QualityError::MaxDepthTooDeep { .. })
    ));
    let empty = QualityParams { size: [0, 48], ..p };
    assert!(matches!(
        empty.check(),
        Err(QualityError::EmptyImage { .. })
    ));
    for degrees in [0.0, -1.0, 181.0, f32::NAN] {
        let bad = QualityParams {
            shading_error_deg: degrees,
            ..p
        };
        assert!(matches!(
            bad.check(),
            Err(QualityError::ShadingError { .. })
        ));
    }
}

#[test]
fn deeper_uniform_tessellations_come_closer_to_the_reference() {
    let Some(mut renderer) = renderer() else {
        return;
    };
    let cage = cube();
    let (lo, hi) = cage.bounds();
    let base = Camera::eye_relative(lo, hi, Vec3::new(0.8, 0.5, 2.2), 45.0, 1, 1);
    let cameras = orbit_cameras(&base, 2);
    let params = QualityParams {
        size: [64, 48],
        max_depth: 2,
        reference_depth: None,
        timing_runs: 1,
        ..QualityParams::default()
    };
    let run = QualityRun::new(&mut renderer, &cage, &cameras, params).unwrap();
    assert_eq!(run.reference_triangles(), 6 * 64 * 2);
    assert!(run.cameras().all(|c| (c.width, c.height) == (64, 48)));
    // The reference against itself: no error at all.
    let same = run.measure(&mut renderer, Config::Uniform(3)).unwrap();
    assert_eq!(same.triangles, 6 * 64 * 2);
    assert_eq!(
        (
            same.silhouette_px_max,
            same.silhouette_px_p99,
            same.shading_deg_p99
        ),
        (0.0, 0.0, 0.0),
        "{same}"
    );
    let all = run.measure_all(&mut renderer, |_| {}).unwrap();
    assert_eq!(all.len(), 10);
    let (u0, u2) = (&all[0], &all[2]);
    assert_eq!((u0.triangles, u2.triangles), (12, 6 * 16 * 2));
    // The depth-0 cube (the cage's limit points) lies well inside the rounded limit surface.
    assert!(u0.silhouette_px_max > 1.0, "{u0}");
    assert!(u2.silhouette_px_max <= u0.silhouette_px_max, "{u2} vs {u0}");
    assert!(u2.shading_deg_p99 < u0.shading_deg_p99, "{u2} vs {u0}");
    for q in &all {
        assert!(q.silhouette_px_p99 <= q.silhouette_px_max, "{q}");
        assert!(q.update_ms >= 0.0 && q.render_ms > 0.0, "{q}");
        let line = q.to_string();
        assert!(line.starts_with(&format!("config={} triangles=", q.config.name())));
        assert!(line.contains(" render_ms="), "{line}");
    }
    // The reference must be in view.
    let away = Camera::new(hi * 10.0, hi * 20.0, Vec3::Y, 45.0, 64, 48);
    let e = QualityRun::new(&mut renderer, &cage, &[away], params).err();
    assert!(
        matches!(e, Some(QualityError::EmptyReference { camera: 0 })),
        "{e:?}"
    );
    assert!(matches!(
        QualityRun::new(&mut renderer, &cage, &[], params).err(),
        Some(QualityError::NoCameras)
    ));
}

#[test]
fn curvature_configurations_name_and_apply_their_parameters() {
    let d = CurvatureParams::default();
    assert_eq!(Config::Curvature(d).name(), "curvature");
    let c = CurvatureParams {
        cone_aperture_deg: 5.0,
        classifier_eps: 0.25,
        projected_size: Some((0.5, 4.0)),
    };
    assert_eq!(
        Config::Curvature(c).name(),
        "curvature-cone5-eps0.25-size0.5-4"
    );
    let off = CurvatureParams {
        projected_size: None,
        ..d
    };
    assert_eq!(
        Config::Curvature(off).name(),
        format!(
            "curvature-cone{}-eps{}-sizeoff",
            d.cone_aperture_deg, d.classifier_eps
        )
    );
    let base = subdiv::depth::DepthParams {
        max_depth: 3,
        ..Default::default()
    };
    let p = c.apply(base);
    assert_eq!(
        (
            p.max_depth,
            p.cone_aperture_deg,
            p.classifier_eps,
            p.projected_size
        ),
        (3, 5.0, 0.25, Some((0.5, 4.0)))
    );
    assert_eq!(p.pixel_error, None);
}
