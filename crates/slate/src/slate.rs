//! The slates: a patch's control points at one level, and the step to the next.
//!
//! A slate's *table* holds the `(n + 3)^2` control points of a patch at level `l` (`n = 2^l`):
//! the patch's own `(n + 1)^2` grid and one ring of neighbours, at table coordinates
//! `(i, j)` with `-1 <= i, j <= n + 1` (Settgast et al., "Adaptive Tessellation of Subdivision
//! Surfaces", Section 3.2, Fig. 2). Alongside go the sharpness of every table edge and, for the
//! Chaikin rule, what is known of the crease beyond the outer ring.
//!
//! A corner whose vertex is not an interior valence-4 vertex (or carries a corner tag) keeps its
//! whole neighbourhood in a *corner array*: a [`Ring`] from `subdiv-rules`, holding all of its
//! `valence` edge neighbours and quads, creases and boundary included. The table covers what a
//! valence-4 corner would; the corner array provides the points the table cannot (the corner
//! itself and its neighbours beyond the table's quadrant).
//!
//! One step ([`Worker::step`]) subdivides the table of slate `i` into the table of slate
//! `1 - i` with the rules of `subdiv-rules`, and refines the corner arrays. Every table is first
//! refined by the smooth regular rules in their separable form (rows split, then split rows
//! combined); a table with creases or boundaries then redoes, with the general face, edge and
//! vertex rules, only its *dirty* points: the ends of sharp edges and the neighbours of missing
//! points. Those lie on the *band* (rows and columns `-1, 0, n, n + 1`, see [`band`]), so the
//! general work grows with the patch's side, not its area.
//!
//! Limit points and normals of the final grid: interior points always take the regular limit
//! masks (separable form); border points take them where their neighbourhood is plain, and
//! otherwise (creases, boundaries) the exact limit of their ring, through a
//! [`QuadRingStencil`] kept per sharpness configuration — [`Ring::limit`] precomputed, so a
//! semi-sharp crease still gets its true limit at any depth.

use glam::{DVec3, Vec3A};
use subdiv_mesh::{CreaseMethod, FaceId, HalfedgeId, Mesh, VertexId};
use subdiv_rules::catmark;
use subdiv_rules::crease::{self, Rule, VertexRules, edge_crease_weight, is_semi_sharp};
use subdiv_rules::{QuadRingStencil, Ring, Scheme};

/// Direction index: 0 = +i (E), 1 = +j (N), 2 = -i (W), 3 = -j (S) — counter-clockwise.
const DI: [i32; 4] = [1, 0, -1, 0];
const DJ: [i32; 4] = [0, 1, 0, -1];

/// One slate's table.
#[derive(Clone, Debug, Default)]
pub(crate) struct Table {
    /// Patch grid size `n` (`2^level`).
    pub n: usize,
    /// Row stride `n + 3`.
    pub s: usize,
    pub p: Vec<Vec3A>,
    pub ex: Vec<bool>,
    /// Sharpness of edge `(i,j)-(i+1,j)`, stored at `(i,j)`.
    pub hs: Vec<f32>,
    /// Sharpness of edge `(i,j)-(i,j+1)`, stored at `(i,j)`.
    pub vs: Vec<f32>,
    /// For each side, (sum, count) of the semi-sharp edges beyond the outer end of each crossing
    /// edge (Chaikin rule only), indexed by position along the side `0..=n`.
    pub far: [Vec<(f32, u32)>; 4],
    /// Sharpness or existence flags may be non-default (set by a general step or gather).
    pub dirty: bool,
}

impl Table {
    fn with_capacity(maxn: usize) -> Table {
        let cap = (maxn + 3) * (maxn + 3);
        Table {
            n: 0,
            s: 0,
            p: vec![Vec3A::ZERO; cap],
            ex: vec![false; cap],
            hs: vec![0.0; cap],
            vs: vec![0.0; cap],
            far: std::array::from_fn(|_| vec![(0.0, 0); maxn + 1]),
            dirty: true,
        }
    }

    /// Prepares the table for grid size `n`. A table for the regular step needs no clearing
    /// (it overwrites every point); sharpness is cleared only if a general step left some, and
    /// then only on the band where it can be (see [`band`]).
    fn reset(&mut self, n: usize, regular: bool) {
        debug_assert!(
            (n + 3) * (n + 3) <= self.p.len(),
            "slate too small for grid {n}"
        );
        if self.dirty && self.s > 0 {
            // Rows -1, 0, n, n + 1 whole; columns -1, 0, n, n + 1 of the rows between.
            let (n, s) = (self.n, self.s);
            for r in [0, 1, n + 1, n + 2] {
                self.hs[r * s..(r + 1) * s].fill(0.0);
                self.vs[r * s..(r + 1) * s].fill(0.0);
            }
            for r in 2..=n {
                for c in [0, 1, n + 1, n + 2] {
                    self.hs[r * s + c] = 0.0;
                    self.vs[r * s + c] = 0.0;
                }
            }
        }
        let was_dirty = self.dirty;
        self.n = n;
        self.s = n + 3;
        if !regular || was_dirty {
            for f in &mut self.far {
                f[..=n].fill((0.0, 0));
            }
        }
        self.dirty = !regular;
    }

    #[inline(always)]
    pub fn at(&self, i: i32, j: i32) -> usize {
        (j + 1) as usize * self.s + (i + 1) as usize
    }

    #[inline]
    fn inside(&self, i: i32, j: i32) -> bool {
        let n = self.n as i32;
        (-1..=n + 1).contains(&i) && (-1..=n + 1).contains(&j)
    }

    /// Sharpness of the edge from `(i,j)` in direction `d`.
    #[inline]
    fn edge_sharp(&self, i: i32, j: i32, d: usize) -> f32 {
        match d {
            0 => self.hs[self.at(i, j)],
            1 => self.vs[self.at(i, j)],
            2 => self.hs[self.at(i - 1, j)],
            _ => self.vs[self.at(i, j - 1)],
        }
    }

    #[inline]
    fn set_edge_sharp(&mut self, i: i32, j: i32, d: usize, s: f32) {
        let k = match d {
            0 => self.at(i, j),
            1 => self.at(i, j),
            2 => self.at(i - 1, j),
            _ => self.at(i, j - 1),
        };
        if d % 2 == 0 {
            self.hs[k] = s
        } else {
            self.vs[k] = s
        }
    }

    /// `true` if the edge from `(i,j)` in direction `d` exists (both ends inside and existing).
    #[inline]
    fn edge_exists(&self, i: i32, j: i32, d: usize) -> bool {
        let (a, b) = (i + DI[d], j + DJ[d]);
        self.inside(a, b) && self.ex[self.at(i, j)] && self.ex[self.at(a, b)]
    }

