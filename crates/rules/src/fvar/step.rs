//! One face-varying refinement step over a region of a mesh: the whole mesh
//! ([`refine_uniform`](crate::refine_uniform)) or the closure of one adaptive Loop pass
//! (`subdiv-redgreen`), with the rules of the parent module.

use glam::{Vec2, Vec3};
use subdiv_mesh::{Dependence, EdgeId, FaceVarying, HalfedgeId, Mesh, VertexId};

use super::{
    Channel, crease_value, dependence, push_value, sibling_corners, siblings, spans,
    vertex_mismatch,
};
use crate::Scheme;
use crate::refine::RefineKernel;

/// Which part of a mesh one face-varying step refines and how it reads the rings
/// ([`refine_face_varying_part`]): the whole mesh for uniform refinement, the closure of one
/// adaptive Loop pass for `subdiv-redgreen` (its moved vertices and split edges, rings without the
/// edges inside green families, the parent's opposite corner for a merged family's edges).
pub trait FVarRegion {
    /// Whether the values at `v` are refined (else its corners keep their values).
    fn refines_vertex(&self, v: VertexId) -> bool;
    /// Whether edge `e` gets values (its midpoint's, one per side of a linear edge).
    fn splits_edge(&self, e: EdgeId) -> bool;
    /// Out half-edges left out of a vertex's ring, as
    /// [`RefineKernel::vertex_point_without`] leaves them out (smooth, not on a seam): the
    /// face of a skipped half-edge stands with the face across it.
    fn skips(&self, h: HalfedgeId) -> bool;
    /// Loop: a half-edge in a face whose origin is the vertex opposite the edge of `h` on
    /// `h`'s side (its value is that face's corner there).
    fn opposite(&self, h: HalfedgeId) -> HalfedgeId;
}

/// The whole mesh: [`refine_uniform`](crate::refine_uniform)'s region.
struct Whole<'a>(&'a Mesh);

impl FVarRegion for Whole<'_> {
    #[inline]
    fn refines_vertex(&self, _: VertexId) -> bool {
        true
    }
    #[inline]
    fn splits_edge(&self, _: EdgeId) -> bool {
        true
    }
    #[inline]
    fn skips(&self, _: HalfedgeId) -> bool {
        false
    }
    #[inline]
    fn opposite(&self, h: HalfedgeId) -> HalfedgeId {
        self.0.prev(h)
    }
}

/// The child values of one face-varying step of a [`FVarRegion`]
/// ([`refine_face_varying_part`]), by half-edge of the parent mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FVarChildren {
    /// Per half-edge with a face: the value of that face's corner at the half-edge's origin in
    /// the child (a refined vertex's new value; the parent's index where the vertex is not
    /// refined); `u32::MAX` for boundary half-edges.
    pub vertex_child: Vec<u32>,
    /// Per half-edge with a face whose edge is split: the value of the edge's midpoint on that
    /// face's side; `u32::MAX` elsewhere.
    pub edge_child: Vec<u32>,
    /// The [`Dependence`] of every value the step leaves in `values`: the input's own (carried,
    /// or on a cage's channel computed from its topology), then the new values'.
    pub dependence: Vec<Dependence>,
}

/// One uniform refinement step of `fv` on the kernel's mesh, whose vertex points the kernel has
/// already computed (so its child sharpness is known). The child channel numbers corners as
/// [`refine_uniform`](crate::refine_uniform) numbers the child faces.
pub(crate) fn refine_face_varying(kernel: &mut RefineKernel<'_>, fv: &FaceVarying) -> FaceVarying {
    let mesh = kernel.mesh();
    let scheme = kernel.scheme();
    let mut out = FaceVarying::default();
    let (mut children, face_value) = refine_values(kernel, fv, &Whole(mesh), &mut out.values);
    out.dependence = std::mem::take(&mut children.dependence);
    child_corners(mesh, scheme, face_value, &children, &mut out);
    out.dependence.resize(out.values.len(), Dependence::Free);
    out
}

/// One face-varying step of `fv` on the `region` of the kernel's mesh: the new values (refined
/// vertices' siblings in vertex order, then the edge values in edge order) appended to
/// `values`, and where every child corner takes its value. Corners of vertices the region
/// does not refine keep their index in `fv`, so `values` should start as `fv.values` when the
/// region is not the whole mesh. The rules are those of uniform refinement (this module's
/// documentation), applied to the ring the region reads; the kernel must have computed the
/// vertex points (hence child sharpness) of every refined vertex and of both ends of every
/// split edge over the same rings.
pub fn refine_face_varying_part(
    kernel: &mut RefineKernel<'_>,
    fv: &FaceVarying,
    region: &impl FVarRegion,
    values: &mut Vec<Vec2>,
) -> FVarChildren {
    refine_values(kernel, fv, region, values).0
}

