//! A sub-patch of a face at some level, as the rings of its corners, and the one local
//! refinement step that makes the rings of its children.
//!
//! The limit surface over a patch depends only on its corners' rings
//! ([`subdiv_rules::Ring`]: each corner with all its edge neighbours, faces, sharpness, the
//! Chaikin information beyond and, at a copy of a non-manifold vertex, the whole vertex's
//! values): every rule that moves a point of the patch's children reads nothing else. One step
//! maps them to the rings of each child's corners: a corner's own child ring is
//! [`Ring::refine`]; the rings of the new edge and face points are assembled from those
//! refined rings ([`Ring::load_quads`], [`Ring::load_triangles`]) with the child sharpness the
//! corners' vertex rules gave the halves of each side. So every rule stays in `subdiv-rules`
//! and is applied there.
//!
//! A patch whose corners are all *regular-compatible* ([`corner_kind`]) is a polynomial patch:
//! the bicubic B-spline (Catmull-Clark) or the quartic box spline (Loop) of its 16 or 12
//! control points, with phantom points reflected across infinitely sharp patch edges and lines
//! (OpenSubdiv's regular patches with a boundary mask, which reproduce the crease rules).
//!
//! Corner order: a quad patch's corners are at `(0,0), (1,0), (1,1), (0,1)` of its local
//! `(s, t)`, a triangle's at `(0,0), (1,0), (0,1)`; in corner `k`'s ring the patch is face
//! `faces[k]`, between ring edge `faces[k]` (towards corner `k + 1`) and `faces[k] + 1`
//! (towards corner `k - 1`).

use glam::DVec3;
use subdiv_mesh::CreaseMethod;
use subdiv_rules::crease::{Rule, is_infinite, is_semi_sharp, semi_sharp_excluding};
use subdiv_rules::{Ring, Scheme};

use crate::basis;

/// The corners of one patch: each corner's ring and the patch's face in it.
#[derive(Clone, Debug, Default)]
pub(crate) struct Corners {
    pub rings: Vec<Ring>,
    pub faces: Vec<usize>,
}

impl Corners {
    fn push(&mut self, ring: Ring, face: usize) {
        self.rings.push(ring);
        self.faces.push(face);
    }

    /// Its rings, borrowed.
    pub(crate) fn refs(&self) -> Vec<&Ring> {
        self.rings.iter().collect()
    }
}

#[inline]
fn wrap(i: isize, n: usize) -> usize {
    i.rem_euclid(n as isize) as usize
}

/// The Chaikin (sum, count) beyond ring `r`'s edge `i`, seen from its far end: the other
/// semi-sharp edges at `r`'s centre.
#[inline]
fn far_of(r: &Ring, i: usize) -> (f32, u32) {
    semi_sharp_excluding(r.edge_sharpnesses(), i, r.whole())
}

/// The ring of the point on side `a -> b` of a Catmull-Clark patch one level down, from the
/// refined rings of its ends (`fa`, `fb`: the patch in them). Ring order: the end `b`, the
/// patch's face point, the end `a`, the face point across the side (absent on a boundary).
fn quad_side_ring(a: &Ring, fa: usize, b: &Ring, fb: usize, method: CreaseMethod) -> Ring {
    let (na, nb, nfa) = (a.valence(), b.valence(), a.face_count());
    let (fa_i, fb_i) = (fa as isize, fb as isize);
    let boundary = a.is_boundary() && fa == 0;
    let eb = wrap(fb_i + 1, nb);
    let mut edges = vec![b.center(), a.diag(fa), a.center()];
    let mut diag = vec![b.edge(fb), a.edge(wrap(fa_i + 1, na))];
    let mut sharp = vec![b.edge_sharpness(eb), 0.0, a.edge_sharpness(fa)];
    let mut far = vec![far_of(b, eb), (0.0, 0), far_of(a, fa)];
    if !boundary {
        edges.push(a.diag(wrap(fa_i - 1, nfa)));
        diag.push(a.edge(wrap(fa_i - 1, na)));
        diag.push(b.edge(wrap(fb_i + 2, nb)));
        sharp.push(0.0);
        far.push((0.0, 0));
    }
    let mut ring = Ring::new();
    let centre = a.edge(fa);
    ring.load_quads(method, centre, 0.0, boundary, &edges, &sharp, &far, &diag);
    ring
}

