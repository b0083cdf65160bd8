//! Per-frame owners of the cage's edges and vertices, and the index buffer: lattice triangles
//! inside, fans and strips along finer sides (Settgast et al. §3.3, adapted to triangles).

use subdiv_mesh::{FaceId, Mesh};
use subdiv_slate::{Depth, LevelUvs, TriLayout, tri_lattice_index};

use super::TriBlock;
#[cfg(doc)]
use crate::runs::RUN_PATCHES;
use crate::runs::{RunOut, concat, dependencies, emit_runs};
use crate::slots::Slots;

/// One-sided normals of triangle corners: (corner index, normal), ascending.
type SidedNormals = Vec<(u32, [f32; 3])>;

/// No active face: the edge or vertex is not drawn.
const NONE: u32 = u32::MAX;

/// Who writes each cage edge's and vertex's points this frame.
pub(crate) struct Owners {
    /// Per cage edge: the resolution it is drawn at (its deeper active side's depth).
    pub(crate) edge_res: Vec<Depth>,
    /// Per cage edge: (face, side of that face) of the owner, `NONE` when not drawn.
    pub(crate) edge_owner: Vec<(u32, u8)>,
    /// Per cage vertex: (face, corner of that face) of the owner, `NONE` when not drawn.
    pub(crate) vertex_owner: Vec<(u32, u8)>,
}

impl Owners {
    /// Edge owner: the deeper active side, on equal depths the layout's owner (the face of the
    /// edge's even half-edge). Vertex owner: the layout's owner (the face of the vertex's out
    /// half-edge) when active, else the first active face around it.
    pub(crate) fn new(mesh: &Mesh, layout: &TriLayout, depth: &[Depth], active: &[bool]) -> Self {
        let mut edge_res = vec![0; mesh.num_edges()];
        let mut edge_owner = vec![(NONE, 0u8); mesh.num_edges()];
        let mut vertex_owner = vec![(NONE, 0u8); mesh.num_vertices()];
        for (f, p) in layout.patches().iter().enumerate() {
            if !active[f] {
                continue;
            }
            let d = depth[f];
            for k in 0..3 {
                let e = p.edges[k].idx();
                let (g, _) = edge_owner[e];
                let take = g == NONE || d > edge_res[e] || (d == edge_res[e] && p.sides[k].owned);
                if take {
                    edge_res[e] = d;
                    edge_owner[e] = (f as u32, k as u8);
                }
                let v = p.corners[k] as usize;
                if vertex_owner[v].0 == NONE || p.corner_owned[k] {
                    vertex_owner[v] = (f as u32, k as u8);
                }
            }
        }
        Owners {
            edge_res,
            edge_owner,
            vertex_owner,
        }
    }

    /// Depth each active patch's lattice is needed at: its own, or a finer neighbour's across a
    /// sharp cage edge (the fans there use this patch's own one-sided normals at the finer
    /// points of the crease). `None` for inactive patches.
    pub(crate) fn required_depths(
        &self,
        mesh: &Mesh,
        layout: &TriLayout,
        depth: &[Depth],
        active: &[bool],
    ) -> Vec<Option<Depth>> {
        layout
            .patches()
            .iter()
            .enumerate()
            .map(|(f, p)| {
                active[f].then(|| {
                    (0..3)
                        .map(|k| p.edges[k])
                        .filter(|&e| mesh.edge_sharpness(e) > 0.0)
                        .map(|e| self.edge_res[e.idx()])
                        .fold(depth[f], Depth::max)
                })
            })
            .collect()
    }
}

