//! Tests of mesh construction: topology, ring order, boundary handling, tags and every
//! validation error.

use super::*;
use crate::options::{BoundaryInterpolation, SHARPNESS_INFINITE};
use crate::soup::{CornerTag, CreaseTag, HoleTag};

fn soup(s: subdiv_test_support::Soup) -> PolygonSoup {
    PolygonSoup::from_faces(s.positions.into_iter().map(Vec3::from).collect(), &s.faces)
}

fn grid(n: u32) -> PolygonSoup {
    soup(subdiv_test_support::height_grid(n, false, 0.0, |_, _| 0.0))
}

fn cube() -> PolygonSoup {
    soup(subdiv_test_support::cube())
}

#[test]
fn cube_topology() {
    let m = Mesh::from_soup(&cube()).unwrap();
    assert_eq!((m.num_vertices(), m.num_edges(), m.num_faces()), (8, 12, 6));
    for v in m.vertices() {
        assert_eq!(m.valence(v), 3);
        assert!(!m.is_boundary_vertex(v));
        // Ring order is counter-clockwise: consecutive outgoing edges share a face.
        let hs: Vec<_> = m.outgoing(v).collect();
        for (i, &h) in hs.iter().enumerate() {
            let n = hs[(i + 1) % hs.len()];
            assert_eq!(m.prev(h).twin(), n);
            assert_eq!(m.from(h), v);
        }
    }
    for e in m.edges() {
        assert!(!m.is_boundary_edge(e));
        assert_eq!(m.edge_sharpness(e), 0.0);
    }
}

#[test]
fn grid_boundary_ring_order() {
    let m = Mesh::from_soup(&grid(2)).unwrap();
    assert_eq!((m.num_vertices(), m.num_edges(), m.num_faces()), (9, 12, 4));
    // Corner vertex 0: two edges, one face; leading edge first, boundary half-edge last.
    let hs: Vec<_> = m.outgoing(VertexId(0)).collect();
    assert_eq!(hs.len(), 2);
    assert!(m.is_boundary_halfedge(hs[0].twin()));
    assert!(m.is_boundary_halfedge(hs[1]));
    // Middle of an edge (vertex 1): three edges, two faces.
    let hs: Vec<_> = m.outgoing(VertexId(1)).collect();
    assert_eq!(hs.len(), 3);
    assert!(m.face(hs[0]).is_some() && m.face(hs[1]).is_some() && !m.face(hs[2]).is_some());
    // Centre vertex: valence 4, interior.
    assert_eq!(m.valence(VertexId(4)), 4);
    assert!(!m.is_boundary_vertex(VertexId(4)));
    let boundary = m.edges().filter(|&e| m.is_boundary_edge(e)).count();
    assert_eq!(boundary, 8);
    for e in m.edges() {
        let want = if m.is_boundary_edge(e) {
            SHARPNESS_INFINITE
        } else {
            0.0
        };
        assert_eq!(m.edge_sharpness(e), want);
    }
    // Boundary loop closes.
    let b0 = m.outgoing(VertexId(0)).last().unwrap();
    let mut h = b0;
    let mut n = 0;
    loop {
        h = m.next(h);
        n += 1;
        assert!(m.is_boundary_halfedge(h));
        if h == b0 || n > 100 {
            break;
        }
    }
    assert_eq!(n, 8);
}

#[test]
fn edge_and_corner_sharpens_corners() {
    let mut s = grid(2);
    s.options.boundary = BoundaryInterpolation::EdgeAndCorner;
    let m = Mesh::from_soup(&s).unwrap();
    for v in [0, 2, 6, 8] {
        assert_eq!(m.vertex_sharpness(VertexId(v)), SHARPNESS_INFINITE);
    }
    assert_eq!(m.vertex_sharpness(VertexId(1)), 0.0);
}