/// The Loop counterpart of [`quad_side_ring`]. Ring order: the end `b`, the points on the
/// patch's other two sides (at `b`, then at `a`), the end `a`, the points on the two sides of
/// the triangle across (absent on a boundary).
fn tri_side_ring(a: &Ring, fa: usize, b: &Ring, fb: usize, method: CreaseMethod) -> Ring {
    let (na, nb) = (a.valence(), b.valence());
    let (fa_i, fb_i) = (fa as isize, fb as isize);
    let boundary = a.is_boundary() && fa == 0;
    let eb = wrap(fb_i + 1, nb);
    let mut edges = vec![
        b.center(),
        b.edge(fb),
        a.edge(wrap(fa_i + 1, na)),
        a.center(),
    ];
    let mut sharp = vec![b.edge_sharpness(eb), 0.0, 0.0, a.edge_sharpness(fa)];
    let mut far = vec![far_of(b, eb), (0.0, 0), (0.0, 0), far_of(a, fa)];
    if !boundary {
        edges.push(a.edge(wrap(fa_i - 1, na)));
        edges.push(b.edge(wrap(fb_i + 2, nb)));
        sharp.extend([0.0, 0.0]);
        far.extend([(0.0, 0), (0.0, 0)]);
    }
    let mut ring = Ring::new();
    ring.load_triangles(method, a.edge(fa), 0.0, boundary, &edges, &sharp, &far);
    ring
}

/// How the children of a Catmull-Clark patch are laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Layout {
    /// The four quadrants of a quad patch, each in the parent's orientation: child `k` holds
    /// corner `k` and `(s, t) = (2 s - [k = 1, 2], 2 t - [k = 2, 3])`.
    Quadrants,
    /// The sub-faces of a face of any size: child `k` starts at corner `k` and runs along edge
    /// `k` (OpenSubdiv's sub-face parameterisation).
    SubFaces,
}

/// A child of a refined patch: a regular patch, or the corners to refine it further.
pub(crate) enum Kid {
    Leaf(Box<RegularPatch>),
    Pending(Corners),
}

/// One local refinement step: every child of `parent` (whose rings it refines in place), in
/// child order (Catmull-Clark: [`Layout`]; Loop: the corner children `0, 1, 2` in the parent's
/// orientation, then the middle triangle, turned half a turn: `(s, t) = (1 - 2 s, 1 - 2 t)`).
/// Children are classified on the shared rings; only those refined further get their own.
pub(crate) fn refine(
    mut parent: Corners,
    scheme: Scheme,
    method: CreaseMethod,
    layout: Layout,
) -> Vec<Kid> {
    let n = parent.rings.len();
    for r in &mut parent.rings {
        r.refine();
    }
    let (rings, f) = (&mut parent.rings, &parent.faces);
    let side = |rings: &[Ring], j: usize| {
        let k = (j + 1) % n;
        match scheme {
            Scheme::CatmullClark => quad_side_ring(&rings[j], f[j], &rings[k], f[k], method),
            Scheme::Loop => tri_side_ring(&rings[j], f[j], &rings[k], f[k], method),
            Scheme::Bilinear => {
                unreachable!("bilinear faces are their corners' patches (FaceSurface::load)")
            }
        }
    };
    let sides: Vec<Ring> = (0..n).map(|j| side(rings, j)).collect();
    // Each child's corners: (which ring: 0..n the refined corners, n..2n the sides, 2n the
    // centre; the face in it), rotated to the child's orientation.
    let mut plans: Vec<Vec<(usize, usize)>> = Vec::with_capacity(n + 1);
    let mut centre = Ring::new();
    match scheme {
        Scheme::CatmullClark => {
            let edges: Vec<DVec3> = (0..n).map(|j| rings[j].edge(f[j])).collect();
            let diag: Vec<DVec3> = (0..n).map(|j| rings[(j + 1) % n].center()).collect();
            let (zero, none) = (vec![0.0; n], vec![(0.0, 0); n]);
            let c = rings[0].diag(f[0]);
            centre.load_quads(method, c, 0.0, false, &edges, &zero, &none, &diag);
            for (k, &fk) in f.iter().enumerate() {
                let prev = (k + n - 1) % n;
                let mut plan = vec![(k, fk), (n + k, 1), (2 * n, prev), (n + prev, 0)];
                if layout == Layout::Quadrants {
                    plan.rotate_left((4 - k) % 4);
                }
                plans.push(plan);
            }
        }
        Scheme::Loop => {
            for (k, &fk) in f.iter().enumerate() {
                let prev = (k + 2) % 3;
                let mut plan = vec![(k, fk), (n + k, 2), (n + prev, 0)];
                plan.rotate_left((3 - k) % 3);
                plans.push(plan);
            }
            plans.push(vec![(n + 1, 1), (n + 2, 1), (n, 1)]);
        }
        Scheme::Bilinear => {
            unreachable!("bilinear faces are their corners' patches (FaceSurface::load)")
        }
    }
    let classes: Vec<Option<RegularPatch>> = plans
        .iter()
        .map(|plan| {
            let refs: Vec<&Ring> = plan
                .iter()
                .map(|&(i, _)| {
                    let r: &Ring = match i {
                        i if i < n => &rings[i],
                        i if i < 2 * n => &sides[i - n],
                        _ => &centre,
                    };
                    r
                })
                .collect();
            let faces: Vec<usize> = plan.iter().map(|&(_, f)| f).collect();
            RegularPatch::of(&refs, &faces, scheme)
        })
        .collect();
    plans
        .iter()
        .zip(classes)
        .map(|(plan, class)| match class {
            Some(p) => Kid::Leaf(Box::new(p)),
            None => {
                let mut c = Corners::default();
                for &(i, face) in plan {
                    let r = match i {
                        i if i < n => std::mem::take(&mut rings[i]),
                        i if i < 2 * n => sides[i - n].clone(),
                        _ => centre.clone(),
                    };
                    c.push(r, face);
                }
                Kid::Pending(c)
            }
        })
        .collect()
}

