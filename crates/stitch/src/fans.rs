//! Crack-free assembly of Catmull-Clark patches tessellated at different depths.
//!
//! Settgast, Müller, Fünfzig and Fellner, "Adaptive Tessellation of Subdivision Surfaces",
//! Section 3.3 and Figs. 4 and 10. Every cage face (a *unit*: one patch, or the level-1 quads of
//! an n-gon) has a depth per frame. Where a unit borders a deeper one, the chord quads along that
//! border are replaced by triangle fans around the limit point of the quad's face point one level
//! down, through the deeper side's own border points. If two neighbouring quads of the same patch
//! are replaced, their shared edge is subdivided too and its limit point joins both fans (the
//! extra step that prevents buckles; [`FanMethod::Simple`] leaves it out, reproducing the
//! paper's Fig. 10 comparison).
//!
//! Watertight to the bit: every point on a cage edge or vertex is referenced through one *owner*
//! patch (the deepest side of the edge), so both sides of a border use the same vertex.
//!
//! Caching (Section 4): each patch keeps its limit points in a block computed at some depth
//! `c`; while the patch's depth does not rise above `c` the block is reused (sampled with
//! stride `2^(c - d)`), and only the index buffer is rebuilt.

use rayon::prelude::*;
use subdiv_mesh::{HalfedgeId, Mesh, VertexId};
use subdiv_slate::{PatchRef, PatchSet, thread_worker};

use crate::AssemblyError;

/// How the quads next to a deeper neighbour are closed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FanMethod {
    /// Fans, plus the subdivided edge between two replaced quads of a patch (the paper's method).
    #[default]
    Subdivided,
    /// Fans only (the paper's "simple method", which shows buckles).
    Simple,
}

/// A patch's cached limit points.
#[derive(Clone, Debug, Default)]
struct Block {
    /// Depth the block was computed at (`-1`: never).
    depth: i32,
    pos: Vec<[f32; 3]>,
    nrm: Vec<[f32; 3]>,
}

/// What one frame produced.
#[derive(Clone, Debug, Default)]
pub struct FrameGeometry {
    /// Vertex positions (all patch blocks, concatenated; shared points are referenced once).
    pub positions: Vec<[f32; 3]>,
    /// Unit limit normals.
    pub normals: Vec<[f32; 3]>,
    /// Triangle list, counter-clockwise.
    pub indices: Vec<u32>,
    /// Per vertex: the depth of the patch it belongs to (for depth colouring).
    pub vertex_depth: Vec<f32>,
    /// Depth of each unit (cage face) this frame; `u8::MAX` for units not drawn.
    pub unit_depth: Vec<u8>,
    /// Bumped whenever `positions`/`normals` changed since the previous frame.
    pub vertex_version: u64,
    /// Patches recomputed this frame.
    pub patches_recomputed: usize,
}

impl FrameGeometry {
    /// Number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.indices.len() / 3
    }

    /// Number of units drawn at each depth (index = depth).
    pub fn units_per_depth(&self) -> Vec<usize> {
        let mut v = Vec::new();
        for &d in &self.unit_depth {
            if d != u8::MAX {
                if v.len() <= d as usize {
                    v.resize(d as usize + 1, 0);
                }
                v[d as usize] += 1;
            }
        }
        v
    }

    /// The referenced vertices only, renumbered (for writing files).
    pub fn compact(&self) -> (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<u32>) {
        let mut map = vec![u32::MAX; self.positions.len()];
        let mut pos = Vec::new();
        let mut nrm = Vec::new();
        let mut idx = Vec::with_capacity(self.indices.len());
        for &i in &self.indices {
            let m = &mut map[i as usize];
            if *m == u32::MAX {
                *m = pos.len() as u32;
                pos.push(self.positions[i as usize]);
                nrm.push(self.normals[i as usize]);
            }
            idx.push(*m);
        }
        (pos, nrm, idx)
    }
}

/// Per-unit topology: its half-edges, in face order.
#[derive(Clone, Debug)]
struct UnitTopo {
    hs: Vec<HalfedgeId>,
}

/// The adaptive assembler: per-mesh patch structure plus the per-patch block cache.
#[derive(Debug)]
pub struct Assembler {
    set: PatchSet,
    units: Vec<UnitTopo>,
    blocks: Vec<Block>,
    block_start: Vec<u32>,
    version: u64,
    maxsd: u32,
    method: FanMethod,
}

