//! Face-varying refinement: one uniform step of a [`FaceVarying`] channel (UVs) alongside the
//! positions, with OpenSubdiv 3.5's face-varying linear interpolation options
//! ([`FVarLinearInterpolation`]; semantics of `Vtr::FVarLevel` and
//! `Far::PrimvarRefiner::InterpolateFaceVarying`).
//!
//! Where the values around a vertex and along its edges agree (no seam) the value is refined
//! with the same rules as the positions (the [`RefineKernel`], crease sharpness included).
//! Where they do not, every distinct value around the vertex (a *sibling*) is refined on its
//! own: as a *corner* (kept) or as a *crease* (`3/4` itself plus `1/8` each of the two values
//! along the seam or boundary that bound its span of faces); values on a seam edge are the
//! midpoints of each side's ends. The options decide which siblings are corners:
//! `none` none but infinitely sharp vertices, `cornersOnly` siblings that span one face,
//! `cornersPlus1` also every sibling of a vertex with three or more, `cornersPlus2` also darts
//! and both siblings where one is a corner, `boundaries` every sibling on a seam or boundary,
//! `all` everything (bilinear). The tags are recomputed at every level from that level's
//! topology, which for infinitely sharp seams gives OpenSubdiv's inherited tags.
//! A crease sibling whose span (or vertex) is semi-sharp stays put while the child is still
//! semi-sharp there and blends crease and corner by the fractional weight in the step where it
//! runs out, as OpenSubdiv does. With `cornersPlus1`/`cornersPlus2`, of two siblings at a
//! vertex where only one span is semi-sharp the other is *held* with it
//! ([`Dependence`], OpenSubdiv's dependent sharpness); that tag depends on the levels before,
//! so refinement carries it in the child channel ([`FaceVarying::dependence`]).

use glam::{Vec2, Vec3};
use subdiv_mesh::{
    Dependence, FVarLinearInterpolation, FaceId, FaceVarying, HalfedgeId, Mesh, VertexId,
};

use crate::Scheme;
use crate::crease::{decrement, fractional_weight, is_infinite, is_semi_sharp};
use crate::refine::RefineKernel;

mod limit;
mod step;
pub use limit::{limit_face_varying, limit_face_varying_exact, semi_sharp_levels};
pub(crate) use step::refine_face_varying;
pub use step::{FVarChildren, FVarRegion, refine_face_varying_part};

/// The options of `Vtr::FVarLevel::completeTopologyFromFaceValues`, as flags.
#[derive(Clone, Copy, Debug)]
struct Flags {
    linear_all: bool,
    linear_boundaries: bool,
    dependent: bool,
    corners_sharp: bool,
    smooth_corners_sharp: bool,
    both_if_one_corner: bool,
    darts: bool,
}

impl Flags {
    /// The flags of `mesh`'s option; the bilinear scheme interpolates every channel linearly
    /// whatever the option (its masks are linear), as `All` does.
    fn new(mesh: &Mesh, scheme: Scheme) -> Flags {
        use FVarLinearInterpolation as F;
        let o = if scheme == Scheme::Bilinear {
            F::All
        } else {
            mesh.options().fvar
        };
        let linear_boundaries = matches!(o, F::All | F::Boundaries);
        let corners_sharp = o != F::None;
        let geom_corners_smooth =
            mesh.options().boundary != subdiv_mesh::BoundaryInterpolation::EdgeAndCorner;
        Flags {
            linear_all: o == F::All,
            linear_boundaries,
            dependent: matches!(o, F::CornersPlus1 | F::CornersPlus2),
            corners_sharp,
            smooth_corners_sharp: geom_corners_smooth && corners_sharp,
            both_if_one_corner: o == F::CornersPlus2,
            darts: o == F::CornersPlus2 || linear_boundaries,
        }
    }
}