    /// `true` if `(i, j)` is an interior point whose 8 neighbours exist and whose 4 edges are
    /// smooth: the regular rules and limit masks apply there exactly.
    #[inline]
    fn is_plain(&self, i: i32, j: i32) -> bool {
        let k = self.at(i, j);
        let s = self.s;
        self.hs[k] == 0.0
            && self.hs[k - 1] == 0.0
            && self.vs[k] == 0.0
            && self.vs[k - s] == 0.0
            && self.ex[k]
            && self.ex[k + 1]
            && self.ex[k - 1]
            && self.ex[k + s]
            && self.ex[k - s]
            && self.ex[k + s + 1]
            && self.ex[k + s - 1]
            && self.ex[k - s + 1]
            && self.ex[k - s - 1]
    }

    /// Marks the points whose rules are not the smooth regular ones: the ends of sharp edges and
    /// the neighbours of missing points. Returns `true` if any point is missing.
    ///
    /// Only the band can hold such points (see [`band`]), so only the band is scanned; `list`
    /// remembers what was marked so that the next call clears just that.
    fn mark_dirty(&self, dirty: &mut Vec<bool>, list: &mut Vec<u32>) -> bool {
        #[cfg(debug_assertions)]
        self.check_band_invariant();
        let s = self.s;
        let len = s * s;
        if dirty.len() < self.p.len() {
            dirty.resize(self.p.len(), false);
        }
        for &k in list.iter() {
            dirty[k as usize] = false;
        }
        list.clear();
        let mut set = |k: usize| {
            if !dirty[k] {
                dirty[k] = true;
                list.push(k as u32);
            }
        };
        let mut missing = false;
        for (i, j) in band(self.n) {
            let k = self.at(i, j);
            if self.hs[k] != 0.0 {
                set(k);
                if k + 1 < len {
                    set(k + 1);
                }
            }
            if self.vs[k] != 0.0 {
                set(k);
                if k + s < len {
                    set(k + s);
                }
            }
            if !self.ex[k] {
                missing = true;
                for dj in -1..=1 {
                    for di in -1..=1 {
                        if self.inside(i + di, j + dj) {
                            set(self.at(i + di, j + dj));
                        }
                    }
                }
            }
        }
        missing
    }

    /// Checks what [`band`] relies on: every point off the band is plain (it exists, its eight
    /// neighbours exist and its four edges are smooth), so sharpness and missing points can only
    /// be found on the band.
    #[cfg(debug_assertions)]
    fn check_band_invariant(&self) {
        let n = self.n as i32;
        for j in 1..n {
            for i in 1..n {
                assert!(
                    self.is_plain(i, j),
                    "slate band invariant broken at ({i}, {j}) of grid {n}"
                );
            }
        }
    }

    /// `true` if the quad with lower-left corner `(i,j)` exists.
    #[inline]
    fn face_exists(&self, i: i32, j: i32) -> bool {
        self.inside(i, j)
            && self.inside(i + 1, j + 1)
            && self.ex[self.at(i, j)]
            && self.ex[self.at(i + 1, j)]
            && self.ex[self.at(i, j + 1)]
            && self.ex[self.at(i + 1, j + 1)]
    }
}

/// A patch corner kept as a full ring (the slate's corner array).
#[derive(Clone, Debug, Default)]
pub(crate) struct Corner {
    pub active: bool,
    pub ring: Ring,
    /// Ring index of the edge along the patch side leaving this corner.
    pub ih: usize,
    pub valence: usize,
    pub boundary: bool,
}

/// Table position and the two patch directions of corner `k` (grid size `n`): the side leaving
/// the corner (`d`) and the side arriving at it, reversed (`d2`, counter-clockwise from `d`).
#[inline]
fn corner_frame(k: usize, n: i32) -> ((i32, i32), usize, usize) {
    match k {
        0 => ((0, 0), 0, 1),
        1 => ((n, 0), 1, 2),
        2 => ((n, n), 2, 3),
        _ => ((0, n), 3, 0),
    }
}

/// The table points where sharp edges and missing points can be: the rows and columns
/// `-1, 0, n, n + 1` (the patch's sides and the outer ring). Gather fills a `4 x 4` table (all
/// band); a step only makes the children of band edges sharp, and only face and edge points of
/// the outer ring missing, so the band of level `l` refines into the band of level `l + 1`. Every
/// general-table loop runs over the band alone; debug builds check the invariant.
fn band(n: usize) -> impl Iterator<Item = (i32, i32)> {
    let n = n as i32;
    let lines = [-1, 0, n, n + 1];
    lines
        .into_iter()
        .flat_map(move |j| (-1..=n + 1).map(move |i| (i, j)))
        .chain((1..n).flat_map(move |j| lines.into_iter().map(move |i| (i, j))))
}

/// Deepest `maxsd` whose worker a thread keeps between tessellations (about 230 KB of tables
/// and scratch at 6); deeper workers (megabytes) are freed when their job ends.
pub const KEEP_MAXSD: u32 = 6;

thread_local! {
    static THREAD_WORKER: std::cell::Cell<Option<Box<Worker>>> = const { std::cell::Cell::new(None) };
}

/// The calling thread's reusable [`Worker`] for patches up to depth `maxsd`: the slates are
/// allocated on a thread's first use and then serve every later patch and every later
/// tessellation on that thread (per-frame updates included), so steady-state tessellation
/// allocates nothing. The worker goes back to the thread when the guard drops; a thread that
/// already holds one (a nested job started while the first guard is alive), or a request deeper
/// than [`KEEP_MAXSD`], gets a fresh worker that is freed at the end instead.
///
/// Reuse cannot change results: every patch starts with a fresh gather, and the worker's only
/// other state, its cache of limit stencils, is keyed by everything a stencil depends on.
///
/// ```
/// let mut w = subdiv_slate::thread_worker(5);
/// assert!(w.table_bytes() > 0);
/// drop(w); // returned to this thread: the next call reuses the same slates
/// let w2 = subdiv_slate::thread_worker(4);
/// assert!(w2.table_bytes() >= subdiv_slate::Worker::new(4).table_bytes());
/// ```
pub fn thread_worker(maxsd: u32) -> WorkerGuard {
    let maxn = 1usize << maxsd;
    let cached = THREAD_WORKER.with(|c| c.take());
    let w = match cached {
        Some(w) if w.maxn >= maxn => w,
        Some(w) => {
            // Too small for this request: put it back for later shallow jobs.
            THREAD_WORKER.with(|c| c.set(Some(w)));
            Box::new(Worker::new(maxsd))
        }
        None => Box::new(Worker::new(maxsd)),
    };
    WorkerGuard(Some(w))
}

