//! The limit surface of one face: a tree of patches grown lazily, down to where each point's
//! patch is regular.
//!
//! The root is the face's patch (Catmull-Clark quads, Loop triangles) or, for other faces,
//! its sub-faces one level down. A patch that is regular is a leaf ([`RegularPatch`]); any
//! other is refined once into its children ([`patch::refine`]) the first time a point falls in
//! it, and the children are kept, so every later point of the face reuses the refinement.
//! Refinement stops at semi-sharp features once they have decayed, at n-gons after one level,
//! and around an irregular vertex only at the vertex itself, where the exact limit is taken
//! ([`corner_limit`]); points closer to such a vertex than `2^-MAX_DEPTH` (far below `f64`
//! resolution of the surface) take the vertex's.

use glam::DVec3;
use subdiv_mesh::{CreaseMethod, FaceId, HalfedgeId, Mesh};
use subdiv_rules::{Ring, Scheme};

use crate::corner::corner_limit;
use crate::domain::Domain;
use crate::patch::{self, Corners, Kid, Layout, Local, RegularPatch, corner_kind};
use crate::{Derivatives, Sample};

/// Deepest refinement below the root patch before a point takes its nearest corner's limit.
const MAX_DEPTH: u32 = 64;

#[derive(Clone, Copy, Debug)]
enum Node {
    /// A regular patch (index into `patches`).
    Leaf(u32),
    /// Refined: the first of its children in `nodes` (4, or Loop 3 corners and the middle).
    Split(u32),
    /// Not yet refined (index into `pending`).
    Pending(u32),
}

/// The limit surface of one face, refined as far as the points asked for need
/// ([`crate::Evaluator::surface`]): evaluating many points of one face through one
/// `FaceSurface` refines its neighbourhood once.
#[derive(Clone, Debug, Default)]
pub struct FaceSurface {
    scheme: Scheme,
    method: CreaseMethod,
    face: u32,
    domain: Option<Domain>,
    roots: Vec<u32>,
    nodes: Vec<Node>,
    patches: Vec<RegularPatch>,
    pending: Vec<Corners>,
    /// The root's corner rings, reused between faces.
    root: Corners,
    halfedges: Vec<HalfedgeId>,
    /// The bilinear scheme: the face's corner positions (its surface is their bilinear patch,
    /// [`crate::bilinear`]).
    corners: Vec<DVec3>,
}

impl FaceSurface {
    /// An empty surface (load a face with [`crate::Evaluator::surface`]).
    pub fn new() -> FaceSurface {
        FaceSurface::default()
    }

    /// The face it is the surface of.
    pub fn face(&self) -> u32 {
        self.face
    }

    /// Its parameter domain.
    pub fn domain(&self) -> Domain {
        self.domain.unwrap_or(Domain::Quad)
    }

    /// Loads face `f` of `mesh` (valid, not a hole), keeping the buffers; `plan`: its control
    /// points where it is one regular patch ([`crate::plan`]).
    pub(crate) fn load(
        &mut self,
        mesh: &Mesh,
        scheme: Scheme,
        f: FaceId,
        plan: Option<&[u32; 16]>,
    ) {
        self.scheme = scheme;
        self.method = mesh.options().crease;
        self.face = f.0;
        let n = mesh.face_size(f);
        let domain = Domain::of(scheme, n);
        self.domain = Some(domain);
        self.roots.clear();
        self.nodes.clear();
        self.patches.clear();
        self.pending.clear();
        self.corners.clear();
        if scheme == Scheme::Bilinear {
            let corners = mesh
                .face_vertices(f)
                .iter()
                .map(|&v| mesh.position(v).as_dvec3());
            self.corners.extend(corners);
            return;
        }
        if let Some(plan) = plan {
            let mut points = [DVec3::ZERO; 16];
            for (p, &v) in points.iter_mut().zip(plan) {
                if v != crate::plan::NONE {
                    *p = mesh.position(subdiv_mesh::VertexId(v)).as_dvec3();
                }
            }
            let triangle = scheme == Scheme::Loop;
            let leaf = self.leaf(RegularPatch {
                points,
                mask: 0,
                triangle,
            });
            self.nodes.push(leaf);
            self.roots.push(0);
            return;
        }
        self.root.rings.resize_with(n, Ring::new);
        self.root.faces.resize(n, 0);
        let mut h = mesh.face_halfedge(f);
        for k in 0..n {
            let v = mesh.from(h);
            let ring = &mut self.root.rings[k];
            ring.load_with_halfedges(mesh, v, scheme, &mut self.halfedges);
            self.root.faces[k] = self.halfedges.iter().position(|&g| g == h).unwrap_or(0);
            h = mesh.next(h);
        }
        if let Domain::SubFaces { .. } = domain {
            let root = std::mem::take(&mut self.root);
            for kid in patch::refine(root, scheme, self.method, Layout::SubFaces) {
                let node = self.node_for(kid);
                self.roots.push(node);
            }
        } else {
            let root = match RegularPatch::of(&self.root.refs(), &self.root.faces, scheme) {
                Some(p) => self.leaf(p),
                None => {
                    self.pending.push(std::mem::take(&mut self.root));
                    Node::Pending(self.pending.len() as u32 - 1)
                }
            };
            self.nodes.push(root);
            self.roots.push(0);
        }
    }

    fn leaf(&mut self, p: RegularPatch) -> Node {
        self.patches.push(p);
        Node::Leaf(self.patches.len() as u32 - 1)
    }

