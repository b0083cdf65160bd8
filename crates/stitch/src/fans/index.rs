//! Index-buffer emission: plain quads (two triangles each) and, next to a deeper neighbour,
//! triangle fans around the limit point of the quad's next-level face point.
//!
//! A plain quad is split along the diagonal from its corner `(i, j)` to `(i + 1, j + 1)`, except
//! a quad at a *pinched* patch corner (two faces with a corner between the same two edges: an
//! interior cage vertex of valence 2, or faces of different pieces of a non-manifold cage whose
//! sides there are copies of the same two non-manifold edges): both faces' corner quads there
//! have the same three border points, the vertex and its two edge neighbours, so if both were
//! split along the chord between the two edge neighbours that chord would carry four
//! triangles. Such a quad is split through the vertex instead, whichever corner of the patch it
//! is.

use subdiv_mesh::Mesh;
use subdiv_slate::{LevelUvs, PatchRef, PatchSet};

use super::edges::Frame;
use super::grid::{side_of_on, side_point};
#[cfg(doc)]
use crate::runs::RUN_PATCHES;
use crate::runs::{RunOut, concat, dependencies, emit_runs, faces_around};

/// No block point of the patch's own (interior points, or a block too coarse).
const NO_OWN: u32 = u32::MAX;

/// A triangle corner: its shared vertex id, the one-sided normal of its own patch's side there
/// (only at border points where the limit surface has a crease or a corner), and where it lies
/// in its own patch's parameters: grid point `(i, j)` of the patch's `2^e` grid (for its
/// face-varying value, [`LevelUvs::value_at`]).
#[derive(Clone, Copy, Debug)]
struct Corner {
    id: u32,
    sided: Option<[f32; 3]>,
    i: u32,
    j: u32,
    e: u8,
}

/// Where [`Frame::emit_patch`] puts each corner's face-varying value: nowhere (`()`, the no-UV
/// path, where the places are never looked up once inlined), or the value of the patch's own
/// side ([`PatchUvs`]).
trait UvSink {
    /// Whether [`UvSink::put`] does anything.
    const WANTED: bool;
    fn put(&mut self, c: &Corner);
}

impl UvSink for () {
    const WANTED: bool = false;
    #[inline(always)]
    fn put(&mut self, _: &Corner) {}
}

/// The face-varying values of one patch's corners, into `out`.
struct PatchUvs<'a> {
    uvs: &'a LevelUvs,
    p: &'a PatchRef,
    face: subdiv_mesh::FaceId,
    out: &'a mut Vec<u32>,
}

impl UvSink for PatchUvs<'_> {
    const WANTED: bool = true;
    #[inline(always)]
    fn put(&mut self, c: &Corner) {
        let v = self
            .uvs
            .value_at(self.p.level, self.p.sub, self.face, c.i, c.j, c.e);
        self.out.push(v);
    }
}

/// One run of patches' output ([`RunOut`]) and the emission scratch of the thread writing it;
/// kept between frames so that a frame allocates nothing once the buffers have grown.
#[derive(Clone, Debug, Default)]
pub(super) struct Chunk {
    run: RunOut,
    /// Per grid point of the patch being emitted: shared id and own block point.
    grid: Vec<(u32, u32)>,
    /// Per grid point: the patch's one-sided normal there, if any.
    grid_sided: Vec<Option<[f32; 3]>>,
    /// The corners of the fan being emitted.
    poly: Vec<Corner>,
}

/// Per run of [`RUN_PATCHES`] patches of `set`, the units (faces) its triangles read
/// ([`faces_around`] their units' faces).
pub(super) fn run_dependencies(mesh: &Mesh, set: &PatchSet) -> Vec<Vec<u32>> {
    let (patches, units) = (set.patches(), set.units());
    dependencies(patches.len(), |p, deps| {
        faces_around(mesh, units[patches[p].unit as usize].face, deps)
    })
}

impl Chunk {
    /// The corner at grid point `(i, j)` (storage index `k`) of the patch being emitted, at its
    /// depth `d`.
    #[inline(always)]
    fn corner(&self, k: usize, (i, j): (u32, u32), d: u32) -> Corner {
        Corner {
            id: self.grid[k].0,
            sided: self.grid_sided.get(k).copied().flatten(),
            i,
            j,
            e: d as u8,
        }
    }
}

/// Appends corner `c` to the chunk: its id, its one-sided normal if it has one, its
/// face-varying value.
#[inline(always)]
fn push(ch: &mut Chunk, uv: &mut impl UvSink, c: Corner) {
    if let Some(nrm) = c.sided {
        ch.run.sided.push((ch.run.tris.len() as u32, nrm));
    }
    ch.run.tris.push(c.id);
    uv.put(&c);
}