/// A worker lent by [`thread_worker`]; derefs to [`Worker`] and returns it to the thread on drop.
#[derive(Debug)]
pub struct WorkerGuard(Option<Box<Worker>>);

impl std::ops::Deref for WorkerGuard {
    type Target = Worker;
    #[inline]
    fn deref(&self) -> &Worker {
        self.0.as_deref().expect("worker present until drop")
    }
}

impl std::ops::DerefMut for WorkerGuard {
    #[inline]
    fn deref_mut(&mut self) -> &mut Worker {
        self.0.as_deref_mut().expect("worker present until drop")
    }
}

impl Drop for WorkerGuard {
    fn drop(&mut self) {
        let Some(w) = self.0.take() else { return };
        if w.maxn > 1usize << KEEP_MAXSD {
            return;
        }
        // Keep the larger of the returned and the held worker (the other is freed).
        let _ = THREAD_WORKER.try_with(|c| {
            let held = c.take();
            c.set(match held {
                Some(h) if h.maxn >= w.maxn => Some(h),
                _ => Some(w),
            });
        });
    }
}

/// Per-thread tessellation state: two slates and four corner arrays, allocated once.
#[derive(Debug)]
pub struct Worker {
    pub(crate) t: [Table; 2],
    pub(crate) corners: [Corner; 4],
    pub(crate) cur: usize,
    pub(crate) regular: bool,
    pub(crate) method: CreaseMethod,
    /// Patch-local origin: tables hold positions relative to it, so that rounding is relative
    /// to the patch's size rather than to its distance from the world origin.
    origin: DVec3,
    origin32: Vec3A,
    hes: Vec<HalfedgeId>,
    // scratch for general rules
    e_pts: Vec<Vec3A>,
    f_pts: Vec<Vec3A>,
    e_sh: Vec<f32>,
    c_sh: Vec<f32>,
    dirs: Vec<usize>,
    r_edges: Vec<DVec3>,
    r_sharp: Vec<f32>,
    r_far: Vec<(f32, u32)>,
    r_diag: Vec<DVec3>,
    maxn: usize,
    /// Scratch for output ids of a patch grid.
    pub(crate) ids: Vec<u32>,
    /// Per table point: near a sharp edge or a missing point (general rules needed).
    dirty: Vec<bool>,
    /// Indices set in `dirty` (cleared by the next marking).
    dirty_list: Vec<u32>,
    /// Three split rows of the separable regular step (`step_regular`).
    split: Vec<Vec3A>,
    /// Three rows of sums of the separable regular limit masks (`limit_interior`).
    sum_b: Vec<Vec3A>,
    sum_a: Vec<Vec3A>,
    /// Interior points with degenerate regular tangents.
    bad: Vec<(i32, i32)>,
    /// Limit stencils of the crease and boundary configurations met by `limit_general`.
    stencils: Vec<(StencilKey, QuadRingStencil)>,
    /// Most recently used entry of `stencils`.
    last_stencil: usize,
}

/// Most configurations a worker keeps stencils for (beyond, the oldest are replaced). Real cages
/// meet few: catmark_pawn 2, catmark_helmet 3 (one per crease direction and sharpness left).
const MAX_STENCILS: usize = 16;

/// A table ring's configuration: what its limit stencil depends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct StencilKey {
    method: CreaseMethod,
    boundary: bool,
    valence: u8,
    diag: u8,
    sharp: [u32; 4],
    far: [(u32, u32); 4],
}

impl Worker {
    /// A worker whose slates hold patches up to depth `maxsd`.
    pub fn new(maxsd: u32) -> Worker {
        let maxn = 1usize << maxsd;
        Worker {
            t: [Table::with_capacity(maxn), Table::with_capacity(maxn)],
            corners: Default::default(),
            cur: 0,
            regular: true,
            method: CreaseMethod::Uniform,
            origin: DVec3::ZERO,
            origin32: Vec3A::ZERO,
            hes: Vec::with_capacity(16),
            e_pts: Vec::with_capacity(4),
            f_pts: Vec::with_capacity(4),
            e_sh: Vec::with_capacity(4),
            c_sh: Vec::with_capacity(4),
            dirs: Vec::with_capacity(4),
            r_edges: Vec::with_capacity(4),
            r_sharp: Vec::with_capacity(4),
            r_far: Vec::with_capacity(4),
            r_diag: Vec::with_capacity(4),
            maxn,
            ids: Vec::new(),
            dirty: Vec::new(),
            dirty_list: Vec::new(),
            split: Vec::new(),
            sum_b: Vec::new(),
            sum_a: Vec::new(),
            bad: Vec::new(),
            stencils: Vec::new(),
            last_stencil: 0,
        }
    }

    /// Bytes held by the two tables (capacity for `maxsd`).
    pub fn table_bytes(&self) -> usize {
        let cap = (self.maxn + 3) * (self.maxn + 3);
        2 * cap * (std::mem::size_of::<Vec3A>() + 1 + 2 * std::mem::size_of::<f32>())
    }

    /// Most bytes the worker's scratch can reach besides the tables and corner arrays (capacity
    /// for `maxsd`): the dirty mask and its list, the rolling rows of the regular step and of the
    /// limit sums, the Chaikin far information and a full stencil cache.
    pub fn scratch_bytes(&self) -> usize {
        let (side, cap) = (self.maxn + 3, (self.maxn + 3) * (self.maxn + 3));
        let v = std::mem::size_of::<Vec3A>();
        // A table ring has at most 4 edges and 4 diagonals: 6 + 4 rows of 9 weights.
        let stencil = std::mem::size_of::<(StencilKey, QuadRingStencil)>() + 10 * 9 * 8;
        cap + 8 * side * 4
            + 3 * side * v
            + 6 * self.maxn * v
            + 2 * 4 * (self.maxn + 1) * std::mem::size_of::<(f32, u32)>()
            + MAX_STENCILS * stencil
    }

