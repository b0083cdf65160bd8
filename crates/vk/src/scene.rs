//! Plain input data for the renderer: mesh, view, shading options, and the
//! CPU-side packing of a mesh into one vertex/index upload.

use glam::{Mat4, Vec3};

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
    /// One scalar per vertex: subdivision depth for [`Shading::Depth`], degree of
    /// interest (any range) for [`Shading::Doi`]. `None` reads as zero.
    pub scalars: Option<&'a [f32]>,
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
        if self.triangles.len() % 3 != 0 {
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

/// An owned mesh, for callers that build geometry on the fly (see
/// [`OwnedMesh::as_render_mesh`]); it is also a [`crate::viewer::FrameSource`]
/// that shows the same geometry every frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OwnedMesh {
    /// See [`RenderMesh::positions`].
    pub positions: Vec<[f32; 3]>,
    /// See [`RenderMesh::normals`].
    pub normals: Vec<[f32; 3]>,
    /// See [`RenderMesh::triangles`].
    pub triangles: Vec<u32>,
    /// See [`RenderMesh::edges`].
    pub edges: Option<Vec<[u32; 2]>>,
    /// See [`RenderMesh::scalars`].
    pub scalars: Option<Vec<f32>>,
    /// See [`RenderMesh::lines`].
    pub lines: Option<Vec<[f32; 3]>>,
}

impl OwnedMesh {
    /// Borrows the mesh for rendering.
    pub fn as_render_mesh(&self) -> RenderMesh<'_> {
        RenderMesh {
            positions: &self.positions,
            normals: &self.normals,
            triangles: &self.triangles,
            edges: self.edges.as_deref(),
            scalars: self.scalars.as_deref(),
            lines: self.lines.as_deref(),
        }
    }
}

/// Camera matrices with Vulkan clip conventions: NDC y points down, depth 0..1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// World to camera (right-handed, camera looks down -z).
    pub view: Mat4,
    /// Camera to clip space (Vulkan conventions, see [`View::perspective`]).
    pub proj: Mat4,
    /// Eye position in world space.
    pub eye: Vec3,
}

impl View {
    /// A right-handed perspective projection for Vulkan: depth 0..1 and y flipped
    /// so that +y in camera space points up in the image.
    pub fn perspective(fov_y_radians: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
        // Guard the preconditions of the glam constructor (it asserts in debug builds).
        let fov = if fov_y_radians.is_finite() {
            fov_y_radians.clamp(1e-3, std::f32::consts::PI - 1e-3)
        } else {
            1.0
        };
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let near = if near.is_finite() && near > 0.0 {
            near
        } else {
            1e-3
        };
        let far = if far.is_finite() && far > near {
            far
        } else {
            near * 1e3
        };
        glam::camera::rh::proj::vulkan::perspective(fov, aspect, near, far)
    }

    /// A view from `eye` towards `target`.
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_radians: f32,
        aspect: f32,
        near: f32,
        far: f32,
    ) -> Self {
        View {
            view: glam::camera::rh::view::look_at_mat4(eye, target, up),
            proj: Self::perspective(fov_y_radians, aspect, near, far),
            eye,
        }
    }

    /// `proj * view`.
    pub fn view_proj(&self) -> Mat4 {
        self.proj * self.view
    }

    /// Unit viewing direction in world space.
    pub fn forward(&self) -> Vec3 {
        let inv = self.view.inverse();
        (-inv.z_axis.truncate()).normalize_or(Vec3::NEG_Z)
    }

    /// World-space direction towards the key light: up-left and behind the viewer.
    pub fn key_light(&self) -> Vec3 {
        let inv = self.view.inverse();
        inv.transform_vector3(Vec3::new(-0.45, 0.6, 0.65))
            .normalize_or(Vec3::Z)
    }

    /// The 12 edges of this view's frustum as 24 line endpoints (for drawing a
    /// frozen culling camera from another one).
    pub fn frustum_lines(&self) -> Vec<[f32; 3]> {
        let inv = self.view_proj().inverse();
        let corner = |x: f32, y: f32, z: f32| inv.project_point3(Vec3::new(x, y, z)).to_array();
        let c = [
            corner(-1.0, -1.0, 0.0),
            corner(1.0, -1.0, 0.0),
            corner(1.0, 1.0, 0.0),
            corner(-1.0, 1.0, 0.0),
            corner(-1.0, -1.0, 1.0),
            corner(1.0, -1.0, 1.0),
            corner(1.0, 1.0, 1.0),
            corner(-1.0, 1.0, 1.0),
        ];
        let edges = [
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 0),
            (4, 5),
            (5, 6),
            (6, 7),
            (7, 4),
            (0, 4),
            (1, 5),
            (2, 6),
            (3, 7),
        ];
        edges.iter().flat_map(|&(a, b)| [c[a], c[b]]).collect()
    }
}

