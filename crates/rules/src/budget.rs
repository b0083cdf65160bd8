//! Output sizes and the memory they may take: the one home of the estimate every tessellator
//! and refiner checks before it allocates its output.
//!
//! [`estimate`] gives the size a [`Request`] asks for on a cage: exact for uniform depth
//! (Catmull-Clark: an n-gon splits into n quads at level 1, each quad into 4 per level after;
//! Loop: each triangle into 4 per level; vertices by Euler's recurrence over the whole cage,
//! holes included, as the slate layouts number them), an upper bound for the adaptive paths (every
//! face at the maximum depth, its patch cache one level deeper, the fans of depth transitions)
//! and for DoI-driven refinement (every face refined at every step). [`Budget`] refuses a
//! request beyond this machine's memory ([`machine_memory`]) or beyond a caller's triangle
//! limit with [`OutputTooLarge`], which states the size asked for. All arithmetic saturates, so
//! the estimate itself never overflows (a saturated count is far beyond any memory).
//! [`try_reserve`] turns an allocation failure of a big buffer into [`OutOfMemory`] instead of an
//! abort.

use std::fmt;

use subdiv_mesh::Mesh;

use crate::{Depth, Scheme};

/// What a caller asks to produce from a cage.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Request {
    /// The uniform limit tessellation at `depth` (the slates, `tessellate_uniform`).
    Uniform {
        /// The scheme.
        scheme: Scheme,
        /// The depth.
        depth: Depth,
    },
    /// The adaptive tessellation with faces at depths up to `max_depth` (the stitched frames of
    /// `subdiv-stitch`).
    Adaptive {
        /// The scheme.
        scheme: Scheme,
        /// The deepest face depth.
        max_depth: Depth,
    },
    /// DoI-driven adaptive Loop refinement by `steps` steps (`subdiv-redgreen`).
    Refine {
        /// The number of steps.
        steps: u32,
    },
}

impl Request {
    /// Whether the size is an upper bound (adaptive paths) rather than exact.
    pub fn is_bound(&self) -> bool {
        !matches!(self, Request::Uniform { .. })
    }
}

impl fmt::Display for Request {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Request::Uniform { depth, .. } => write!(f, "depth {depth}"),
            Request::Adaptive { max_depth, .. } => write!(f, "max depth {max_depth}"),
            Request::Refine { steps } => write!(f, "{steps} refinement steps"),
        }
    }
}

/// The size of an output: counts and bytes. Uniform requests give the exact counts of the
/// tessellation; adaptive ones bounds.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct OutputSize {
    /// Vertices (limit points; for the adaptive paths the points of every cached patch block).
    pub vertices: u64,
    /// Faces: polygons at depth 0, quads for Catmull-Clark, triangles for Loop and for every
    /// adaptive or refined mesh.
    pub faces: u64,
    /// Triangles the faces make when drawn (a quad is two, an n-gon n - 2).
    pub triangles: u64,
    /// Bytes of the output buffers (positions, normals, indices, UVs; the adaptive paths their
    /// patch cache and frame buffers, refinement its half-edge mesh): approximate, without
    /// what a caller makes of the output.
    pub bytes: u64,
}

/// What a request was measured against.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Limit {
    /// The memory this machine has available ([`machine_memory`]), in bytes.
    Memory {
        /// Bytes.
        bytes: u64,
    },
    /// A caller's triangle limit (the CLI's `--max-triangles`).
    Triangles {
        /// The most triangles allowed.
        max: u64,
    },
}

impl fmt::Display for Limit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Limit::Memory { bytes } => write!(
                f,
                "this machine has {} of memory available",
                format_bytes(*bytes)
            ),
            Limit::Triangles { max } => {
                write!(f, "the limit is {} triangles", format_count(*max))
            }
        }
    }
}

/// A request whose output is beyond the memory or the triangle limit, refused before anything
/// was allocated. The message states the request, the size it asks for and the limit, e.g.
/// "depth 12 on 588 faces asks for 9,865,003,008 quads (19,730,006,016 triangles,
/// 9,865,052,161 vertices, about 404 GiB of output); this machine has 21.9 GiB of memory
/// available".
#[derive(Clone, Debug, PartialEq, Eq, Hash, thiserror::Error)]
#[error("{}", self.message())]
pub struct OutputTooLarge {
    /// What was asked for.
    pub request: Request,
    /// Faces of the cage it was asked of.
    pub cage_faces: u64,
    /// The size it asks for ([`estimate`]).
    pub size: OutputSize,
    /// The limit it exceeds.
    pub limit: Limit,
}