/// `interpolateboundary none` (OpenSubdiv's rule): the faces at a vertex with a boundary edge
/// not tagged infinitely sharp are holes; a vertex whose boundary edges are all tagged
/// infinitely sharp hides nothing, whatever its other boundary vertices do.
#[test]
fn boundary_none_hides_faces_at_unsharpened_boundary_edges() {
    let hidden = |s: &PolygonSoup| -> Vec<bool> { Mesh::from_soup(s).unwrap().holes().to_vec() };
    let mut s = grid(3);
    s.options.boundary = BoundaryInterpolation::None;
    // Every boundary vertex has an untagged boundary edge: only the middle face is drawn.
    let plain = hidden(&s);
    assert_eq!(plain.iter().filter(|&&h| !h).count(), 1);
    assert!(!plain[4]);
    // Every boundary edge tagged infinitely sharp: nothing is hidden.
    let ring: Vec<(i64, i64)> = (0..3)
        .flat_map(|i| {
            [
                (i, i + 1),
                (12 + i, 13 + i),
                (4 * i, 4 * i + 4),
                (4 * i + 3, 4 * i + 7),
            ]
        })
        .collect();
    assert_eq!(ring.len(), 12);
    let tag = |s: &mut PolygonSoup, edges: &[(i64, i64)], sharpness: f32| {
        for &(a, b) in edges {
            s.creases.push(CreaseTag {
                a,
                b,
                sharpness,
                line: None,
            });
        }
    };
    let mut sharp = s.clone();
    tag(&mut sharp, &ring, SHARPNESS_INFINITE);
    assert!(hidden(&sharp).iter().all(|&h| !h));
    // One boundary edge semi-sharp (0-1): the faces at vertices 0 and 1 are hidden.
    let mut one = s.clone();
    tag(&mut one, &ring[1..], SHARPNESS_INFINITE);
    tag(&mut one, &ring[..1], 9.5);
    let h = hidden(&one);
    assert_eq!(
        h,
        [true, true, false, false, false, false, false, false, false]
    );
    // Edge-only keeps every face; a tagged hole stays a hole.
    let mut edge_only = grid(3);
    edge_only.holes.push(HoleTag { f: 8, line: None });
    let h = hidden(&edge_only);
    assert!(h[8] && h.iter().filter(|&&x| x).count() == 1);
}

#[test]
fn tags_apply() {
    let mut s = cube();
    s.creases.push(CreaseTag {
        a: 0,
        b: 2,
        sharpness: 2.5,
        line: Some(3),
    });
    s.corners.push(CornerTag {
        v: 7,
        sharpness: 1.0,
        line: None,
    });
    s.holes.push(HoleTag { f: 1, line: None });
    let m = Mesh::from_soup(&s).unwrap();
    let h = m.find_halfedge(VertexId(2), VertexId(0)).unwrap();
    assert_eq!(m.edge_sharpness(h.edge()), 2.5);
    assert_eq!(m.vertex_sharpness(VertexId(7)), 1.0);
    assert!(m.is_hole(FaceId(1)) && !m.is_hole(FaceId(0)));
}

fn err(s: &PolygonSoup) -> MeshError {
    Mesh::from_soup(s).unwrap_err()
}

#[test]
fn error_index_out_of_range() {
    let s = PolygonSoup::from_faces(vec![Vec3::ZERO; 3], &[vec![0, 1, 3]]);
    assert!(matches!(
        err(&s),
        MeshError::IndexOutOfRange {
            face: 0,
            index: 3,
            count: 3,
            ..
        }
    ));
    let mut s = PolygonSoup {
        positions: vec![Vec3::ZERO; 3],
        ..Default::default()
    };
    s.push_face([0, 1, -1]);
    assert!(matches!(
        err(&s),
        MeshError::IndexOutOfRange { index: -1, .. }
    ));
}

#[test]
fn error_small_face() {
    let s = PolygonSoup::from_faces(vec![Vec3::ZERO; 3], &[vec![0, 1]]);
    assert!(matches!(
        err(&s),
        MeshError::FaceTooSmall {
            face: 0,
            len: 2,
            ..
        }
    ));
}

#[test]
fn error_repeated_vertex() {
    let s = PolygonSoup::from_faces(vec![Vec3::ZERO; 3], &[vec![0, 1, 2, 1]]);
    assert!(matches!(
        err(&s),
        MeshError::RepeatedVertex {
            face: 0,
            vertex: 1,
            ..
        }
    ));
}

#[test]
fn error_non_finite() {
    let mut s = cube();
    s.positions[5].y = f32::NAN;
    s.vertex_lines = (1..=8).collect();
    let e = err(&s);
    assert!(
        matches!(
            e,
            MeshError::NonFinite {
                vertex: 5,
                line: Some(6),
                ..
            }
        ),
        "{e:?}"
    );
    s.positions[5].y = f32::INFINITY;
    assert!(matches!(err(&s), MeshError::NonFinite { vertex: 5, .. }));
}

#[test]
fn error_non_manifold_edge() {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE];
    let s = PolygonSoup::from_faces(p, &[vec![0, 1, 2], vec![1, 0, 3], vec![0, 1, 4]]);
    let e = err(&s);
    assert!(
        matches!(e, MeshError::NonManifoldEdge { a: 0, b: 1, .. }),
        "{e:?}"
    );
}