/// Per-frame data derived from the depths.
struct Frame<'a> {
    mesh: &'a Mesh,
    set: &'a PatchSet,
    units: &'a [UnitTopo],
    depth: &'a [u8],
    /// Per edge: resolution (max depth of its active units) and owner unit.
    edge_res: Vec<u8>,
    edge_owner: Vec<u32>,
    vertex_owner: Vec<(u32, u32)>,
    blocks: &'a [Block],
    block_start: &'a [u32],
}

impl Assembler {
    /// Sets up the patches of `mesh`. `maxsd` is the deepest depth that will be requested.
    pub fn new(mesh: &Mesh, maxsd: u32) -> Result<Assembler, AssemblyError> {
        if maxsd > subdiv_slate::MAX_DEPTH - 1 {
            return Err(AssemblyError::TooDeep {
                depth: maxsd,
                max: subdiv_slate::MAX_DEPTH - 1,
            });
        }
        let set = PatchSet::new(mesh)?;
        let units = set
            .units()
            .iter()
            .map(|u| {
                let h0 = mesh.face_halfedge(u.face);
                let mut hs = vec![h0];
                let mut h = mesh.next(h0);
                while h != h0 {
                    hs.push(h);
                    h = mesh.next(h);
                }
                UnitTopo { hs }
            })
            .collect();
        let n = set.patches().len();
        Ok(Assembler {
            set,
            units,
            blocks: vec![
                Block {
                    depth: -1,
                    ..Default::default()
                };
                n
            ],
            block_start: vec![0; n + 1],
            version: 0,
            maxsd,
            method: FanMethod::Subdivided,
        })
    }

    /// Chooses the fan method.
    pub fn set_method(&mut self, m: FanMethod) {
        self.method = m;
    }

    /// The patch structure.
    pub fn patch_set(&self) -> &PatchSet {
        &self.set
    }

    /// Smallest depth a unit can have (level-1 units need at least 1).
    pub fn min_depth(&self, unit: usize) -> u8 {
        self.set.units()[unit].irregular as u8
    }

    /// Drops all cached blocks (e.g. after the mesh's positions changed).
    pub fn invalidate(&mut self) {
        for b in &mut self.blocks {
            b.depth = -1;
        }
    }

    /// Builds a frame: `depth[u]` per unit (cage face; clamped to `min_depth..=maxsd`) and
    /// `active[u]` (units not drawn, e.g. culled or holes, are `false`).
    pub fn frame(
        &mut self,
        mesh: &Mesh,
        depth: &[u8],
        active: &[bool],
        out: &mut FrameGeometry,
    ) -> Result<(), AssemblyError> {
        let nu = self.set.units().len();
        if depth.len() != nu || active.len() != nu {
            return Err(AssemblyError::Length {
                what: "depth/active",
                got: depth.len().min(active.len()),
                want: nu,
            });
        }
        let depth: Vec<u8> = (0..nu)
            .map(|u| depth[u].clamp(self.min_depth(u), self.maxsd as u8))
            .collect();
        let fr = Frame::new(
            mesh,
            &self.set,
            &self.units,
            &depth,
            active,
            &self.blocks,
            &self.block_start,
        );
        // Required depth per patch: its own, plus one where it must fan towards a deeper side.
        let required: Vec<i32> = self
            .set
            .patches()
            .iter()
            .map(|p| {
                if active[p.unit as usize] {
                    fr.patch_depth(p) as i32 + fr.fans(p).iter().any(|&x| x) as i32
                } else {
                    -1
                }
            })
            .collect();
        let _ = fr;
        // Refuse frames whose blocks would not fit in memory.
        let total: u64 = (0..required.len())
            .map(|i| {
                let d = required[i].max(self.blocks[i].depth);
                if d < 0 { 0 } else { ((1u64 << d) + 1).pow(2) }
            })
            .sum();
        if total > subdiv_slate::MAX_POINTS {
            return Err(AssemblyError::TooLarge { points: total });
        }
        // Recompute the blocks that are too coarse.
        let todo: Vec<usize> = (0..required.len())
            .filter(|&i| required[i] > self.blocks[i].depth)
            .collect();
        let set = &self.set;
        let maxsd = self.maxsd + 1;
        let mut fresh: Vec<(usize, Block)> = todo
            .par_iter()
            .map_init(
                || thread_worker(maxsd),
                |w, &i| {
                    let p = &set.patches()[i];
                    let d = required[i] as u32;
                    let n = (1usize << d) + 1;
                    let mut b = Block {
                        depth: d as i32,
                        pos: vec![[0.0; 3]; n * n],
                        nrm: vec![[0.0; 3]; n * n],
                    };
                    w.patch_grid(set.source(mesh, p), p.src_face, d, &mut b.pos, &mut b.nrm);
                    (i, b)
                },
            )
            .collect();
        let recomputed = fresh.len();
        for (i, b) in fresh.drain(..) {
            self.blocks[i] = b;
        }
        // Vertex buffer: the blocks, concatenated.
        if recomputed > 0 || out.positions.is_empty() {
            let mut acc = 0u32;
            for (i, b) in self.blocks.iter().enumerate() {
                self.block_start[i] = acc;
                acc += b.pos.len() as u32;
            }
            self.block_start[self.blocks.len()] = acc;
            out.positions.clear();
            out.normals.clear();
            out.vertex_depth.clear();
            for b in &self.blocks {
                out.positions.extend_from_slice(&b.pos);
                out.normals.extend_from_slice(&b.nrm);
            }
            self.version += 1;
        }
        out.vertex_version = self.version;
        out.patches_recomputed = recomputed;
        let fr = Frame::new(
            mesh,
            &self.set,
            &self.units,
            &depth,
            active,
            &self.blocks,
            &self.block_start,
        );
        // Depth per vertex (of the patch whose block holds it, at this frame's depth).
        out.vertex_depth.clear();
        out.vertex_depth.resize(out.positions.len(), 0.0);
        for (i, p) in self.set.patches().iter().enumerate() {
            let d = depth[p.unit as usize] as f32;
            out.vertex_depth[self.block_start[i] as usize..self.block_start[i + 1] as usize]
                .fill(d);
        }
        // Index buffer: each patch's triangles, in parallel, then concatenated in patch order.
        let method = self.method;
        let tris: Vec<Vec<u32>> = self
            .set
            .patches()
            .par_iter()
            .map(|p| {
                let mut v = Vec::new();
                if active[p.unit as usize] && !mesh.is_hole(self.set.units()[p.unit as usize].face)
                {
                    fr.emit_patch(p, method, &mut v);
                }
                v
            })
            .collect();
        out.indices.clear();
        for t in tris {
            out.indices.extend_from_slice(&t);
        }
        out.unit_depth = (0..nu)
            .map(|u| if active[u] { depth[u] } else { u8::MAX })
            .collect();
        Ok(())
    }
}