/// The faces of one sibling value around a vertex (`Vtr::FVarLevel::ValueSpan`).
#[derive(Clone, Copy, Debug, Default)]
struct Span {
    size: usize,
    start: usize,
    /// Seams inside the span, or runs of faces beyond the first (a value met again).
    disjoint: i32,
    /// Infinitely sharp edges inside the span.
    inf: u32,
    /// Semi-sharp edges inside the span.
    semi: u32,
}

impl Span {
    /// Whether the span makes its value a corner whatever the options: disjoint, or cut by an
    /// infinitely sharp edge.
    #[inline]
    fn sharp(&self) -> bool {
        self.disjoint != 0 || self.inf > 0
    }
}

/// The channel and the topology it needs: the corner of every half-edge with a face and which
/// edges are seams.
struct Channel<'a> {
    mesh: &'a Mesh,
    fv: &'a FaceVarying,
    /// Face corner of each half-edge's origin in its face (`u32::MAX` for boundary half-edges).
    corner: Vec<u32>,
    /// Edges whose faces disagree at either end.
    seam: Vec<bool>,
    flags: Flags,
    /// Out half-edges left out of their origin's ring ([`FVarRegion::skips`]; empty: none).
    skip: Vec<bool>,
}

impl<'a> Channel<'a> {
    /// The channel `fv` of `mesh` with its corners and seams.
    fn new(mesh: &'a Mesh, fv: &'a FaceVarying, scheme: Scheme) -> Channel<'a> {
        let mut corner = vec![u32::MAX; mesh.num_halfedges()];
        let (offsets, _) = mesh.face_lists();
        for f in mesh.faces() {
            let verts = mesh.face_vertices(f);
            let mut h = mesh.face_halfedge(f);
            for _ in 0..verts.len() {
                let k = verts.iter().position(|&v| v == mesh.from(h)).unwrap_or(0);
                corner[h.idx()] = offsets[f.idx()] + k as u32;
                h = mesh.next(h);
            }
        }
        let mut ch = Channel {
            mesh,
            fv,
            corner,
            seam: vec![false; mesh.num_edges()],
            flags: Flags::new(mesh, scheme),
            skip: Vec::new(),
        };
        for e in mesh.edges() {
            let (h0, h1) = (e.halfedge(0), e.halfedge(1));
            if mesh.face(h0).is_some() && mesh.face(h1).is_some() {
                ch.seam[e.idx()] = ch.index(h0) != ch.index(mesh.next(h1))
                    || ch.index(mesh.next(h0)) != ch.index(h1);
            }
        }
        ch
    }
    /// Value index of `h`'s face at `h`'s origin.
    #[inline]
    fn index(&self, h: HalfedgeId) -> u32 {
        self.fv.indices[self.corner[h.idx()] as usize]
    }
    /// Value of `h`'s face at `h`'s origin.
    #[inline]
    fn value(&self, h: HalfedgeId) -> Vec3 {
        self.fv.values[self.index(h) as usize].extend(0.0)
    }
    /// Value at the end of `h` in a face of its edge.
    #[inline]
    fn end_value(&self, h: HalfedgeId) -> Vec3 {
        if self.mesh.face(h).is_some() {
            self.value(self.mesh.next(h))
        } else {
            self.value(h.twin())
        }
    }
    /// Whether out half-edge `h` is left out of its origin's ring.
    #[inline]
    fn skips(&self, h: HalfedgeId) -> bool {
        self.skip.get(h.idx()).copied().unwrap_or(false)
    }
    /// The half-edge into a vertex `v` along the far edge of the face of `h` (out of `v`):
    /// `prev(h)`, or past the faces that stand with it across skipped edges.
    #[inline]
    fn far_edge(&self, h: HalfedgeId) -> HalfedgeId {
        let mesh = self.mesh;
        let mut p = mesh.prev(h);
        for _ in 0..mesh.num_halfedges() {
            let next = p.twin();
            if !self.skips(next) || !mesh.face(next).is_some() {
                break;
            }
            p = mesh.prev(next);
        }
        p
    }
    /// Edge with linear face-varying interpolation: a seam or, with linear boundaries, a
    /// boundary edge.
    #[inline]
    fn linear_edge(&self, h: HalfedgeId) -> bool {
        self.seam[h.edge().idx()]
            || (self.flags.linear_boundaries && self.mesh.is_boundary_edge(h.edge()))
    }
}