/// An orbiting camera around a target point; produces [`View`]s.
///
/// The viewer and headless renders use the same camera, so a screenshot of the
/// viewer equals a headless render with the same camera and size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// Point the camera looks at.
    pub target: Vec3,
    /// Distance from eye to target.
    pub distance: f32,
    /// Rotation about the world y axis, radians.
    pub yaw: f32,
    /// Elevation, radians (clamped to just under ±90°).
    pub pitch: f32,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Radius of the scene around `target`; sets the near and far planes.
    pub radius: f32,
}

impl OrbitCamera {
    /// A camera that frames the box `lo..hi`, seen from the front-right and above.
    pub fn framing(lo: Vec3, hi: Vec3) -> Self {
        let target = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-6);
        let fov_y = 35f32.to_radians();
        let distance = radius / (fov_y * 0.5).sin() * 1.05;
        OrbitCamera {
            target,
            distance,
            yaw: 0.6,
            pitch: 0.45,
            fov_y,
            radius,
        }
    }

    /// [`OrbitCamera::framing`] for the bounds of `mesh`; a unit box if it is empty.
    pub fn framing_mesh(mesh: &RenderMesh<'_>) -> Self {
        let (lo, hi) = mesh
            .bounds()
            .unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
        Self::framing(lo, hi)
    }

    /// Eye position.
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + self.distance * Vec3::new(cp * sy, sp, cp * cy)
    }

    /// The view for an image of the given aspect ratio (width / height).
    pub fn view(&self, aspect: f32) -> View {
        let near = (self.distance - 2.0 * self.radius)
            .max(self.distance * 1e-3)
            .max(1e-6);
        let far = (self.distance + 2.0 * self.radius).max(near * 2.0);
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        View::look_at(
            self.eye(),
            self.target,
            Vec3::Y,
            self.fov_y,
            aspect,
            near,
            far,
        )
    }

    /// Rotates by a mouse drag of (`dx`, `dy`) radians.
    pub fn rotate(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx;
        let limit = 89f32.to_radians();
        self.pitch = (self.pitch + dy).clamp(-limit, limit);
    }

    /// Multiplies the distance by `factor` (wheel zoom), within sane limits.
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance * factor).clamp(self.radius * 1e-3, self.radius * 1e3);
        }
    }
}

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
}

impl Shading {
    /// All modes with their command-line names.
    pub const ALL: [(Shading, &'static str); 5] = [
        (Shading::Smooth, "smooth"),
        (Shading::Flat, "flat"),
        (Shading::Wire, "wire"),
        (Shading::Depth, "depth"),
        (Shading::Doi, "doi"),
    ];

    /// The command-line name (`smooth`, `flat`, `wire`, `depth`, `doi`).
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

    fn shader_mode(self) -> f32 {
        match self {
            Shading::Depth => 2.0,
            Shading::Doi => 3.0,
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
    /// Draw [`RenderMesh::lines`] (when present).
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
        }
    }
}

/// Bytes per packed vertex: position (3 f32), normal (3 f32), scalar (1 f32).
pub(crate) const VERTEX_STRIDE: u64 = 28;

/// Where the parts of a packed mesh lie in the upload buffer, and their counts.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Layout {
    /// Shared vertices (also used by the edges).
    pub vertices: u64,
    /// Triangle vertices: `vertices` (indexed) or split flat vertices (not indexed).
    pub tri_vertices: u64,
    pub tri_indexed: bool,
    pub tri_indices: u64,
    pub tri_count: u32,
    pub edge_indices: u64,
    pub edge_count: u32,
    pub line_vertices: u64,
    pub line_count: u32,
    pub total: u64,
    /// Heat-map scalar range (min, 1/range).
    pub scalar_min: f32,
    pub scalar_inv_range: f32,
}

fn align(x: u64) -> u64 {
    x.div_ceil(16) * 16
}