/// [`refine_face_varying_part`], also returning the Catmull-Clark face values (empty for Loop).
fn refine_values(
    kernel: &mut RefineKernel<'_>,
    fv: &FaceVarying,
    region: &impl FVarRegion,
    values: &mut Vec<Vec2>,
) -> (FVarChildren, Vec<Vec3>) {
    let mesh = kernel.mesh();
    let scheme = kernel.scheme();
    let (offsets, _) = mesh.face_lists();
    let mut ch = Channel::new(mesh, fv, scheme);
    let skip: Vec<bool> = (0..mesh.num_halfedges() as u32)
        .map(|h| region.skips(HalfedgeId(h)))
        .collect();
    if skip.contains(&true) {
        ch.skip = skip;
    }

    // Face values (Catmull-Clark): the centroid of the corners.
    let mut face_value = Vec::new();
    if scheme.splits_to_quads() {
        face_value = mesh
            .faces()
            .map(|f| {
                let r = offsets[f.idx()] as usize..offsets[f.idx() + 1] as usize;
                let n = r.len() as f32;
                r.map(|c| fv.corner(c).extend(0.0)).sum::<Vec3>() / n
            })
            .collect::<Vec<Vec3>>();
    }
    let mut out = FVarChildren {
        vertex_child: vec![u32::MAX; mesh.num_halfedges()],
        edge_child: vec![u32::MAX; mesh.num_halfedges()],
        dependence: Vec::new(),
    };
    let mut hs = Vec::new();
    let mut sib = Vec::new();
    let mut uniq = Vec::new();
    let mut tags = if values.is_empty() {
        Vec::new()
    } else {
        super::value_dependence(&ch, values.len())
    };
    for v in mesh.vertices() {
        if !region.refines_vertex(v) {
            for h in mesh.outgoing(v).filter(|&h| mesh.face(h).is_some()) {
                out.vertex_child[h.idx()] = ch.index(h);
            }
            continue;
        }
        hs.clear();
        hs.extend(
            mesh.outgoing(v)
                .filter(|&h| mesh.face(h).is_some() && !region.skips(h)),
        );
        if hs.is_empty() {
            continue;
        }
        vertex_values(
            &ch,
            kernel,
            region,
            v,
            &face_value,
            (&mut hs, &mut sib, &mut uniq),
            (values, &mut tags),
            &mut out.vertex_child,
        );
        // A skipped half-edge's face stands with the face across it.
        for h in mesh.outgoing(v) {
            let mut g = h;
            for _ in 0..mesh.valence(v) {
                if !region.skips(g) || !mesh.face(g).is_some() {
                    break;
                }
                g = mesh.next(g.twin());
            }
            if g != h && mesh.face(h).is_some() {
                out.vertex_child[h.idx()] = out.vertex_child[g.idx()];
            }
        }
    }
    edge_values(
        &ch,
        kernel,
        region,
        &face_value,
        values,
        &mut out.edge_child,
    );
    tags.resize(values.len(), Dependence::Free);
    out.dependence = tags;
    (out, face_value)
}

/// The child values of the corners around the refined vertex `v` (`ring.0`: its out
/// half-edges with a face that the region reads, in order; the other two are scratch).
#[allow(clippy::too_many_arguments)]
fn vertex_values(
    ch: &Channel<'_>,
    kernel: &mut RefineKernel<'_>,
    region: &impl FVarRegion,
    v: VertexId,
    face_value: &[Vec3],
    ring: (&mut Vec<HalfedgeId>, &mut Vec<usize>, &mut Vec<u32>),
    (values, tags): (&mut Vec<Vec2>, &mut Vec<Dependence>),
    vertex_child: &mut [u32],
) {
    let mesh = ch.mesh;
    let (hs, sib, uniq) = ring;
    // OpenSubdiv walks an interior vertex's faces from its lowest-numbered one.
    if !mesh.is_boundary_vertex(v)
        && let Some(k) = (0..hs.len()).min_by_key(|&k| mesh.face(hs[k]).0)
    {
        hs.rotate_left(k);
    }
    siblings(ch, hs, sib, uniq);
    if !vertex_mismatch(ch, v, hs.len()) {
        let centre = ch.value(hs[0]);
        let p = if ch.flags.linear_all {
            centre
        } else {
            kernel.vertex_point_over(
                v,
                centre,
                |h| ch.end_value(h),
                |f| face_value[f.idx()],
                |h| region.skips(h),
            )
        };
        let i = push_value(values, p);
        tags.push(Dependence::Free);
        for &h in hs.iter() {
            vertex_child[h.idx()] = i;
        }
        return;
    }
    let sp = spans(ch, hs, sib, uniq.len());
    let corners = sibling_corners(ch, v, &sp);
    let dep = dependence(ch, v, uniq, &sp);
    let base = values.len() as u32;
    for (s, &is_corner) in corners.iter().enumerate() {
        let first = sib.iter().position(|&x| x == s).unwrap_or(0);
        let centre = ch.value(hs[first]);
        let (p, child) = if is_corner || ch.flags.linear_all {
            (centre, Dependence::Free)
        } else {
            crease_value(ch, kernel, v, hs, (&sp, s), dep[s], centre)
        };
        push_value(values, p);
        tags.push(child);
    }
    for (k, &h) in hs.iter().enumerate() {
        vertex_child[h.idx()] = base + sib[k] as u32;
    }
}

