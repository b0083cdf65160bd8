use super::*;
use subdiv_mesh::parse_obj;

/// Found by fuzzing: a pillow (two triangles on one vertex triple) made Loop refinement
/// build a non-manifold child mesh and report an internal error.
#[test]
fn loop_refuses_a_two_triangle_pillow() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\n\
                f 4 5 6\nf 1 2 3\nf 3 2 1\n";
    let m = Mesh::from_soup(&parse_obj(text).unwrap()).unwrap();
    let e = refine_uniform(&m, Scheme::Loop).unwrap_err();
    assert!(
        matches!(e, RulesError::DoubledTriangle { face: 2, other: 1 }),
        "{e:?}"
    );
    assert!(
        e.to_string().starts_with("faces 2 and 1 are triangles"),
        "{e}"
    );
    // Catmull-Clark refines the same pillow.
    assert_eq!(
        refine_uniform(&m, Scheme::CatmullClark)
            .unwrap()
            .num_faces(),
        9
    );
    // Triangles sharing one edge are fine.
    let fan = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 3 2 4\n";
    let m = Mesh::from_soup(&parse_obj(fan).unwrap()).unwrap();
    assert_eq!(refine_uniform(&m, Scheme::Loop).unwrap().num_faces(), 8);
}

/// The `f64` positions follow the same rules as the `f32` mesh: on a cage with creases,
/// a corner, n-gons, a boundary and Chaikin decay, every level-3 point agrees with the `f32`
/// refinement to `f32` rounding, for both schemes.
#[test]
fn f64_positions_follow_the_f32_refinement() {
    let text = "v 0 0 0\nv 1 0 0.2\nv 2 0 0\nv 0 1 0.1\nv 1 1 0.7\nv 2 1 0\nv 0 2 0\nv 1 2 0.3\n\
                v 2 2 0\nf 1 2 5 4\nf 2 3 6 5\nf 4 5 8 7\nf 5 6 9 8\nt crease 2/1/0 3 4 1.5\n\
                t crease 2/1/0 4 5 0.75\nt corner 1/1/0 0 2.5\nt creasemethod 0/0/1 chaikin\n";
    let cage = Mesh::from_soup(&parse_obj(text).unwrap()).unwrap();
    let tri = subdiv_mesh::triangulate(&cage).unwrap();
    for (m, scheme) in [(&cage, Scheme::CatmullClark), (&tri, Scheme::Loop)] {
        let (r, pos) = refine_uniform_levels_f64(m, scheme, 3).unwrap();
        let r32 = refine_uniform_levels(m, scheme, 3).unwrap();
        assert_eq!(r.positions(), r32.positions());
        assert_eq!(pos.len(), r.num_vertices());
        for (p, q) in pos.iter().zip(r.positions()) {
            assert!((*p - q.as_dvec3()).length() < 1e-5, "{scheme:?}: {p} {q}");
        }
    }
}

/// Found by fuzzing: finite coordinates near `f32::MAX` overflowed to infinite points (an
/// internal error from the refined mesh's validation).
#[test]
fn huge_coordinates_are_refused_and_the_bound_is_safe() {
    let cube = &subdiv_test_support::cube().obj();
    let mut m = Mesh::from_soup(&parse_obj(cube).unwrap()).unwrap();
    m.positions_mut()[6].y = 3.4e38;
    for depth in [0, 1] {
        let e = refine_uniform_levels(&m, Scheme::CatmullClark, depth).unwrap_err();
        assert!(
            matches!(e, RulesError::HugeCoordinate { vertex: 6, .. }),
            "{e:?}"
        );
        assert!(
            e.to_string()
                .starts_with("vertex 6 has a coordinate beyond"),
            "{e}"
        );
    }
    // Not a number and infinity: `max_element` ignores NaN, so it needs its own test.
    for (x, bad) in [(f32::NAN, "NaN"), (f32::NEG_INFINITY, "-inf")] {
        let mut m = Mesh::from_soup(&parse_obj(cube).unwrap()).unwrap();
        m.positions_mut()[5].z = x;
        let e = refine_uniform_levels(&m, Scheme::CatmullClark, 1).unwrap_err();
        assert!(
            matches!(e, RulesError::NonFiniteCoordinate { vertex: 5, .. }),
            "{e:?}"
        );
        assert!(
            e.to_string()
                .starts_with("vertex 5 has a coordinate that is not a finite number")
                && e.to_string().contains(bad),
            "{e}"
        );
    }
    // At the bound (every vertex, either sign) the refinement and its limit are finite.
    let mut m = Mesh::from_soup(&parse_obj(cube).unwrap()).unwrap();
    for p in m.positions_mut() {
        *p = (*p * 2.0 - glam::Vec3::ONE) * MAX_COORDINATE;
    }
    let t = crate::tessellate_uniform(&m, Scheme::CatmullClark, 3).unwrap();
    assert!(
        t.positions()
            .iter()
            .chain(t.normals())
            .flatten()
            .all(|x| x.is_finite())
    );
}
