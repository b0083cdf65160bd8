//! The per-frame [`Assembler`] and its per-patch block cache (Section 4): each patch keeps its
//! limit points in a block computed at some depth `c`; while the patch's depth does not rise
//! above `c` the block is reused (sampled with stride `2^(c - d)`), and only the index buffer is
//! rebuilt.

use std::collections::HashMap;

use rayon::prelude::*;
use subdiv_mesh::{HalfedgeId, Mesh};
use subdiv_rules::{Budget, Request, Scheme, TriangleBuffers, VertexScalar};
use subdiv_slate::{Depth, LevelUvs, MAX_DEPTH, PatchGrids, PatchSet};

use super::edges::{Frame, halfedge_sides};
use super::geometry::{AdaptiveFrame, UpdateParts, lap};
use super::index::{Chunk, FanMethod, run_dependencies};
use crate::AssemblyError;
use crate::slots::Slots;

/// The deepest face depth the assembler accepts: one below [`MAX_DEPTH`], since a patch next to a
/// deeper one is computed one level deeper for its fan centres and subdivided edges.
pub const MAX_ADAPTIVE_DEPTH: Depth = MAX_DEPTH - 1;

/// A patch's cached limit points.
#[derive(Clone, Debug, Default)]
pub(super) struct Block {
    /// Depth the block was computed at (`None`: never).
    pub(super) depth: Option<Depth>,
    pub(super) pos: Vec<[f32; 3]>,
    pub(super) nrm: Vec<[f32; 3]>,
    /// The patch's own one-sided limit normals at its border points on creases and corners:
    /// (index in `pos`, normal), ascending (`PatchGrids::grid`).
    pub(super) sided: Vec<(u32, [f32; 3])>,
    /// Which computation this is: unique among the assembler's blocks (0: none yet), so that
    /// a run of patches' triangles can tell whether a block they read was replaced.
    pub(super) stamp: u64,
}

impl Block {
    /// The patch's own one-sided normal at block index `k`, if the point has one.
    pub(super) fn sided_at(&self, k: u32) -> Option<[f32; 3]> {
        self.sided
            .binary_search_by_key(&k, |&(i, _)| i)
            .ok()
            .map(|x| self.sided[x].1)
    }
}

/// Per-unit topology: its half-edges, in face order, and which of its corners are pinched.
#[derive(Clone, Debug)]
pub(super) struct UnitTopo {
    pub(super) hs: Vec<HalfedgeId>,
    /// Per corner `k` (the start of `hs[k]`): another face has a corner between the same two
    /// edges, so the two faces' corner quads share all three of their border points there
    /// ([`pinched_corners`]).
    pub(super) pinched: Vec<bool>,
}

/// Per unit (its half-edges `units[u]`) and corner `k` (the start of `hs[k]`): whether another
/// face has a corner between the same two edges. On a manifold cage that is an interior vertex
/// of valence 2 (the face across side `k` is also the face across side `k - 1`); on a
/// non-manifold one also a face of another piece whose sides there are copies of the same two
/// non-manifold edges (`SeamCurves::groups`), whose points are the same bits. A lone boundary
/// corner is not pinched: nothing lies across it.
fn pinched_corners(mesh: &Mesh, set: &PatchSet, units: &[Vec<HalfedgeId>]) -> Vec<Vec<bool>> {
    let ne = mesh.num_edges() as u32;
    // Each edge's class: itself, or its seam (all copies of one non-manifold edge).
    let mut class: Vec<u32> = (0..ne).collect();
    for (g, copies) in set.seams().groups().iter().enumerate() {
        for e in copies {
            class[e.idx()] = ne + g as u32;
        }
    }
    let key = |hs: &[HalfedgeId], k: usize| {
        let a = class[hs[(k + hs.len() - 1) % hs.len()].edge().idx()];
        let b = class[hs[k].edge().idx()];
        (a.min(b), a.max(b))
    };
    let mut count: HashMap<(u32, u32), u32> = HashMap::new();
    for hs in units {
        for k in 0..hs.len() {
            *count.entry(key(hs, k)).or_default() += 1;
        }
    }
    units
        .iter()
        .map(|hs| {
            (0..hs.len())
                .map(|k| count.get(&key(hs, k)).is_some_and(|&c| c > 1))
                .collect()
        })
        .collect()
}

