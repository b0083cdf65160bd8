//! The per-thread tessellation state ([`Worker`]): two slates, four corner arrays and scratch,
//! and the whole pipeline of one patch ([`Worker::patch_grid_sided`]: gather, steps, limits).
//!
//! The stages live in their own modules: [`gather`](crate::gather) fills slate 0 from the mesh,
//! [`step`](crate::step) subdivides one slate into the other, [`limit`](crate::limit) evaluates
//! the final grid.

use glam::{DVec3, Vec3A};
use subdiv_mesh::{CreaseMethod, FaceId, HalfedgeId, Mesh};
use subdiv_rules::{Depth, QuadRingStencil};

use crate::limit::{MAX_STENCILS, StencilKey};
use crate::table::{Corner, Table};
use crate::wide::InteriorOut;

/// Per-thread tessellation state: two slates and four corner arrays, allocated once.
#[derive(Debug)]
pub(crate) struct Worker {
    pub(crate) t: [Table; 2],
    pub(crate) corners: [Corner; 4],
    pub(crate) cur: usize,
    pub(crate) regular: bool,
    pub(crate) method: CreaseMethod,
    /// Patch-local origin: tables hold positions relative to it, so that rounding is relative
    /// to the patch's size rather than to its distance from the world origin.
    pub(crate) origin: DVec3,
    pub(crate) origin32: Vec3A,
    pub(crate) hes: Vec<HalfedgeId>,
    pub(crate) maxn: usize,
    /// Scratch for output ids of a patch grid.
    pub(crate) ids: Vec<u32>,
    /// Per table point: near a sharp edge or a missing point (general rules needed).
    pub(crate) dirty: Vec<bool>,
    /// Indices set in `dirty` (cleared by the next marking).
    pub(crate) dirty_list: Vec<u32>,
    /// The sharp edges of the table last marked (see `Table::mark_dirty`).
    pub(crate) sharp_edges: Vec<(u32, u8)>,
    /// Three split rows of the separable regular step (`step_regular`).
    pub(crate) split: Vec<Vec3A>,
    /// Three rows of sums of the separable regular limit masks (`limit_interior`).
    pub(crate) sum_b: Vec<Vec3A>,
    pub(crate) sum_a: Vec<Vec3A>,
    /// The same rows in SoA form, with one transposed table row (`wide::interior_rows`).
    pub(crate) wide: Vec<f32>,
    /// Interior points with degenerate regular tangents.
    pub(crate) bad: Vec<(i32, i32)>,
    /// Limit stencils of the crease and boundary configurations met by `limit_general`.
    pub(crate) stencils: Vec<(StencilKey, QuadRingStencil)>,
    /// Most recently used entry of `stencils`.
    pub(crate) last_stencil: usize,
    /// One-sided normals of the faces of the ring last evaluated (`limit_sided`).
    pub(crate) sided: Vec<DVec3>,
    /// Grid points `(i, j)` of the last patch with a one-sided normal of its side.
    pub(crate) sided_points: Vec<(u32, u32, Vec3A)>,
}

impl Worker {
    /// A worker whose slates hold patches up to depth `max_depth`.
    pub fn new(max_depth: Depth) -> Worker {
        let maxn = 1usize << max_depth;
        Worker {
            t: [Table::with_capacity(maxn), Table::with_capacity(maxn)],
            corners: Default::default(),
            cur: 0,
            regular: true,
            method: CreaseMethod::Uniform,
            origin: DVec3::ZERO,
            origin32: Vec3A::ZERO,
            hes: Vec::with_capacity(16),
            maxn,
            ids: Vec::new(),
            dirty: Vec::new(),
            dirty_list: Vec::new(),
            sharp_edges: Vec::new(),
            split: Vec::new(),
            sum_b: Vec::new(),
            sum_a: Vec::new(),
            wide: Vec::new(),
            bad: Vec::new(),
            stencils: Vec::new(),
            last_stencil: 0,
            sided: Vec::new(),
            sided_points: Vec::new(),
        }
    }

    /// Bytes held by the two tables (capacity for `max_depth`).
    pub fn table_bytes(&self) -> usize {
        let cap = (self.maxn + 3) * (self.maxn + 3);
        2 * cap * (std::mem::size_of::<Vec3A>() + 1 + 2 * std::mem::size_of::<f32>())
    }

    /// Most bytes the worker's scratch can reach besides the tables and corner arrays (capacity
    /// for `max_depth`): the dirty mask and its list, the list of sharp edges (two per band
    /// point), the rolling rows of the regular step and of the limit sums (AoS and SoA), the Chaikin far
    /// information and a full stencil cache.
    pub fn scratch_bytes(&self) -> usize {
        let (side, cap) = (self.maxn + 3, (self.maxn + 3) * (self.maxn + 3));
        let v = std::mem::size_of::<Vec3A>();
        // A table ring has at most 4 edges and 4 diagonals: 6 + 4 rows of 9 weights.
        let stencil = std::mem::size_of::<(StencilKey, QuadRingStencil)>() + 10 * 9 * 8;
        cap + 8 * side * 4
            + 2 * (8 * self.maxn + 8) * std::mem::size_of::<(u32, u8)>()
            + 3 * side * v
            + 6 * self.maxn * v
            + crate::wide::scratch_len(self.maxn) * 4
            + 2 * 4 * (self.maxn + 1) * std::mem::size_of::<(f32, u32)>()
            + MAX_STENCILS * stencil
    }

    /// Tessellates the quad `face` of `mesh` (whose 1-neighbourhood is all quads) at `depth` and
    /// writes the limit points and normals of its `(2^depth + 1)^2` grid, row by row (`i` along
    /// the face's first edge, `j` along its last edge reversed), and in `sided` (cleared first;
    /// grid index ascending) the one-sided limit normal of this patch's side at the border
    /// points where the limit surface has a crease or a corner (see
    /// `subdiv_rules::Ring::limit_sided`; `nrm` holds the averaged normal there).
    pub fn patch_grid_sided(
        &mut self,
        mesh: &Mesh,
        face: FaceId,
        depth: Depth,
        pos: &mut [[f32; 3]],
        nrm: &mut [[f32; 3]],
        sided: &mut Vec<(u32, [f32; 3])>,
    ) {
        sided.clear();
        let n = 1usize << depth;
        let w = n + 1;
        assert!(
            pos.len() >= w * w && nrm.len() >= w * w,
            "grid buffers too small"
        );
        assert!(n <= self.maxn, "depth exceeds the worker's slates");
        self.gather(mesh, face);
        for _ in 0..depth {
            self.step();
        }
        let n = n as i32;
        for j in 0..=n {
            let row = j as usize * w;
            // The border: whole first and last rows, the two ends of the others.
            let step = if j == 0 || j == n {
                1
            } else {
                n.max(1) as usize
            };
            for i in (0..=n).step_by(step) {
                let (p, q, side) = self.limit_sided(i, j, true);
                pos[row + i as usize] = p.to_array();
                nrm[row + i as usize] = q.to_array();
                if let Some(s) = side {
                    sided.push(((row + i as usize) as u32, s.to_array()));
                }
            }
        }
        self.limit_interior(&mut InteriorOut {
            pos,
            nrm,
            first: w + 1,
            stride: w,
        });
    }
}
