//! Tests of [`super::patch_errors`].

use super::*;
use subdiv_mesh::parse_obj;

fn cube() -> Mesh {
    Mesh::from_soup(&parse_obj(&subdiv_test_support::cube().obj()).unwrap()).unwrap()
}

#[test]
fn deviations_fall_with_depth_and_match_a_dense_check() {
    let mesh = cube();
    let set = PatchSet::new(&mesh).unwrap();
    let tolerance = 2f32.to_radians();
    let e = patch_errors(&mesh, &set, 3, tolerance);
    assert!(e.closed);
    assert_eq!(e.shading_tolerance, tolerance);
    for f in &e.faces {
        for l in 1..f.deviation.len() {
            assert!(f.deviation[l] < f.deviation[l - 1], "{:?}", f.deviation);
        }
        let sh = &f.shading;
        assert_eq!(sh.elements.len(), ELEMENTS_PER_SIDE * ELEMENTS_PER_SIDE);
        assert_eq!(sh.weight, 1.0);
        // The elements tile the face's limit patch: a cube face's patch (a rounded square
        // well inside the unit square: the limit of a cube cage is a blob of about 0.38 of
        // its area per face) has an area between 0.2 and 1.
        let area: f32 = sh.elements.iter().map(|el| el.area).sum();
        assert!(area > 0.2 && area < 1.0, "{area}");
        // Outlier area per depth, summed over the elements.
        let at = |k: usize, l: usize, sc: usize| sh.outlier_area[(k * 4 + l) * sh.scales + sc];
        let per_depth: Vec<f32> = (0..4)
            .map(|l| (0..sh.elements.len()).map(|k| at(k, l, 0)).sum())
            .collect();
        // Depth 0 of a cube face: the corner normals (54.7° off the face's axis)
        // interpolated across two triangles are more than 2° off over a good part of the
        // face (up to 6.7°); every level down shrinks that area, and three levels down
        // almost nothing is left.
        assert!(per_depth[0] > 0.1 * area, "{per_depth:?}");
        assert!(
            per_depth.windows(2).all(|w| w[1] < w[0] || w[1] == 0.0),
            "{per_depth:?}"
        );
        assert!(per_depth[3] < 0.01 * area, "{per_depth:?}");
        // Depth 3 drawn into a depth-5 sample grid: 32 × 32 cells, 8 × 8 per element.
        assert_eq!(sh.scales, 4);
        for (k, el) in sh.elements.iter().enumerate() {
            assert!(el.area > 0.0 && el.normal.is_normalized(), "{el:?}");
            assert!(
                (el.cell * el.cell * 64.0 / el.area - 1.0).abs() < 1e-3,
                "{el:?}"
            );
            for l in 0..4 {
                assert!((0..sh.scales).all(|sc| at(k, l, sc) <= el.area * 1.0001));
            }
            // At depth 3 a drawn quad spans 4 × 4 cells: averaged over the whole quad
            // (scale 2) the interpolated and the limit normals agree better than per cell.
            assert!(at(k, 3, 2) <= at(k, 3, 0), "{el:?}");
        }
        // A cube face's limit patch turns its normal by well under 90° but more than 10°.
        let half = f.normals.cos.acos().to_degrees();
        assert!(half > 10.0 && half < 90.0, "{half}");
    }
    // Depth-0 deviation of a cube face: its limit patch bulges from the chord quad by a
    // visible fraction of the edge; a sphere-like cube has deviation between 1 % and 30 %.
    let d0 = e.faces[0].deviation[0];
    assert!(d0 > 0.01 && d0 < 0.3, "{d0}");
}

#[test]
fn open_meshes_are_not_closed_and_cones_merge() {
    let quad =
        Mesh::from_soup(&parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap())
            .unwrap();
    let set = PatchSet::new(&quad).unwrap();
    let e = patch_errors(&quad, &set, 2, 0.5f32.to_radians());
    assert!(!e.closed);
    // A flat quad: the limit surface lies in the quad's plane; what remains is where its
    // outline leaves the chord triangles (a real gap on screen), falling with depth; the
    // normals are all +z.
    let d = &e.faces[0].deviation;
    assert!(d.windows(2).all(|w| w[1] < w[0]), "{d:?}");
    assert!((e.faces[0].normals.axis - Vec3::Z).length() < 1e-6);
    // Flat: interpolated normals are the limit normal, nothing is beyond even 0.5°.
    assert!(
        e.faces[0].shading.outlier_area.iter().all(|&a| a == 0.0),
        "{e:?}"
    );
    assert!(e.faces[0].normals.cos > 0.9999);
    let a = NormalCone {
        axis: Vec3::Z,
        cos: 10f32.to_radians().cos(),
    };
    let b = NormalCone {
        axis: Vec3::X,
        cos: 10f32.to_radians().cos(),
    };
    let m = merge_cones(&[a, b]);
    assert!((m.cos.acos().to_degrees() - 55.0).abs() < 0.01);
    assert_eq!(merge_cones(&[a, NormalCone::ANY]).cos, -1.0);
}
