//! Face-varying limit values: the limit of a [`FaceVarying`] channel at every vertex of a
//! (refined) mesh, as OpenSubdiv 3.5's `Far::PrimvarRefiner::LimitFaceVarying` computes it.
//!
//! A vertex whose values agree around it (no seam, not made linear) takes the vertex's own
//! limit mask, chosen by its rule at this level ([`Rule::determine`]: smooth and dart the
//! smooth mask, crease the crease mask, corner the value itself) and applied to the values of
//! its ring. At a vertex with siblings (a seam, or a boundary made linear) each sibling is a
//! corner (its value) or a crease (`2/3` itself and `1/6` each of the values ending its span).
//! Siblings whose span is still semi-sharp, or that are held by another's
//! ([`subdiv_mesh::Dependence`]), are corners too (OpenSubdiv's semi-sharp value tag), and
//! `all` (bilinear) keeps every value. Like OpenSubdiv, the smooth mask takes the corner
//! two steps round each face as its diagonal, so the values are the true limit on all-quad
//! (Catmull-Clark level ≥ 1) and all-triangle meshes.

use glam::{DVec3, Vec2};
use subdiv_mesh::{FaceVarying, HalfedgeId, Mesh, VertexId};

use super::{
    Channel, Span, dependence, face_ring, sibling_corners, siblings, spans, vertex_mismatch,
};
use crate::crease::{is_semi_sharp, rule_with_whole};
use crate::{Depth, MAX_DEPTH, RulesError, Scheme, catmark, loop_scheme};

/// The limit face-varying values of `mesh`'s UVs (`None` without UVs), one value per distinct
/// (vertex, sibling); `indices` aligned with the mesh's face corners, as in the input channel.
/// Applied to the level-`d` uniform refinement of a cage, these are the values of the limit
/// points of the depth-`d` tessellation ([`crate::tessellate_uniform`]).
pub fn limit_face_varying(mesh: &Mesh, scheme: Scheme) -> Option<FaceVarying> {
    let fv = mesh.uv()?;
    let ch = Channel::new(mesh, fv, scheme);
    let mut out = FaceVarying {
        values: Vec::with_capacity(mesh.num_vertices()),
        indices: vec![0; fv.indices.len()],
        dependence: Vec::new(),
    };
    let mut hs = Vec::new();
    let mut sib = Vec::new();
    let mut uniq = Vec::new();
    let mut ring = RingValues::default();
    for v in mesh.vertices() {
        // The same walk as refinement, so siblings are numbered alike.
        if !face_ring(mesh, v, &mut hs) {
            continue;
        }
        if !vertex_mismatch(&ch, v, hs.len()) {
            let centre = ch.value(hs[0]).as_dvec3();
            let p = if ch.flags.linear_all {
                centre
            } else {
                ring.vertex_limit(&ch, v, scheme, centre)
            };
            let i = push(&mut out, p);
            for &h in &hs {
                out.indices[ch.corner[h.idx()] as usize] = i;
            }
            continue;
        }
        siblings(&ch, &hs, &mut sib, &mut uniq);
        let sp = spans(&ch, &hs, &sib, uniq.len());
        let corners = sibling_corners(&ch, v, &sp);
        let semi_vertex = is_semi_sharp(mesh.vertex_sharpness(v));
        let dep = dependence(&ch, v, &uniq, &sp);
        let base = out.values.len() as u32;
        for (s, &is_corner) in corners.iter().enumerate() {
            let first = sib.iter().position(|&x| x == s).unwrap_or(0);
            let centre = ch.value(hs[first]).as_dvec3();
            let span = sp[s];
            let held = dep[s] != subdiv_mesh::Dependence::Free;
            let p = if is_corner || ch.flags.linear_all || span.semi > 0 || semi_vertex || held {
                centre
            } else {
                centre * (2.0 / 3.0) + span_ends(&ch, &hs, span).as_dvec3() * (1.0 / 6.0)
            };
            push(&mut out, p);
        }
        for (k, &h) in hs.iter().enumerate() {
            out.indices[ch.corner[h.idx()] as usize] = base + sib[k] as u32;
        }
    }
    Some(out)
}

/// Levels of uniform refinement after which `mesh` has no semi-sharp edge or vertex left
/// (sharpness decays by at least one per level under both crease rules).
pub fn semi_sharp_levels(mesh: &Mesh) -> Depth {
    mesh.edge_sharpnesses()
        .iter()
        .chain(mesh.vertex_sharpnesses())
        .filter(|&&s| is_semi_sharp(s))
        .map(|&s| s.ceil().min(f32::from(MAX_DEPTH)) as Depth)
        .max()
        .unwrap_or(0)
}

