//! Unit tests of the red-green closure.

use glam::Vec3;
use subdiv_mesh::{FaceId, Mesh, PolygonSoup, VertexId};

use super::*;
use crate::RedGreenError;

/// A regular triangle strip grid of `n x n` quads cut into triangles, in the plane z = 0.
fn grid(n: u32) -> Mesh {
    let g = subdiv_test_support::height_grid(n, true, 0.0, |_, _| 0.0);
    let p = g.positions.into_iter().map(Vec3::from).collect();
    Mesh::from_soup(&PolygonSoup::from_faces(p, &g.faces)).unwrap()
}

/// Midpoints for every split edge, appended after the existing vertices.
fn midpoints(mesh: &Mesh, c: &Closure) -> (Vec<VertexId>, Vec<Vec3>) {
    let mut pos = mesh.positions().to_vec();
    let mut mid = vec![VertexId::NONE; mesh.num_edges()];
    for e in mesh.edges() {
        if c.split_edge[e.idx()] {
            let [a, b] = mesh.edge_vertices(e);
            mid[e.idx()] = VertexId(pos.len() as u32);
            pos.push((mesh.position(a) + mesh.position(b)) * 0.5);
        }
    }
    (mid, pos)
}

fn step(mesh: &Mesh, state: &GreenState, sel: &[bool]) -> (Mesh, GreenState, Closure) {
    let c = close(mesh, state, sel).unwrap();
    let (mid, pos) = midpoints(mesh, &c);
    let a = assemble(mesh, state, &c, &mid, &pos).unwrap();
    let m = Mesh::from_soup(&PolygonSoup::from_faces(pos, &a.triangles)).unwrap();
    (m, a.state, c)
}

fn boundary_edges(m: &Mesh) -> usize {
    m.edges().filter(|&e| m.is_boundary_edge(e)).count()
}

#[test]
fn one_two_three_split_closures() {
    let mesh = grid(3);
    let area: f32 = 9.0;
    // Select a single interior triangle: its three neighbours each get one split edge.
    let sel: Vec<bool> = mesh.faces().map(|f| f.0 == 8).collect();
    let (m, st, c) = step(&mesh, &GreenState::new(mesh.num_faces()), &sel);
    assert_eq!(c.red_face.iter().filter(|&&r| r).count(), 1);
    assert_eq!(m.num_faces(), 18 - 1 + 4 + 3);
    assert_eq!(st.families.len(), 3);
    assert!(st.families.iter().all(|g| g.num_splits() == 1));
    assert_eq!(
        boundary_edges(&m),
        12,
        "conforming: only the outer boundary"
    );
    let total: f32 = m.faces().map(|f| tri_area(&m, f)).sum();
    assert!((total - area).abs() < 1e-4);
    // Face with two split edges: select two triangles around one non-selected one.
    let p = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::new(0.5, 1.0, 0.0),
        Vec3::new(1.5, 1.0, 0.0),
        Vec3::new(-0.5, 1.0, 0.0),
    ];
    let mesh = Mesh::from_soup(&PolygonSoup::from_faces(
        p,
        &[[0u32, 1, 2], [1, 3, 2], [0, 2, 4]],
    ))
    .unwrap();
    let (m, st, _) = step(&mesh, &GreenState::new(3), &[false, true, true]);
    assert_eq!(m.num_faces(), 4 + 4 + 3);
    assert_eq!(st.families.len(), 1);
    assert_eq!(st.families[0].num_splits(), 2);
    assert_eq!(
        boundary_edges(&m),
        9,
        "the five outer edges, four of them halved"
    );
}

fn tri_area(m: &Mesh, f: FaceId) -> f32 {
    let v = m.face_vertices(f);
    let (a, b, c) = (m.position(v[0]), m.position(v[1]), m.position(v[2]));
    (b - a).cross(c - a).length() * 0.5
}

#[test]
fn three_split_edges_promote_to_red() {
    let mesh = grid(3);
    // Neighbours of face 8 on all three sides: faces sharing an edge with it.
    let h0 = mesh.face_halfedge(FaceId(8));
    let nb: Vec<u32> = [h0, mesh.next(h0), mesh.prev(h0)]
        .iter()
        .map(|h| mesh.face(h.twin()).0)
        .collect();
    let sel: Vec<bool> = mesh.faces().map(|f| nb.contains(&f.0)).collect();
    let c = close(&mesh, &GreenState::new(mesh.num_faces()), &sel).unwrap();
    assert!(c.red_face[8], "a face with three split edges is refined");
    assert_eq!(c.red_face.iter().filter(|&&r| r).count(), 4);
}