impl OutputTooLarge {
    fn message(&self) -> String {
        let s = &self.size;
        let (at_most, kind, on) = match self.request {
            Request::Uniform {
                scheme: Scheme::CatmullClark,
                depth: 0,
            } => ("", "faces", "faces"),
            Request::Uniform {
                scheme: Scheme::CatmullClark,
                ..
            } => ("", "quads", "faces"),
            Request::Uniform { .. } => ("", "triangles", "faces"),
            Request::Adaptive { .. } => ("at most ", "triangles", "faces"),
            Request::Refine { .. } => ("at most ", "triangles", "triangles"),
        };
        let triangles = if kind == "triangles" {
            String::new()
        } else {
            format!("{} triangles, ", format_count(s.triangles))
        };
        format!(
            "{} on {} {on} asks for {at_most}{} {kind} ({triangles}{} vertices, about {} of \
             output); {}",
            self.request,
            format_count(self.cage_faces),
            format_count(s.faces),
            format_count(s.vertices),
            format_bytes(s.bytes),
            self.limit
        )
    }
}

/// A big buffer could not be allocated (`Vec::try_reserve` failed): reported instead of the
/// allocator's abort.
#[derive(Clone, Debug, PartialEq, Eq, Hash, thiserror::Error)]
#[error("out of memory: cannot allocate {} for {what}", format_bytes(*bytes))]
pub struct OutOfMemory {
    /// The buffer.
    pub what: &'static str,
    /// Bytes asked for.
    pub bytes: u64,
}

/// Reserves room for `additional` more elements in `v`, or reports [`OutOfMemory`] naming
/// `what` (a capacity overflow too).
pub fn try_reserve<T>(
    v: &mut Vec<T>,
    additional: usize,
    what: &'static str,
) -> Result<(), OutOfMemory> {
    v.try_reserve(additional).map_err(|_| OutOfMemory {
        what,
        bytes: (additional as u64).saturating_mul(std::mem::size_of::<T>() as u64),
    })
}

/// [`try_reserve`], then resizes `v` to `len` elements of `value`.
pub fn try_resize<T: Clone>(
    v: &mut Vec<T>,
    len: usize,
    value: T,
    what: &'static str,
) -> Result<(), OutOfMemory> {
    try_reserve(v, len.saturating_sub(v.len()), what)?;
    v.resize(len, value);
    Ok(())
}

/// The limits a request is checked against: bytes of memory and triangles, each optional.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Budget {
    /// The most bytes the output may take (`None`: no limit).
    pub max_bytes: Option<u64>,
    /// The most triangles the output may have (`None`: no limit).
    pub max_triangles: Option<u64>,
}

impl Budget {
    /// No limit at all.
    pub fn unlimited() -> Budget {
        Budget::default()
    }

    /// This machine's available memory ([`machine_memory`]; no limit where it cannot be read),
    /// no triangle limit: what every library entry point checks.
    pub fn machine() -> Budget {
        Budget {
            max_bytes: machine_memory(),
            max_triangles: None,
        }
    }

    /// This budget with a triangle limit (`None` keeps none).
    pub fn with_max_triangles(self, max: Option<u64>) -> Budget {
        Budget {
            max_triangles: max,
            ..self
        }
    }

    /// The size `request` asks for on `mesh` ([`estimate`]), or [`OutputTooLarge`] when it is
    /// beyond the triangle limit or the memory (the triangle limit named first).
    pub fn check(&self, mesh: &Mesh, request: Request) -> Result<OutputSize, OutputTooLarge> {
        let size = estimate(mesh, request);
        self.check_size(request, mesh.num_faces() as u64, size)
    }

