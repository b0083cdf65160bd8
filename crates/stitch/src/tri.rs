//! Crack-free assembly of Loop's triangular patches tessellated at different depths: Settgast et
//! al. §3.3 adapted to triangles.
//!
//! Every cage triangle is a patch with a depth per frame. A cage edge is drawn at the resolution
//! of its deeper side, and its points are written once, by that side (its *owner*; on equal
//! depths the owner of the uniform [`TriLayout`]); a cage vertex is written by one active patch
//! around it (the layout's owner when it is drawn). Since depths are powers of two apart, the
//! coarser side's points along the edge are a subset of the finer side's: the coarser patch keeps
//! its lattice triangles inside and replaces each triangle with an edge on a finer side by a fan
//! from the triangle's opposite lattice point through the finer side's own points (a corner
//! triangle with two finer sides is a strip between the two point rows; a depth-0 patch with
//! three finer sides is split at the side midpoints first, which the finer sides hold). No
//! extra points are evaluated, so every drawn point is a point of some patch's uniform lattice.
//!
//! Caching (Section 4): a patch keeps its lattice computed at some depth `c` and reuses it
//! (sampled with stride `2^(c - d)`) while its required depth stays at or below `c`.
//!
//! **Invariants.** Watertight to the bit: every point on a cage edge or vertex is referenced
//! through its one owner, so both sides of a border reference the same vertex; after welding
//! equal coordinates every interior edge has exactly two triangles and the open edges are the
//! cage's boundary. A freshly computed patch at depth `d` holds exactly the points of
//! `tessellate_tri` at depth `d` that the uniform layout lets it own.

mod emit;

use rayon::prelude::*;
use subdiv_mesh::Mesh;
use subdiv_rules::{Budget, Request, Scheme, TriangleBuffers, VertexScalar};
use subdiv_slate::{Depth, LevelUvs, MAX_DEPTH, TriLayout, tri_lattice_len, tri_patch_lattice};

use crate::fans::lap;
use crate::runs::{Emitted, RunOut};
use crate::slots::Slots;
use crate::{AdaptiveFrame, AssemblyError, UpdateParts};
use emit::TriFrame;

/// A patch's cached lattice.
#[derive(Clone, Debug, Default)]
pub(crate) struct TriBlock {
    /// Depth the lattice was computed at (`None`: never).
    pub(crate) depth: Option<Depth>,
    pub(crate) pos: Vec<[f32; 3]>,
    pub(crate) nrm: Vec<[f32; 3]>,
    /// One-sided normals of this patch at its border points (lattice index, normal), ascending.
    pub(crate) sided: Vec<(u32, [f32; 3])>,
    /// Which computation this is: unique among the assembler's lattices (0: none yet), so
    /// that a run of faces' triangles can tell whether a lattice they read was replaced.
    pub(crate) stamp: u64,
}

/// The adaptive assembler of Loop cages (triangles only): per-face patches, their lattice
/// cache, and the frame's index buffer with fans between depths.
#[derive(Debug)]
pub struct TriAssembler {
    layout: TriLayout,
    blocks: Vec<TriBlock>,
    /// Where each lattice's points live in the frame's vertex buffer.
    slots: Slots,
    /// The vertex ranges the last frame rewrote.
    dirty: Vec<std::ops::Range<u32>>,
    version: u64,
    max_depth: Depth,
    /// The cage's face-varying limit values, kept while frames need no finer level.
    uvs: Option<LevelUvs>,
    /// The index emission's runs, kept between frames, and per run the faces its triangles
    /// read ([`emit::run_dependencies`]).
    runs: Vec<RunOut>,
    deps: Vec<Vec<u32>>,
    /// The last lattice stamp handed out.
    stamps: u64,
    /// Runs of the last frame that kept their triangles.
    pub(crate) runs_kept: usize,
}

