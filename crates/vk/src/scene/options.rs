//! Shading modes and the other options of a render.

/// How triangles are coloured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Shading {
    /// Per-vertex normals, grey material, key light + headlight.
    #[default]
    Smooth,
    /// Face normals (vertices are split per triangle on the CPU).
    Flat,
    /// Hidden-line wireframe only (surfaces fill depth but no colour).
    Wire,
    /// Per-vertex scalar as subdivision depth through a discrete palette.
    Depth,
    /// Per-vertex scalar (degree of interest) as a heat map.
    Doi,
    /// Per-vertex colours ([`RenderMesh::colors`](super::RenderMesh::colors), linear RGB in
    /// 0..1, clamped), lit as [`Shading::Smooth`] lights its grey.
    Color,
}

impl Shading {
    /// All modes with their command-line names.
    pub const ALL: [(Shading, &'static str); 6] = [
        (Shading::Smooth, "smooth"),
        (Shading::Flat, "flat"),
        (Shading::Wire, "wire"),
        (Shading::Depth, "depth"),
        (Shading::Doi, "doi"),
        (Shading::Color, "color"),
    ];

    /// The command-line name (`smooth`, `flat`, `wire`, `depth`, `doi`, `color`).
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(s, _)| *s == self)
            .map_or("smooth", |(_, n)| n)
    }

    /// Parses a command-line name.
    pub fn from_name(name: &str) -> Option<Shading> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(s, _)| *s)
    }

    pub(super) fn shader_mode(self) -> f32 {
        match self {
            Shading::Depth => 2.0,
            Shading::Doi => 3.0,
            Shading::Color => 4.0,
            _ => 0.0,
        }
    }
}

/// Rendering options besides mesh and view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Surface shading.
    pub shading: Shading,
    /// Draw the edges over the shaded surface.
    pub wire_overlay: bool,
    /// Draw [`RenderMesh::lines`](super::RenderMesh::lines) (when present).
    pub show_lines: bool,
    /// Draw the extra lines without depth test (always on top).
    pub lines_on_top: bool,
    /// Background colour, RGBA in 0..1.
    pub background: [f32; 4],
    /// Wireframe colour, RGBA in 0..1.
    pub wire_color: [f32; 4],
    /// Extra-line colour, RGBA in 0..1.
    pub line_color: [f32; 4],
    /// Wireframe line width in pixels (clamped to what the device supports).
    pub wire_width: f32,
    /// Extra-line width in pixels.
    pub line_width: f32,
    /// Scalar range mapped onto the heat map for [`Shading::Doi`]; `None`: the
    /// mesh's own minimum and maximum.
    pub scalar_range: Option<(f32, f32)>,
    /// Draw the colour legend of [`Shading::Depth`] or [`Shading::Doi`] in the top-right
    /// corner (levels and their colours, or the heat map with its range); nothing for the
    /// other shadings.
    pub legend: bool,
    /// Samples per pixel of the colour image (1, 2, 4 or 8): multisampling anti-aliases
    /// silhouettes, creases and lines; each triangle is still shaded once per pixel, at a
    /// point inside it. `None`: [`DEFAULT_SAMPLES`](crate::DEFAULT_SAMPLES) where the device
    /// supports it, else the most it supports below that. A count the device lacks is an
    /// error ([`VkError::Samples`](crate::VkError::Samples)). Depth, normals and scalars
    /// ([`AuxImage`](crate::AuxImage)) are point-sampled at pixel centres whatever the count.
    pub samples: Option<u32>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            shading: Shading::Smooth,
            wire_overlay: false,
            show_lines: true,
            lines_on_top: true,
            background: [1.0, 1.0, 1.0, 1.0],
            wire_color: [0.05, 0.05, 0.08, 1.0],
            line_color: [0.85, 0.1, 0.1, 1.0],
            wire_width: 1.0,
            line_width: 2.0,
            scalar_range: None,
            legend: false,
            samples: None,
        }
    }
}