#[test]
fn error_non_manifold_vertex() {
    // Two triangles touching only at vertex 0 (a bow-tie).
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, -Vec3::X, -Vec3::Y];
    let s = PolygonSoup::from_faces(p, &[vec![0, 1, 2], vec![0, 3, 4]]);
    assert!(matches!(
        err(&s),
        MeshError::NonManifoldVertex { vertex: 0, .. }
    ));
    // Two closed cones sharing their apex: no boundary at the apex, two fans.
    let mut p = vec![Vec3::ZERO];
    let mut faces = Vec::new();
    for (k, z) in [(0u32, 1.0f32), (1, -1.0)] {
        let base = 1 + k * 3;
        for i in 0..3 {
            let a = i as f32 * 2.1;
            p.push(Vec3::new(a.cos(), a.sin(), z));
        }
        faces.push(vec![0, base, base + 1]);
        faces.push(vec![0, base + 1, base + 2]);
        faces.push(vec![0, base + 2, base]);
        faces.push(vec![base, base + 2, base + 1]);
    }
    let s = PolygonSoup::from_faces(p, &faces);
    assert!(matches!(
        err(&s),
        MeshError::NonManifoldVertex { vertex: 0, .. }
    ));
}

#[test]
fn error_orientation() {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE];
    let s = PolygonSoup::from_faces(p, &[vec![0, 1, 2], vec![0, 1, 3]]);
    assert!(matches!(
        err(&s),
        MeshError::InconsistentOrientation {
            a: 0,
            b: 1,
            face: 1,
            other: 0,
            ..
        }
    ));
}

#[test]
fn error_tags() {
    let mut s = cube();
    s.creases.push(CreaseTag {
        a: 0,
        b: 7,
        sharpness: 1.0,
        line: Some(20),
    });
    assert!(matches!(
        err(&s),
        MeshError::TagMissingEdge {
            a: 0,
            b: 7,
            line: Some(20)
        }
    ));
    let mut s = cube();
    s.creases.push(CreaseTag {
        a: 0,
        b: 70,
        sharpness: 1.0,
        line: None,
    });
    assert!(matches!(
        err(&s),
        MeshError::TagMissingVertex { vertex: 70, .. }
    ));
    let mut s = cube();
    s.corners.push(CornerTag {
        v: 9,
        sharpness: 1.0,
        line: None,
    });
    assert!(matches!(
        err(&s),
        MeshError::TagMissingVertex {
            tag: "corner",
            vertex: 9,
            ..
        }
    ));
    let mut s = cube();
    s.holes.push(HoleTag { f: 6, line: None });
    assert!(matches!(err(&s), MeshError::TagMissingFace { face: 6, .. }));
    let mut s = cube();
    s.creases.push(CreaseTag {
        a: 0,
        b: 2,
        sharpness: f32::NAN,
        line: None,
    });
    assert!(matches!(err(&s), MeshError::BadSharpness { .. }));
    let mut s = cube();
    s.corners.push(CornerTag {
        v: 0,
        sharpness: -1.0,
        line: None,
    });
    assert!(matches!(err(&s), MeshError::BadSharpness { .. }));
}

#[test]
fn error_empty() {
    let s = PolygonSoup {
        positions: vec![Vec3::ZERO],
        ..Default::default()
    };
    assert_eq!(err(&s), MeshError::Empty);
}

#[test]
fn high_valence_fan() {
    // A disk with a valence-360 centre.
    let n = 360u32;
    let mut p = vec![Vec3::ZERO];
    for i in 0..n {
        let a = i as f32 / n as f32 * std::f32::consts::TAU;
        p.push(Vec3::new(a.cos(), a.sin(), 0.0));
    }
    let faces: Vec<Vec<u32>> = (0..n).map(|i| vec![0, 1 + i, 1 + (i + 1) % n]).collect();
    let m = Mesh::from_soup(&PolygonSoup::from_faces(p, &faces)).unwrap();
    assert_eq!(m.valence(VertexId(0)), 360);
    assert_eq!(m.max_valence(), 360);
}

#[test]
fn same_topology_ignores_positions_only() {
    let a = Mesh::from_soup(&cube()).unwrap();
    let mut moved = a.clone();
    moved.positions_mut()[3] += Vec3::new(0.5, -0.25, 1.0);
    assert!(a.same_topology(&moved));
    // Sharper, holed or another mesh: not the same.
    let mut sharp = a.clone();
    sharp.set_edge_sharpness(EdgeId(2), 1.5);
    assert!(!a.same_topology(&sharp));
    let mut holed = a.clone();
    holed.set_holes(vec![false, true, false, false, false, false]);
    assert!(!a.same_topology(&holed));
    let mut flipped = cube();
    flipped.face_indices[..4].reverse();
    flipped.face_indices[4..8].reverse();
    flipped.face_indices[8..]
        .chunks_mut(4)
        .for_each(<[i64]>::reverse);
    let other = Mesh::from_soup(&flipped).unwrap();
    assert!(!a.same_topology(&other));
    assert!(!a.same_topology(&Mesh::from_soup(&grid(2)).unwrap()));
}
