//! Building a [`StencilTable`]: the limit position and first derivatives at every parameter
//! point as weights of the cage points, probed from `subdiv-eval`.
//!
//! The limit surface of a face, and its derivatives, are linear in the points of the face's
//! neighbourhood `N(F)` (the vertices of every face that shares a vertex with it: its patch's
//! support, for n-gons through their level-1 quads). The cage's vertices are coloured so that
//! no two vertices of one neighbourhood share a colour; a *probe* cage puts colour `3k + c` at
//! the `c`-th unit vector and every other vertex at the origin, so evaluating it gives, in
//! coordinate `c` of every point's position and derivatives, the weight of the one vertex of
//! that colour in the point's neighbourhood. `ceil(colours / 3)` evaluations of all the points
//! give every weight (OpenSubdiv's `LimitStencilTableFactory` refines instead; both are the
//! same linear maps).

use glam::DVec3;
use subdiv_eval::{Derivatives, Domain, Evaluator, Query, Sample};
use subdiv_mesh::{FaceId, Mesh};
use subdiv_rules::{Scheme, VertexParams};

use crate::StencilError;
use crate::support::Neighbourhoods;

/// Points a block holds: the kernel computes eight points at a time.
pub(crate) const LANES: usize = 8;

/// Floats of one support vertex in one block: eight position weights, eight `d/du` weights,
/// eight `d/dv` weights.
pub(crate) const BLOCK_FLOATS: usize = 3 * LANES;

/// The lane of a block that holds no point.
pub(crate) const NO_POINT: u32 = u32::MAX;

/// Most bytes of weights a table is made with (before faces alike share theirs): about a
/// million points of a regular cage. What a frame reads from memory grows with it.
pub const MAX_TABLE_BYTES: usize = 64 << 20;

/// How far a stencil's position weights may sum from 1 (an affine combination, up to rounding
/// in `f64` and the `f32` they are kept in).
const PARTITION_TOLERANCE: f64 = 1e-4;

/// How far a point of the table may lie from the evaluator's on a moved cage, over the cage's
/// size (the table's sums of `f32` weights round at about `1e-7`).
const POSITION_TOLERANCE: f64 = 1e-6;

/// How far (radians) a normal of the table may turn from the evaluator's on a moved cage (the
/// rounding of the `f32` weights turns it by a few `1e-7`; a limit the probes do not give
/// linearly, by far more).
const NORMAL_TOLERANCE: f64 = 1e-4;

/// The points of one cage face: its support and its blocks of eight points.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Group {
    /// First support vertex in [`StencilTable::support`].
    pub support: u32,
    /// Support size.
    pub len: u32,
    /// First block (its lanes at `8 * first_block` in [`StencilTable::targets`]).
    pub first_block: u32,
    /// Number of blocks.
    pub blocks: u32,
    /// Number of points (the lanes after them hold none).
    pub points: u32,
    /// First weight in [`StencilTable::weights`].
    pub weights: usize,
}

/// The limit position and first derivatives of a fixed set of parameter points as linear maps
/// of the cage's points: built once per topology ([`StencilTable::new`]), applied to every
/// frame of a moving cage ([`StencilTable::apply`]), which writes positions and unit normals.
///
/// Weights are kept per face over the face's support, eight points a block, so that one frame
/// reads each support vertex once per block and runs the sums eight points at a time.
#[derive(Clone, Debug)]
pub struct StencilTable {
    pub(crate) groups: Vec<Group>,
    pub(crate) support: Vec<u32>,
    pub(crate) targets: Vec<u32>,
    pub(crate) weights: Vec<f32>,
    /// Lanes whose stencil is their cage vertex's ring limit (`ring.rs`).
    pub(crate) ring_stencils: usize,
    num_points: usize,
    num_vertices: usize,
}