/// A point of the frame: its vertex index; where the emitting patch's own lattice holds the
/// same point, its index there (for the patch's one-sided normals), else `NONE`; and where it
/// lies on the emitting patch: lattice point `(i, j)` at resolution `r` (for its UV on the
/// patch's side of any seam).
/// Per run of [`RUN_PATCHES`] faces of `layout`, the faces its triangles read: those sharing
/// a corner or a side with its faces, among which [`Owners`] finds every owner they name.
pub(crate) fn run_dependencies(layout: &TriLayout, mesh: &Mesh) -> Vec<Vec<u32>> {
    let patches = layout.patches();
    let mut at_vertex: Vec<Vec<u32>> = vec![Vec::new(); mesh.num_vertices()];
    let mut at_edge: Vec<Vec<u32>> = vec![Vec::new(); mesh.num_edges()];
    for (f, p) in patches.iter().enumerate() {
        for k in 0..3 {
            at_vertex[p.corners[k] as usize].push(f as u32);
            at_edge[p.edges[k].idx()].push(f as u32);
        }
    }
    dependencies(patches.len(), |f, deps| {
        let p = &patches[f];
        for k in 0..3 {
            deps.extend_from_slice(&at_vertex[p.corners[k] as usize]);
            deps.extend_from_slice(&at_edge[p.edges[k].idx()]);
        }
    })
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Pt {
    id: u32,
    key: u32,
    at: (u32, u32, Depth),
}

/// What emission reads.
pub(crate) struct TriFrame<'a> {
    pub(crate) layout: &'a TriLayout,
    pub(crate) depth: &'a [Depth],
    pub(crate) owners: &'a Owners,
    pub(crate) blocks: &'a [TriBlock],
    pub(crate) slots: &'a Slots,
}

/// Lattice coordinates at side `n` of side `k`'s point `t` (counted from corner `k`).
#[inline]
fn side_coords(n: u32, k: usize, t: u32) -> (u32, u32) {
    match k {
        0 => (t, 0),
        1 => (n - t, t),
        _ => (0, n - t),
    }
}

