//! Tests of `shading.rs`.

use super::*;
use crate::pixel_error::{NormalCone, PatchError};

fn cam() -> Camera {
    Camera::new(
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::ZERO,
        Vec3::Y,
        60.0,
        800,
        600,
    )
}

#[test]
fn screen_density_matches_a_projected_square() {
    // A small square facing the eye, off axis: the density times its area is the area of
    // its projection.
    let c = cam();
    for (centre, normal) in [
        (Vec3::ZERO, Vec3::Z),
        (Vec3::new(2.0, 1.0, 0.0), Vec3::Z),
        (
            Vec3::new(-1.0, 2.0, 1.0),
            Vec3::new(0.3, 0.2, 1.0).normalize(),
        ),
    ] {
        let h = 0.01f32;
        let (u, v) = {
            let u = normal.any_orthonormal_vector();
            (u, normal.cross(u))
        };
        let q: Vec<_> = [(-h, -h), (h, -h), (h, h), (-h, h)]
            .iter()
            .map(|&(a, b)| c.project(centre + u * a + v * b).unwrap())
            .collect();
        let shoelace: f32 = (0..4)
            .map(|i| q[i].perp_dot(q[(i + 1) % 4]))
            .sum::<f32>()
            .abs()
            * 0.5;
        let e = AreaElement {
            centre,
            normal,
            area: 4.0 * h * h,
            cell: h,
        };
        let est = ScreenArea::new(&c, true).density(&e) * e.area;
        assert!((est / shoelace - 1.0).abs() < 0.01, "{est} vs {shoelace}");
        // Facing away: hidden on a closed surface, seen from behind on an open one.
        let back = AreaElement {
            normal: -normal,
            ..e
        };
        assert_eq!(ScreenArea::new(&c, true).density(&back), 0.0);
        assert!((ScreenArea::new(&c, false).density(&back) * e.area / shoelace - 1.0).abs() < 0.01);
    }
    // Behind the eye and off screen: nothing.
    let behind = AreaElement {
        centre: Vec3::new(0.0, 0.0, 20.0),
        normal: -Vec3::Z,
        area: 1.0,
        cell: 0.1,
    };
    assert_eq!(ScreenArea::new(&c, false).density(&behind), 0.0);
    let aside = AreaElement {
        centre: Vec3::new(100.0, 0.0, 0.0),
        normal: Vec3::Z,
        area: 1.0,
        cell: 0.1,
    };
    assert_eq!(ScreenArea::new(&c, true).density(&aside), 0.0);
}

/// A face of one element at `x` facing the eye, with outlier areas per depth 0..=3.
fn face(x: f32, outliers: [f32; 4]) -> PatchError {
    PatchError {
        deviation: vec![0.0; 4],
        shading: ShadingError {
            elements: vec![AreaElement {
                centre: Vec3::new(x, 0.0, 0.0),
                normal: Vec3::Z,
                area: 1.0,
                cell: 1e-3,
            }],
            outlier_area: outliers.to_vec(),
            scales: 1,
            weight: 1.0,
        },
        normals: NormalCone::ANY,
        outline: false,
    }
}

fn closed(faces: Vec<PatchError>) -> PatchErrors {
    PatchErrors {
        faces,
        closed: true,
        shading_tolerance: 0.0,
    }
}

#[test]
fn outliers_are_read_at_the_pixel_footprint() {
    // 100 clean faces and one whose outliers show per sample cell (scale 0) but vanish when
    // averaged over 2 × 2 cells (scale 1), as a strip far narrower than a pixel does.
    let c = cam();
    let mut faces: Vec<PatchError> = (0..100)
        .map(|i| face(-1.0 + i as f32 * 0.02, [0.0; 4]))
        .collect();
    faces.push(face(0.1, [0.0; 4]));
    let o = 0.05 * 101.0;
    for f in &mut faces {
        let sh = &mut f.shading;
        sh.scales = 2;
        sh.outlier_area = vec![0.0; 8];
    }
    faces[100].shading.outlier_area[0] = o; // depth 0, scale 0
    let active = vec![true; faces.len()];
    // Cells of 1 mm: a pixel (about 2 cm at this distance) holds many, so scale 1 is read
    // and nothing is raised.
    let mut depth = vec![0u8; faces.len()];
    raise_for_shading(&c, &closed(faces.clone()), &active, &[], &mut depth, 3);
    assert!(depth.iter().all(|&d| d == 0), "{depth:?}");
    // Cells of 10 cm are larger than a pixel: scale 0 is read and the face is raised.
    for f in &mut faces {
        f.shading.elements[0].cell = 0.1;
    }
    let mut depth = vec![0u8; faces.len()];
    raise_for_shading(&c, &closed(faces), &active, &[], &mut depth, 3);
    assert_eq!(depth[100], 1);
}