/// The adaptive assembler: per-mesh patch structure plus the per-patch block cache.
#[derive(Debug)]
pub struct Assembler {
    set: PatchSet,
    units: Vec<UnitTopo>,
    /// Per half-edge: its side in its unit ([`halfedge_sides`]).
    side: Vec<u8>,
    /// The index emission's per-run buffers, kept between frames.
    chunks: Vec<Chunk>,
    /// Per run of patches: the units its triangles read ([`run_dependencies`]).
    pub(super) deps: Vec<Vec<u32>>,
    /// The last block stamp handed out.
    stamps: u64,
    /// Runs of the last frame that kept their triangles.
    pub(super) runs_kept: usize,
    blocks: Vec<Block>,
    /// Where each block's points live in the frame's vertex buffer.
    slots: Slots,
    /// The vertex ranges the last frame rewrote.
    dirty: Vec<std::ops::Range<u32>>,
    version: u64,
    max_depth: Depth,
    method: FanMethod,
    /// The cage's face-varying limit values, at the deepest level a frame has needed so far.
    uvs: Option<LevelUvs>,
    /// Catmull-Clark, or bilinear (the patch set's).
    scheme: Scheme,
}

impl Assembler {
    /// Sets up the patches of `mesh`. `max_depth` is the deepest depth that will be requested;
    /// it is at most [`MAX_ADAPTIVE_DEPTH`] (a patch next to a deeper one is computed one level
    /// deeper for its fan centres). A cage whose frames could be beyond this machine's memory
    /// with every face at `max_depth` is refused with [`AssemblyError::OutputTooLarge`].
    pub fn new(mesh: &Mesh, max_depth: Depth) -> Result<Assembler, AssemblyError> {
        Assembler::with_budget(mesh, max_depth, &Budget::machine())
    }

    /// [`Assembler::new`] checked against `budget` instead of this machine's memory
    /// ([`Budget::unlimited`]: frames are still refused one by one beyond [`MAX_POINTS`]).
    ///
    /// [`MAX_POINTS`]: subdiv_slate::MAX_POINTS
    pub fn with_budget(
        mesh: &Mesh,
        max_depth: Depth,
        budget: &Budget,
    ) -> Result<Assembler, AssemblyError> {
        Assembler::with_scheme(mesh, Scheme::CatmullClark, max_depth, budget)
    }

    /// [`Assembler::new`] for the bilinear surface of `mesh`: its patches
    /// ([`PatchSet::bilinear`]) meet with a crease at every edge, so every fan corner on a patch
    /// border takes its own patch's normal.
    pub fn bilinear(mesh: &Mesh, max_depth: Depth) -> Result<Assembler, AssemblyError> {
        Assembler::with_scheme(mesh, Scheme::Bilinear, max_depth, &Budget::machine())
    }

    /// `scheme` is Catmull-Clark or bilinear (Loop has [`crate::TriAssembler`]).
    fn with_scheme(
        mesh: &Mesh,
        scheme: Scheme,
        max_depth: Depth,
        budget: &Budget,
    ) -> Result<Assembler, AssemblyError> {
        if max_depth > MAX_ADAPTIVE_DEPTH {
            return Err(AssemblyError::TooDeep {
                depth: max_depth,
                max: MAX_ADAPTIVE_DEPTH,
            });
        }
        // Refuse before allocating: every face at the maximum depth beyond the budget.
        budget.check(mesh, Request::Adaptive { scheme, max_depth })?;
        let set = match scheme {
            Scheme::Bilinear => PatchSet::bilinear(mesh)?,
            _ => PatchSet::new(mesh)?,
        };
        let halfedges: Vec<Vec<HalfedgeId>> = set
            .units()
            .iter()
            .map(|u| mesh.face_halfedges(u.face).collect())
            .collect();
        let pinched = pinched_corners(mesh, &set, &halfedges);
        let units: Vec<UnitTopo> = halfedges
            .into_iter()
            .zip(pinched)
            .map(|(hs, pinched)| UnitTopo { hs, pinched })
            .collect();
        let n = set.patches().len();
        let side = halfedge_sides(mesh, &units);
        let deps = run_dependencies(mesh, &set);
        Ok(Assembler {
            set,
            units,
            side,
            chunks: Vec::new(),
            deps,
            stamps: 0,
            runs_kept: 0,
            blocks: vec![
                Block {
                    depth: None,
                    ..Default::default()
                };
                n
            ],
            slots: Slots::new(n),
            dirty: Vec::new(),
            version: 0,
            max_depth,
            method: FanMethod::Subdivided,
            uvs: None,
            scheme,
        })
    }