    /// Gathers the 1-neighbourhood of quad `f` of `mesh` (whose neighbourhood is all quads) into
    /// slate 0 (paper Fig. 2).
    pub(crate) fn gather(&mut self, mesh: &Mesh, f: FaceId) {
        self.cur = 0;
        self.method = mesh.options().crease;
        self.origin32 = Vec3A::from(mesh.position(mesh.from(mesh.face_halfedge(f))));
        self.origin = self.origin32.as_dvec3();
        let origin32 = self.origin32;
        let t = &mut self.t[0];
        t.dirty = true;
        t.reset(1, false);
        let mut vid = [[VertexId::NONE; 4]; 4]; // [j+1][i+1]
        let h0 = mesh.face_halfedge(f);
        let hs = [h0, mesh.next(h0), mesh.next(mesh.next(h0)), mesh.prev(h0)];
        let cpos = [(0, 0), (1, 0), (1, 1), (0, 1)];
        // Outward direction of side k.
        let out = [(0, -1), (1, 0), (0, 1), (-1, 0)];
        for k in 0..4 {
            let (ci, cj) = cpos[k];
            vid[(cj + 1) as usize][(ci + 1) as usize] = mesh.from(hs[k]);
        }
        for k in 0..4 {
            let tw = hs[k].twin();
            if mesh.face(tw).is_some() {
                let x = mesh.to(mesh.next(tw));
                let y = mesh.to(mesh.next(mesh.next(tw)));
                let (ai, aj) = cpos[k];
                let (bi, bj) = cpos[(k + 1) % 4];
                let (oi, oj) = out[k];
                vid[(aj + oj + 1) as usize][(ai + oi + 1) as usize] = x;
                vid[(bj + oj + 1) as usize][(bi + oi + 1) as usize] = y;
            }
        }
        self.regular = true;
        // Table edges and their half-edges: the face's sides, the three other sides of each edge
        // neighbour, and the two outer sides of each regular corner's diagonal face. Directions:
        // 0 = +i, 1 = +j, 2 = -i, 3 = -j; `side_dir[k]` runs along side k, `out_dir[k]` away from it.
        let side_dir = [0usize, 1, 2, 3];
        let out_dir = [3usize, 0, 1, 2];
        let mut edges: [((i32, i32), usize, HalfedgeId); 24] = [((0, 0), 0, HalfedgeId::NONE); 24];
        let mut ne = 0;
        for k in 0..4 {
            edges[ne] = (cpos[k], side_dir[k], hs[k]);
            ne += 1;
            let tw = hs[k].twin();
            if mesh.face(tw).is_some() {
                let g1 = mesh.next(tw);
                let g2 = mesh.next(g1);
                let (ai, aj) = cpos[k];
                let (oi, oj) = out[k];
                edges[ne] = (cpos[k], out_dir[k], g1);
                edges[ne + 1] = ((ai + oi, aj + oj), side_dir[k], g2);
                edges[ne + 2] = (cpos[(k + 1) % 4], out_dir[k], mesh.next(g2));
                ne += 3;
            }
        }
        // Corners: an interior valence-4 corner without a corner tag completes the table with its
        // diagonal vertex; any other corner keeps its whole ring in a corner array.
        for k in 0..4 {
            let v = mesh.from(hs[k]);
            let boundary = mesh.is_boundary_vertex(v);
            let mut valence = 0usize;
            for _ in mesh.outgoing(v) {
                valence += 1;
                if valence > 4 {
                    break;
                }
            }
            // Sharp edges at an interior valence-4 corner are table edges like any other (the
            // general step's rules handle them); a corner tag has no place in the table.
            let c = &mut self.corners[k];
            c.active = valence != 4 || boundary || mesh.vertex_sharpness(v) > 0.0;
            c.boundary = boundary;
            if c.active {
                c.ring
                    .load_with_halfedges(mesh, v, Scheme::CatmullClark, &mut self.hes);
                c.valence = self.hes.len();
                c.ih = self.hes.iter().position(|&h| h == hs[k]).unwrap_or(0);
                if boundary || c.ring.vertex_sharpness() > 0.0 {
                    self.regular = false;
                }
            } else {
                c.valence = 4;
                let g = mesh.prev(mesh.prev(hs[k]).twin()).twin(); // corner -> behind
                let gn = mesh.next(g);
                let d = mesh.to(gn);
                let (ci, cj) = cpos[k];
                let (o1i, o1j) = out[k];
                let (o2i, o2j) = out[(k + 3) % 4];
                vid[(cj + o1j + o2j + 1) as usize][(ci + o1i + o2i + 1) as usize] = d;
                edges[ne] = ((ci + o2i, cj + o2j), out_dir[k], gn);
                edges[ne + 1] = (
                    (ci + o1i, cj + o1j),
                    out_dir[(k + 3) % 4],
                    mesh.next(gn).twin(),
                );
                ne += 2;
            }
        }
        for j in -1..=2i32 {
            for i in -1..=2i32 {
                let v = vid[(j + 1) as usize][(i + 1) as usize];
                let k = t.at(i, j);
                t.ex[k] = v.is_some();
                t.p[k] = if v.is_some() {
                    Vec3A::from(mesh.position(v)) - origin32
                } else {
                    Vec3A::ZERO
                };
            }
        }
        for &((i, j), d, h) in &edges[..ne] {
            let s = mesh.edge_sharpness(h.edge());
            if s > 0.0 {
                self.regular = false;
                t.set_edge_sharp(i, j, d, s);
            }
        }
        // Missing points anywhere except the diagonal spots of irregular corners mean boundary.
        for j in -1..=2i32 {
            for i in -1..=2i32 {
                let diag_spot = (i == -1 || i == 2) && (j == -1 || j == 2);
                if !t.ex[t.at(i, j)] && !diag_spot {
                    self.regular = false;
                }
            }
        }
        // Far ends of the crossing edges, for the Chaikin rule.
        if self.method == CreaseMethod::Chaikin {
            self.regular = false;
            for side in 0..4 {
                for s in 0..=1i32 {
                    let (ii, jj, oi, oj) = side_crossing(side, s, 1);
                    let a = vid[(jj + 1) as usize][(ii + 1) as usize];
                    let b = vid[(oj + 1) as usize][(oi + 1) as usize];
                    if !(a.is_some() && b.is_some()) {
                        continue;
                    }
                    let Some(h) = mesh.find_halfedge(a, b) else {
                        continue;
                    };
                    let mut sum = 0.0;
                    let mut cnt = 0;
                    for g in mesh.outgoing(b) {
                        let sh = mesh.edge_sharpness(g.edge());
                        if g.edge() != h.edge() && is_semi_sharp(sh) {
                            sum += sh;
                            cnt += 1;
                        }
                    }
                    t.far[side][s as usize] = (sum, cnt);
                }
            }
        }
    }