/// Appends a value (the `x`, `y` of `p`); its index.
#[inline]
fn push_value(values: &mut Vec<Vec2>, p: Vec3) -> u32 {
    values.push(Vec2::new(p.x, p.y));
    (values.len() - 1) as u32
}

/// The value of crease sibling `s` at `v` (OpenSubdiv's `PrimvarRefiner::interpFVarFromVerts`)
/// and its [`Dependence`] in the child: `3/4` itself and `1/8` each of the values that end its
/// span (`sp[s]`). A sibling whose span (or vertex) is still semi-sharp in the child stays put;
/// one whose semi-sharpness runs out in this step blends the two by the fractional weight of
/// the span's edges. A held sibling (`dep`) follows the other sibling's span instead, and stays
/// put one step longer while the vertex keeps other semi-sharp edges.
fn crease_value(
    ch: &Channel<'_>,
    kernel: &RefineKernel<'_>,
    v: VertexId,
    hs: &[HalfedgeId],
    (sp, s): (&[Span], usize),
    dep: Dependence,
    centre: Vec3,
) -> (Vec3, Dependence) {
    let mesh = ch.mesh;
    let n = hs.len();
    let ends = limit::span_ends(ch, hs, sp[s]);
    let held = dep == Dependence::Held && sp.len() == 2;
    let sharp = if held { sp[1 - s] } else { sp[s] };
    let vs = mesh.vertex_sharpness(v);
    let mut w_corner = 0.0f32;
    if sharp.semi > 0 || is_semi_sharp(vs) {
        // Edges inside the span: edge `i` lies between faces `i - 1` and `i`.
        let inner = (1..sharp.size).map(|j| hs[(sharp.start + j) % n]);
        // Still a corner in the child while the vertex itself stays semi-sharp there
        // (`Vtr::FVarRefinement::reclassifySemisharpValues` leaves every value of such a
        // vertex as it was) or an edge inside the span does.
        if is_semi_sharp(decrement(vs))
            || inner
                .clone()
                .any(|h| is_semi_sharp(kernel.child_sharpness(h)))
        {
            let child = if held {
                Dependence::Held
            } else {
                Dependence::Free
            };
            return (centre, child);
        }
        if held
            && mesh
                .outgoing(v)
                .any(|h| is_semi_sharp(kernel.child_sharpness(h)))
        {
            return (centre, Dependence::Released);
        }
        let parent: Vec<f32> = inner
            .clone()
            .map(|h| mesh.edge_sharpness(h.edge()))
            .collect();
        let child: Vec<f32> = inner.map(|h| kernel.child_sharpness(h)).collect();
        w_corner = fractional_weight(mesh.options().crease, vs, decrement(vs), &parent, &child);
    }
    let w_crease = 1.0 - w_corner;
    let p = centre * (w_crease * 0.75 + w_corner) + ends * (w_crease * 0.125);
    (p, Dependence::Free)
}

/// The [`Dependence`] of each sibling around `v` (`uniq`: their values, `sp`: their spans):
/// the channel's own where refinement carried it; on a cage's channel OpenSubdiv's first tags
/// (`Vtr::FVarLevel::completeTopologyFromFaceValues`): with `cornersPlus1` or `cornersPlus2`,
/// of two siblings at a vertex that is not semi-sharp itself, the one whose span has no
/// semi-sharp edge is held where the other's has some.
fn dependence(ch: &Channel<'_>, v: VertexId, uniq: &[u32], sp: &[Span]) -> Vec<Dependence> {
    let carried = &ch.fv.dependence;
    if !carried.is_empty() {
        return uniq
            .iter()
            .map(|&i| carried.get(i as usize).copied().unwrap_or_default())
            .collect();
    }
    let mut dep = vec![Dependence::Free; uniq.len()];
    if ch.flags.dependent
        && uniq.len() == 2
        && sp.len() == 2
        && !is_semi_sharp(ch.mesh.vertex_sharpness(v))
        && (sp[0].semi > 0) != (sp[1].semi > 0)
    {
        dep[usize::from(sp[0].semi > 0)] = Dependence::Held;
    }
    dep
}