    /// The frame data (edge resolutions, owners, point ids) of `depth` and `active` over the
    /// blocks as cached.
    pub(super) fn frame_data<'a>(
        &'a self,
        mesh: &'a Mesh,
        depth: &'a [Depth],
        active: &'a [bool],
    ) -> Frame<'a> {
        Frame::new(
            mesh,
            &self.set,
            &self.units,
            &self.side,
            depth,
            active,
            &self.blocks,
            &self.slots,
        )
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
    pub fn min_depth(&self, unit: usize) -> Depth {
        self.set.units()[unit].irregular as Depth
    }

    /// The deepest unit depth every patch of `unit` has cached (`None`: some patch has
    /// nothing): drawing the unit at most that deep tessellates nothing.
    pub fn cached_depth(&self, unit: usize) -> Option<Depth> {
        let u = &self.set.units()[unit];
        let level = u.irregular as Depth;
        let first = u.first_patch as usize;
        self.blocks[first..first + u.patch_count as usize]
            .iter()
            .map(|b| b.depth.map(|d| d + level))
            .min()
            .flatten()
    }

    /// Quads of the patch grids per depth in frame `g` (index = depth), before the fans that
    /// join different depths: what Settgast et al. Fig. 6 counts. A unit at depth `d` has
    /// `4^d` quads, a level-1 unit of `n` patches `n * 4^(d - 1)`; undrawn units count nothing.
    pub fn quads_per_depth(&self, g: &AdaptiveFrame) -> Vec<u64> {
        let mut v = Vec::new();
        for (unit, &d) in self.set.units().iter().zip(g.unit_depth()) {
            if d == u8::MAX {
                continue;
            }
            if v.len() <= d as usize {
                v.resize(d as usize + 1, 0);
            }
            let level = unit.irregular as u32;
            v[d as usize] += unit.patch_count as u64 * 4u64.pow((d as u32).saturating_sub(level));
        }
        v
    }

    /// After the cage's positions moved (its topology the same): the local level-1 points follow
    /// ([`PatchSet::move_to`]) and every cached block is dropped; the patches stay.
    pub fn move_to(&mut self, mesh: &Mesh) {
        self.set.move_to(mesh);
        self.invalidate();
    }

    /// Drops all cached blocks (e.g. after the mesh's positions changed).
    pub fn invalidate(&mut self) {
        for b in &mut self.blocks {
            b.depth = None;
        }
        // The face-varying values do not depend on the positions: kept.
    }

    /// Builds a frame: `depth[u]` per unit (cage face; clamped to `min_depth..=max_depth`) and
    /// `active[u]` (units not drawn, e.g. culled or holes, are `false`).
    pub fn frame(
        &mut self,
        mesh: &Mesh,
        depth: &[Depth],
        active: &[bool],
        out: &mut AdaptiveFrame,
    ) -> Result<(), AssemblyError> {
        let nu = self.set.units().len();
        if depth.len() != nu || active.len() != nu {
            return Err(AssemblyError::Length {
                what: "depth/active",
                got: depth.len().min(active.len()),
                want: nu,
            });
        }
        let mut t = std::time::Instant::now();
        let depth: Vec<Depth> = (0..nu)
            .map(|u| depth[u].clamp(self.min_depth(u), self.max_depth))
            .collect();
        let required = self.required_depths(mesh, &depth, active);
        self.check_size(&required)?;
        let mut stitch = lap(&mut t);
        let (changed, points) = self.recompute_blocks(mesh, &required);
        let tessellate = lap(&mut t);
        let relink = !changed.is_empty() || out.surface.num_vertices() == 0;
        self.dirty.clear();
        out.surface.write_triangles(VertexScalar::Depth, |b| {
            self.write_frame(
                mesh,
                &depth,
                active,
                relink.then_some(&changed),
                b,
                &mut stitch,
            )
        })??;
        let buffers = lap(&mut t) - stitch;
        out.set_bookkeeping(self.version, (changed.len(), points), &depth, active);
        out.dirty.clone_from(&self.dirty);
        out.parts = UpdateParts {
            depths: 0.0,
            tessellate,
            stitch,
            buffers,
        };
        Ok(())
    }

    /// Writes the frame's surface into `b`: with `changed`, the blocks recomputed this frame
    /// into their slots of the vertex buffer; the vertex depths, the face-varying values and
    /// the triangles; adds the time the index buffer took to `stitch`.
    fn write_frame(
        &mut self,
        mesh: &Mesh,
        depth: &[Depth],
        active: &[bool],
        changed: Option<&Vec<usize>>,
        b: &mut TriangleBuffers<'_>,
        stitch: &mut f64,
    ) -> Result<(), AssemblyError> {
        if let Some(changed) = changed {
            let blocks = &self.blocks;
            let block = |i: usize| (&blocks[i].pos[..], &blocks[i].nrm[..]);
            self.slots.write(b, block, changed, &mut self.dirty)?;
            self.version += 1;
        }
        self.fill_vertex_depth(depth, b);
        // Face-varying values: every corner's point lies on a grid at most one level below the
        // deepest drawn unit (fan centres, subdivided edges).
        let deepest = (0..depth.len())
            .filter(|&u| active[u])
            .map(|u| depth[u])
            .max();
        if let (true, Some(d)) = (mesh.uv().is_some(), deepest) {
            let level = d + 1;
            if self.uvs.as_ref().is_none_or(|u| u.level() < level) {
                self.uvs = LevelUvs::new(mesh, self.scheme, level)?;
                b.uvs.clear();
            }
            if b.uvs.is_empty() {
                *b.uvs = self
                    .uvs
                    .as_ref()
                    .map(|u| u.values.clone())
                    .unwrap_or_default();
            }
        }
        let uvs = match (mesh.uv().is_some(), deepest) {
            (true, Some(_)) => self.uvs.as_ref(),
            _ => None,
        };
        // Index buffer: each patch's triangles, in parallel, then concatenated in patch order.
        let t = std::time::Instant::now();
        let mut chunks = std::mem::take(&mut self.chunks);
        let kept = self.frame_data(mesh, depth, active).emit_frame(
            active,
            self.method,
            uvs,
            Some(&self.deps),
            &mut chunks,
            b.triangles,
            b.corner_normals,
            b.uv_indices,
        );
        (self.chunks, self.runs_kept) = (chunks, kept);
        *stitch += t.elapsed().as_secs_f64();
        Ok(())
    }

    /// Required depth per patch: its own, plus one where it must fan towards a deeper side
    /// (`None` for inactive patches). A side fanned towards a deeper unit across a sharp cage
    /// edge (every edge of a bilinear cage) needs the deeper side's resolution: the fans there
    /// use this patch's own one-sided normals at the deeper points of the crease.
    fn required_depths(&self, mesh: &Mesh, depth: &[Depth], active: &[bool]) -> Vec<Option<Depth>> {
        let fr = self.frame_data(mesh, depth, active);
        let bilinear = self.scheme == Scheme::Bilinear;
        self.set
            .patches()
            .iter()
            .map(|p| {
                active[p.unit as usize].then(|| {
                    let fans = fr.fans(p);
                    let own = fr.patch_depth(p) as Depth + Depth::from(fans.iter().any(|&x| x));
                    let crease = (0..4)
                        .filter(|&k| fans[k])
                        .filter_map(|k| fr.side_edge(p, k))
                        .filter(|e| bilinear || mesh.edge_sharpness(*e) > 0.0)
                        .map(|e| fr.edge_res[e.idx()] - p.level)
                        .max()
                        .unwrap_or(0);
                    own.max(crease)
                })
            })
            .collect()
    }

    /// Refuses frames whose blocks would not fit in memory.
    fn check_size(&self, required: &[Option<Depth>]) -> Result<(), AssemblyError> {
        let total: u64 = (0..required.len())
            .map(|i| match required[i].max(self.blocks[i].depth) {
                None => 0,
                Some(d) => ((1u64 << d) + 1).pow(2),
            })
            .sum();
        if total > subdiv_slate::MAX_POINTS {
            return Err(AssemblyError::TooLarge { points: total });
        }
        Ok(())
    }

    /// Recomputes the blocks that are too coarse for `required`; returns which (ascending),
    /// and their points. A recomputed block reuses the buffers of the block it replaces.
    fn recompute_blocks(&mut self, mesh: &Mesh, required: &[Option<Depth>]) -> (Vec<usize>, usize) {
        let todo: Vec<usize> = (0..required.len())
            .filter(|&i| required[i] > self.blocks[i].depth)
            .collect();
        let set = &self.set;
        let max_depth = self.max_depth + 1;
        let mut fresh: Vec<(usize, Block)> = todo
            .iter()
            .map(|&i| (i, std::mem::take(&mut self.blocks[i])))
            .collect();
        fresh.par_iter_mut().for_each_init(
            || PatchGrids::new(mesh, set, max_depth),
            |grids, (i, b)| {
                let p = &set.patches()[*i];
                // Only patches with a required depth are recomputed (`None` is below any).
                let d = required[*i].unwrap_or_default();
                let n = (1usize << d) + 1;
                b.depth = Some(d);
                for v in [&mut b.pos, &mut b.nrm] {
                    v.clear();
                    v.resize(n * n, [0.0; 3]);
                }
                grids.grid(p, d, &mut b.pos, &mut b.nrm, &mut b.sided);
                // Seam points from their chains: the copies of a non-manifold edge, in
                // different pieces and blocks, agree to the bit.
                set.write_seam_points(mesh, p, d, &mut b.pos);
            },
        );
        let points = fresh.iter().map(|(_, b)| b.pos.len()).sum();
        for (i, mut b) in fresh.drain(..) {
            self.stamps += 1;
            b.stamp = self.stamps;
            self.blocks[i] = b;
        }
        (todo, points)
    }

    /// The last frame's vertex buffer for the cage `stand_in` (this assembler's cage with other
    /// positions: a vertex primvar's values standing in for them, three floats at a time): each
    /// block the frame draws recomputed at its depth from `stand_in`, point for point where the
    /// frame holds its points. Linear data thereby gets the positions' limit masks
    /// ([`crate::frame_primvars`]).
    pub fn stand_in_points(&self, stand_in: &Mesh) -> Vec<[f32; 3]> {
        let mut set = self.set.clone();
        set.move_to(stand_in);
        let set = &set;
        let max_depth = self.max_depth + 1;
        let blocks: Vec<Vec<[f32; 3]>> = (0..self.blocks.len())
            .into_par_iter()
            .map_init(
                || PatchGrids::new(stand_in, set, max_depth),
                |grids, i| match self.blocks[i].depth {
                    Some(d) if self.slots.holds(i) => {
                        let p = &set.patches()[i];
                        let n = (1usize << d) + 1;
                        let mut pos = vec![[0.0; 3]; n * n];
                        let (mut nrm, mut sided) = (vec![[0.0; 3]; n * n], Vec::new());
                        grids.grid(p, d, &mut pos, &mut nrm, &mut sided);
                        set.write_seam_points(stand_in, p, d, &mut pos);
                        pos
                    }
                    _ => Vec::new(),
                },
            )
            .collect();
        self.slots.gather(|i| &blocks[i])
    }

    /// The face-varying values of the last frame (`frame`, made by this assembler) for the cage
    /// `stand_in` (this cage with other face-varying data: a face-varying primvar's values
    /// standing in for its UVs): the values at the level the frame needs and the value of every
    /// corner of the frame's triangles, looked up as the frame's own UVs are
    /// ([`crate::frame_primvars`]).
    pub fn stand_in_corner_values(
        &self,
        stand_in: &Mesh,
        frame: &AdaptiveFrame,
    ) -> Result<(Vec<[f32; 2]>, Vec<u32>), AssemblyError> {
        // Every corner's point lies on a grid at most one level below the deepest unit.
        let Some((depth, active, uvs)) = frame.stand_in_uvs(stand_in, self.scheme, 1)? else {
            return Ok((Vec::new(), Vec::new()));
        };
        let fr = self.frame_data(stand_in, &depth, &active);
        let (mut chunks, mut tris, mut sided, mut corners) = Default::default();
        fr.emit_frame(
            &active,
            self.method,
            Some(&uvs),
            None,
            &mut chunks,
            &mut tris,
            &mut sided,
            &mut corners,
        );
        check_corners(&tris, frame)?;
        Ok((uvs.values, corners))
    }

    /// Depth per vertex (of the patch whose block holds it, at this frame's depth).
    fn fill_vertex_depth(&self, depth: &[Depth], b: &mut TriangleBuffers<'_>) {
        b.scalar.clear();
        b.scalar.resize(b.positions.len(), 0.0);
        for (i, p) in self.set.patches().iter().enumerate() {
            let d = depth[p.unit as usize] as f32;
            b.scalar[self.slots.range(i)].fill(d);
        }
    }
}

/// That `tris`, emitted again for other face-varying data, are `frame`'s triangles.
pub(crate) fn check_corners(tris: &[u32], frame: &AdaptiveFrame) -> Result<(), AssemblyError> {
    if tris != frame.surface.face_indices() {
        return Err(AssemblyError::Length {
            what: "face-varying corners of the frame emitted again",
            got: tris.len(),
            want: frame.surface.face_indices().len(),
        });
    }
    Ok(())
}

#[cfg(test)]
#[path = "assembler_tests.rs"]
mod tests;