    /// One subdivision step: slate `cur` to slate `1 - cur`, corner arrays refined in place.
    pub(crate) fn step(&mut self) {
        let (a, b) = self.t.split_at_mut(1);
        let (src, dst) = if self.cur == 0 {
            (&a[0], &mut b[0])
        } else {
            (&b[0], &mut a[0])
        };
        let n = src.n as i32;
        dst.reset(src.n * 2, self.regular);
        for c in self.corners.iter_mut() {
            if c.active {
                c.ring.refine();
            }
        }
        if self.regular {
            step_regular(src, dst, &mut self.split);
        } else {
            let scratch = Scratch {
                dirty: &mut self.dirty,
                dirty_list: &mut self.dirty_list,
                split: &mut self.split,
                e_pts: &mut self.e_pts,
                f_pts: &mut self.f_pts,
                e_sh: &mut self.e_sh,
                c_sh: &mut self.c_sh,
                dirs: &mut self.dirs,
            };
            step_general(src, dst, &self.corners, self.method, scratch);
        }
        // Corner arrays fill the table where it cannot be computed.
        for k in 0..4 {
            let c = &self.corners[k];
            if !c.active {
                continue;
            }
            let ((ci, cj), d, d2) = corner_frame(k, 2 * n);
            write_corner(dst, c, ci, cj, d, d2, self.origin);
        }
        self.cur = 1 - self.cur;
    }

    /// Limit position and normal of grid point `(i, j)` of the current slate. Each point is
    /// evaluated once per patch (corner arrays are consumed by their evaluation).
    #[inline]
    pub(crate) fn limit(&mut self, i: i32, j: i32) -> (Vec3A, Vec3A) {
        let n = self.t[self.cur].n as i32;
        if (i == 0 || i == n) && (j == 0 || j == n) {
            let k = match (i == 0, j == 0) {
                (true, true) => 0,
                (false, true) => 1,
                (false, false) => 2,
                (true, false) => 3,
            };
            if self.corners[k].active {
                // Corner arrays hold world positions (in f64).
                let (p, nrm) = self.corners[k].ring.limit();
                return (Vec3A::from(p.as_vec3()), Vec3A::from(nrm.as_vec3()));
            }
        }
        let t = &self.t[self.cur];
        if self.regular || t.is_plain(i, j) {
            let k = t.at(i, j);
            let s = t.s;
            let p = &t.p;
            let e = [p[k + 1], p[k + s], p[k - 1], p[k - s]];
            let dg = [p[k + s + 1], p[k + s - 1], p[k - s - 1], p[k - s + 1]];
            let (pos, t1, t2) = catmark::limit(p[k], &e, &dg, Rule::Smooth);
            let nrm = t1.cross(t2);
            let len = nrm.length();
            if len > 0.0 && len.is_finite() {
                return (pos + self.origin32, nrm / len);
            }
        }
        self.limit_general(i, j)
    }

    /// Limits of all interior grid points `(i, j)`, `1 <= i, j <= n - 1`, of the current slate,
    /// passed row by row to `emit(i, j, position, normal)`.
    ///
    /// Off the band every point is plain (see [`band`]), general table or not, so the regular
    /// limit masks apply to every interior point; they are evaluated in their separable form
    /// (`catmark::limit_row_sums` once per table row, shared by the three output rows around it).
    #[inline]
    pub(crate) fn limit_interior(&mut self, mut emit: impl FnMut(i32, i32, Vec3A, Vec3A)) {
        let t = &self.t[self.cur];
        let n = t.n as i32;
        if n < 2 {
            return;
        }
        debug_assert!(
            (1..n).all(|j| (1..n).all(|i| t.is_plain(i, j))),
            "interior points of a slate must be plain"
        );
        let cnt = (n - 1) as usize;
        // Row sums of table rows 0..=n in a three-row rolling buffer.
        if self.sum_b.len() < 3 * cnt {
            self.sum_b.resize(3 * cnt, Vec3A::ZERO);
            self.sum_a.resize(3 * cnt, Vec3A::ZERO);
        }
        let (sb, sa) = (&mut self.sum_b[..3 * cnt], &mut self.sum_a[..3 * cnt]);
        let slot = |r: i32| (r % 3) as usize * cnt..((r % 3) as usize + 1) * cnt;
        let sums = |j: i32, sb: &mut [Vec3A], sa: &mut [Vec3A]| {
            let base = t.at(0, j);
            catmark::limit_row_sums(
                &t.p[base..base + cnt + 2],
                &mut sb[slot(j)],
                &mut sa[slot(j)],
            );
        };
        sums(0, sb, sa);
        sums(1, sb, sa);
        let o = self.origin32;
        let mut bad = std::mem::take(&mut self.bad);
        bad.clear();
        for j in 1..n {
            sums(j + 1, sb, sa);
            let (bs, b0, bn) = (&sb[slot(j - 1)], &sb[slot(j)], &sb[slot(j + 1)]);
            let (as_, a0, an) = (&sa[slot(j - 1)], &sa[slot(j)], &sa[slot(j + 1)]);
            for x in 0..cnt {
                let (pos, t1, t2) =
                    catmark::limit_regular_from_sums([bs[x], b0[x], bn[x]], [as_[x], a0[x], an[x]]);
                let nrm = t1.cross(t2);
                let len2 = nrm.length_squared();
                if len2 > 0.0 && len2.is_finite() {
                    emit(x as i32 + 1, j, pos + o, nrm * len2.sqrt().recip());
                } else {
                    bad.push((x as i32 + 1, j));
                }
            }
        }
        // Degenerate tangents: those points exactly, through a ring.
        for &(i, j) in &bad {
            let (pos, nrm) = self.limit(i, j);
            emit(i, j, pos, nrm);
        }
        self.bad = bad;
    }