/// The face-varying limit of `mesh`'s UVs taken where no semi-sharp feature is left: like the
/// limit positions ([`Ring::limit`](crate::Ring::limit)), the mesh is refined (uniformly,
/// [`semi_sharp_levels`] times) and [`limit_face_varying`] taken there, each corner of `mesh`
/// reading the value of the corner of its descendant face at the same vertex. Without
/// semi-sharp features this is [`limit_face_varying`] itself (OpenSubdiv's values); with them
/// it does not depend on the level it is taken at, so tessellations of any depth (and the
/// adaptive ones, whose patches mix depths) agree on every point's value, where OpenSubdiv's
/// `LimitFaceVarying` approximates until the sharpness has run out.
pub fn limit_face_varying_exact(
    mesh: &Mesh,
    scheme: Scheme,
) -> Result<Option<FaceVarying>, RulesError> {
    let levels = semi_sharp_levels(mesh);
    if levels == 0 || mesh.uv().is_none() {
        return Ok(limit_face_varying(mesh, scheme));
    }
    let deep = crate::refine_uniform_levels(mesh, scheme, levels)?;
    let Some(lim) = limit_face_varying(&deep, scheme) else {
        return Ok(None);
    };
    let (offsets, _) = mesh.face_lists();
    let (per, loop_scheme) = match scheme {
        Scheme::CatmullClark | Scheme::Bilinear => (4usize, false),
        Scheme::Loop => (3usize, true),
    };
    let mut remap = vec![u32::MAX; lim.values.len()];
    let mut out = FaceVarying::default();
    for f in mesh.faces() {
        for k in 0..mesh.face_size(f) as u32 {
            // Child `k` of a face starts at its corner `k` (its vertex child); then child 0.
            let mut child = if loop_scheme {
                4 * f.0 + k
            } else {
                offsets[f.idx()] + k
            };
            for _ in 1..levels {
                child *= 4;
            }
            let i = lim.indices[per * child as usize] as usize;
            if remap[i] == u32::MAX {
                remap[i] = out.values.len() as u32;
                out.values.push(lim.values[i]);
            }
            out.indices.push(remap[i]);
        }
    }
    Ok(Some(out))
}

/// The sum of the two values that end a sibling's span (OpenSubdiv's
/// `FVarLevel::getVertexCreaseEndValues`): the far ends of its first and last edges.
#[inline]
pub(super) fn span_ends(ch: &Channel<'_>, hs: &[HalfedgeId], span: Span) -> glam::Vec3 {
    let mesh = ch.mesh;
    let n = hs.len();
    let first = hs[span.start % n];
    let last = hs[(span.start + n - 1 + span.size.max(1)) % n];
    ch.value(mesh.next(first)) + ch.value(ch.far_edge(last))
}

/// Scratch for one vertex's ring of values (kept across vertices: no allocation per vertex).
#[derive(Default)]
struct RingValues {
    edges: Vec<DVec3>,
    diag: Vec<DVec3>,
    sharpness: Vec<f32>,
}

impl RingValues {
    /// The limit of the continuous value `centre` at `v` by `v`'s own limit mask.
    fn vertex_limit(
        &mut self,
        ch: &Channel<'_>,
        v: VertexId,
        scheme: Scheme,
        centre: DVec3,
    ) -> DVec3 {
        let mesh = ch.mesh;
        self.edges.clear();
        self.diag.clear();
        self.sharpness.clear();
        for h in mesh.outgoing(v) {
            self.edges.push(ch.end_value(h).as_dvec3());
            self.sharpness.push(mesh.edge_sharpness(h.edge()));
            if mesh.face(h).is_some() {
                self.diag.push(ch.value(mesh.next(mesh.next(h))).as_dvec3());
            }
        }
        let whole = mesh.whole_vertex_edges(v);
        let rule = rule_with_whole(mesh.vertex_sharpness(v), &self.sharpness, whole);
        match scheme {
            Scheme::CatmullClark => catmark::limit(centre, &self.edges, &self.diag, rule).0,
            // Linear: a value is its own limit (also reached through `linear_all`).
            Scheme::Bilinear => centre,
            Scheme::Loop => {
                loop_scheme::limit(centre, &self.edges, rule, mesh.is_boundary_vertex(v)).0
            }
        }
    }
}

/// Appends a value; its index.
#[inline]
fn push(out: &mut FaceVarying, p: DVec3) -> u32 {
    out.values.push(Vec2::new(p.x as f32, p.y as f32));
    (out.values.len() - 1) as u32
}
