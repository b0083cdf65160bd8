//! The mesh the renderer draws: [`RenderMesh`], borrowed buffers.

use glam::Vec3;

use crate::error::{Result, VkError};

/// Borrowed triangle mesh (plus optional edges, scalars and extra lines) to render.
///
/// All coordinates are world space. Nothing here depends on other subdiv crates.
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderMesh<'a> {
    /// Vertex positions.
    pub positions: &'a [[f32; 3]],
    /// Per-vertex normals (same length as `positions`; need not be unit length).
    pub normals: &'a [[f32; 3]],
    /// Triangle corner indices into `positions`, three per triangle.
    pub triangles: &'a [u32],
    /// Edges for wireframe drawing (the polygon edges, not triangle diagonals).
    /// `None`: the triangle edges are used.
    pub edges: Option<&'a [[u32; 2]]>,
    /// One scalar per vertex: subdivision depth for
    /// [`Shading::Depth`](super::Shading::Depth), degree of interest (any range)
    /// for [`Shading::Doi`](super::Shading::Doi). `None` reads as zero.
    pub scalars: Option<&'a [f32]>,
    /// One colour per vertex (linear RGB, 0..1) for [`Shading::Color`](super::Shading::Color);
    /// `None` reads as the grey of [`Shading::Smooth`](super::Shading::Smooth).
    pub colors: Option<&'a [[f32; 3]]>,
    /// Extra line segments drawn on top (e.g. silhouette polylines), as pairs of
    /// endpoints: `lines[2 * i]` to `lines[2 * i + 1]`.
    pub lines: Option<&'a [[f32; 3]]>,
}

impl RenderMesh<'_> {
    /// Checks lengths and index ranges; the renderer calls this before uploading.
    pub fn validate(&self) -> Result<()> {
        let n = self.positions.len();
        if self.normals.len() != n {
            return Err(VkError::InvalidMesh(format!(
                "{} normals for {n} positions",
                self.normals.len()
            )));
        }
        if n > u32::MAX as usize {
            return Err(VkError::InvalidMesh(format!(
                "{n} vertices exceed the u32 index range"
            )));
        }
        if !self.triangles.len().is_multiple_of(3) {
            return Err(VkError::InvalidMesh(format!(
                "triangle index count {} is not a multiple of 3",
                self.triangles.len()
            )));
        }
        if let Some(bad) = self.triangles.iter().find(|&&i| i as usize >= n) {
            return Err(VkError::InvalidMesh(format!(
                "triangle index {bad} out of range ({n} vertices)"
            )));
        }
        if let Some(edges) = self.edges
            && let Some(bad) = edges.iter().flatten().find(|&&i| i as usize >= n)
        {
            return Err(VkError::InvalidMesh(format!(
                "edge index {bad} out of range ({n} vertices)"
            )));
        }
        if let Some(s) = self.scalars
            && s.len() != n
        {
            return Err(VkError::InvalidMesh(format!(
                "{} scalars for {n} positions",
                s.len()
            )));
        }
        if let Some(c) = self.colors
            && c.len() != n
        {
            return Err(VkError::InvalidMesh(format!(
                "{} colours for {n} positions",
                c.len()
            )));
        }
        if let Some(lines) = self.lines
            && lines.len() % 2 != 0
        {
            return Err(VkError::InvalidMesh(format!(
                "{} line endpoints is not an even number",
                lines.len()
            )));
        }
        Ok(())
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len() / 3
    }

    /// Axis-aligned bounds of the positions, `None` for an empty mesh.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut it = self.positions.iter().map(|p| Vec3::from_array(*p));
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    const N: [[f32; 3]; 3] = [[0.0, 0.0, 1.0]; 3];

    #[test]
    fn validate_rejects_bad_meshes() {
        let good = RenderMesh {
            positions: &P,
            normals: &N,
            triangles: &[0, 1, 2],
            ..Default::default()
        };
        assert!(good.validate().is_ok());
        let bad_index = RenderMesh {
            triangles: &[0, 1, 3],
            ..good
        };
        assert!(matches!(bad_index.validate(), Err(VkError::InvalidMesh(_))));
        let bad_count = RenderMesh {
            triangles: &[0, 1],
            ..good
        };
        assert!(bad_count.validate().is_err());
        let bad_normals = RenderMesh {
            normals: &N[..2],
            ..good
        };
        assert!(bad_normals.validate().is_err());
        let bad_scalars = RenderMesh {
            scalars: Some(&[1.0]),
            ..good
        };
        assert!(bad_scalars.validate().is_err());
        let bad_colors = RenderMesh {
            colors: Some(&[[1.0, 0.0, 0.0]]),
            ..good
        };
        assert!(bad_colors.validate().is_err());
        let bad_edges = RenderMesh {
            edges: Some(&[[0, 7]]),
            ..good
        };
        assert!(bad_edges.validate().is_err());
        let bad_lines = RenderMesh {
            lines: Some(&P),
            ..good
        };
        assert!(bad_lines.validate().is_err());
    }
}