impl TriAssembler {
    /// Sets up the patches of `mesh` (triangles only; what Loop refuses is a
    /// [`AssemblyError::Rules`]); `max_depth` is the deepest depth that will be requested, at
    /// most [`MAX_DEPTH`]. A cage whose frames could be beyond this machine's memory with every
    /// face at `max_depth` is refused with [`AssemblyError::OutputTooLarge`].
    pub fn new(mesh: &Mesh, max_depth: Depth) -> Result<TriAssembler, AssemblyError> {
        TriAssembler::with_budget(mesh, max_depth, &Budget::machine())
    }

    /// [`TriAssembler::new`] checked against `budget` instead of this machine's memory.
    pub fn with_budget(
        mesh: &Mesh,
        max_depth: Depth,
        budget: &Budget,
    ) -> Result<TriAssembler, AssemblyError> {
        if max_depth > MAX_DEPTH {
            return Err(AssemblyError::TooDeep {
                depth: max_depth,
                max: MAX_DEPTH,
            });
        }
        // Refuse before allocating: every face at the maximum depth beyond the budget.
        budget.check(
            mesh,
            Request::Adaptive {
                scheme: Scheme::Loop,
                max_depth,
            },
        )?;
        let layout = TriLayout::new(mesh, 1)?;
        let n = layout.patches().len();
        let deps = emit::run_dependencies(&layout, mesh);
        Ok(TriAssembler {
            layout,
            blocks: vec![TriBlock::default(); n],
            slots: Slots::new(n),
            dirty: Vec::new(),
            version: 0,
            max_depth,
            uvs: None,
            runs: Vec::new(),
            deps,
            stamps: 0,
            runs_kept: 0,
        })
    }

    /// The patches' topology (a uniform layout; its point ids are not used).
    pub fn layout(&self) -> &TriLayout {
        &self.layout
    }

    /// The depth of face `f`'s cached lattice (`None`: none): drawing the face at most that
    /// deep tessellates nothing.
    pub fn cached_depth(&self, f: usize) -> Option<Depth> {
        self.blocks.get(f).and_then(|b| b.depth)
    }

    /// Drops all cached lattices (e.g. after the mesh's positions changed).
    pub fn invalidate(&mut self) {
        for b in &mut self.blocks {
            b.depth = None;
        }
        // The face-varying values do not depend on the positions: kept.
    }

    /// Triangles of the patch lattices per depth in frame `g` (index = depth): `4^d` per drawn
    /// face, before the fans that join different depths.
    pub fn triangles_per_depth(&self, g: &AdaptiveFrame) -> Vec<u64> {
        let mut v = Vec::new();
        for &d in g.unit_depth() {
            if d == u8::MAX {
                continue;
            }
            if v.len() <= d as usize {
                v.resize(d as usize + 1, 0);
            }
            v[d as usize] += 1u64 << (2 * d as u32);
        }
        v
    }

    /// Builds a frame: `depth[f]` per cage face (clamped to `0..=max_depth`) and `active[f]`
    /// (faces not drawn, e.g. culled, are `false`; holes, among them the faces
    /// `interpolateboundary none` hides, are never drawn).
    pub fn frame(
        &mut self,
        mesh: &Mesh,
        depth: &[Depth],
        active: &[bool],
        out: &mut AdaptiveFrame,
    ) -> Result<(), AssemblyError> {
        let nf = self.layout.patches().len();
        if depth.len() != nf || active.len() != nf {
            return Err(AssemblyError::Length {
                what: "depth/active",
                got: depth.len().min(active.len()),
                want: nf,
            });
        }
        let mut t = std::time::Instant::now();
        let depth: Vec<Depth> = depth.iter().map(|&d| d.min(self.max_depth)).collect();
        let active: Vec<bool> = (0..nf)
            .map(|f| active[f] && self.layout.patches()[f].visible)
            .collect();
        let owners = emit::Owners::new(mesh, &self.layout, &depth, &active);
        let required = owners.required_depths(mesh, &self.layout, &depth, &active);
        self.check_size(&required)?;
        let mut stitch = lap(&mut t);
        let (changed, points) = self.recompute_blocks(mesh, &required);
        let tessellate = lap(&mut t);
        let relink = !changed.is_empty() || out.surface.num_vertices() == 0;
        self.dirty.clear();
        out.surface.write_triangles(VertexScalar::Depth, |b| {
            let changed = relink.then_some(&changed);
            self.write_frame(mesh, &depth, &active, &owners, changed, b, &mut stitch)
        })??;
        let buffers = lap(&mut t) - stitch;
        out.set_bookkeeping(self.version, (changed.len(), points), &depth, &active);
        out.dirty.clone_from(&self.dirty);
        out.parts = UpdateParts {
            depths: 0.0,
            tessellate,
            stitch,
            buffers,
        };
        Ok(())
    }