/// The out half-edges of `v` with a face, in `hs`, as OpenSubdiv walks them: an interior
/// vertex's from its lowest-numbered face. False where `v` has no face.
fn face_ring(mesh: &Mesh, v: VertexId, hs: &mut Vec<HalfedgeId>) -> bool {
    hs.clear();
    hs.extend(mesh.outgoing(v).filter(|&h| mesh.face(h).is_some()));
    if !mesh.is_boundary_vertex(v)
        && let Some(k) = (0..hs.len()).min_by_key(|&k| mesh.face(hs[k]).0)
    {
        hs.rotate_left(k);
    }
    !hs.is_empty()
}

/// The [`Dependence`] of the first `len` values of the channel: its own where refinement
/// carried it, else [`dependence`] at every vertex of the cage.
fn value_dependence(ch: &Channel<'_>, len: usize) -> Vec<Dependence> {
    let mut out = ch.fv.dependence.clone();
    if out.is_empty() && ch.flags.dependent {
        out.resize(len, Dependence::Free);
        let mesh = ch.mesh;
        let (mut hs, mut sib, mut uniq) = (Vec::new(), Vec::new(), Vec::new());
        for v in mesh.vertices() {
            if !face_ring(mesh, v, &mut hs) {
                continue;
            }
            siblings(ch, &hs, &mut sib, &mut uniq);
            if uniq.len() != 2 || !vertex_mismatch(ch, v, hs.len()) {
                continue;
            }
            let sp = spans(ch, &hs, &sib, uniq.len());
            for (s, d) in dependence(ch, v, &uniq, &sp).into_iter().enumerate() {
                if d != Dependence::Free
                    && let Some(t) = out.get_mut(uniq[s] as usize)
                {
                    *t = d;
                }
            }
        }
    }
    out.resize(len, Dependence::Free);
    out
}

/// The sibling of each face around a vertex (`hs`: its out half-edges with a face, in order),
/// exactly as `Vtr::FVarLevel::completeTopologyFromFaceValues` numbers them; `uniq` gets the
/// value index of each sibling. A value met again after two others, with the second differing
/// from the first, becomes a new sibling (OpenSubdiv compares with the first sibling only
/// there), so a value in disjoint runs may count as several siblings, each refined on its own.
fn siblings(ch: &Channel<'_>, hs: &[HalfedgeId], sib: &mut Vec<usize>, uniq: &mut Vec<u32>) {
    sib.clear();
    uniq.clear();
    let mut prev = u32::MAX;
    for &h in hs {
        let i = ch.index(h);
        let s = if uniq.is_empty() {
            uniq.push(i);
            0
        } else if i == prev {
            sib[sib.len() - 1]
        } else if uniq.len() == 1 || (uniq.len() == 2 && uniq[0] != i) {
            uniq.push(i);
            uniq.len() - 1
        } else {
            match uniq.iter().position(|&u| u == i) {
                Some(s) => s,
                None => {
                    uniq.push(i);
                    uniq.len() - 1
                }
            }
        };
        sib.push(s);
        prev = i;
    }
}

/// Whether the values at `v` (with `faces` faces in its ring) are refined apart from the vertex
/// rules: a seam ends at `v`, a boundary vertex is made linear (linear boundaries, or a
/// one-face corner made sharp), or `v` is a copy of a non-manifold vertex whose values differ
/// ([`Mesh::is_fvar_corner`], every value a corner).
fn vertex_mismatch(ch: &Channel<'_>, v: VertexId, faces: usize) -> bool {
    let mesh = ch.mesh;
    if mesh.is_fvar_corner(v) || mesh.outgoing(v).any(|h| ch.seam[h.edge().idx()]) {
        return true;
    }
    if !mesh.is_boundary_vertex(v) {
        return false;
    }
    ch.flags.linear_boundaries || (faces == 1 && ch.flags.smooth_corners_sharp)
}