    /// A new node for a child.
    fn node_for(&mut self, kid: Kid) -> u32 {
        let node = match kid {
            Kid::Leaf(p) => self.leaf(*p),
            Kid::Pending(c) => {
                self.pending.push(c);
                Node::Pending(self.pending.len() as u32 - 1)
            }
        };
        self.nodes.push(node);
        self.nodes.len() as u32 - 1
    }

    /// Refines pending node `i`.
    fn expand(&mut self, i: u32) {
        let Node::Pending(c) = self.nodes[i as usize] else {
            return;
        };
        let corners = std::mem::take(&mut self.pending[c as usize]);
        let kids = patch::refine(corners, self.scheme, self.method, Layout::Quadrants);
        let first = self.nodes.len() as u32;
        for kid in kids {
            self.node_for(kid);
        }
        self.nodes[i as usize] = Node::Split(first);
    }

    /// Evaluates at `(sub, s, t)` of the domain's [`Domain::locate`].
    pub(crate) fn eval_located(&mut self, sub: usize, s: f64, t: f64, d: Derivatives) -> Sample {
        if self.scheme == Scheme::Bilinear {
            let n = self.corners.len();
            let [p, ds, dt, dst] =
                crate::bilinear::over_face(|k| self.corners[k], n, false, sub, s, t);
            let local = Local {
                p,
                ds,
                dt,
                dst,
                ..Local::default()
            };
            let scale = self.domain().derivative_scale();
            return Sample::from_local(&local, scale, d == Derivatives::Second);
        }
        let tri = self.scheme == Scheme::Loop;
        let corner_at: &[(f64, f64)] = if tri {
            &[(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]
        } else {
            &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
        };
        let second = d == Derivatives::Second;
        let (mut node, mut s, mut t) = (self.roots[sub], s, t);
        // d/du of the face = scale * d/ds of the node (a sign for Loop's turned triangles).
        let mut scale = self.domain().derivative_scale();
        let mut depth = 0u32;
        loop {
            match self.nodes[node as usize] {
                Node::Leaf(p) => {
                    let local = self.patches[p as usize].eval(s, t, second);
                    return Sample::from_local(&local, scale, second);
                }
                Node::Split(first) => {
                    let (k, s2, t2, factor) = child_of(tri, s, t);
                    (node, s, t) = (first + k, s2, t2);
                    scale *= factor;
                    depth += 1;
                }
                Node::Pending(c) => {
                    let corners = &self.pending[c as usize];
                    let exact = corner_at.iter().position(|&(a, b)| a == s && b == t);
                    let singular = exact.filter(|&k| {
                        let r = &corners.rings[k];
                        !r.needs_refinement()
                            && corner_kind(r, corners.faces[k], self.scheme).is_none()
                    });
                    let nearest = || {
                        let d2 = |&(a, b): &(f64, f64)| (a - s).powi(2) + (b - t).powi(2);
                        (0..corner_at.len())
                            .min_by(|&i, &j| d2(&corner_at[i]).total_cmp(&d2(&corner_at[j])))
                            .unwrap_or(0)
                    };
                    let at = singular.or_else(|| (depth >= MAX_DEPTH).then(nearest));
                    if let Some(k) = at {
                        let lim = corner_limit(&corners.rings[k], corners.faces[k], self.scheme);
                        let local = corner_local(tri, k, &lim);
                        return Sample::from_local(&local, scale, second);
                    }
                    self.expand(node);
                }
            }
        }
    }
}

/// The child holding local `(s, t)`, its coordinates there and the derivative factor.
#[inline]
fn child_of(tri: bool, s: f64, t: f64) -> (u32, f64, f64, f64) {
    if tri {
        if s >= 0.5 {
            (1, 2.0 * s - 1.0, 2.0 * t, 2.0)
        } else if t >= 0.5 {
            (2, 2.0 * s, 2.0 * t - 1.0, 2.0)
        } else if s + t <= 0.5 {
            (0, 2.0 * s, 2.0 * t, 2.0)
        } else {
            (3, 1.0 - 2.0 * s, 1.0 - 2.0 * t, -2.0)
        }
    } else {
        match (s >= 0.5, t >= 0.5) {
            (false, false) => (0, 2.0 * s, 2.0 * t, 2.0),
            (true, false) => (1, 2.0 * s - 1.0, 2.0 * t, 2.0),
            (true, true) => (2, 2.0 * s - 1.0, 2.0 * t - 1.0, 2.0),
            (false, true) => (3, 2.0 * s, 2.0 * t - 1.0, 2.0),
        }
    }
}

/// A corner limit in the patch's local frame: `next` and `prev` run from corner `k` towards
/// its neighbours.
fn corner_local(tri: bool, k: usize, lim: &crate::corner::CornerLimit) -> Local {
    let (n, p) = (lim.next, lim.prev);
    let (ds, dt) = if tri {
        match k {
            0 => (n, p),
            1 => (-p, n - p),
            _ => (p - n, -n),
        }
    } else {
        match k {
            0 => (n, p),
            1 => (-p, n),
            2 => (-n, -p),
            _ => (p, -n),
        }
    };
    Local {
        p: lim.position,
        ds,
        dt,
        ..Local::default()
    }
}

impl Sample {
    fn from_local(l: &Local, scale: f64, second: bool) -> Sample {
        let s2 = scale * scale;
        let z = DVec3::ZERO;
        Sample {
            position: l.p,
            du: l.ds * scale,
            dv: l.dt * scale,
            duu: if second { l.dss * s2 } else { z },
            duv: if second { l.dst * s2 } else { z },
            dvv: if second { l.dtt * s2 } else { z },
        }
    }
}