/// How a corner takes part in a regular patch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct CornerKind {
    /// The patch side towards the next corner is infinitely sharp.
    pub next: bool,
    /// The patch side towards the previous corner is infinitely sharp.
    pub prev: bool,
    /// (Loop) an infinitely sharp line runs through the corner along no patch side.
    pub line: bool,
}

/// Whether corner ring `r` (the patch its face `f`) is one a polynomial patch reproduces:
/// a smooth interior vertex of the regular valence (4, Loop 6); a crease vertex (two
/// infinitely sharp edges, nothing semi-sharp) whose sector holding the patch has the faces of
/// a regular half-plane (2, Loop 3); or a corner the patch alone fills between two infinitely
/// sharp sides. `None` for anything else: an extraordinary vertex, a dart, semi-sharpness,
/// non-quads, a copy of a non-manifold vertex.
pub(crate) fn corner_kind(r: &Ring, f: usize, scheme: Scheme) -> Option<CornerKind> {
    if r.has_master() || !r.whole().is_empty() || is_semi_sharp(r.vertex_sharpness()) {
        return None;
    }
    let sharp = r.edge_sharpnesses();
    if sharp.iter().any(|&s| is_semi_sharp(s)) {
        return None;
    }
    if scheme == Scheme::CatmullClark && !r.all_quads() {
        return None;
    }
    let (regular, half) = match scheme {
        Scheme::CatmullClark => (4, 2),
        Scheme::Loop => (6, 3),
        Scheme::Bilinear => {
            unreachable!("bilinear faces are their corners' patches (FaceSurface::load)")
        }
    };
    let (n, nf) = (r.valence(), r.face_count());
    let kind = |next, prev, line| Some(CornerKind { next, prev, line });
    match Rule::determine(r.vertex_sharpness(), sharp) {
        Rule::Smooth if !r.is_boundary() && n == regular => kind(false, false, false),
        Rule::Smooth | Rule::Dart => None,
        Rule::Crease([a, b]) => {
            let (start, count) = if r.is_boundary() {
                (0, nf)
            } else if a <= f && f < b {
                (a, b - a)
            } else {
                (b, n - (b - a))
            };
            if count != half {
                return None;
            }
            match (scheme, (f + n - start) % n) {
                (_, 0) => kind(true, false, false),
                (Scheme::CatmullClark, 1) | (Scheme::Loop, 2) => kind(false, true, false),
                (Scheme::Loop, 1) => kind(false, false, true),
                _ => None,
            }
        }
        Rule::Corner => {
            let both = is_infinite(sharp[f]) && is_infinite(sharp[(f + 1) % n]);
            if both { kind(true, true, false) } else { None }
        }
    }
}

/// The edge neighbour of ring `r` in lattice direction `d` from the patch's face `f` (0 and 1
/// the patch's sides, counting on counter-clockwise), `None` where the ring has none (beyond a
/// boundary, or a ring not of the regular valence).
fn lattice_edge(r: &Ring, f: usize, d: usize, regular: usize) -> Option<DVec3> {
    lattice_index(r.valence(), r.is_boundary(), f, d, regular).map(|i| r.edge(i))
}

/// [`lattice_edge`] for the vertex opposite the centre in a quad (`d`: the quad after edge `d`).
fn lattice_diag(r: &Ring, f: usize, d: usize, regular: usize) -> Option<DVec3> {
    lattice_index(r.face_count(), r.is_boundary(), f, d, regular).map(|i| r.diag(i))
}

fn lattice_index(
    count: usize,
    boundary: bool,
    f: usize,
    d: usize,
    regular: usize,
) -> Option<usize> {
    if !boundary {
        return (count == regular).then_some((f + d) % regular);
    }
    let p = f + d;
    if p < count {
        Some(p)
    } else {
        p.checked_sub(regular)
    }
}

/// A regular patch: its control points (16 B-spline points, or 12 box spline points and four
/// unused) and boundary mask (see [`crate::basis`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RegularPatch {
    pub points: [DVec3; 16],
    pub mask: u8,
    pub triangle: bool,
}