    /// Writes the frame's surface into `b`: with `changed`, the lattices recomputed this frame
    /// into their slots of the vertex buffer; the vertex depths, the face-varying values and
    /// the triangles; adds the time the index buffer took to `stitch`.
    #[allow(clippy::too_many_arguments)]
    fn write_frame(
        &mut self,
        mesh: &Mesh,
        depth: &[Depth],
        active: &[bool],
        owners: &emit::Owners,
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
        b.scalar.clear();
        b.scalar.resize(b.positions.len(), 0.0);
        for (f, &d) in depth.iter().enumerate() {
            b.scalar[self.slots.range(f)].fill(d as f32);
        }
        let with_uvs = self.level_uvs(mesh, depth, active, b.uvs)?;
        let uvs = self.uvs.as_ref().filter(|_| with_uvs);
        let fr = TriFrame {
            layout: &self.layout,
            depth,
            owners,
            blocks: &self.blocks,
            slots: &self.slots,
        };
        let t = std::time::Instant::now();
        self.runs_kept = fr.emit_frame(
            active,
            uvs,
            Some(&self.deps),
            &mut self.runs,
            b.triangles,
            b.corner_normals,
            b.uv_indices,
        );
        *stitch += t.elapsed().as_secs_f64();
        Ok(())
    }

    /// Readies `self.uvs`, the face-varying limit values for this frame, refined again only when
    /// a deeper level than the cached one is needed, with their values in `out_uvs`; `false`
    /// (and `out_uvs` empty) without UVs or with nothing drawn. Every drawn point is a lattice
    /// point at most at the deepest drawn depth (fans use only points of the finer side's
    /// lattice), so that level suffices.
    fn level_uvs(
        &mut self,
        mesh: &Mesh,
        depth: &[Depth],
        active: &[bool],
        out_uvs: &mut Vec<[f32; 2]>,
    ) -> Result<bool, AssemblyError> {
        let deepest = (0..depth.len())
            .filter(|&f| active[f])
            .map(|f| depth[f])
            .max();
        let (true, Some(level)) = (mesh.uv().is_some(), deepest) else {
            out_uvs.clear();
            return Ok(false);
        };
        if self.uvs.as_ref().is_none_or(|u| u.level() < level) {
            self.uvs = LevelUvs::new(mesh, subdiv_rules::Scheme::Loop, level)?;
            out_uvs.clear();
        }
        if out_uvs.is_empty() {
            *out_uvs = self
                .uvs
                .as_ref()
                .map(|u| u.values.clone())
                .unwrap_or_default();
        }
        Ok(self.uvs.is_some())
    }

    /// Refuses frames whose lattices would not fit in memory.
    fn check_size(&self, required: &[Option<Depth>]) -> Result<(), AssemblyError> {
        let total: u64 = (0..required.len())
            .map(|i| match required[i].max(self.blocks[i].depth) {
                None => 0,
                Some(d) => tri_lattice_len(d) as u64,
            })
            .sum();
        if total > subdiv_slate::MAX_POINTS {
            return Err(AssemblyError::TooLarge { points: total });
        }
        Ok(())
    }