impl TriFrame<'_> {
    /// Frame vertex of patch `g`'s lattice point `(i, j)` at resolution `r`.
    #[inline]
    fn lattice(&self, g: u32, i: u32, j: u32, r: Depth) -> u32 {
        let c = self.blocks[g as usize]
            .depth
            .expect("owners' lattices are computed");
        let s = c - r;
        self.slots.start(g as usize) + tri_lattice_index(1 << c, i << s, j << s)
    }

    /// Patch `f`'s own lattice index of its point `(i, j)` at resolution `r`, if it holds it.
    #[inline]
    fn key(&self, f: usize, i: u32, j: u32, r: Depth) -> u32 {
        match self.blocks[f].depth {
            Some(c) if c >= r => tri_lattice_index(1 << c, i << (c - r), j << (c - r)),
            _ => NONE,
        }
    }

    /// Corner `k` of patch `f`, through the vertex's owner.
    fn corner(&self, f: usize, k: usize) -> Pt {
        let v = self.layout.patches()[f].corners[k] as usize;
        let (g, c) = self.owners.vertex_owner[v];
        let (i, j) = side_coords(1, c as usize, 0);
        let (a, b) = side_coords(1, k, 0);
        Pt {
            id: self.lattice(g, i, j, 0),
            key: self.key(f, a, b, 0),
            at: (a, b, 0),
        }
    }

    /// Point `t` (of `2^r`, from corner `k`) of side `k` of patch `f`, through the owners.
    fn side(&self, f: usize, k: usize, t: u32, r: Depth) -> Pt {
        let n = 1u32 << r;
        if t == 0 {
            return self.corner(f, k);
        }
        if t == n {
            return self.corner(f, (k + 1) % 3);
        }
        let e = self.layout.patches()[f].edges[k].idx();
        let (g, k2) = self.owners.edge_owner[e];
        // The two faces of an edge run along it in opposite directions.
        let t2 = if g as usize == f { t } else { n - t };
        let (i, j) = side_coords(n, k2 as usize, t2);
        let (a, b) = side_coords(n, k, t);
        Pt {
            id: self.lattice(g, i, j, r),
            key: self.key(f, a, b, r),
            at: (a, b, r),
        }
    }

    /// Patch `f`'s lattice point `(i, j)` at its own depth.
    fn own(&self, f: usize, i: u32, j: u32) -> Pt {
        let d = self.depth[f];
        let n = 1u32 << d;
        let res = |k: usize| self.owners.edge_res[self.layout.patches()[f].edges[k].idx()];
        let on_side = |k: usize, t: u32| self.side(f, k, t << (res(k) - d), res(k));
        match (i, j) {
            (0, 0) => self.corner(f, 0),
            (i, 0) if i == n => self.corner(f, 1),
            (0, j) if j == n => self.corner(f, 2),
            (i, 0) => on_side(0, i),
            (i, j) if i + j == n => on_side(1, j),
            (0, j) => on_side(2, n - j),
            (i, j) => Pt {
                id: self.lattice(f as u32, i, j, d),
                key: NONE,
                at: (i, j, d),
            },
        }
    }

    /// The index buffer of every active patch (in face order), the one-sided normals of its
    /// triangles' corners and, with `uvs`, the face-varying value of every corner on the
    /// emitting patch's side of any seam in `uv_indices` (parallel to `indices`; cleared
    /// first); emitted in runs of [`RUN_PATCHES`] faces into `runs` (grown as needed, kept by
    /// the caller between frames). With `deps` (per run, [`run_dependencies`]), a run whose
    /// state ([`TriFrame::run_key`]) stayed keeps its triangles; returns the runs kept.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn emit_frame(
        &self,
        active: &[bool],
        uvs: Option<&LevelUvs>,
        deps: Option<&[Vec<u32>]>,
        runs: &mut Vec<RunOut>,
        indices: &mut Vec<u32>,
        corner_normals: &mut SidedNormals,
        uv_indices: &mut Vec<u32>,
    ) -> usize {
        let key = deps.map(|deps| {
            move |c: usize, faces, key: &mut Vec<u64>| {
                self.run_key(&deps[c], faces, active, uvs, key)
            }
        });
        let (n, kept) = emit_runs(
            runs,
            active.len(),
            |run| run,
            key,
            |faces, run| {
                for f in faces.filter(|&f| active[f]) {
                    let mut out = Emit {
                        indices: &mut run.tris,
                        sided: &mut run.sided,
                        uv: &mut run.uv,
                        block: &self.blocks[f],
                        uvs,
                        face: FaceId(f as u32),
                    };
                    self.emit_patch(f, &mut out);
                }
            },
        );
        concat(runs[..n].iter(), indices, corner_normals, uv_indices);
        kept
    }

    /// The state a run's triangles are a function of, into `key` (empty): the face-varying
    /// level, and per face of `deps` its activity and depth, where its lattice lies in the
    /// vertex buffer and how deep it is; then which computation each of the run's own faces'
    /// lattices holds (`faces`), which only the one-sided normals it copies from them depend
    /// on. Returns the length of the first part.
    fn run_key(
        &self,
        deps: &[u32],
        faces: std::ops::Range<usize>,
        active: &[bool],
        uvs: Option<&LevelUvs>,
        key: &mut Vec<u64>,
    ) -> usize {
        key.push(uvs.map_or(0, |u| u64::from(u.level()) + 1));
        for &f in deps {
            let f = f as usize;
            let b = &self.blocks[f];
            let depth = b.depth.map_or(0, |d| u64::from(d) + 1);
            key.push((u64::from(self.depth[f]) << 1) | u64::from(active[f]));
            key.push((u64::from(self.slots.start(f)) << 8) | depth);
        }
        let structure = key.len();
        key.extend(faces.map(|f| self.blocks[f].stamp));
        structure
    }

    /// Patch `f`'s triangles: lattice triangles, with those on a finer side filled by
    /// [`fill`].
    fn emit_patch(&self, f: usize, out: &mut Emit<'_>) {
        let d = self.depth[f];
        let n = 1u32 << d;
        let p = &self.layout.patches()[f];
        let res = p.edges.map(|e| self.owners.edge_res[e.idx()]);
        let fine = res.map(|r| r > d);
        let mut rows: [Vec<Pt>; 3] = Default::default();
        for b in 0..n {
            for a in 0..n - b {
                let on = [
                    b == 0 && fine[0],
                    a + b + 1 == n && fine[1],
                    a == 0 && fine[2],
                ];
                if on.iter().any(|&x| x) {
                    // Side params (from the side's first corner) of the triangle's edges.
                    let params = [(0, a), (1, b), (2, n - b - 1)];
                    let ends = [(a, b, a + 1, b), (a + 1, b, a, b + 1), (a, b + 1, a, b)];
                    for k in 0..3 {
                        rows[k].clear();
                        if on[k] {
                            let m = res[k] - d;
                            let t0 = params[k].1 << m;
                            for t in t0..=t0 + (1 << m) {
                                rows[k].push(self.side(f, params[k].0, t, res[k]));
                            }
                        } else {
                            let (i0, j0, i1, j1) = ends[k];
                            rows[k].push(self.own(f, i0, j0));
                            rows[k].push(self.own(f, i1, j1));
                        }
                    }
                    fill(&rows[0], &rows[1], &rows[2], out);
                } else {
                    out.tri(
                        self.own(f, a, b),
                        self.own(f, a + 1, b),
                        self.own(f, a, b + 1),
                    );
                }
                if a + b + 1 < n {
                    out.tri(
                        self.own(f, a + 1, b),
                        self.own(f, a + 1, b + 1),
                        self.own(f, a, b + 1),
                    );
                }
            }
        }
    }
}