    /// [`Budget::check`] of a size already estimated.
    pub fn check_size(
        &self,
        request: Request,
        cage_faces: u64,
        size: OutputSize,
    ) -> Result<OutputSize, OutputTooLarge> {
        let refuse = |limit| OutputTooLarge {
            request,
            cage_faces,
            size,
            limit,
        };
        if let Some(max) = self.max_triangles
            && size.triangles > max
        {
            return Err(refuse(Limit::Triangles { max }));
        }
        if let Some(bytes) = self.max_bytes
            && size.bytes > bytes
        {
            return Err(refuse(Limit::Memory { bytes }));
        }
        Ok(size)
    }
}

/// The memory this process can use, in bytes: `MemAvailable` of `/proc/meminfo` (`MemTotal`
/// where the kernel has no `MemAvailable`), or the cgroup's `memory.max` less its
/// `memory.current` where lower. `None` (no limit) off Linux or when neither can be read.
pub fn machine_memory() -> Option<u64> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let mem = read("/proc/meminfo").and_then(|t| parse_meminfo(&t));
    let cgroup = cgroup_dirs(read("/proc/self/cgroup").as_deref())
        .into_iter()
        .filter_map(|dir| {
            let max = parse_cgroup_max(&read(&format!("{dir}/memory.max"))?)?;
            let current = read(&format!("{dir}/memory.current"))
                .and_then(|t| t.trim().parse::<u64>().ok())
                .unwrap_or(0);
            Some(max.saturating_sub(current))
        })
        .min();
    match (mem, cgroup) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// The cgroup v2 directories whose `memory.max` bound this process: its own (from
/// `/proc/self/cgroup`'s `0::PATH` line) and the root of the mount.
fn cgroup_dirs(self_cgroup: Option<&str>) -> Vec<String> {
    let mut dirs = vec![String::from("/sys/fs/cgroup")];
    if let Some(path) = self_cgroup
        .and_then(|t| t.lines().find_map(|l| l.strip_prefix("0::")))
        .map(str::trim)
        .filter(|p| !p.is_empty() && *p != "/")
    {
        dirs.push(format!("/sys/fs/cgroup{path}"));
    }
    dirs
}

/// `MemAvailable` (else `MemTotal`) of a `/proc/meminfo` text, in bytes.
pub fn parse_meminfo(text: &str) -> Option<u64> {
    let field = |name: &str| {
        text.lines().find_map(|l| {
            let rest = l.strip_prefix(name)?.strip_prefix(':')?;
            let mut words = rest.split_whitespace();
            let n: u64 = words.next()?.parse().ok()?;
            let unit = match words.next() {
                Some("kB") => 1024,
                None => 1,
                Some(_) => return None,
            };
            Some(n.saturating_mul(unit))
        })
    };
    field("MemAvailable").or_else(|| field("MemTotal"))
}

/// A cgroup v2 `memory.max` in bytes (`None` for `max`: no limit).
pub fn parse_cgroup_max(text: &str) -> Option<u64> {
    text.trim().parse().ok()
}

/// Bytes per output vertex: position and normal, `f32` each.
const VERTEX_BYTES: u64 = 24;
/// Bytes per UV value (`[f32; 2]`) and per UV index.
const UV_BYTES: u64 = 8 + 4;

/// The size `request` asks for on `mesh`: exact counts for [`Request::Uniform`], upper bounds
/// for [`Request::Adaptive`] and [`Request::Refine`]; bytes approximate (see [`OutputSize`]).
pub fn estimate(mesh: &Mesh, request: Request) -> OutputSize {
    match request {
        Request::Uniform { scheme, depth } => uniform(mesh, scheme, depth),
        Request::Adaptive { scheme, max_depth } => adaptive(mesh, scheme, max_depth),
        Request::Refine { steps } => refine(mesh, steps),
    }
}

/// `4^k`, saturating.
fn pow4(k: u32) -> u64 {
    4u64.saturating_pow(k)
}

/// `2^k`, saturating.
fn pow2(k: u32) -> u64 {
    2u64.saturating_pow(k)
}

/// Counts of the whole cage (holes included) and of its drawn faces.
struct CageCounts {
    vertices: u64,
    edges: u64,
    faces: u64,
    corners: u64,
    drawn_faces: u64,
    drawn_corners: u64,
    has_uv: bool,
}

