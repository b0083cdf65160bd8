//! Topological and feature statistics of a mesh (what `subdiv info` reports).

use std::collections::BTreeMap;

use crate::UnionFind;
use crate::mesh::Mesh;
use crate::options::SHARPNESS_INFINITE;

/// Counts describing a mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshStats {
    /// Vertices (isolated ones included).
    pub vertices: usize,
    /// Edges.
    pub edges: usize,
    /// Faces (holes included).
    pub faces: usize,
    /// Face size -> number of faces.
    pub face_sizes: BTreeMap<usize, usize>,
    /// Vertex valence -> number of vertices (isolated vertices have valence 0).
    pub valences: BTreeMap<usize, usize>,
    /// Number of boundary loops.
    pub boundary_loops: usize,
    /// Number of boundary edges.
    pub boundary_edges: usize,
    /// Interior edges with finite positive sharpness.
    pub semi_sharp_edges: usize,
    /// Interior edges with infinite sharpness.
    pub infinite_edges: usize,
    /// Largest finite edge sharpness (0 if none).
    pub max_edge_sharpness: f32,
    /// Vertices with positive sharpness.
    pub sharp_vertices: usize,
    /// Faces tagged as holes.
    pub holes: usize,
    /// Vertices without faces.
    pub isolated_vertices: usize,
    /// Connected components (of faces).
    pub components: usize,
    /// Euler characteristic V - E + F (isolated vertices excluded).
    pub euler: i64,
    /// Genus, assuming orientable components: `(2 C - chi - B) / 2`.
    pub genus: i64,
}

impl MeshStats {
    /// Computes the statistics of `mesh`.
    pub fn of(mesh: &Mesh) -> MeshStats {
        let mut face_sizes = BTreeMap::new();
        for f in mesh.faces() {
            *face_sizes.entry(mesh.face_size(f)).or_insert(0) += 1;
        }
        let mut valences = BTreeMap::new();
        let mut isolated = 0;
        for v in mesh.vertices() {
            if mesh.is_isolated(v) {
                isolated += 1;
            }
            *valences.entry(mesh.valence(v)).or_insert(0) += 1;
        }
        // Boundary loops: walk every boundary half-edge loop once.
        let mut seen = vec![false; mesh.num_halfedges()];
        let mut loops = 0;
        let mut boundary_edges = 0;
        for h in 0..mesh.num_halfedges() {
            let h = crate::HalfedgeId(h as u32);
            if !mesh.is_boundary_halfedge(h) || seen[h.idx()] {
                continue;
            }
            loops += 1;
            let mut g = h;
            while !seen[g.idx()] {
                seen[g.idx()] = true;
                boundary_edges += 1;
                g = mesh.next(g);
            }
        }
        let mut semi = 0;
        let mut inf = 0;
        let mut max_s = 0.0f32;
        for e in mesh.edges() {
            if mesh.is_boundary_edge(e) {
                continue;
            }
            let s = mesh.edge_sharpness(e);
            if s >= SHARPNESS_INFINITE {
                inf += 1;
            } else if s > 0.0 {
                semi += 1;
                max_s = max_s.max(s);
            }
        }
        let sharp_vertices = mesh
            .vertices()
            .filter(|&v| mesh.vertex_sharpness(v) > 0.0)
            .count();
        let holes = mesh.faces().filter(|&f| mesh.is_hole(f)).count();
        // Components: union-find over faces through shared edges.
        let mut parent = UnionFind::new(mesh.num_faces());
        for e in mesh.edges() {
            let (a, b) = (mesh.face(e.halfedge(0)), mesh.face(e.halfedge(1)));
            if a.is_some() && b.is_some() {
                parent.union(a.idx(), b.idx());
            }
        }
        let components = (0..mesh.num_faces())
            .filter(|&f| parent.find(f) == f)
            .count();
        let euler = (mesh.num_vertices() - isolated) as i64 - mesh.num_edges() as i64
            + mesh.num_faces() as i64;
        let genus = (2 * components as i64 - euler - loops as i64) / 2;
        MeshStats {
            vertices: mesh.num_vertices(),
            edges: mesh.num_edges(),
            faces: mesh.num_faces(),
            face_sizes,
            valences,
            boundary_loops: loops,
            boundary_edges,
            semi_sharp_edges: semi,
            infinite_edges: inf,
            max_edge_sharpness: max_s,
            sharp_vertices,
            holes,
            isolated_vertices: isolated,
            components,
            euler,
            genus,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse_obj;

    #[test]
    fn torus_and_open_grid() {
        // A 4x4 quad torus: genus 1, closed.
        let mut s = String::new();
        for j in 0..4 {
            for i in 0..4 {
                let (u, v) = (i as f32 * 1.57, j as f32 * 1.57);
                s += &format!(
                    "v {} {} {}\n",
                    (2.0 + v.cos()) * u.cos(),
                    (2.0 + v.cos()) * u.sin(),
                    v.sin()
                );
            }
        }
        for j in 0..4 {
            for i in 0..4 {
                let a = j * 4 + i + 1;
                let b = j * 4 + (i + 1) % 4 + 1;
                let c = ((j + 1) % 4) * 4 + (i + 1) % 4 + 1;
                let d = ((j + 1) % 4) * 4 + i + 1;
                s += &format!("f {a} {b} {c} {d}\n");
            }
        }
        let m = Mesh::from_soup(&parse_obj(&s).unwrap()).unwrap();
        let st = MeshStats::of(&m);
        assert_eq!(
            (st.euler, st.genus, st.boundary_loops, st.components),
            (0, 1, 0, 1)
        );
        assert_eq!(st.valences.get(&4), Some(&16));
        // A crease tag on a diagonal that is not an edge is refused.
        let soup =
            parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nt crease 2/1/0 0 2 1\n")
                .unwrap();
        assert!(Mesh::from_soup(&soup).is_err());
    }

    #[test]
    fn quad_with_isolated_vertex() {
        let m = Mesh::from_soup(
            &parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 9 9 9\nf 1 2 3 4\n").unwrap(),
        )
        .unwrap();
        let st = MeshStats::of(&m);
        assert_eq!(
            (
                st.boundary_loops,
                st.boundary_edges,
                st.isolated_vertices,
                st.genus,
                st.euler
            ),
            (1, 4, 1, 0, 1)
        );
    }
}