    /// Tessellates the quad `face` of `mesh` (whose 1-neighbourhood is all quads) at `depth` and
    /// writes the limit points and normals of its `(2^depth + 1)^2` grid, row by row (`i` along
    /// the face's first edge, `j` along its last edge reversed).
    ///
    /// ```
    /// use subdiv_mesh::{parse_obj, FaceId, Mesh};
    /// let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
    ///             f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    /// let mesh = Mesh::from_soup(&parse_obj(cube)?)?;
    /// let mut w = subdiv_slate::Worker::new(5);
    /// let (mut p, mut n) = (vec![[0.0; 3]; 25], vec![[0.0; 3]; 25]);
    /// w.patch_grid(&mesh, FaceId(0), 2, &mut p, &mut n);
    /// assert!((p[12][2] - 0.0).abs() < 0.2); // the centre of face 0 (z = 0 side) lies near z = 0
    /// # Ok::<(), subdiv_mesh::MeshError>(())
    /// ```
    pub fn patch_grid(
        &mut self,
        mesh: &Mesh,
        face: FaceId,
        depth: u32,
        pos: &mut [[f32; 3]],
        nrm: &mut [[f32; 3]],
    ) {
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
                let (p, q) = self.limit(i, j);
                pos[row + i as usize] = p.to_array();
                nrm[row + i as usize] = q.to_array();
            }
        }
        self.limit_interior(|i, j, p, q| {
            let k = j as usize * w + i as usize;
            pos[k] = p.to_array();
            nrm[k] = q.to_array();
        });
    }

    /// Limit through a ring built from the table (creases, boundaries, degenerate tangents).
    fn limit_general(&mut self, i: i32, j: i32) -> (Vec3A, Vec3A) {
        let t = &self.t[self.cur];
        // Counter-clockwise directions, starting after a missing one (boundary).
        self.dirs.clear();
        let present: [bool; 4] = std::array::from_fn(|d| t.edge_exists(i, j, d));
        let start = (0..4)
            .find(|&d| !present[(d + 3) % 4] && present[d])
            .unwrap_or(0);
        for k in 0..4 {
            let d = (start + k) % 4;
            if present[d] {
                self.dirs.push(d);
            }
        }
        let boundary = self.dirs.len() < 4;
        let chaikin = self.method == CreaseMethod::Chaikin;
        self.r_edges.clear();
        self.r_sharp.clear();
        self.r_far.clear();
        self.r_diag.clear();
        for (k, &d) in self.dirs.iter().enumerate() {
            let (ni, nj) = (i + DI[d], j + DJ[d]);
            self.r_edges.push(t.p[t.at(ni, nj)].as_dvec3());
            self.r_sharp.push(t.edge_sharp(i, j, d));
            // Far-end information only matters to the Chaikin rule.
            self.r_far.push(if chaikin {
                far_info(t, &self.corners, ni, nj, (d + 2) % 4)
            } else {
                (0.0, 0)
            });
            if !boundary || k + 1 < self.dirs.len() {
                let d2 = (d + 1) % 4;
                self.r_diag
                    .push(t.p[t.at(i + DI[d] + DI[d2], j + DJ[d] + DJ[d2])].as_dvec3());
            }
        }
        let center = t.p[t.at(i, j)].as_dvec3();
        // The ring's limit is linear in its points with weights fixed by its configuration:
        // one stencil per configuration, computed by the ring's own refinement on first use.
        let mut key = StencilKey {
            method: self.method,
            boundary,
            valence: self.r_edges.len() as u8,
            diag: self.r_diag.len() as u8,
            sharp: [0; 4],
            far: [(0, 0); 4],
        };
        for (k, (&s, &(fs, fc))) in self.r_sharp.iter().zip(&self.r_far).enumerate() {
            key.sharp[k] = s.to_bits();
            key.far[k] = (fs.to_bits(), fc);
        }
        let hit = match self.stencils.get(self.last_stencil) {
            Some((k, _)) if *k == key => Some(self.last_stencil),
            _ => self.stencils.iter().position(|(k, _)| *k == key),
        };
        let idx = hit.unwrap_or_else(|| {
            let st = QuadRingStencil::new(
                self.method,
                boundary,
                &self.r_sharp,
                &self.r_far,
                self.r_diag.len(),
            );
            if self.stencils.len() < MAX_STENCILS {
                self.stencils.push((key, st));
                self.stencils.len() - 1
            } else {
                let slot = (self.last_stencil + 1) % MAX_STENCILS;
                self.stencils[slot] = (key, st);
                slot
            }
        });
        self.last_stencil = idx;
        let (p, nrm) = self.stencils[idx]
            .1
            .limit(center, &self.r_edges, &self.r_diag);
        (
            Vec3A::from((p + self.origin).as_vec3()),
            Vec3A::from(nrm.as_vec3()),
        )
    }
}

/// Table coordinates of the crossing edge at position `s` along side `side` (grid `n`): the
/// inner end `(i, j)` and the outer end `(oi, oj)`.
#[inline]
fn side_crossing(side: usize, s: i32, n: i32) -> (i32, i32, i32, i32) {
    match side {
        0 => (s, 0, s, -1),
        1 => (n, s, n + 1, s),
        2 => (s, n, s, n + 1),
        _ => (0, s, -1, s),
    }
}

/// Semi-sharp (sum, count) at table vertex `(i, j)` excluding its edge in direction `excl`.
fn far_info(t: &Table, corners: &[Corner; 4], i: i32, j: i32, excl: usize) -> (f32, u32) {
    let n = t.n as i32;
    for k in 0..4 {
        let ((ci, cj), d, d2) = corner_frame(k, n);
        if ci == i && cj == j && corners[k].active {
            let c = &corners[k];
            let m = c.valence;
            let excl_idx = ring_index_of_dir(c, d, d2, excl).unwrap_or(usize::MAX);
            let mut sum = 0.0;
            let mut cnt = 0;
            for r in 0..m {
                let s = c.ring.edge_sharpness(r);
                if r != excl_idx && is_semi_sharp(s) {
                    sum += s;
                    cnt += 1;
                }
            }
            return (sum, cnt);
        }
    }
    if (0..=n).contains(&i) && (0..=n).contains(&j) {
        let mut sum = 0.0;
        let mut cnt = 0;
        for d in 0..4 {
            if d != excl && t.edge_exists(i, j, d) {
                let s = t.edge_sharp(i, j, d);
                if is_semi_sharp(s) {
                    sum += s;
                    cnt += 1;
                }
            }
        }
        return (sum, cnt);
    }
    // Outer ring: only the crossing edge's far half lies beyond the table.
    let (side, pos) = if j == -1 {
        (0, i)
    } else if i == n + 1 {
        (1, j)
    } else if j == n + 1 {
        (2, i)
    } else {
        (3, j)
    };
    if (0..=n).contains(&pos) {
        t.far[side][pos as usize]
    } else {
        (0.0, 0)
    }
}

/// Ring index of the corner's edge in table direction `dir` (None if the ring has no such edge).
#[inline]
fn ring_index_of_dir(c: &Corner, d: usize, d2: usize, dir: usize) -> Option<usize> {
    let m = c.valence;
    let off = if dir == d {
        0isize
    } else if dir == d2 {
        1
    } else if dir == (d + 2) % 4 {
        2
    } else {
        -1
    };
    let idx = c.ih as isize + off;
    if c.boundary {
        if idx < 0 || idx >= m as isize {
            None
        } else {
            Some(idx as usize)
        }
    } else {
        if off == 2 && m < 4 {
            // valence 3: the edge opposite d is the one before d (shared slot)
            return Some((c.ih + m - 1) % m);
        }
        Some(((idx + m as isize) % m as isize) as usize)
    }
}