/// Edge values of the region's split edges: one per edge, or one per side of a linear edge.
fn edge_values(
    ch: &Channel<'_>,
    kernel: &RefineKernel<'_>,
    region: &impl FVarRegion,
    face_value: &[Vec3],
    values: &mut Vec<Vec2>,
    edge_child: &mut [u32],
) {
    let mesh = ch.mesh;
    let scheme = kernel.scheme();
    for e in mesh.edges().filter(|&e| region.splits_edge(e)) {
        let (h0, h1) = (e.halfedge(0), e.halfedge(1));
        if ch.linear_edge(h0) || ch.flags.linear_all {
            let mut shared = None;
            for h in [h0, h1] {
                if mesh.face(h).is_some() {
                    let mid = (ch.value(h) + ch.value(mesh.next(h))) * 0.5;
                    // Without a seam both sides agree: one value.
                    let i = match shared {
                        Some(i) if !ch.seam[e.idx()] => i,
                        _ => push_value(values, mid),
                    };
                    shared = Some(i);
                    edge_child[h.idx()] = i;
                }
            }
            continue;
        }
        let h = if mesh.face(h0).is_some() { h0 } else { h1 };
        let (a, b) = if h == h0 {
            (ch.value(h0), ch.value(mesh.next(h0)))
        } else {
            (ch.value(mesh.next(h1)), ch.value(h1))
        };
        let p = kernel.edge_point_with(e, a, b, |h| match scheme {
            Scheme::CatmullClark | Scheme::Bilinear => face_value[mesh.face(h).idx()],
            Scheme::Loop => ch.value(region.opposite(h)),
        });
        let i = push_value(values, p);
        for h in [h0, h1] {
            if mesh.face(h).is_some() {
                edge_child[h.idx()] = i;
            }
        }
    }
}

/// Appends the Catmull-Clark face values to `out` and the value of every child face corner, in
/// the child face order of [`refine_uniform`](crate::refine_uniform).
fn child_corners(
    mesh: &Mesh,
    scheme: Scheme,
    face_value: Vec<Vec3>,
    children: &FVarChildren,
    out: &mut FaceVarying,
) {
    let face_base = out.values.len() as u32;
    if scheme.splits_to_quads() {
        for p in face_value {
            push_value(&mut out.values, p);
        }
    }
    let vc = |h: HalfedgeId| children.vertex_child[h.idx()];
    let ev = |h: HalfedgeId| children.edge_child[h.idx()];
    for f in mesh.faces() {
        let h0 = mesh.face_halfedge(f);
        match scheme {
            Scheme::CatmullClark | Scheme::Bilinear => {
                let mut h = h0;
                let mut hp = mesh.prev(h0);
                for _ in 0..mesh.face_size(f) {
                    out.indices.extend([vc(h), ev(h), face_base + f.0, ev(hp)]);
                    hp = h;
                    h = mesh.next(h);
                }
            }
            Scheme::Loop => {
                let (ha, hb, hc) = (h0, mesh.next(h0), mesh.prev(h0));
                out.indices.extend([vc(ha), ev(ha), ev(hc)]);
                out.indices.extend([vc(hb), ev(hb), ev(ha)]);
                out.indices.extend([vc(hc), ev(hc), ev(hb)]);
                out.indices.extend([ev(ha), ev(hb), ev(hc)]);
            }
        }
    }
}
