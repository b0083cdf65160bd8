//! Level balancing: a selection closure applied before the red-green closure.
//!
//! Every face carries a refinement level: 0 in the cage, `l + 1` for the four children of a
//! level-`l` triangle refined red, `l` for the green triangles closing a level-`l` triangle
//! (they stand in for their parent). [`balance`] extends a selection until, after the step, the
//! levels of any two faces sharing a vertex differ by at most one (2:1 balance across vertices,
//! as in restricted quadtrees and the classic red-green refinement of Bank, Sherman & Weiser).
//!
//! Why: Loop's vertex rule moves a vertex by about `β` times the length of its ring's edges. When
//! a vertex's ring mixes a fine side and a side several levels coarser, the long coarse edges
//! pull the vertex by a large multiple of the fine triangles' size at every step, and the fine
//! triangles beside it get thin (on the bunny with the view-angle DoI the smallest angle fell
//! from 13° to 0.4° in five unbalanced steps). With balanced levels every ring's edges are within
//! a factor of about two of each other, which bounds the distortion per step as in uniform Loop.
//!
//! It also refines red every triangle that would get two split edges (the classic rule of Bank,
//! Sherman & Weiser: green closure only for one hanging vertex), so every green triangle is a
//! median bisection of a red one. The paper's Fig. 1(b) closes two split edges with two
//! triangulation edges; that cut along the quadrilateral's diagonal can make angles well below
//! half the parent's.
//!
//! And it never lets a green bisection make an angle below a bound (the rule of Bank, Sherman &
//! Weiser: a green closure that would cut a small angle is replaced by a red refinement, which
//! propagates): a triangle whose bisection at its split edge's midpoint would make an angle
//! below half the cage's smallest angle, or worse than an exact bisection of its own smallest
//! angle while below three quarters of the cage's, is refined red. Bisecting the short edge opposite a thin triangle's small
//! angle about halves that angle (the teapot's lip strips, 3.09°, lost half of it to one green
//! split); bisecting a long edge does not.
//!
//! This knows nothing of DoIs; it only grows a face selection.

use glam::Vec3;
use subdiv_mesh::{FaceId, Mesh};

use super::close::{Closure, close};

/// A green bisection whose smallest angle is at least this fraction of the cage's smallest angle
/// is always allowed (see `bisection_keeps`): greens make no angle below the cage's. Measured on
/// the teapot (smallest angle after five steps over the seven DoIs of `tests/tests/doi.rs`,
/// bound 1.54°; view-angle DoI triangles in brackets): no guard 1.38° (419 394), 0.5 1.42°
/// (419 764), 0.6 1.54° (423 411), 0.75 1.57° (425 673), 0.85 1.79° (430 647), 1.0 1.98°
/// (436 434).
const GUARD: f32 = 1.0;

/// A triangle whose smallest angle is at least this (20°) is fat: the smoothing that follows a
/// step turns its angles by a small fraction of themselves, so an exact bisection of its
/// smallest angle may go down to the red-green bound itself (an equilateral triangle's median
/// makes exactly half its angles; without this a cage of equilateral triangles would be
/// refined uniformly). A thin triangle's angles move by a large fraction of themselves (the
/// teapot's lip, where one smoothing moves a vertex by about a strip's width).
const FAT: f32 = 20.0 * std::f32::consts::PI / 180.0;
use super::green::GreenState;
use crate::RedGreenError;
use crate::error::check_len;

