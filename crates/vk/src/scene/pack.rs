//! CPU-side packing of a mesh into one vertex/index upload, and the
//! push-constant blocks of the shaders.

use glam::Vec3;

use super::{RenderMesh, RenderOptions, Shading, View};
use crate::error::{Result, VkError};
use crate::overlay::Overlay;

/// Bytes per packed vertex: position (3 f32), normal (3 f32), scalar (1 f32).
pub(crate) const VERTEX_STRIDE: u64 = 28;

/// Bytes per colour of the triangles' second vertex stream (3 f32).
pub(crate) const COLOR_STRIDE: u64 = 12;

// Where no colours are drawn the colour stream reads the vertex section: no further than it.
const _: () = assert!(COLOR_STRIDE <= VERTEX_STRIDE);

/// The colour of a vertex without one under [`Shading::Color`]: the grey of
/// [`Shading::Smooth`].
const GREY: [f32; 3] = [0.8; 3];

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
    /// The triangles' second vertex stream, one colour (3 f32) per vertex: the colour section
    /// with [`Shading::Color`]; otherwise `tri_vertices` (the shaders read no colour then, and
    /// those bytes are at least as many as the stream would read).
    pub tri_colors: u64,
    pub edge_indices: u64,
    pub edge_count: u32,
    pub line_vertices: u64,
    pub line_count: u32,
    /// Overlay rectangles as triangles: position (pixels), colour in the normal slot, alpha
    /// in the scalar slot; six vertices per rectangle.
    pub overlay_vertices: u64,
    pub overlay_vertex_count: u32,
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
pub(crate) fn pack(
    mesh: &RenderMesh<'_>,
    options: &RenderOptions,
    overlay: &Overlay,
) -> Result<(Vec<u8>, Layout)> {
    pack_from(mesh, options, overlay, true).map(|(bytes, layout, _)| (bytes, layout))
}