impl StencilTable {
    /// The stencils of the points `params` (point `i` at cage face `params.face[i]`, `(u, v)`
    /// = `params.uv[i]` in the face's domain, as `subdiv_eval::Domain` defines it) on `mesh`'s
    /// `scheme` limit surface. At a cage vertex where the evaluator settles its limit
    /// numerically, the table takes the vertex's ring refined `corner_level` times and its
    /// masks, as a tessellation of that depth does (`ring.rs`). Errors name the point or face:
    /// a parameter point outside its face or on a hole, a cage the scheme refuses, or a limit
    /// the table cannot hold.
    pub fn new(
        mesh: &Mesh,
        scheme: Scheme,
        params: &VertexParams,
        corner_level: u32,
    ) -> Result<StencilTable, StencilError> {
        let n = params.face.len();
        if params.uv.len() != n {
            return Err(StencilError::Params(format!(
                "{} faces but {} (u, v) pairs",
                n,
                params.uv.len()
            )));
        }
        let nf = mesh.num_faces();
        if let Some(i) = params.face.iter().position(|&f| f as usize >= nf) {
            return Err(StencilError::Params(format!(
                "point {i} names face {} of a cage of {nf} faces",
                params.face[i]
            )));
        }
        let balanced = crate::balance::balance(mesh, scheme, params);
        let params = balanced.as_ref().unwrap_or(params);
        // Points grouped by face, in face order.
        let mut count = vec![0u32; nf + 1];
        for &f in &params.face {
            count[f as usize + 1] += 1;
        }
        for f in 0..nf {
            count[f + 1] += count[f];
        }
        let mut order = vec![0u32; n];
        let mut next = count.clone();
        for (i, &f) in params.face.iter().enumerate() {
            order[next[f as usize] as usize] = i as u32;
            next[f as usize] += 1;
        }
        let neighbourhoods = Neighbourhoods::new(mesh);
        let colours = neighbourhoods.colours(mesh.num_vertices());
        let mut table = StencilTable {
            groups: Vec::new(),
            support: Vec::new(),
            targets: Vec::new(),
            weights: Vec::new(),
            ring_stencils: 0,
            num_points: n,
            num_vertices: mesh.num_vertices(),
        };
        // The queries in group order: group `g`'s points are `queries[count[f]..count[f + 1]]`.
        let mut queries = Vec::with_capacity(n);
        for f in 0..nf {
            let pts = &mut order[count[f] as usize..count[f + 1] as usize];
            if pts.is_empty() {
                continue;
            }
            // In the face's own frame (by v, then u): faces alike in their neighbourhood and
            // in the points they hold get the same weights, stored once (`share`).
            pts.sort_by(|&a, &b| {
                let (pa, pb) = (params.uv[a as usize], params.uv[b as usize]);
                pa[1].total_cmp(&pb[1]).then(pa[0].total_cmp(&pb[0]))
            });
            let pts = &*pts;
            let support = neighbourhoods.of(f);
            let blocks = pts.len().div_ceil(LANES);
            let bytes = (table.weights.len() + blocks * support.len() * BLOCK_FLOATS) * 4;
            if bytes > MAX_TABLE_BYTES {
                return Err(StencilError::TooLarge { bytes });
            }
            table.groups.push(Group {
                support: table.support.len() as u32,
                len: support.len() as u32,
                first_block: (table.targets.len() / LANES) as u32,
                blocks: blocks as u32,
                points: pts.len() as u32,
                weights: table.weights.len(),
            });
            table.support.extend_from_slice(support);
            table.targets.extend_from_slice(pts);
            let len = table.targets.len();
            table.targets.resize(len.next_multiple_of(LANES), NO_POINT);
            table.weights.resize(
                table.weights.len() + blocks * support.len() * BLOCK_FLOATS,
                0.0,
            );
            for &p in pts {
                let [u, v] = params.uv[p as usize];
                queries.push(Query::new(f as u32, f64::from(u), f64::from(v)));
            }
        }
        table.probe(mesh, scheme, &colours, &queries)?;
        let moved = moved_cage(mesh);
        let vertices = table.verify(mesh, &moved, scheme, &queries)?;
        table.ring_lanes(&moved, scheme, &colours, vertices, corner_level)?;
        table.share();
        Ok(table)
    }

    /// Number of points the table writes.
    pub fn num_points(&self) -> usize {
        self.num_points
    }