/// Grows `selected` (one flag per face of `mesh`, with levels `level`) until the red-green
/// closure of the selection leaves the levels 2:1 balanced across vertices (for every face `f`
/// refined in the step, new level `level[f] + 1`, every face sharing a vertex with `f` has level
/// at least `level[f]` afterwards), no face is left with two split edges and no green
/// bisection cuts an angle too small for `cage_angle` (the cage's smallest angle in radians; 0
/// allows every bisection; see the module documentation). Returns the
/// grown selection and its closure; the number of faces added is the cost of balancing.
///
/// If the levels are balanced before the step they are balanced after it. With every face (or
/// no face) selected the selection is returned unchanged.
///
/// ```
/// use subdiv_mesh::{Mesh, PolygonSoup, glam::Vec3};
/// use subdiv_redgreen::red_green::{balance, GreenState};
/// // A fan of three triangles around vertex 0; face 1 is one level finer than its neighbours.
/// let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(-1.0, 0.0, 0.0), Vec3::new(0.0, -1.0, 0.0)];
/// let mesh = Mesh::from_soup(&PolygonSoup::from_faces(p, &[[0u32, 1, 2], [0, 2, 3], [0, 3, 4]]))?;
/// let (sel, _) = balance(&mesh, &GreenState::new(3), &[0, 1, 0], &[false, true, false], 0.0)?;
/// // Refining face 1 to level 2 needs its vertex-neighbours at level 1 at least.
/// assert_eq!(sel, vec![true, true, true]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn balance(
    mesh: &Mesh,
    state: &GreenState,
    level: &[u8],
    selected: &[bool],
    cage_angle: f32,
) -> Result<(Vec<bool>, Closure), RedGreenError> {
    check_len("face levels", level.len(), mesh.num_faces())?;
    let mut sel = selected.to_vec();
    let mut top = vec![0u8; mesh.num_vertices()];
    loop {
        let c = close(mesh, state, &sel)?;
        // The highest level around every vertex after the step.
        top.iter_mut().for_each(|t| *t = 0);
        for f in mesh.faces() {
            let l = level[f.idx()].saturating_add(u8::from(c.red_face[f.idx()]));
            for v in mesh.face_vertices(f) {
                top[v.idx()] = top[v.idx()].max(l);
            }
        }
        let mut grown = false;
        for f in mesh.faces() {
            let i = f.idx();
            if c.red_face[i] || sel[i] {
                continue;
            }
            let limit = level[i].saturating_add(1);
            let h0 = mesh.face_halfedge(f);
            let splits = [h0, mesh.next(h0), mesh.prev(h0)]
                .iter()
                .filter(|h| c.split_edge[h.edge().idx()])
                .count();
            if splits >= 2
                || mesh.face_vertices(f).iter().any(|v| top[v.idx()] > limit)
                || (splits == 1 && !bisection_keeps(mesh, state, &c, f, cage_angle))
            {
                sel[i] = true;
                grown = true;
            }
        }
        if !grown {
            return Ok((sel, c));
        }
    }
}

/// Whether the green bisection of `f` (one split edge) at its split edge's midpoint keeps the
/// angles: its smallest angle is at least [`GUARD`] times `cage_angle` (the cage's smallest
/// angle; the margin is for the smoothing that follows), or `f` is fat ([`FAT`]) and the
/// bisection's smallest angle is at least half of `cage_angle` (the red-green bound) and half
/// of `f`'s own (the cut is no worse than an exact bisection of `f`'s smallest angle: an
/// equilateral triangle's median, not a thin triangle's short-edge median). A green face keeps
/// (its family merges instead).
fn bisection_keeps(
    mesh: &Mesh,
    state: &GreenState,
    c: &Closure,
    f: FaceId,
    cage_angle: f32,
) -> bool {
    if state.family(f).is_some() {
        return true;
    }
    let h0 = mesh.face_halfedge(f);
    let mut h = h0;
    for _ in 0..3 {
        if c.split_edge[h.edge().idx()] {
            break;
        }
        h = mesh.next(h);
    }
    let p = |v| mesh.position(v);
    let (a, b, o) = (p(mesh.from(h)), p(mesh.to(h)), p(mesh.to(mesh.next(h))));
    let m = (a + b) * 0.5;
    let child = smallest_angle(a, m, o).min(smallest_angle(m, b, o));
    // Relative slack for rounding: an exact bisection is not refused for an ulp.
    const SLACK: f32 = 1.0 - 1e-4;
    child >= GUARD * cage_angle
        || (child >= 0.5 * SLACK * cage_angle && {
            let own = smallest_angle(a, b, o);
            own >= FAT && child >= 0.5 * SLACK * own
        })
}

/// The smallest corner angle (radians) of triangle `a b c`; 0 for a degenerate one.
#[inline]
pub(crate) fn smallest_angle(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let corner = |p: Vec3, q: Vec3, r: Vec3| {
        let (u, v) = (q - p, r - p);
        if u.length_squared() == 0.0 || v.length_squared() == 0.0 {
            0.0
        } else {
            u.angle_between(v)
        }
    };
    corner(a, b, c).min(corner(b, c, a)).min(corner(c, a, b))
}