    /// Recomputes the lattices that are too coarse for `required`; returns which (ascending)
    /// and their points. A recomputed lattice reuses the buffers of the one it replaces.
    fn recompute_blocks(&mut self, mesh: &Mesh, required: &[Option<Depth>]) -> (Vec<usize>, usize) {
        let todo: Vec<usize> = (0..required.len())
            .filter(|&i| required[i] > self.blocks[i].depth)
            .collect();
        let layout = &self.layout;
        let mut fresh: Vec<(usize, TriBlock)> = todo
            .iter()
            .map(|&i| (i, std::mem::take(&mut self.blocks[i])))
            .collect();
        fresh.par_iter_mut().for_each(|(i, b)| {
            let d = required[*i].unwrap_or_default();
            b.depth = Some(d);
            let p = &layout.patches()[*i];
            tri_patch_lattice(mesh, layout, p, d, &mut b.pos, &mut b.nrm, &mut b.sided);
        });
        let points = fresh.iter().map(|(_, b)| b.pos.len()).sum();
        for (i, mut b) in fresh {
            self.stamps += 1;
            b.stamp = self.stamps;
            self.blocks[i] = b;
        }
        (todo, points)
    }

    /// The last frame's vertex buffer for the cage `stand_in` (this assembler's cage with other
    /// positions), as [`Assembler::stand_in_points`](crate::Assembler::stand_in_points) gives
    /// it for Catmull-Clark.
    pub fn stand_in_points(&self, stand_in: &Mesh) -> Vec<[f32; 3]> {
        let layout = &self.layout;
        let blocks: Vec<Vec<[f32; 3]>> = (0..self.blocks.len())
            .into_par_iter()
            .map(|i| match self.blocks[i].depth {
                Some(d) if self.slots.holds(i) => {
                    let p = &layout.patches()[i];
                    let mut b = TriBlock::default();
                    tri_patch_lattice(stand_in, layout, p, d, &mut b.pos, &mut b.nrm, &mut b.sided);
                    b.pos
                }
                _ => Vec::new(),
            })
            .collect();
        self.slots.gather(|i| &blocks[i])
    }

    /// The face-varying values of the last frame for the cage `stand_in`, as
    /// [`Assembler::stand_in_corner_values`](crate::Assembler::stand_in_corner_values) gives
    /// them for Catmull-Clark.
    pub fn stand_in_corner_values(
        &self,
        stand_in: &Mesh,
        frame: &AdaptiveFrame,
    ) -> Result<(Vec<[f32; 2]>, Vec<u32>), AssemblyError> {
        // Every drawn point is a lattice point at most at the deepest drawn depth.
        let Some((depth, active, uvs)) = frame.stand_in_uvs(stand_in, Scheme::Loop, 0)? else {
            return Ok((Vec::new(), Vec::new()));
        };
        let (tris, _, corners) = self.emit_afresh(stand_in, &depth, &active, Some(&uvs));
        crate::fans::check_corners(&tris, frame)?;
        Ok((uvs.values, corners))
    }

    /// The triangles, one-sided corner normals and face-varying corner values of a frame of
    /// `depth` and `active` (clamped and masked as [`TriAssembler::frame`] takes them) over the
    /// lattices as cached, every run emitted.
    fn emit_afresh(
        &self,
        mesh: &Mesh,
        depth: &[Depth],
        active: &[bool],
        uvs: Option<&LevelUvs>,
    ) -> Emitted {
        let owners = emit::Owners::new(mesh, &self.layout, depth, active);
        let fr = TriFrame {
            layout: &self.layout,
            depth,
            owners: &owners,
            blocks: &self.blocks,
            slots: &self.slots,
        };
        let (mut runs, mut tris, mut sided, mut corners) = Default::default();
        fr.emit_frame(
            active,
            uvs,
            None,
            &mut runs,
            &mut tris,
            &mut sided,
            &mut corners,
        );
        (tris, sided, corners)
    }

    /// Where frame vertex `index` comes from: (face, lattice depth, lattice index), for tests
    /// and tools that compare the frame with uniform tessellations.
    pub fn vertex_source(&self, index: u32) -> Option<(usize, Depth, u32)> {
        let (f, k) = self.slots.block_of(index)?;
        let d = self.blocks.get(f)?.depth?;
        Some((f, d, k))
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod uv_tests;