    /// Number of cage vertices it reads.
    pub fn num_vertices(&self) -> usize {
        self.num_vertices
    }

    /// Number of points at cage vertices whose stencil is the vertex's ring limit (see
    /// `ring.rs`): every point at a cage vertex.
    pub fn ring_stencils(&self) -> usize {
        self.ring_stencils
    }

    /// Bytes the table holds (what one frame reads, but for the cage points).
    pub fn bytes(&self) -> usize {
        self.weights.len() * 4 + self.targets.len() * 4 + self.support.len() * 4
    }

    /// Evaluates the probe cages and stores each weight where it belongs.
    fn probe(
        &mut self,
        mesh: &Mesh,
        scheme: Scheme,
        colours: &[u32],
        queries: &[Query],
    ) -> Result<(), StencilError> {
        let num_colours = colours.iter().map(|&c| c + 1).max().unwrap_or(0);
        let mut cage = mesh.clone();
        let mut samples = vec![Sample::default(); queries.len()];
        for probe in 0..num_colours.div_ceil(3) {
            probe_cage(&mut cage, colours, probe);
            let eval = Evaluator::new(&cage, scheme)?;
            eval.evaluate_many(queries, Derivatives::First, &mut samples)
                .map_err(StencilError::Eval)?;
            let mut first_point = 0;
            for g in &self.groups {
                let support = &self.support[g.support as usize..][..g.len as usize];
                for r in 0..g.points as usize {
                    let s = &samples[first_point + r];
                    let (b, l) = (r / LANES, r % LANES);
                    for (j, &v) in support.iter().enumerate() {
                        let c = colours[v as usize];
                        if c / 3 != probe {
                            continue;
                        }
                        let k = (c % 3) as usize;
                        let at = g.weights + (b * g.len as usize + j) * BLOCK_FLOATS + l;
                        self.weights[at] = s.position[k] as f32;
                        self.weights[at + LANES] = s.du[k] as f32;
                        self.weights[at + 2 * LANES] = s.dv[k] as f32;
                    }
                }
                first_point += g.points as usize;
            }
        }
        Ok(())
    }

    /// Whether lane `l` of block `b` of group `g` has position weights that sum to 1 (an
    /// affine combination). A support vertex outside the face's neighbourhood, which the
    /// colouring does not separate, shows here, and so does a limit the probes cannot give
    /// (see [`StencilTable::verify`]).
    fn partition(&self, g: &Group, b: usize, l: usize) -> bool {
        let s = g.len as usize;
        let sum: f64 = (0..s)
            .map(|j| f64::from(self.weights[g.weights + (b * s + j) * BLOCK_FLOATS + l]))
            .sum();
        (sum - 1.0).abs() <= PARTITION_TOLERANCE
    }

    /// The position and derivative sums of a lane for the cage points `points`, in `f64`,
    /// about the face's first support vertex as [`StencilTable::apply`] takes them.
    pub(crate) fn lane_sums(
        &self,
        g: &Group,
        b: usize,
        l: usize,
        points: &[glam::Vec3],
    ) -> [DVec3; 3] {
        let s = g.len as usize;
        let support = &self.support[g.support as usize..][..s];
        let origin = support
            .first()
            .map_or(DVec3::ZERO, |&v| points[v as usize].as_dvec3());
        let mut sums = [DVec3::ZERO; 3];
        for (j, &v) in support.iter().enumerate() {
            let at = g.weights + (b * s + j) * BLOCK_FLOATS + l;
            let p = points[v as usize].as_dvec3() - origin;
            for (k, sum) in sums.iter_mut().enumerate() {
                *sum += p * f64::from(self.weights[at + k * LANES]);
            }
        }
        sums[0] += origin;
        sums
    }