impl CageCounts {
    fn of(mesh: &Mesh) -> CageCounts {
        let (mut corners, mut drawn_faces, mut drawn_corners) = (0u64, 0u64, 0u64);
        for f in mesh.faces() {
            let n = mesh.face_size(f) as u64;
            corners = corners.saturating_add(n);
            if !mesh.is_hole(f) {
                drawn_faces += 1;
                drawn_corners = drawn_corners.saturating_add(n);
            }
        }
        CageCounts {
            vertices: mesh.num_vertices() as u64,
            edges: mesh.num_edges() as u64,
            faces: mesh.num_faces() as u64,
            corners,
            drawn_faces,
            drawn_corners,
            has_uv: mesh.uv().is_some(),
        }
    }
}

/// Vertices of the uniform level-`depth` refinement of the whole cage: each level adds one
/// vertex per edge (and per face for Catmull-Clark); an edge splits in two and each face adds
/// one edge per corner (Catmull-Clark) or three (Loop).
fn refined_vertices(c: &CageCounts, scheme: Scheme, depth: Depth) -> u64 {
    let (mut v, mut e, mut f, mut corners) = (c.vertices, c.edges, c.faces, c.corners);
    for _ in 0..depth {
        match scheme {
            Scheme::CatmullClark | Scheme::Bilinear => {
                v = v.saturating_add(e).saturating_add(f);
                e = e.saturating_mul(2).saturating_add(corners);
                f = corners;
                corners = f.saturating_mul(4);
            }
            Scheme::Loop => {
                v = v.saturating_add(e);
                e = e.saturating_mul(2).saturating_add(f.saturating_mul(3));
                f = f.saturating_mul(4);
            }
        }
    }
    v
}

/// The uniform tessellation: exact counts.
fn uniform(mesh: &Mesh, scheme: Scheme, depth: Depth) -> OutputSize {
    let c = CageCounts::of(mesh);
    let vertices = refined_vertices(&c, scheme, depth);
    let d = u32::from(depth);
    let (faces, corners_per_face, triangles) = match (scheme, depth) {
        (Scheme::CatmullClark | Scheme::Bilinear, 0) => {
            let tris = c
                .drawn_corners
                .saturating_sub(c.drawn_faces.saturating_mul(2));
            (c.drawn_faces, 0, tris)
        }
        (Scheme::CatmullClark | Scheme::Bilinear, _) => {
            let quads = c.drawn_corners.saturating_mul(pow4(d - 1));
            (quads, 4, quads.saturating_mul(2))
        }
        (Scheme::Loop, _) => {
            let tris = c.drawn_faces.saturating_mul(pow4(d));
            (tris, 3, tris)
        }
    };
    let corners = if corners_per_face == 0 {
        c.drawn_corners
    } else {
        faces.saturating_mul(corners_per_face)
    };
    let uv = if c.has_uv { UV_BYTES } else { 0 };
    let bytes = vertices
        .saturating_mul(VERTEX_BYTES)
        .saturating_add(corners.saturating_mul(4 + uv))
        .saturating_add(faces.saturating_add(1).saturating_mul(4));
    OutputSize {
        vertices,
        faces,
        triangles,
        bytes,
    }
}

/// Points of a quad block at depth `d`: `(2^d + 1)^2`.
fn quad_block(d: u32) -> u64 {
    let s = pow2(d).saturating_add(1);
    s.saturating_mul(s)
}

/// Points of a triangle lattice at depth `d`: `(2^d + 1)(2^d + 2) / 2`.
fn tri_lattice(d: u32) -> u64 {
    let n = pow2(d);
    n.saturating_add(1).saturating_mul(n.saturating_add(2)) / 2
}

