//! Test geometry shared by the examples.

use std::f32::consts::TAU;

use subdiv_vk::RenderMesh;

/// A torus with quad edges (no diagonals), a per-quad "depth" and a smooth scalar.
pub struct Torus {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub triangles: Vec<u32>,
    pub edges: Vec<[u32; 2]>,
    pub scalars: Vec<f32>,
    pub silhouette: Vec<[f32; 3]>,
}

pub fn torus(segments: u32, rings: u32) -> Torus {
    let (big, small) = (1.0f32, 0.4f32);
    let mut t = Torus {
        positions: vec![],
        normals: vec![],
        triangles: vec![],
        edges: vec![],
        scalars: vec![],
        silhouette: vec![],
    };
    // Vertices are duplicated per quad so each quad carries its own depth value.
    for i in 0..segments {
        for j in 0..rings {
            let base = t.positions.len() as u32;
            let depth = ((i / 4 + j / 3) % 5) as f32;
            for (di, dj) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
                let u = (i + di) as f32 / segments as f32 * TAU;
                let v = (j + dj) as f32 / rings as f32 * TAU;
                let n = [v.cos() * u.cos(), v.sin(), v.cos() * u.sin()];
                let p = [
                    (big + small * v.cos()) * u.cos(),
                    small * v.sin(),
                    (big + small * v.cos()) * u.sin(),
                ];
                t.positions.push(p);
                t.normals.push(n);
                t.scalars.push(depth);
            }
            t.triangles
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
            t.edges.extend([
                [base, base + 1],
                [base + 1, base + 2],
                [base + 2, base + 3],
                [base + 3, base],
            ]);
        }
    }
    // The outer equator as a stand-in silhouette polyline.
    for i in 0..64 {
        for k in [i, i + 1] {
            let u = k as f32 / 64.0 * TAU;
            t.silhouette
                .push([(big + small) * u.cos(), 0.0, (big + small) * u.sin()]);
        }
    }
    t
}

impl Torus {
    /// The torus's buffers for the renderer.
    pub fn render_mesh(&self) -> RenderMesh<'_> {
        let mut m = RenderMesh::default();
        (m.positions, m.normals) = (&self.positions, &self.normals);
        (m.triangles, m.edges) = (&self.triangles, Some(&self.edges[..]));
        (m.scalars, m.lines) = (Some(&self.scalars[..]), Some(&self.silhouette[..]));
        m
    }
}