/// One patch's output, appended to its run's.
struct Emit<'a> {
    indices: &'a mut Vec<u32>,
    sided: &'a mut SidedNormals,
    /// The face-varying value of every corner (parallel to `indices`; empty without UVs).
    uv: &'a mut Vec<u32>,
    /// The emitting patch's lattice (its one-sided normals).
    block: &'a TriBlock,
    /// The cage's face-varying limit values, `None` without UVs.
    uvs: Option<&'a LevelUvs>,
    /// The emitting patch's cage face.
    face: FaceId,
}

impl Emit<'_> {
    /// Appends a counter-clockwise triangle, its corners' one-sided normals and, with UVs,
    /// their values on this patch's side.
    #[inline]
    fn tri(&mut self, a: Pt, b: Pt, c: Pt) {
        for q in [a, b, c] {
            if let Some(u) = self.uvs {
                let (i, j, r) = q.at;
                self.uv.push(u.tri_value_at(self.face, i, j, r));
            }
            if q.key != NONE
                && let Ok(x) = self.block.sided.binary_search_by_key(&q.key, |&(k, _)| k)
            {
                self.sided
                    .push((self.indices.len() as u32, self.block.sided[x].1));
            }
            self.indices.push(q.id);
        }
    }
}

/// Triangulates the triangle whose counter-clockwise sides are the point rows `l0` (corner 0 to
/// 1), `l1` (1 to 2) and `l2` (2 to 0), each with both ends and at least two points, the
/// longer ones with `2^k + 1` points: one triangle when no row has inner points; a fan from the
/// opposite corner through the one row that has; a strip between two rows from their shared
/// corner; three rows split at their midpoints into four such triangles.
fn fill(l0: &[Pt], l1: &[Pt], l2: &[Pt], out: &mut Emit<'_>) {
    let rows = [l0, l1, l2];
    let fine = rows.map(|r| r.len() > 2);
    match fine.iter().filter(|&&x| x).count() {
        0 => out.tri(l0[0], l1[0], l2[0]),
        1 => {
            let k = fine.iter().position(|&x| x).expect("one row");
            let (row, apex) = (rows[k], rows[(k + 2) % 3][0]);
            for w in row.windows(2) {
                out.tri(w[0], w[1], apex);
            }
        }
        2 => {
            // Rotate so the plain row is `l1`: the strip runs from corner 0 along `l0` and
            // along `l2` backwards.
            let k = fine.iter().position(|&x| !x).expect("one plain row");
            let p = rows[(k + 2) % 3];
            let q = rows[(k + 1) % 3];
            strip(p, q, out);
        }
        _ => {
            let (h0, h1, h2) = (l0.len() / 2, l1.len() / 2, l2.len() / 2);
            let (m0, m1, m2) = (l0[h0], l1[h1], l2[h2]);
            fill(&l0[..=h0], &[m0, m2], &l2[h2..], out);
            fill(&l0[h0..], &l1[..=h1], &[m1, m0], out);
            fill(&[m2, m1], &l1[h1..], &l2[..=h2], out);
            out.tri(m0, m1, m2);
        }
    }
}

/// Strip between row `p` (corner 0 to 1) and row `q` (corner 2 to 0) of a counter-clockwise
/// triangle, from corner 0 to the closing side from corner 1 to 2: every triangle has two
/// points on one row and one on the other, advancing the row that lags in parameter.
fn strip(p: &[Pt], q: &[Pt], out: &mut Emit<'_>) {
    let a = p.len() - 1;
    let b = q.len() - 1;
    // `q` backwards: qq(j) runs from corner 0 (j = 0) to corner 2 (j = b).
    let qq = |j: usize| q[b - j];
    out.tri(p[0], p[1], qq(1));
    let (mut i, mut j) = (1, 1);
    while i < a || j < b {
        if i < a && (j == b || (i + 1) * b <= (j + 1) * a) {
            out.tri(p[i], p[i + 1], qq(j));
            i += 1;
        } else {
            out.tri(p[i], qq(j + 1), qq(j));
            j += 1;
        }
    }
}