/// Copies a refined corner array into the table around its corner `(ci, cj)`.
fn write_corner(t: &mut Table, c: &Corner, ci: i32, cj: i32, d: usize, d2: usize, origin: DVec3) {
    let r = &c.ring;
    let m = c.valence;
    let put = |t: &mut Table, i: i32, j: i32, p: Option<DVec3>| {
        let k = t.at(i, j);
        match p {
            Some(p) => {
                t.p[k] = Vec3A::from((p - origin).as_vec3());
                t.ex[k] = true;
            }
            None => {
                t.p[k] = Vec3A::from((r.center() - origin).as_vec3());
                t.ex[k] = false;
            }
        }
    };
    put(t, ci, cj, Some(r.center()));
    let back = (d + 2) % 4; // -d
    let down = (d2 + 2) % 4; // -d2
    let e_back = ring_index_of_dir(c, d, d2, back);
    let e_down = ring_index_of_dir(c, d, d2, down);
    put(t, ci + DI[back], cj + DJ[back], e_back.map(|x| r.edge(x)));
    put(t, ci + DI[down], cj + DJ[down], e_down.map(|x| r.edge(x)));
    // The diagonal behind the corner exists only for an interior valence-4 vertex.
    let diag = if !c.boundary && m == 4 {
        Some(r.diag((c.ih + 2) % 4))
    } else {
        None
    };
    put(t, ci + DI[back] + DI[down], cj + DJ[back] + DJ[down], diag);
    // Child sharpness of the corner's edges.
    for dir in [d, d2, back, down] {
        let (ni, nj) = (ci + DI[dir], cj + DJ[dir]);
        if !t.inside(ni, nj) {
            continue;
        }
        let s = ring_index_of_dir(c, d, d2, dir)
            .map(|x| r.edge_sharpness(x))
            .unwrap_or(0.0);
        t.set_edge_sharp(ci, cj, dir, s);
    }
}

/// Smooth regular step: no sharpness, no boundary. The face, edge and vertex rules of a regular
/// grid in their separable form (`catmark::split_row` and friends): each source row is split
/// along its length, and neighbouring split rows combine into the rows of `dst`. Split rows live
/// in a three-row rolling buffer `split`. Active corners get a (meaningless) vertex point too:
/// `write_corner` replaces it.
fn step_regular(src: &Table, dst: &mut Table, split: &mut Vec<Vec3A>) {
    let ss = src.s;
    let ds = dst.s;
    debug_assert_eq!(ds, 2 * ss - 3);
    if split.len() < 3 * ds {
        split.resize(3 * ds, Vec3A::ZERO);
    }
    // Storage row y of dst is level coordinate y - 1: odd coordinates (even y) lie between split
    // rows y / 2 and y / 2 + 1, even ones (odd y) at split row (y + 1) / 2.
    let slot = |r: usize| (r % 3) * ds..(r % 3 + 1) * ds;
    for (r, row) in src.p[..ss * ss].chunks_exact(ss).enumerate() {
        catmark::split_row(row, &mut split[slot(r)]);
        if r == 0 {
            continue;
        }
        let h = &split[..3 * ds];
        if r >= 2 {
            let y = 2 * r - 3;
            let out = &mut dst.p[y * ds..(y + 1) * ds];
            catmark::split_rows_even(&h[slot(r - 2)], &h[slot(r - 1)], &h[slot(r)], out);
        }
        let y = 2 * r - 2;
        let out = &mut dst.p[y * ds..(y + 1) * ds];
        catmark::split_rows_mid(&h[slot(r - 1)], &h[slot(r)], out);
    }
    dst.ex[..ds * ds].fill(true);
}

struct Scratch<'a> {
    dirty: &'a mut Vec<bool>,
    dirty_list: &'a mut Vec<u32>,
    split: &'a mut Vec<Vec3A>,
    e_pts: &'a mut Vec<Vec3A>,
    f_pts: &'a mut Vec<Vec3A>,
    e_sh: &'a mut Vec<f32>,
    c_sh: &'a mut Vec<f32>,
    dirs: &'a mut Vec<usize>,
}