/// [`pack`], optionally leaving out the shared-vertex section at the start
/// (when the destination buffer still holds it): the returned bytes then
/// belong at the returned offset, and the layout is the same as with vertices.
pub(crate) fn pack_from(
    mesh: &RenderMesh<'_>,
    options: &RenderOptions,
    overlay: &Overlay,
    with_vertices: bool,
) -> Result<(Vec<u8>, Layout, u64)> {
    mesh.validate()?;
    // The common sections' size up front: no reallocation (and no page faults) while packing.
    let mut out = Vec::with_capacity(
        with_vertices as usize * (mesh.positions.len() * VERTEX_STRIDE as usize + 16)
            + mesh.triangles.len() * 4
            + 64,
    );
    let mut layout = Layout {
        vertices: 0,
        ..Layout::default()
    };
    let base = if with_vertices {
        for (i, (p, n)) in mesh.positions.iter().zip(mesh.normals).enumerate() {
            push_vertex(&mut out, *p, *n, scalar(mesh, i));
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
        push_flat_triangles(&mut out, mesh);
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
    layout.tri_colors = layout.tri_vertices;
    if options.shading == Shading::Color {
        layout.tri_colors = at(&out);
        for i in 0..mesh.positions.len() {
            let c = mesh.colors.map_or(GREY, |c| c[i]);
            for v in c {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        pad(&mut out);
    }

    if options.wire_overlay || options.shading == Shading::Wire {
        layout.edge_indices = at(&out);
        let count = push_edges(&mut out, mesh);
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

    if !overlay.is_empty() {
        layout.overlay_vertices = at(&out);
        for r in &overlay.rects {
            let [x0, y0] = r.min;
            let [x1, y1] = r.max;
            let [red, green, blue, alpha] = r.color;
            for (x, y) in [(x0, y0), (x1, y0), (x1, y1), (x0, y0), (x1, y1), (x0, y1)] {
                push_vertex(&mut out, [x, y, 0.0], [red, green, blue], alpha);
            }
        }
        layout.overlay_vertex_count = count_u32(overlay.rects.len() * 6, "overlay rectangles")?;
        pad(&mut out);
    }

    let (lo, hi) = scalar_range(mesh, options);
    layout.scalar_min = lo;
    layout.scalar_inv_range = if hi > lo { 1.0 / (hi - lo) } else { 0.0 };
    layout.total = at(&out);
    Ok((out, layout, base))
}

/// The scalar of vertex `i`; zero without scalars.
fn scalar(mesh: &RenderMesh<'_>, i: usize) -> f32 {
    mesh.scalars.map_or(0.0, |s| s[i])
}

/// The packed shared vertices `range` of `mesh` (the bytes of [`pack`]'s vertex section at
/// offset `range.start * VERTEX_STRIDE`), into `out` (cleared first).
pub(crate) fn pack_vertices(
    mesh: &RenderMesh<'_>,
    range: std::ops::Range<usize>,
    out: &mut Vec<u8>,
) {
    out.clear();
    out.reserve(range.len() * VERTEX_STRIDE as usize);
    for i in range {
        push_vertex(out, mesh.positions[i], mesh.normals[i], scalar(mesh, i));
    }
}

/// Appends three split vertices per triangle, each carrying the face normal.
fn push_flat_triangles(out: &mut Vec<u8>, mesh: &RenderMesh<'_>) {
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
            push_vertex(out, mesh.positions[i], normal.to_array(), scalar(mesh, i));
        }
    }
}

/// Appends the edge index pairs (the mesh's own edges, else the unique
/// triangle edges) and returns how many edges were written.
fn push_edges(out: &mut Vec<u8>, mesh: &RenderMesh<'_>) -> usize {
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
    count
}

/// The heat-map range: `options.scalar_range`, else the finite scalars' own
/// minimum and maximum, else 0..1.
pub(crate) fn scalar_range(mesh: &RenderMesh<'_>, options: &RenderOptions) -> (f32, f32) {
    options.scalar_range.unwrap_or_else(|| {
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
    })
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

/// The push-constant block of the overlay shaders: `2 / size` per axis after the (unused)
/// matrix.
pub(crate) fn overlay_push_constants(size: [u32; 2]) -> [u8; 128] {
    let mut floats = [0f32; 32];
    floats[16] = 2.0 / size[0].max(1) as f32;
    floats[17] = 2.0 / size[1].max(1) as f32;
    to_bytes(&floats)
}

fn to_bytes(floats: &[f32; 32]) -> [u8; 128] {
    let mut out = [0u8; 128];
    for (chunk, f) in out.chunks_exact_mut(4).zip(floats) {
        chunk.copy_from_slice(&f.to_le_bytes());
    }
    out
}

/// Whether `ranges` (in any order) cover every index of `want`; an empty `want` is covered.
pub(crate) fn covers(ranges: &[std::ops::Range<u32>], want: std::ops::Range<u32>) -> bool {
    let mut inside: Vec<&std::ops::Range<u32>> = ranges
        .iter()
        .filter(|r| r.end > want.start && r.start < want.end)
        .collect();
    inside.sort_unstable_by_key(|r| r.start);
    let mut next = want.start;
    for r in inside {
        if r.start > next {
            break;
        }
        next = next.max(r.end);
    }
    next >= want.end
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    const N: [[f32; 3]; 3] = [[0.0, 0.0, 1.0]; 3];

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
        let (bytes, layout) = pack(&mesh, &options, &Overlay::default()).unwrap();
        assert_eq!(layout.edge_count, 5);
        assert_eq!(layout.tri_count, 2);
        assert!(layout.total as usize == bytes.len() && bytes.len() % 16 == 0);
        let with_edges = RenderMesh {
            edges: Some(&[[0, 1], [1, 2], [2, 3], [3, 0]]),
            ..mesh
        };
        assert_eq!(
            pack(&with_edges, &options, &Overlay::default())
                .unwrap()
                .1
                .edge_count,
            4
        );
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
        for shading in [Shading::Smooth, Shading::Flat, Shading::Color] {
            let options = RenderOptions {
                shading,
                wire_overlay: true,
                ..Default::default()
            };
            let mut overlay = Overlay::default();
            overlay.text(2.0, 3.0, 1, [1.0; 4], "7");
            let (full, layout, zero) = pack_from(&mesh, &options, &overlay, true).unwrap();
            let (tail, tail_layout, offset) = pack_from(&mesh, &options, &overlay, false).unwrap();
            assert_eq!(
                layout.overlay_vertex_count as usize,
                overlay.rects.len() * 6
            );
            assert_eq!(zero, 0);
            assert_eq!(offset, 96); // 3 vertices * 28 bytes, aligned to 16
            assert_eq!(&full[offset as usize..], &tail[..]);
            assert_eq!(format!("{layout:?}"), format!("{tail_layout:?}"));
        }
    }

    #[test]
    fn colours_are_a_stream_of_their_own_under_color_shading() {
        let colors = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let mesh = RenderMesh {
            positions: &P,
            normals: &N,
            triangles: &[0, 1, 2],
            colors: Some(&colors),
            ..Default::default()
        };
        let color = RenderOptions {
            shading: Shading::Color,
            ..Default::default()
        };
        let (bytes, layout) = pack(&mesh, &color, &Overlay::default()).unwrap();
        assert_ne!(layout.tri_colors, layout.tri_vertices);
        assert_eq!(layout.tri_colors % 16, 0);
        let at = layout.tri_colors as usize;
        let read =
            |k: usize| f32::from_le_bytes(bytes[at + 4 * k..at + 4 * k + 4].try_into().unwrap());
        let stream: Vec<f32> = (0..9).map(read).collect();
        assert_eq!(stream, colors.concat());
        // Without colours the stream is grey; other shadings read the vertex section instead.
        let grey = RenderMesh {
            colors: None,
            ..mesh
        };
        let (bytes, layout) = pack(&grey, &color, &Overlay::default()).unwrap();
        let at = layout.tri_colors as usize;
        assert_eq!(
            f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()),
            GREY[0]
        );
        let (_, smooth) = pack(&mesh, &RenderOptions::default(), &Overlay::default()).unwrap();
        assert_eq!(smooth.tri_colors, smooth.tri_vertices);
    }
}