#[test]
fn raises_the_cheapest_outliers_until_the_budget_holds() {
    let c = cam();
    let share = MODELLED_SHARE * OUTLIER_SHARE;
    // 100 faces without outliers, one whose outliers vanish at depth 1, one whose outliers
    // (as large) vanish only at depth 3: together 2 % of the area, four times the budget.
    let mut faces: Vec<PatchError> = (0..100)
        .map(|i| face(-1.0 + i as f32 * 0.02, [0.0; 4]))
        .collect();
    let o = 0.01 * 102.0;
    faces.push(face(0.1, [o, 0.0, 0.0, 0.0]));
    faces.push(face(0.2, [o, o, o, 0.0]));
    let active = vec![true; faces.len()];
    let mut depth = vec![0u8; faces.len()];
    let left = raise_for_shading(&c, &closed(faces.clone()), &active, &[], &mut depth, 3);
    // Both must go: the cheap one to 1, the dear one to 3 (nothing in between helps).
    assert_eq!(&depth[100..], &[1, 3]);
    assert!(depth[..100].iter().all(|&d| d == 0));
    assert!(left <= share, "{left}");
    // Only the cheap one is needed when the dear one is small enough for the budget.
    let small = 0.1 * o * share / 0.01;
    faces[101] = face(0.2, [small, small, small, 0.0]);
    let mut depth = vec![0u8; faces.len()];
    raise_for_shading(&c, &closed(faces.clone()), &active, &[], &mut depth, 3);
    assert_eq!(&depth[100..], &[1, 0]);
    // Hidden (facing away) or inactive faces are never raised.
    let mut hidden = faces.clone();
    hidden[100].shading.elements[0].normal = -Vec3::Z;
    let mut depth = vec![0u8; faces.len()];
    raise_for_shading(&c, &closed(hidden), &active, &[], &mut depth, 3);
    assert_eq!(depth[100], 0);
    let mut off = active.clone();
    off[100] = false;
    let mut depth = vec![0u8; faces.len()];
    raise_for_shading(&c, &closed(faces.clone()), &off, &[], &mut depth, 3);
    assert_eq!(depth[100], 0);
    // Never beyond the cap, and depths already deeper stay.
    let mut depth = vec![2u8; faces.len()];
    raise_for_shading(&c, &closed(faces), &active, &[], &mut depth, 2);
    assert!(depth.iter().all(|&d| d == 2));
}

#[test]
fn the_outlier_table_does_not_depend_on_the_thread_count() {
    // 3000 faces of 16 elements over each other (occlusion), with outliers at every depth and
    // scale, contours, and inactive faces: enough for many parallel tasks.
    let c = cam();
    let mut faces = Vec::new();
    for i in 0..3000u32 {
        let t = i as f32 * 0.37;
        let elements: Vec<AreaElement> = (0..16)
            .map(|k| AreaElement {
                centre: Vec3::new(
                    t.sin() * 3.0 + k as f32 * 0.01,
                    t.cos() * 2.0,
                    (t * 1.3).sin(),
                ),
                normal: Vec3::new((t + k as f32).sin() * 0.3, 0.2, 1.0).normalize(),
                // Areas over 13 orders of magnitude: their f64 sum rounds, so its order shows.
                area: 1e-3 * (1.0 + (t * 0.7).sin().abs()) * 10f32.powi(-((i % 13) as i32)),
                cell: 1e-3 * (1.0 + k as f32),
            })
            .collect();
        let outlier_area = (0..16 * 4 * 3)
            .map(|j| 1e-4 * ((j as f32 + t) * 0.9).sin().abs())
            .collect();
        let mut p = face(0.0, [0.0; 4]);
        p.deviation = vec![0.02, 0.01, 1e-3, 0.0];
        p.shading = ShadingError {
            elements,
            outlier_area,
            scales: 3,
            weight: 1.0,
        };
        faces.push(p);
    }
    let errors = PatchErrors {
        faces,
        closed: false,
        shading_tolerance: 0.1,
    };
    let active: Vec<bool> = (0..3000).map(|f| f % 7 != 3).collect();
    let contour: Vec<f32> = (0..3000)
        .map(|f| if f % 5 == 0 { 4.0 } else { 0.0 })
        .collect();
    let table = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| OutlierTable::new(&c, &errors, &active, &contour, 3))
    };
    let one = table(1);
    assert!(one.visible > 0.0 && one.rows.iter().any(|&o| o > 0.0));
    for threads in [2, 5] {
        let t = table(threads);
        assert_eq!(
            t.visible.to_bits(),
            one.visible.to_bits(),
            "{threads} threads"
        );
        assert_eq!(t.rows, one.rows, "{threads} threads");
        assert_eq!(t.face_visible, one.face_visible, "{threads} threads");
    }
}