/// The adaptive frames with faces at depths up to `max_depth`: upper bounds. Catmull-Clark:
/// a face of n corners is at most n level-1 patches (one patch for a quad among quads, which the
/// bound does not need to tell apart) at depth `max_depth - 1`, each drawing at most
/// `2·4^d` grid triangles plus, along its four sides, a fan of at most `2^d + 6` triangles in
/// place of each of its `4·2^d` side quads (through a deeper neighbour's points and the next
/// level's face point), that is at most `2·4^d + 8·2^d + 16` per patch for `d = max_depth - 1`
/// (the fan terms grow slower than the grid's); its block is cached one level deeper for the
/// fan centres. Loop: a triangle draws at most `4^d` lattice triangles plus a fan per side
/// (`2^d` more each) and the split of a three-sided transition, `4^d + 3·2^d + 4`, from
/// lattices at `max_depth`. Vertices are the points of every cached block (the frame holds them
/// all, concatenated).
fn adaptive(mesh: &Mesh, scheme: Scheme, max_depth: Depth) -> OutputSize {
    let c = CageCounts::of(mesh);
    let d = u32::from(max_depth);
    let (vertices, triangles) = match scheme {
        // Bilinear units are Catmull-Clark's (a quad one patch, other faces level-1 quads).
        Scheme::CatmullClark | Scheme::Bilinear => {
            // Level-1 patches at one level less; a depth-0 face is still its level-1 quads.
            let p = d.saturating_sub(1);
            let per_patch = pow4(p)
                .saturating_mul(2)
                .saturating_add(pow2(p).saturating_mul(8))
                .saturating_add(16);
            (
                c.drawn_corners.saturating_mul(quad_block(p + 1)),
                c.drawn_corners.saturating_mul(per_patch),
            )
        }
        Scheme::Loop => {
            let per_patch = pow4(d)
                .saturating_add(pow2(d).saturating_mul(3))
                .saturating_add(4);
            (
                c.drawn_faces.saturating_mul(tri_lattice(d)),
                c.drawn_faces.saturating_mul(per_patch),
            )
        }
    };
    // Blocks (position, normal) and the frame's copy of them with a depth per vertex; three
    // indices per triangle and a UV per corner.
    let uv = if c.has_uv { 3 * 8 } else { 0 };
    let bytes = vertices
        .saturating_mul(2 * VERTEX_BYTES + 4)
        .saturating_add(triangles.saturating_mul(12 + uv));
    OutputSize {
        vertices,
        faces: triangles,
        triangles,
        bytes,
    }
}

/// Bytes per vertex of a refined half-edge mesh: position, the previous level's position, an
/// out half-edge, sharpness, level data.
const REFINED_VERTEX_BYTES: u64 = 48;
/// Bytes per triangle of a refined half-edge mesh: three half-edges (next, vertex, face, twin
/// data), the face's half-edge, level and green family, and its limit in the output surface.
const REFINED_TRIANGLE_BYTES: u64 = 96;

/// DoI-driven refinement by `steps` steps: at most the uniform Loop refinement at that level
/// (a step at most quadruples a triangle: red; green splits make two or three; every vertex is
/// a vertex of the uniform refinement at its level).
fn refine(mesh: &Mesh, steps: u32) -> OutputSize {
    let c = CageCounts::of(mesh);
    let depth = Depth::try_from(steps).unwrap_or(Depth::MAX);
    let vertices = refined_vertices(&c, Scheme::Loop, depth);
    let triangles = c.faces.saturating_mul(pow4(steps));
    let uv = if c.has_uv { 3 * UV_BYTES } else { 0 };
    let bytes = vertices
        .saturating_mul(REFINED_VERTEX_BYTES)
        .saturating_add(triangles.saturating_mul(REFINED_TRIANGLE_BYTES + uv));
    OutputSize {
        vertices,
        faces: triangles,
        triangles,
        bytes,
    }
}

/// `n` with thousands separators: `872,415,232`.
pub fn format_count(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, ch) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(ch);
    }
    out
}

/// Bytes in binary units with three significant digits: `95.2 GiB`, `512 bytes`.
pub fn format_bytes(b: u64) -> String {
    const UNITS: [&str; 6] = ["KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    if b < 1024 {
        return format!("{b} bytes");
    }
    let mut x = b as f64 / 1024.0;
    let mut unit = 0;
    while x >= 1024.0 && unit + 1 < UNITS.len() {
        x /= 1024.0;
        unit += 1;
    }
    let digits = if x >= 100.0 {
        0
    } else if x >= 10.0 {
        1
    } else {
        2
    };
    format!("{x:.digits$} {}", UNITS[unit])
}

#[cfg(test)]
mod tests;