/// Position and derivatives in a patch's local `(s, t)`.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Local {
    pub p: DVec3,
    pub ds: DVec3,
    pub dt: DVec3,
    pub dss: DVec3,
    pub dst: DVec3,
    pub dtt: DVec3,
}

impl RegularPatch {
    /// The patch of `c` if every corner is regular-compatible and their sharp sides and lines
    /// fit a boundary mask.
    pub(crate) fn of(rings: &[&Ring], faces: &[usize], scheme: Scheme) -> Option<RegularPatch> {
        let n = rings.len();
        let mut kinds = [CornerKind {
            next: false,
            prev: false,
            line: false,
        }; 4];
        for k in 0..n {
            kinds[k] = corner_kind(rings[k], faces[k], scheme)?;
        }
        let mut sides = 0u8;
        let mut lines = 0u8;
        for k in 0..n {
            if kinds[k].next != kinds[(k + 1) % n].prev {
                return None;
            }
            sides |= u8::from(kinds[k].next) << k;
            lines |= u8::from(kinds[k].line) << k;
        }
        match scheme {
            Scheme::CatmullClark => Some(Self::quad(rings, faces, sides)),
            Scheme::Loop => {
                let mask = match (sides, lines) {
                    (e, 0) => e,
                    (0, v) => v | 8,
                    (e, v) if e.count_ones() == 1 && v == 1 << ((e.trailing_zeros() + 2) % 3) => {
                        e | 16
                    }
                    _ => return None,
                };
                Some(Self::triangle(rings, faces, mask))
            }
            Scheme::Bilinear => {
                unreachable!("bilinear faces are their corners' patches (FaceSurface::load)")
            }
        }
    }

    fn quad(rings: &[&Ring], faces: &[usize], mask: u8) -> RegularPatch {
        // Per corner: its position, and where its ring's points beyond the patch go (edge
        // neighbours in lattice directions 2 and 3, the quad after direction 2).
        const AT: [[(usize, usize); 4]; 4] = [
            [(1, 1), (0, 1), (1, 0), (0, 0)],
            [(2, 1), (2, 0), (3, 1), (3, 0)],
            [(2, 2), (3, 2), (2, 3), (3, 3)],
            [(1, 2), (1, 3), (0, 2), (0, 3)],
        ];
        let mut points = [DVec3::ZERO; 16];
        for k in 0..4 {
            let (r, f) = (rings[k], faces[k]);
            let at = |(i, j): (usize, usize)| 4 * j + i;
            points[at(AT[k][0])] = r.center();
            for (slot, p) in [
                (AT[k][1], lattice_edge(r, f, 2, 4)),
                (AT[k][2], lattice_edge(r, f, 3, 4)),
                (AT[k][3], lattice_diag(r, f, 2, 4)),
            ] {
                if let Some(p) = p {
                    points[at(slot)] = p;
                }
            }
        }
        RegularPatch {
            points,
            mask,
            triangle: false,
        }
    }

    fn triangle(rings: &[&Ring], faces: &[usize], mask: u8) -> RegularPatch {
        // Per corner: its index, and the indices of its edge neighbours in lattice directions
        // 3, 4 and 5.
        const AT: [[usize; 4]; 3] = [[4, 3, 0, 1], [5, 2, 6, 9], [8, 11, 10, 7]];
        let mut points = [DVec3::ZERO; 16];
        for k in 0..3 {
            let (r, f) = (rings[k], faces[k]);
            points[AT[k][0]] = r.center();
            for d in 3..6 {
                if let Some(p) = lattice_edge(r, f, d, 6) {
                    points[AT[k][d - 2]] = p;
                }
            }
        }
        RegularPatch {
            points,
            mask,
            triangle: true,
        }
    }

    /// Position and derivatives at local `(s, t)`.
    #[inline]
    pub(crate) fn eval(&self, s: f64, t: f64, second: bool) -> Local {
        if self.triangle {
            combine(
                &self.points[..12],
                &basis::box_spline(s, t, self.mask, second),
                second,
            )
        } else {
            combine(
                &self.points,
                &basis::bspline(s, t, self.mask, second),
                second,
            )
        }
    }
}

/// The points `pts` weighted by `w`.
#[inline]
fn combine<const N: usize>(pts: &[DVec3], w: &basis::Weights<N>, second: bool) -> Local {
    let mut out = Local::default();
    for (k, &x) in pts.iter().enumerate() {
        out.p += x * w.p[k];
        out.ds += x * w.ds[k];
        out.dt += x * w.dt[k];
    }
    if second {
        for (k, &x) in pts.iter().enumerate() {
            out.dss += x * w.dss[k];
            out.dst += x * w.dst[k];
            out.dtt += x * w.dtt[k];
        }
    }
    out
}