/// Whether quad `(i, j)` of an `n x n` patch lies along a side that fans (`fans[k]`, side `k`:
/// bottom, right, top, left).
#[inline(always)]
fn replaced(fans: [bool; 4], n: u32, i: u32, j: u32) -> bool {
    (fans[0] && j == 0) || (fans[1] && i == n - 1) || (fans[2] && j == n - 1) || (fans[3] && i == 0)
}

/// How the quads next to a deeper neighbour are closed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FanMethod {
    /// Fans, plus the subdivided edge between two replaced quads of a patch (the paper's method).
    #[default]
    Subdivided,
    /// Fans only (the paper's "simple method", which shows buckles).
    Simple,
}

impl Frame<'_> {
    /// The frame's index buffer: each active, non-hole patch's triangles, emitted in parallel
    /// by runs of [`RUN_PATCHES`] patches into `chunks` (grown as needed, kept by the caller
    /// between frames), then concatenated in patch order into `out` (cleared first); and in
    /// `corner_normals` (cleared first; corner index in `out`, ascending) each patch's own
    /// one-sided normal at the triangle corners on creases and corners of the limit surface.
    /// With `uvs`, the face-varying value of every triangle corner on its own patch's side goes
    /// to `uv_indices` (cleared first; parallel to `out`).
    ///
    /// With `deps` (per run, [`run_dependencies`]), a run whose state ([`Frame::chunk_key`])
    /// is the one its kept triangles were emitted from keeps them ([`RunOut::keep`]): the same
    /// output as emitting it again, without the work. Without, every run is emitted. Returns
    /// the runs kept.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn emit_frame(
        &self,
        active: &[bool],
        method: FanMethod,
        uvs: Option<&LevelUvs>,
        deps: Option<&[Vec<u32>]>,
        chunks: &mut Vec<Chunk>,
        out: &mut Vec<u32>,
        corner_normals: &mut Vec<(u32, [f32; 3])>,
        uv_indices: &mut Vec<u32>,
    ) -> usize {
        let patches = self.set.patches();
        let key = deps.map(|deps| {
            move |c: usize, run, key: &mut Vec<u64>| {
                self.chunk_key(&deps[c], run, active, method, uvs, key)
            }
        });
        let (runs, kept) = emit_runs(
            chunks,
            patches.len(),
            |ch| &mut ch.run,
            key,
            |run, ch| {
                for p in &patches[run] {
                    let face = self.set.units()[p.unit as usize].face;
                    if !active[p.unit as usize] || self.mesh.is_hole(face) {
                        continue;
                    }
                    match uvs {
                        Some(uvs) => {
                            let mut out = std::mem::take(&mut ch.run.uv);
                            let mut sink = PatchUvs {
                                uvs,
                                p,
                                face,
                                out: &mut out,
                            };
                            self.emit_patch(p, method, ch, &mut sink);
                            ch.run.uv = out;
                        }
                        None => self.emit_patch(p, method, ch, &mut ()),
                    }
                }
            },
        );
        concat(
            chunks[..runs].iter().map(|c| &c.run),
            out,
            corner_normals,
            uv_indices,
        );
        kept
    }

    /// The state a run's triangles are a function of, into `key` (empty): the fan
    /// method, the face-varying level, and per unit of `deps` its activity and depth and, per
    /// patch, where its block lies in the vertex buffer and how deep it is; then which
    /// computation each of the run's own patches' blocks holds (`patches`), which only the
    /// one-sided normals the run copies from them depend on (which points have one depends on
    /// the topology alone). Returns the length of the first part.
    fn chunk_key(
        &self,
        deps: &[u32],
        patches: std::ops::Range<usize>,
        active: &[bool],
        method: FanMethod,
        uvs: Option<&LevelUvs>,
        key: &mut Vec<u64>,
    ) -> usize {
        let level = uvs.map_or(0, |u| u64::from(u.level()) + 1);
        key.push(((method as u64) << 32) | level);
        let units = self.set.units();
        for &u in deps {
            let u = u as usize;
            key.push((u64::from(self.depth[u]) << 1) | u64::from(active[u]));
            let first = units[u].first_patch as usize;
            for pi in first..first + units[u].patch_count as usize {
                let b = &self.blocks[pi];
                let depth = b.depth.map_or(0, |d| u64::from(d) + 1);
                key.push((u64::from(self.slots.start(pi)) << 8) | depth);
            }
        }
        let structure = key.len();
        key.extend(patches.map(|pi| self.blocks[pi].stamp));
        structure
    }

    /// Fills `ch.grid` with the shared id and own block point of every point of patch `p`'s
    /// depth-`d` grid (interior points straight from the patch's block, border points through
    /// their owners), and `ch.grid_sided` with the patch's one-sided normals at its border points
    /// (left empty when the patch has none).
    fn fill_grid(&self, pi: usize, p: &PatchRef, d: u32, ch: &mut Chunk) {
        let n = 1u32 << d;
        let w = (n + 1) as usize;
        ch.grid.clear();
        ch.grid.resize(w * w, (0, NO_OWN));
        // Interior: the patch's own block, sampled with the block's stride.
        let b = &self.blocks[pi];
        let bd = u32::from(b.depth.unwrap_or_default());
        debug_assert!(bd >= d, "block too coarse");
        let (stride, bw) = (1u32 << (bd - d), (1u32 << bd) + 1);
        let start = self.slots.start(pi);
        for j in 1..n {
            let row = start + j * stride * bw;
            for i in 1..n {
                ch.grid[j as usize * w + i as usize] = (row + i * stride, NO_OWN);
            }
        }
        let mut border = |i: u32, j: u32| {
            ch.grid[j as usize * w + i as usize] =
                (self.point_id(pi, p, i, j), self.own(pi, i, j, d));
        };
        for i in 0..=n {
            border(i, 0);
            border(i, n);
        }
        for j in 1..n {
            border(0, j);
            border(n, j);
        }
        ch.grid_sided.clear();
        if !b.sided.is_empty() {
            ch.grid_sided.resize(w * w, None);
            for (k, &(_, o)) in ch.grid.iter().enumerate() {
                if o != NO_OWN {
                    ch.grid_sided[k] = self.own_sided(pi, o);
                }
            }
        }
    }

    /// The triangles of one patch, appended to `ch.run.tris` with the patch's one-sided normals
    /// at its border corners in `ch.run.sided`, and each corner's face-varying value in `uv`; quad by
    /// quad, row by row.
    fn emit_patch<U: UvSink>(&self, p: &PatchRef, method: FanMethod, ch: &mut Chunk, uv: &mut U) {
        let pi = self.patch_index(p.unit as usize, p.sub as usize);
        let d = self.patch_depth(p);
        let n = 1u32 << d;
        let fans = self.fans(p);
        self.fill_grid(pi, p, d, ch);
        let any = fans.iter().any(|&x| x);
        // Pinched patch corners (level-1 patches: only corner 0 is a cage vertex, and the
        // default diagonal already runs through it).
        let pinched = |k: usize| p.level == 0 && self.units[p.unit as usize].pinched[k];
        let any_flip = (0..4).any(pinched);
        // Split quad (i, j) through its corners 1 and 3 instead of 0 and 2? Only a patch's
        // corner quads can be.
        let flip = |i: u32, j: u32| -> bool {
            let at = |k: usize| {
                let (ci, cj) = [(0, 0), (n - 1, 0), (n - 1, n - 1), (0, n - 1)][k];
                i == ci && j == cj && pinched(k)
            };
            any_flip && (at(1) || at(3)) && !(at(0) || at(2))
        };
        // No one-sided normals and no face-varying values: plain quads straight from the grid.
        let plain = !U::WANTED && ch.grid_sided.is_empty();
        let w = (n + 1) as usize;
        for j in 0..n {
            for i in 0..n {
                if any && replaced(fans, n, i, j) {
                    self.emit_fan(p, pi, (i, j), fans, method, ch, uv);
                    continue;
                }
                let (r0, r1, iu) = (j as usize * w, (j as usize + 1) * w, i as usize);
                let quad = [r0 + iu, r0 + iu + 1, r1 + iu + 1, r1 + iu];
                let order = if flip(i, j) {
                    [0, 1, 3, 1, 2, 3]
                } else {
                    [0, 1, 2, 0, 2, 3]
                };
                if plain {
                    let g = &ch.grid;
                    let [a, b, c, e] = quad.map(|k| g[k].0);
                    let ids = [a, b, c, e];
                    let [o0, o1, o2, o3, o4, o5] = order;
                    ch.run
                        .tris
                        .extend_from_slice(&[ids[o0], ids[o1], ids[o2], ids[o3], ids[o4], ids[o5]]);
                    continue;
                }
                let at = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                for k in order {
                    let c = ch.corner(quad[k], at[k], d);
                    push(ch, uv, c);
                }
            }
        }
    }

    /// The fan that replaces quad `(i, j)` of patch `p` (index `pi`) next to a deeper
    /// neighbour: triangles around the limit point of the quad's next-level face point through
    /// its corners, the deeper side's points on its fanned sides, and (subdivided method) the
    /// midpoints of its inner edges to other replaced quads.
    #[allow(clippy::too_many_arguments)]
    fn emit_fan<U: UvSink>(
        &self,
        p: &PatchRef,
        pi: usize,
        (i, j): (u32, u32),
        fans: [bool; 4],
        method: FanMethod,
        ch: &mut Chunk,
        uv: &mut U,
    ) {
        let d = self.patch_depth(p);
        let n = 1u32 << d;
        let w = (n + 1) as usize;
        let (ci, cj) = (2 * i + 1, 2 * j + 1);
        let centre = Corner {
            id: self.own(pi, ci, cj, d + 1),
            sided: None,
            i: ci,
            j: cj,
            e: d as u8 + 1,
        };
        let mut poly = std::mem::take(&mut ch.poly);
        poly.clear();
        // The quad's four edges, counter-clockwise: bottom, right, top, left; each from its
        // start corner (inclusive) to its end corner (exclusive).
        let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
        for (ek, &(ci, cj)) in corners.iter().enumerate() {
            poly.push(ch.corner(cj as usize * w + ci as usize, (ci, cj), d));
            let (ni, nj) = corners[(ek + 1) % 4];
            // Is this edge on a fanned side of the patch?
            let on_side = match ek {
                0 if j == 0 => Some(0),
                1 if i + 1 == n => Some(1),
                2 if j + 1 == n => Some(2),
                3 if i == 0 => Some(3),
                _ => None,
            };
            if let Some(k) = on_side.filter(|&k| fans[k]) {
                self.push_fine_points(p, pi, k, (ci, cj), (ni, nj), n, &mut poly);
            } else if on_side.is_none() && method == FanMethod::Subdivided {
                // Inner edge: subdivide it if the quad across is replaced too.
                let (oi, oj) = match ek {
                    0 => (i, j.wrapping_sub(1)),
                    1 => (i + 1, j),
                    2 => (i, j + 1),
                    _ => (i.wrapping_sub(1), j),
                };
                if oi < n && oj < n && replaced(fans, n, oi, oj) {
                    // An inner edge's midpoint: inside the patch.
                    let (mi, mj) = (ci + ni, cj + nj);
                    poly.push(Corner {
                        id: self.own(pi, mi, mj, d + 1),
                        sided: None,
                        i: mi,
                        j: mj,
                        e: d as u8 + 1,
                    });
                }
            }
        }
        for k in 0..poly.len() {
            push(ch, uv, centre);
            push(ch, uv, poly[k]);
            push(ch, uv, poly[(k + 1) % poly.len()]);
        }
        ch.poly = poly;
    }

    /// The deeper neighbour's points strictly between two corners of a border quad on side `k`,
    /// each with this patch's own one-sided normal there where its block is that deep.
    #[allow(clippy::too_many_arguments)]
    fn push_fine_points(
        &self,
        p: &PatchRef,
        pi: usize,
        k: usize,
        a: (u32, u32),
        b: (u32, u32),
        n: u32,
        poly: &mut Vec<Corner>,
    ) {
        let u = p.unit as usize;
        let hs = &self.units[u].hs;
        let d = self.patch_depth(p);
        let (_, sa) = side_of_on(k, a.0, a.1, n);
        let (_, sb) = side_of_on(k, b.0, b.1, n);
        // Cage half-edge and the parameter range (at unit resolution) the side covers.
        let (h, ud, offset) = if p.level == 0 {
            (hs[k], d, 0)
        } else {
            let nsub = hs.len();
            let sub = p.sub as usize;
            match k {
                0 => (hs[sub], d + 1, 0),
                _ => (hs[(sub + nsub - 1) % nsub], d + 1, n),
            }
        };
        let r = self.edge_res[h.edge().idx()] as u32;
        let delta = r - ud;
        let (t0, t1) = ((offset + sa) << delta, (offset + sb) << delta);
        // This patch's own copy of the point at `t`: parameter `t - (offset << delta)` along
        // its side `k` at its own depth `r - level` (sides run the way their half-edges do).
        let dp = r - u32::from(p.level);
        let deep = self.has_depth(pi, dp);
        let point = |t: u32| {
            let (i, j) = side_point(k, t - (offset << delta), 1 << dp);
            let sided = if deep {
                self.own_sided(pi, self.own(pi, i, j, dp))
            } else {
                None
            };
            Corner {
                id: self.edge_point_id(h, t, r),
                sided,
                i,
                j,
                e: dp as u8,
            }
        };
        if t1 > t0 {
            for t in t0 + 1..t1 {
                poly.push(point(t));
            }
        } else {
            for t in (t1 + 1..t0).rev() {
                poly.push(point(t));
            }
        }
    }
}

#[cfg(test)]
#[path = "index_tests.rs"]
mod tests;