impl<'a> Frame<'a> {
    fn new(
        mesh: &'a Mesh,
        set: &'a PatchSet,
        units: &'a [UnitTopo],
        depth: &'a [u8],
        active: &'a [bool],
        blocks: &'a [Block],
        block_start: &'a [u32],
    ) -> Frame<'a> {
        let ne = mesh.num_edges();
        let mut edge_res = vec![0u8; ne];
        let mut edge_owner = vec![u32::MAX; ne];
        for e in mesh.edges() {
            // Canonical order: the face of half-edge 0 first.
            for side in 0..2 {
                let f = mesh.face(e.halfedge(side));
                if !f.is_some() || !active[f.idx()] {
                    continue;
                }
                let d = depth[f.idx()];
                if edge_owner[e.idx()] == u32::MAX || d > edge_res[e.idx()] {
                    edge_res[e.idx()] = d;
                    edge_owner[e.idx()] = f.0;
                }
            }
        }
        let mut vertex_owner = vec![(u32::MAX, 0u32); mesh.num_vertices()];
        for v in mesh.vertices() {
            for h in mesh.outgoing(v) {
                let f = mesh.face(h);
                if f.is_some() && active[f.idx()] {
                    let k = units[f.idx()].hs.iter().position(|&x| x == h).unwrap_or(0) as u32;
                    vertex_owner[v.idx()] = (f.0, k);
                    break;
                }
            }
        }
        Frame {
            mesh,
            set,
            units,
            depth,
            edge_res,
            edge_owner,
            vertex_owner,
            blocks,
            block_start,
        }
    }

    /// The patch's own subdivision depth (level-1 patches are one less than their unit).
    #[inline]
    fn patch_depth(&self, p: &PatchRef) -> u32 {
        self.depth[p.unit as usize] as u32 - p.level as u32
    }

    /// For each side of a patch: does it border a deeper unit?
    fn fans(&self, p: &PatchRef) -> [bool; 4] {
        let u = p.unit as usize;
        let d = self.depth[u];
        let hs = &self.units[u].hs;
        let mut f = [false; 4];
        if p.level == 0 {
            for k in 0..4 {
                f[k] = self.edge_res[hs[k].edge().idx()] > d;
            }
        } else {
            let n = hs.len();
            let k = p.sub as usize;
            f[0] = self.edge_res[hs[k].edge().idx()] > d;
            f[3] = self.edge_res[hs[(k + n - 1) % n].edge().idx()] > d;
        }
        f
    }

    /// Output id of point `(i, j)` of patch `pi`'s own block at depth-`d` grid coordinates,
    /// where `d` may be the patch depth or one more (for fan centres and subdivided edges):
    /// `scale` = 1 for patch-depth coordinates, 2 for one level finer.
    #[inline]
    fn own(&self, pi: usize, i: u32, j: u32, d_coords: u32) -> u32 {
        let b = &self.blocks[pi];
        debug_assert!(b.depth >= d_coords as i32, "block too coarse");
        let stride = 1u32 << (b.depth as u32 - d_coords);
        let w = (1u32 << b.depth) + 1;
        self.block_start[pi] + j * stride * w + i * stride
    }

    fn patch_index(&self, unit: usize, sub: usize) -> usize {
        (self.set.units()[unit].first_patch as usize) + sub
    }

    /// Id of cage vertex `v` (through its owner unit).
    fn vertex_id(&self, v: VertexId) -> u32 {
        let (f, k) = self.vertex_owner[v.idx()];
        let u = f as usize;
        let unit = &self.set.units()[u];
        if unit.irregular {
            let pi = self.patch_index(u, k as usize);
            return self.own(pi, 0, 0, 0);
        }
        let pi = self.patch_index(u, 0);
        let d = self.depth[u] as u32;
        let n = 1u32 << d;
        let (i, j) = [(0, 0), (n, 0), (n, n), (0, n)][k as usize];
        self.own(pi, i, j, d)
    }

    /// Id of the point at parameter `t / 2^res` along half-edge `h` (from its start), where
    /// `res` is at most the edge's resolution this frame; `t` in `0..=2^res`.
    fn edge_point_id(&self, h: HalfedgeId, t: u32, res: u32) -> u32 {
        let mesh = self.mesh;
        if t == 0 {
            return self.vertex_id(mesh.from(h));
        }
        if t == 1 << res {
            return self.vertex_id(mesh.to(h));
        }
        let e = h.edge();
        let r = self.edge_res[e.idx()] as u32;
        debug_assert!(res <= r);
        let t = t << (r - res);
        let owner = self.edge_owner[e.idx()] as usize;
        let hs = &self.units[owner].hs;
        // The owner's half-edge of this edge, and the parameter along it.
        let (k, th) = match hs.iter().position(|&x| x == h) {
            Some(k) => (k, t),
            None => (
                hs.iter().position(|&x| x == h.twin()).unwrap_or(0),
                (1 << r) - t,
            ),
        };
        let unit = &self.set.units()[owner];
        if !unit.irregular {
            let pi = self.patch_index(owner, 0);
            let n = 1u32 << r;
            let (i, j) = side_point(k, th, n);
            return self.own(pi, i, j, r);
        }
        let ns = 1u32 << (r - 1);
        let nsub = hs.len();
        if th <= ns {
            let pi = self.patch_index(owner, k);
            let (i, j) = side_point(0, th, ns);
            self.own(pi, i, j, r - 1)
        } else {
            let pi = self.patch_index(owner, (k + 1) % nsub);
            let (i, j) = side_point(3, th - ns, ns);
            self.own(pi, i, j, r - 1)
        }
    }

    /// Id of grid point `(i, j)` (patch-depth coordinates) of patch `p`, through the owners of
    /// shared points. `fine` > 0 means coordinates one level finer (only for points on fanned
    /// sides, which are owned by the deeper neighbour, or the patch's own interior).
    fn point_id(&self, pi: usize, p: &PatchRef, i: u32, j: u32) -> u32 {
        let d = self.patch_depth(p);
        let n = 1u32 << d;
        let interior = i > 0 && i < n && j > 0 && j < n;
        if interior {
            return self.own(pi, i, j, d);
        }
        let u = p.unit as usize;
        let hs = &self.units[u].hs;
        let (k, s) = side_of(i, j, n);
        if p.level == 0 {
            return self.edge_point_id(hs[k], s, d);
        }
        // Level-1 patch: sides 0 and 3 are halves of cage edges, 1 and 2 inner edges of the unit.
        let nsub = hs.len();
        let sub = p.sub as usize;
        let ud = d + 1;
        match k {
            0 => self.edge_point_id(hs[sub], s, ud),
            3 => self.edge_point_id(hs[(sub + nsub - 1) % nsub], n + s, ud),
            1 => {
                // Inner edge `sub`, owned by this patch (s from the edge point to the face point);
                // its start is the midpoint of cage edge `sub`, owned through that edge.
                if s == 0 {
                    self.edge_point_id(hs[sub], n, ud)
                } else if s == n {
                    self.face_point_id(u)
                } else {
                    self.own(pi, i, j, d)
                }
            }
            _ => {
                // Side 2 runs from the face point to the previous inner edge's edge point.
                if s == 0 {
                    return self.face_point_id(u);
                }
                let prev = self.patch_index(u, (sub + nsub - 1) % nsub);
                let (pi2, pj2) = side_point(1, n - s, n);
                self.own(prev, pi2, pj2, d)
            }
        }
    }

    fn face_point_id(&self, u: usize) -> u32 {
        let pi = self.patch_index(u, 0);
        let d = self.depth[u] as u32 - 1;
        let n = 1u32 << d;
        self.own(pi, n, n, d)
    }

    /// The triangles of one patch.
    fn emit_patch(&self, p: &PatchRef, method: FanMethod, out: &mut Vec<u32>) {
        let pi = self.patch_index(p.unit as usize, p.sub as usize);
        let d = self.patch_depth(p);
        let n = 1u32 << d;
        let fans = self.fans(p);
        let replaced = |i: u32, j: u32| -> bool {
            (fans[0] && j == 0)
                || (fans[1] && i == n - 1)
                || (fans[2] && j == n - 1)
                || (fans[3] && i == 0)
        };
        let any = fans.iter().any(|&x| x);
        let id = |i: u32, j: u32| self.point_id(pi, p, i, j);
        let mut poly: Vec<u32> = Vec::with_capacity(16);
        for j in 0..n {
            for i in 0..n {
                if !(any && replaced(i, j)) {
                    let (a, b, c, e) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                    out.extend_from_slice(&[a, b, c, a, c, e]);
                    continue;
                }
                // Fan around the limit point of the quad's next-level face point.
                let centre = self.own(pi, 2 * i + 1, 2 * j + 1, d + 1);
                poly.clear();
                // The quad's four edges, counter-clockwise: bottom, right, top, left; each from
                // its start corner (inclusive) to its end corner (exclusive).
                let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                for (ek, &(ci, cj)) in corners.iter().enumerate() {
                    poly.push(id(ci, cj));
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
                        if oi < n && oj < n && replaced(oi, oj) {
                            poly.push(self.own(pi, ci + ni, cj + nj, d + 1));
                        }
                    }
                }
                for k in 0..poly.len() {
                    out.extend_from_slice(&[centre, poly[k], poly[(k + 1) % poly.len()]]);
                }
            }
        }
    }

    /// The deeper neighbour's points strictly between two corners of a border quad on side `k`.
    #[allow(clippy::too_many_arguments)]
    fn push_fine_points(
        &self,
        p: &PatchRef,
        pi: usize,
        k: usize,
        a: (u32, u32),
        b: (u32, u32),
        n: u32,
        poly: &mut Vec<u32>,
    ) {
        let _ = pi;
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
        if t1 > t0 {
            for t in t0 + 1..t1 {
                poly.push(self.edge_point_id(h, t, r));
            }
        } else {
            for t in (t1 + 1..t0).rev() {
                poly.push(self.edge_point_id(h, t, r));
            }
        }
    }
}

/// Grid coordinates of the point at parameter `s` along side `k` of an `n`-grid (sides run
/// counter-clockwise from corner `k` to corner `k + 1`).
#[inline]
fn side_point(k: usize, s: u32, n: u32) -> (u32, u32) {
    match k {
        0 => (s, 0),
        1 => (n, s),
        2 => (n - s, n),
        _ => (0, n - s),
    }
}

/// Side and parameter of a border point (corners belong to the side they start).
#[inline]
fn side_of(i: u32, j: u32, n: u32) -> (usize, u32) {
    if j == 0 && i < n {
        (0, i)
    } else if i == n && j < n {
        (1, j)
    } else if j == n && i > 0 {
        (2, n - i)
    } else {
        (3, n - j)
    }
}

/// Parameter of a point known to lie on side `k` (corners included, either end).
#[inline]
fn side_of_on(k: usize, i: u32, j: u32, n: u32) -> (usize, u32) {
    match k {
        0 => (0, i),
        1 => (1, j),
        2 => (2, n - i),
        _ => (3, n - j),
    }
}