    /// The table against the evaluator on the `moved` cage: a point whose weights are not
    /// affine or whose position or normal differs is not linear in the cage, an error. Points at
    /// cage vertices are returned with their vertices for [`StencilTable::ring_lanes`]: there
    /// the slates take the masks of the vertex's ring refined to the depth (OpenSubdiv's value
    /// at that level, which is not the limit the evaluator gives at a dart or a vertex of
    /// valence 2), and the evaluator settles some limits numerically, not linearly.
    fn verify(
        &self,
        mesh: &Mesh,
        moved: &Mesh,
        scheme: Scheme,
        queries: &[Query],
    ) -> Result<Vec<RingLane>, StencilError> {
        let eval = Evaluator::new(moved, scheme)?;
        let mut samples = vec![Sample::default(); queries.len()];
        eval.evaluate_many(queries, Derivatives::First, &mut samples)
            .map_err(StencilError::Eval)?;
        let size = cage_size(mesh);
        let mut lanes = Vec::new();
        let mut first_point = 0;
        for (gi, g) in self.groups.iter().enumerate() {
            for r in 0..g.points as usize {
                let (b, l) = (r / LANES, r % LANES);
                let sums = self.lane_sums(g, b, l, moved.positions());
                let want = &samples[first_point + r];
                let target = self.targets[g.first_block as usize * LANES + r];
                // Every cage vertex takes its ring's masks, as the slates' corners do.
                if let Some(vertex) = cage_vertex(mesh, scheme, queries[first_point + r]) {
                    lanes.push(RingLane {
                        group: gi,
                        block: b,
                        lane: l,
                        target,
                        vertex,
                    });
                } else if !close(sums, want.position, want.normal(), size)
                    || !self.partition(g, b, l)
                {
                    return Err(StencilError::Support { point: target });
                }
            }
            first_point += g.points as usize;
        }
        Ok(lanes)
    }
}

/// A lane at a cage vertex whose stencil comes from the vertex's ring (`ring.rs`).
pub(crate) struct RingLane {
    pub group: usize,
    pub block: usize,
    pub lane: usize,
    pub target: u32,
    pub vertex: u32,
}

/// Whether a lane's sums (position, two tangents) give `position` and the unit `normal` to
/// the tolerances, on a cage of size `size`.
pub(crate) fn close(sums: [DVec3; 3], position: DVec3, normal: DVec3, size: f64) -> bool {
    let n = sums[1].cross(sums[2]).normalize_or_zero();
    (sums[0] - position).length() <= POSITION_TOLERANCE * size
        && (n == DVec3::ZERO) == (normal == DVec3::ZERO)
        && (n == DVec3::ZERO || n.angle_between(normal) <= NORMAL_TOLERANCE)
}

/// The diagonal of the cage's bounding box (at least the smallest positive `f64`).
pub(crate) fn cage_size(mesh: &Mesh) -> f64 {
    let (lo, hi) = mesh.bounds();
    f64::from((hi - lo).length()).max(f64::MIN_POSITIVE)
}

/// `mesh` with every vertex moved by up to a tenth of its size (deterministic): the cage the
/// table is checked on.
fn moved_cage(mesh: &Mesh) -> Mesh {
    let mut cage = mesh.clone();
    let size = cage_size(mesh) as f32;
    for (i, p) in cage.positions_mut().iter_mut().enumerate() {
        let h = |k: u64| {
            let x = (i as u64 * 3 + k).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40;
            (x as f32 / (1u64 << 24) as f32 - 0.5) * 0.2 * size
        };
        *p += glam::Vec3::new(h(0), h(1), h(2));
    }
    cage
}

/// Probe `probe` of the colouring: colour `3 * probe + c` at the `c`-th unit vector, every
/// other vertex at the origin.
pub(crate) fn probe_cage(cage: &mut Mesh, colours: &[u32], probe: u32) {
    for (p, &c) in cage.positions_mut().iter_mut().zip(colours) {
        *p = glam::Vec3::ZERO;
        if c / 3 == probe {
            p[(c % 3) as usize] = 1.0;
        }
    }
}

/// The cage vertex at parameter point `q`, if it is one (a corner of its face's domain).
fn cage_vertex(mesh: &Mesh, scheme: Scheme, q: Query) -> Option<u32> {
    let f = FaceId(q.face);
    let verts = mesh.face_vertices(f);
    let domain = Domain::of(scheme, verts.len());
    (0..verts.len())
        .find(|&k| domain.corner(k) == [q.u, q.v])
        .map(|k| verts[k].0)
}