fn push_vertex(out: &mut Vec<u8>, p: [f32; 3], n: [f32; 3], s: f32) {
    for v in p.iter().chain(n.iter()).chain(std::iter::once(&s)) {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

fn pad(out: &mut Vec<u8>) {
    out.resize(align(out.len() as u64) as usize, 0);
}

fn count_u32(n: usize, what: &str) -> Result<u32> {
    u32::try_from(n).map_err(|_| VkError::InvalidMesh(format!("too many {what}: {n}")))
}

/// Packs `mesh` for drawing with `options` into one byte array (vertices and
/// u32 indices, 16-byte aligned sections).
pub(crate) fn pack(mesh: &RenderMesh<'_>, options: &RenderOptions) -> Result<(Vec<u8>, Layout)> {
    pack_from(mesh, options, true).map(|(bytes, layout, _)| (bytes, layout))
}

/// [`pack`], optionally leaving out the shared-vertex section at the start
/// (when the destination buffer still holds it): the returned bytes then
/// belong at the returned offset, and the layout is the same as with vertices.
pub(crate) fn pack_from(
    mesh: &RenderMesh<'_>,
    options: &RenderOptions,
    with_vertices: bool,
) -> Result<(Vec<u8>, Layout, u64)> {
    mesh.validate()?;
    let scalar = |i: usize| mesh.scalars.map_or(0.0, |s| s[i]);
    let mut out = Vec::new();
    let mut layout = Layout {
        vertices: 0,
        ..Layout::default()
    };
    let base = if with_vertices {
        for (i, (p, n)) in mesh.positions.iter().zip(mesh.normals).enumerate() {
            push_vertex(&mut out, *p, *n, scalar(i));
        }
        pad(&mut out);
        0
    } else {
        align(mesh.positions.len() as u64 * VERTEX_STRIDE)
    };
    let at = |out: &Vec<u8>| base + out.len() as u64;

    layout.tri_count = count_u32(mesh.triangle_count(), "triangles")?;
    if options.shading == Shading::Flat {
        layout.tri_vertices = at(&out);
        layout.tri_indexed = false;
        for t in mesh.triangles.chunks_exact(3) {
            let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
            let [pa, pb, pc] =
                [mesh.positions[a], mesh.positions[b], mesh.positions[c]].map(Vec3::from_array);
            let mut normal = (pb - pa).cross(pc - pa).normalize_or_zero();
            // Keep the face normal on the side of the vertex normals, so faces of
            // inconsistently wound input still light like the smooth mode.
            let avg = [a, b, c]
                .iter()
                .map(|&i| Vec3::from_array(mesh.normals[i]))
                .sum::<Vec3>();
            if normal.dot(avg) < 0.0 {
                normal = -normal;
            }
            for i in [a, b, c] {
                push_vertex(&mut out, mesh.positions[i], normal.to_array(), scalar(i));
            }
        }
        pad(&mut out);
    } else {
        layout.tri_vertices = layout.vertices;
        layout.tri_indexed = true;
        layout.tri_indices = at(&out);
        for i in mesh.triangles {
            out.extend_from_slice(&i.to_le_bytes());
        }
        pad(&mut out);
    }

    if options.wire_overlay || options.shading == Shading::Wire {
        layout.edge_indices = at(&out);
        let mut count = 0usize;
        match mesh.edges {
            Some(edges) => {
                for e in edges {
                    out.extend_from_slice(&e[0].to_le_bytes());
                    out.extend_from_slice(&e[1].to_le_bytes());
                }
                count = edges.len();
            }
            None => {
                let mut edges: Vec<(u32, u32)> = mesh
                    .triangles
                    .chunks_exact(3)
                    .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
                    .map(|(a, b)| (a.min(b), a.max(b)))
                    .collect();
                edges.sort_unstable();
                edges.dedup();
                for (a, b) in &edges {
                    out.extend_from_slice(&a.to_le_bytes());
                    out.extend_from_slice(&b.to_le_bytes());
                }
                count += edges.len();
            }
        }
        layout.edge_count = count_u32(count, "edges")?;
        pad(&mut out);
    }

    if options.show_lines
        && let Some(lines) = mesh.lines
    {
        layout.line_vertices = at(&out);
        for p in lines {
            push_vertex(&mut out, *p, [0.0; 3], 0.0);
        }
        layout.line_count = count_u32(lines.len() / 2, "lines")?;
        pad(&mut out);
    }

    let (lo, hi) = options.scalar_range.unwrap_or_else(|| {
        mesh.scalars
            .map(|s| {
                s.iter()
                    .filter(|v| v.is_finite())
                    .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| {
                        (lo.min(v), hi.max(v))
                    })
            })
            .filter(|(lo, hi)| lo <= hi)
            .unwrap_or((0.0, 1.0))
    });
    layout.scalar_min = lo;
    layout.scalar_inv_range = if hi > lo { 1.0 / (hi - lo) } else { 0.0 };
    layout.total = at(&out);
    Ok((out, layout, base))
}

/// The 128-byte push-constant block of the triangle shaders.
pub(crate) fn mesh_push_constants(
    view: &View,
    options: &RenderOptions,
    layout: &Layout,
) -> [u8; 128] {
    let mut floats = [0f32; 32];
    floats[..16].copy_from_slice(&view.view_proj().to_cols_array());
    floats[16..19].copy_from_slice(&view.eye.to_array());
    floats[20..23].copy_from_slice(&view.forward().to_array());
    floats[24..27].copy_from_slice(&view.key_light().to_array());
    floats[28] = layout.scalar_min;
    floats[29] = layout.scalar_inv_range;
    floats[30] = options.shading.shader_mode();
    to_bytes(&floats)
}

/// The push-constant block of the line shaders (view-projection and colour).
pub(crate) fn line_push_constants(view: &View, color: [f32; 4]) -> [u8; 128] {
    let mut floats = [0f32; 32];
    floats[..16].copy_from_slice(&view.view_proj().to_cols_array());
    floats[16..20].copy_from_slice(&color);
    to_bytes(&floats)
}

fn to_bytes(floats: &[f32; 32]) -> [u8; 128] {
    let mut out = [0u8; 128];
    for (chunk, f) in out.chunks_exact_mut(4).zip(floats) {
        chunk.copy_from_slice(&f.to_le_bytes());
    }
    out
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

    #[test]
    fn pack_derives_unique_triangle_edges() {
        let quad_p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let quad_n = [[0.0, 0.0, 1.0]; 4];
        let mesh = RenderMesh {
            positions: &quad_p,
            normals: &quad_n,
            triangles: &[0, 1, 2, 0, 2, 3],
            ..Default::default()
        };
        let options = RenderOptions {
            wire_overlay: true,
            ..Default::default()
        };
        let (bytes, layout) = pack(&mesh, &options).unwrap();
        assert_eq!(layout.edge_count, 5);
        assert_eq!(layout.tri_count, 2);
        assert!(layout.total as usize == bytes.len() && bytes.len() % 16 == 0);
        let with_edges = RenderMesh {
            edges: Some(&[[0, 1], [1, 2], [2, 3], [3, 0]]),
            ..mesh
        };
        assert_eq!(pack(&with_edges, &options).unwrap().1.edge_count, 4);
    }

    #[test]
    fn pack_without_vertices_is_the_tail_of_the_full_pack() {
        let mesh = RenderMesh {
            positions: &P,
            normals: &N,
            triangles: &[0, 1, 2],
            lines: Some(&P[..2]),
            ..Default::default()
        };
        for shading in [Shading::Smooth, Shading::Flat] {
            let options = RenderOptions {
                shading,
                wire_overlay: true,
                ..Default::default()
            };
            let (full, layout, zero) = pack_from(&mesh, &options, true).unwrap();
            let (tail, tail_layout, offset) = pack_from(&mesh, &options, false).unwrap();
            assert_eq!(zero, 0);
            assert_eq!(offset, 96); // 3 vertices * 28 bytes, aligned to 16
            assert_eq!(&full[offset as usize..], &tail[..]);
            assert_eq!(format!("{layout:?}"), format!("{tail_layout:?}"));
        }
    }

    #[test]
    fn camera_frames_the_box() {
        let cam = OrbitCamera::framing(Vec3::splat(-1.0), Vec3::splat(1.0));
        let view = cam.view(1.0);
        let centre = view.view_proj().project_point3(Vec3::ZERO);
        assert!(centre.x.abs() < 1e-5 && centre.y.abs() < 1e-5);
        assert!(centre.z > 0.0 && centre.z < 1.0);
        // +y in the world is up in the image, i.e. negative NDC y in Vulkan.
        let top = view.view_proj().project_point3(Vec3::new(0.0, 0.5, 0.0));
        assert!(top.y < 0.0);
    }
}
