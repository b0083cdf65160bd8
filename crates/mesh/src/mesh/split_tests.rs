//! Building a mesh after [`PolygonSoup::split_nonmanifold_vertices`].

use super::*;

#[test]
fn split_bowtie_and_cones() {
    let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, -Vec3::X, -Vec3::Y];
    let mut s = PolygonSoup::from_faces(p, &[vec![0, 1, 2], vec![0, 3, 4]]);
    s.corners.push(crate::soup::CornerTag {
        v: 0,
        sharpness: 2.0,
        line: None,
    });
    let created = s.split_nonmanifold_vertices();
    assert_eq!(created, vec![(0, 5)]);
    let m = Mesh::from_soup(&s).unwrap();
    assert_eq!(m.num_vertices(), 6);
    assert_eq!(m.position(VertexId(5)), Vec3::ZERO);
    assert_eq!(m.vertex_sharpness(VertexId(5)), 2.0);
    assert_eq!(m.face_vertices(FaceId(1))[0], VertexId(5));
    // A manifold soup is left alone.
    let mut s = PolygonSoup::from_faces(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[vec![0, 1, 2]]);
    assert!(s.split_nonmanifold_vertices().is_empty());
}