#[test]
fn green_faces_merge_back_and_never_nest() {
    let mut mesh = grid(4);
    let mut state = GreenState::new(mesh.num_faces());
    // Refine around a point that moves across the grid; greens next to it must merge.
    let min_angle = |m: &Mesh| {
        let mut worst = 180.0f32;
        for f in m.faces() {
            let v = m.face_vertices(f);
            for k in 0..3 {
                let a = m.position(v[k]);
                let b = m.position(v[(k + 1) % 3]);
                let c = m.position(v[(k + 2) % 3]);
                worst = worst.min((b - a).angle_between(c - a).to_degrees());
            }
        }
        worst
    };
    for s in 0..4 {
        let target = Vec3::new(1.3 + 0.4 * s as f32, 1.7, 0.0);
        let sel: Vec<bool> = mesh
            .faces()
            .map(|f| mesh.face_centroid(f).distance(target) < 0.9)
            .collect();
        let (m, st, c) = step(&mesh, &state, &sel);
        if s > 0 {
            assert!(c.merged.iter().any(|&x| x), "step {s} merges a family back");
        }
        // Conforming: every boundary edge lies on the grid's outer square.
        for e in m.edges().filter(|&e| m.is_boundary_edge(e)) {
            let [a, b] = m.edge_vertices(e);
            let (a, b) = (m.position(a), m.position(b));
            let on = |x: f32| x == 0.0 || x == 4.0;
            assert!(
                (on(a.x) && a.x == b.x) || (on(a.y) && a.y == b.y),
                "step {s}: crack at {a} {b}"
            );
        }
        // Every green face's parent is a real triangle of the mesh's surface: no nesting,
        // so no face is thinner than half the original angles split twice.
        assert!(min_angle(&m) > 10.0, "step {s}: {}", min_angle(&m));
        for g in &st.families {
            assert!(g.num_splits() == 1 || g.num_splits() == 2);
        }
        mesh = m;
        state = st;
    }
}

#[test]
fn bad_input() {
    let mesh = grid(1);
    assert!(matches!(
        close(&mesh, &GreenState::new(2), &[true]),
        Err(RedGreenError::LengthMismatch { want: 2, .. })
    ));
    let quad = Mesh::from_soup(&PolygonSoup::from_faces(
        vec![Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y],
        &[[0u32, 1, 2, 3]],
    ))
    .unwrap();
    let e = close(&quad, &GreenState::new(1), &[true]).unwrap_err();
    assert_eq!(
        e,
        RedGreenError::Mesh(subdiv_mesh::MeshError::NotTriangles { face: 0, size: 4 })
    );
    assert!(e.to_string().contains("face 0 has 4 vertices"));
    let c = close(&mesh, &GreenState::new(2), &[true, false]).unwrap();
    let mid = vec![VertexId::NONE; mesh.num_edges()];
    assert!(matches!(
        assemble(&mesh, &GreenState::new(2), &c, &mid, mesh.positions()),
        Err(RedGreenError::BadMidpoint { .. })
    ));
    let bad = GreenState {
        family_of_face: vec![0, NO_FAMILY],
        families: vec![],
    };
    assert!(matches!(
        close(&mesh, &bad, &[false, false]),
        Err(RedGreenError::FamilyOutOfRange {
            face: 0,
            family: 0,
            ..
        })
    ));
}

#[test]
fn balance_refuses_green_bisections_of_a_small_angle() {
    // A fat triangle 0 between two thin ones (2.8 × 0.15, as the teapot's lip strips): thin
    // triangle 1 shares its short edge with 0, thin triangle 2 its long edge.
    let p = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.15, 0.0, 0.0),
        Vec3::new(0.075, -0.3, 0.0),
        Vec3::new(0.075, 2.8, 0.0),
        Vec3::new(1.0, -0.2, 0.0),
    ];
    let faces = [[0u32, 2, 1], [0, 1, 3], [2, 4, 1]];
    let mesh = Mesh::from_soup(&PolygonSoup::from_faces(p, &faces)).unwrap();
    let state = GreenState::new(3);
    let angle = |f: usize| {
        let v = faces[f].map(|i| mesh.position(VertexId(i)));
        smallest_angle(v[0], v[1], v[2])
    };
    let cage = (0..3).map(angle).fold(f32::MAX, f32::min);
    assert!(
        (cage.to_degrees() - 3.07).abs() < 0.05,
        "{}",
        cage.to_degrees()
    );
    // Refining face 0: the plain closure bisects face 1's short edge, which halves its 3°
    // angle; balance refines it red instead. Face 2 has no split edge.
    let sel = [true, false, false];
    let c = close(&mesh, &state, &sel).unwrap();
    assert_eq!(c.red_face, vec![true, false, false]);
    let (grown, c) = balance(&mesh, &state, &[0; 3], &sel, cage).unwrap();
    assert_eq!(grown, vec![true, true, false]);
    assert_eq!(c.red_face, vec![true, true, false]);
    // Without the bound (0) the green bisection stays.
    let (grown, _) = balance(&mesh, &state, &[0; 3], &sel, 0.0).unwrap();
    assert_eq!(grown, vec![true, false, false]);
    // Refining face 1 splits face 0's short edge only and face 2 is untouched.
    let (grown, _) = balance(&mesh, &state, &[0; 3], &[false, true, false], cage).unwrap();
    assert_eq!(grown, vec![false, true, false]);
}
