//! Splitting a polygon cage into triangles for Loop subdivision.

use subdiv_mesh::{Mesh, PolygonSoup, VertexId};

use crate::DoiError;

/// Splits every face of `mesh` into triangles: quads along their shorter diagonal, larger
/// polygons as a fan from their first vertex. Triangles stay as they are. Groups, holes, edge
/// and vertex sharpness and the scheme options carry over; the new diagonals are smooth.
///
/// ```
/// use subdiv_doi::triangulate;
/// use subdiv_mesh::{parse_obj, Mesh};
/// let m = Mesh::from_soup(&parse_obj("v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nv 1 2 0\nf 1 2 3 4\nf 4 3 5\n")?)?;
/// let t = triangulate(&m)?;
/// assert_eq!(t.num_faces(), 3);
/// assert!(t.faces().all(|f| t.face_size(f) == 3));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn triangulate(mesh: &Mesh) -> Result<Mesh, DoiError> {
    let mut soup = PolygonSoup {
        positions: mesh.positions().to_vec(),
        options: mesh.options(),
        groups: mesh.groups().to_vec(),
        ..Default::default()
    };
    let mut holes = Vec::new();
    for f in mesh.faces() {
        let v: Vec<i64> = mesh.face_vertices(f).iter().map(|x| x.0 as i64).collect();
        let tris: Vec<[i64; 3]> = match v.len() {
            3 => vec![[v[0], v[1], v[2]]],
            4 => {
                let p = |i: usize| mesh.position(VertexId(v[i] as u32));
                if p(0).distance_squared(p(2)) <= p(1).distance_squared(p(3)) {
                    vec![[v[0], v[1], v[2]], [v[0], v[2], v[3]]]
                } else {
                    vec![[v[0], v[1], v[3]], [v[1], v[2], v[3]]]
                }
            }
            n => (1..n - 1).map(|k| [v[0], v[k], v[k + 1]]).collect(),
        };
        for t in tris {
            soup.push_face(t);
            soup.face_groups.push(mesh.face_group(f));
            holes.push(mesh.is_hole(f));
        }
    }
    let mut out = Mesh::from_soup(&soup)?;
    out.set_holes(holes);
    for e in mesh.edges() {
        let s = mesh.edge_sharpness(e);
        if s > 0.0 && !mesh.is_boundary_edge(e) {
            let [a, b] = mesh.edge_vertices(e);
            if let Some(h) = out.find_halfedge(a, b) {
                out.set_edge_sharpness(h.edge(), s);
            }
        }
    }
    for v in mesh.vertices() {
        let s = mesh.vertex_sharpness(v);
        if s > out.vertex_sharpness(v) {
            out.set_vertex_sharpness(v, s);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::parse_obj;

    #[test]
    fn keeps_creases_groups_and_area() {
        let m = Mesh::from_soup(
            &parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\ng a\nf 1 2 3 4\ng b\nf 2 5 6 3\nt crease 2/1/0 1 2 2.5\n")
                .unwrap(),
        )
        .unwrap();
        let t = triangulate(&m).unwrap();
        assert_eq!(t.num_faces(), 4);
        assert_eq!(t.groups(), &["a".to_string(), "b".to_string()]);
        assert_eq!(t.face_groups(), &[0, 0, 1, 1]);
        let e = t.find_halfedge(VertexId(1), VertexId(2)).unwrap().edge();
        assert_eq!(t.edge_sharpness(e), 2.5);
        let area: f32 = t
            .faces()
            .map(|f| {
                let v = t.face_vertices(f);
                (t.position(v[1]) - t.position(v[0]))
                    .cross(t.position(v[2]) - t.position(v[0]))
                    .length()
                    / 2.0
            })
            .sum();
        assert!((area - 2.0).abs() < 1e-6);
        // A hexagon becomes a fan of four.
        let hex = Mesh::from_soup(
            &parse_obj(
                "v 2 0 0\nv 1 2 0\nv -1 2 0\nv -2 0 0\nv -1 -2 0\nv 1 -2 0\nf 1 2 3 4 5 6\n",
            )
            .unwrap(),
        )
        .unwrap();
        assert_eq!(triangulate(&hex).unwrap().num_faces(), 4);
    }
}