/// The spans of the siblings around a vertex (`Vtr::FVarLevel::gatherValueSpans`): edge `i`
/// lies between faces `i - 1` and `i`.
fn spans(ch: &Channel<'_>, hs: &[HalfedgeId], sib: &[usize], count: usize) -> Vec<Span> {
    let mesh = ch.mesh;
    let n = hs.len();
    let v = mesh.from(hs[0]);
    let boundary = mesh.is_boundary_vertex(v);
    let sharp = |h: HalfedgeId| is_infinite(mesh.edge_sharpness(h.edge()));
    let semi = |h: HalfedgeId| is_semi_sharp(mesh.edge_sharpness(h.edge()));
    // An edge inside a span: a seam there makes it disjoint, else its sharpness counts.
    let inside = |sp: &mut Span, h: HalfedgeId| {
        if ch.seam[h.edge().idx()] {
            sp.disjoint += 1;
        } else if sharp(h) {
            sp.inf += 1;
        } else if semi(h) {
            sp.semi += 1;
        }
    };
    let mut sp = vec![Span::default(); count];
    if count == 1 && !boundary {
        // An interior dart: disjoint with a second seam.
        for h in mesh.outgoing(v) {
            if ch.seam[h.edge().idx()] {
                if sp[0].size > 0 {
                    sp[0].disjoint = 1;
                    break;
                }
                sp[0].size = n;
                sp[0].start = hs.iter().position(|&x| x == h).unwrap_or(0);
            } else if sharp(h) {
                sp[0].inf += 1;
            } else if semi(h) {
                sp[0].semi += 1;
            }
        }
        sp[0].size = n;
        return sp;
    }
    sp[0].size = 1;
    if !boundary && sib[n - 1] == 0 {
        inside(&mut sp[0], hs[0]);
    }
    for i in 1..n {
        let s = sib[i];
        if s == sib[i - 1] {
            inside(&mut sp[s], hs[i]);
        } else {
            if sp[s].size > 0 {
                sp[s].disjoint += 1;
            }
            sp[s].start = i;
        }
        sp[s].size += 1;
    }
    // Span 0 wrapping round counted its second run as disjoint.
    if sib[n - 1] == 0 && !boundary {
        sp[0].disjoint -= 1;
    }
    sp
}

/// Which siblings around `v` (with spans `sp`) are corners (kept) rather than creases, by the
/// options (`Vtr::FVarLevel::completeTopologyFromFaceValues`).
fn sibling_corners(ch: &Channel<'_>, v: VertexId, sp: &[Span]) -> Vec<bool> {
    let count = sp.len();
    let mesh = ch.mesh;
    let fl = ch.flags;
    let boundary = mesh.is_boundary_vertex(v);
    let all = fl.linear_boundaries
        || is_infinite(mesh.vertex_sharpness(v))
        || mesh.is_fvar_corner(v)
        || (fl.dependent && count > 2)
        || (fl.darts && count == 1 && !boundary);
    if all {
        return vec![true; count];
    }
    if fl.dependent && count == 2 {
        let mut all = sp[0].sharp() || sp[1].sharp();
        if fl.both_if_one_corner {
            all |= sp[0].size == 1 || sp[1].size == 1;
        }
        if all {
            return vec![true; count];
        }
    }
    sp.iter()
        .map(|s| s.sharp() || (s.size == 1 && fl.corners_sharp))
        .collect()
}

/// The face-varying value of every corner of face `f` (for tests and writers).
pub fn face_uvs(mesh: &Mesh, f: FaceId) -> Option<Vec<Vec2>> {
    let fv = mesh.uv()?;
    let (offsets, _) = mesh.face_lists();
    Some(
        (offsets[f.idx()]..offsets[f.idx() + 1])
            .map(|c| fv.corner(c as usize))
            .collect(),
    )
}