/// General step: creases, boundaries, fractional sharpness, Chaikin.
fn step_general(
    src: &Table,
    dst: &mut Table,
    corners: &[Corner; 4],
    method: CreaseMethod,
    sc: Scratch<'_>,
) {
    let n = src.n as i32;
    let is_corner = |i: i32, j: i32| -> Option<usize> {
        (0..4).find(|&k| {
            let ((ci, cj), _, _) = corner_frame(k, n);
            ci == i && cj == j && corners[k].active
        })
    };
    // The smooth regular rules everywhere first; then the general rules where they differ.
    step_regular(src, dst, sc.split);
    let missing = src.mark_dirty(sc.dirty, sc.dirty_list);
    if missing {
        // Missing points lie on the outer ring, so only faces touching it can be missing.
        for j in -1..=n {
            let all = j == -1 || j == n;
            for i in -1..=n {
                if (all || i == -1 || i == n) && !src.face_exists(i, j) {
                    let k = dst.at(2 * i + 1, 2 * j + 1);
                    dst.ex[k] = false;
                }
            }
        }
    }
    // Child sharpness at active corners comes from their (already refined) corner arrays.
    for (k, c) in corners.iter().enumerate() {
        if c.active {
            let ((ci, cj), d, d2) = corner_frame(k, n);
            for dir in 0..4 {
                if let Some(x) = ring_index_of_dir(c, d, d2, dir) {
                    dst.set_edge_sharp(2 * ci, 2 * cj, dir, c.ring.edge_sharpness(x));
                }
            }
        }
    }
    // Vertex points and the child sharpness of their edges, at the patch's dirty points.
    let ss = src.s;
    for &kk in sc.dirty_list.iter() {
        let kk = kk as usize;
        let (i, j) = ((kk % ss) as i32 - 1, (kk / ss) as i32 - 1);
        if !((0..=n).contains(&i) && (0..=n).contains(&j) && src.ex[kk]) {
            continue;
        }
        if (i == 0 || i == n) && (j == 0 || j == n) && is_corner(i, j).is_some() {
            continue;
        }
        {
            sc.dirs.clear();
            sc.e_pts.clear();
            sc.e_sh.clear();
            sc.f_pts.clear();
            for d in 0..4 {
                if src.edge_exists(i, j, d) {
                    sc.dirs.push(d);
                    sc.e_pts.push(src.p[src.at(i + DI[d], j + DJ[d])]);
                    sc.e_sh.push(src.edge_sharp(i, j, d));
                }
            }
            for d in 0..4 {
                let d2 = (d + 1) % 4;
                let (fi, fj) = (i + (DI[d] + DI[d2] - 1) / 2, j + (DJ[d] + DJ[d2] - 1) / 2);
                if src.face_exists(fi, fj) {
                    sc.f_pts.push(dst.p[dst.at(2 * fi + 1, 2 * fj + 1)]);
                }
            }
            sc.c_sh.clear();
            sc.c_sh.resize(sc.e_sh.len(), 0.0);
            let rules = VertexRules::new(method, 0.0, sc.e_sh, sc.c_sh);
            let v = src.p[src.at(i, j)];
            let k = dst.at(2 * i, 2 * j);
            dst.p[k] = catmark::vertex_point(v, sc.e_pts, sc.f_pts, &rules);
            dst.ex[k] = true;
            for (x, &d) in sc.dirs.iter().enumerate() {
                dst.set_edge_sharp(2 * i, 2 * j, d, sc.c_sh[x]);
            }
        }
    }
    // Edge points of horizontal edges (i,j)-(i+1,j) (`dir` 0) and vertical ones (i,j)-(i,j+1)
    // (`dir` 1) with a dirty end.
    let mut edge = |i: i32, j: i32, dir: usize| {
        let (bi, bj) = (i + DI[dir], j + DJ[dir]);
        // A missing end marks both ends dirty, so clean edges exist.
        if !(sc.dirty[src.at(i, j)] || sc.dirty[src.at(bi, bj)]) {
            return;
        }
        if !src.edge_exists(i, j, dir) {
            let k = dst.at(i + bi, j + bj);
            dst.ex[k] = false;
            return;
        }
        let s = src.edge_sharp(i, j, dir);
        let sides: [(i32, i32); 2] = if dir == 0 {
            [(i, j - 1), (i, j)]
        } else {
            [(i - 1, j), (i, j)]
        };
        if s == 0.0
            && src.face_exists(sides[0].0, sides[0].1)
            && src.face_exists(sides[1].0, sides[1].1)
        {
            // A smooth edge between two faces: the regular pass computed it alike.
            return;
        }
        // Child sharpness at each end: from the vertex rules (inner ends) or the far info.
        let child_at = |vi: i32, vj: i32, toward: usize| -> f32 {
            if (0..=n).contains(&vi) && (0..=n).contains(&vj) {
                dst.edge_sharp(2 * vi, 2 * vj, toward)
            } else {
                // Far-end information only matters to the Chaikin rule.
                let far = if method == CreaseMethod::Chaikin {
                    far_info(src, corners, vi, vj, (toward + 2) % 4)
                } else {
                    (0.0, 0)
                };
                crease::child_edge_sharpness(method, s, far)
            }
        };
        let c0 = child_at(i, j, dir);
        let c1 = child_at(bi, bj, (dir + 2) % 4);
        let w = edge_crease_weight(method, s, [c0, c1]);
        let mut faces = [Vec3A::ZERO; 2];
        let mut nf = 0;
        // Faces on either side of the edge.
        let sides: [(i32, i32); 2] = if dir == 0 {
            [(i, j - 1), (i, j)]
        } else {
            [(i - 1, j), (i, j)]
        };
        for (fi, fj) in sides {
            if src.face_exists(fi, fj) {
                faces[nf] = dst.p[dst.at(2 * fi + 1, 2 * fj + 1)];
                nf += 1;
            }
        }
        let e = catmark::edge_point(src.p[src.at(i, j)], src.p[src.at(bi, bj)], &faces[..nf], w);
        let k = dst.at(i + bi, j + bj);
        dst.p[k] = e;
        dst.ex[k] = true;
        // New far info for crossing edges leaving the table (Chaikin only).
        let outer = |vi: i32, vj: i32| !((0..=n).contains(&vi) && (0..=n).contains(&vj));
        if method == CreaseMethod::Chaikin && (outer(i, j) || outer(bi, bj)) {
            let (oi, oj, toward) = if outer(i, j) {
                (i, j, dir)
            } else {
                (bi, bj, (dir + 2) % 4)
            };
            let cf =
                crease::child_edge_sharpness(method, s, far_info(src, corners, oi, oj, toward));
            let info = if is_semi_sharp(cf) { (cf, 1) } else { (0.0, 0) };
            let (side, pos) = if oj == -1 {
                (0, 2 * i)
            } else if oi == n + 1 {
                (1, 2 * j)
            } else if oj == n + 1 {
                (2, 2 * i)
            } else {
                (3, 2 * j)
            };
            if (0..=2 * n).contains(&pos) {
                dst.far[side][pos as usize] = info;
            }
        }
    };
    // Every edge with a dirty end, once: from its dirty end with the lower index. Horizontal edges
    // of rows 0..=n and vertical edges of columns 0..=n (the outer ring's own edges have no
    // children in the next table).
    for &kk in sc.dirty_list.iter() {
        let kk = kk as usize;
        let (i, j) = ((kk % ss) as i32 - 1, (kk / ss) as i32 - 1);
        for d in 0..4 {
            let (qi, qj) = (i + DI[d], j + DJ[d]);
            if !src.inside(qi, qj) {
                continue;
            }
            let qk = src.at(qi, qj);
            if sc.dirty[qk] && qk < kk {
                continue;
            }
            let (ei, ej, dir) = if d < 2 { (i, j, d) } else { (qi, qj, d - 2) };
            let row = if dir == 0 { ej } else { ei };
            if (0..=n).contains(&row) {
                edge(ei, ej, dir);
            }
        }
    }
    // The outer ends of crossing edges exist as edge points; new outer-ring vertices beyond
    // (odd positions) are face points (already marked).
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slates(w: &Worker) -> *const Vec3A {
        w.t[0].p.as_ptr()
    }

    #[test]
    fn thread_worker_is_reused_and_deep_workers_are_not_kept() {
        // Run on a fresh thread so that other tests' workers are not involved.
        std::thread::spawn(|| {
            let a = thread_worker(5);
            let pa = slates(&a);
            // While `a` is lent, a nested request gets its own worker.
            let b = thread_worker(5);
            let pb = slates(&b);
            assert_ne!(pb, pa);
            // The first one returned is kept (`b`); `a`, as large, is freed.
            drop(b);
            drop(a);
            // The same slates serve the next requests, shallower ones too.
            assert_eq!(slates(&thread_worker(5)), pb);
            assert_eq!(slates(&thread_worker(3)), pb);
            // A deeper request than the held worker gets a bigger one, which replaces it.
            let c = thread_worker(KEEP_MAXSD);
            let pc = slates(&c);
            assert!(c.maxn == 1 << KEEP_MAXSD);
            drop(c);
            assert_eq!(slates(&thread_worker(2)), pc);
            // Past KEEP_MAXSD the worker is freed at the end; the kept one stays.
            let d = thread_worker(KEEP_MAXSD + 1);
            assert!(d.maxn == 1 << (KEEP_MAXSD + 1));
            drop(d);
            assert_eq!(slates(&thread_worker(2)), pc);
        })
        .join()
        .unwrap();
    }
}
