//! The parameter point of every output point of a uniform tessellation: the cage face and the
//! `(u, v)` in that face's domain, in OpenSubdiv's `Bfr` parameterisation as
//! `subdiv_eval::Domain` defines it (this crate does not depend on `subdiv-eval`; the tests
//! check the two agree).
//!
//! Every output point is written by one owner patch, so its parameter point is the one of the
//! owner's grid point, mapped onto the owner's cage face:
//! - a level-0 quad patch is its cage quad: grid `(i, j)` is `(i / n, j / n)` in the unit
//!   square, turned so that the patch's corners land on their face vertices' domain corners;
//! - a level-1 quad patch is the quad at corner `k` of a cage face `F` (an n-gon, or a quad next
//!   to one), whose corners are vertex `k`, the midpoint of edge `k`, the centre and the midpoint
//!   of edge `k - 1`: of an n-gon its sub-face tile `k`, of a quad its quarter at corner `k`;
//! - a Loop patch is its cage triangle, grid `(i, j)` at barycentric `(i / n, j / n)` from the
//!   patch's corner 0, turned onto the face's own vertex order.
//!
//! All these values are dyadic with few bits, so they are exact in `f32`.

use subdiv_mesh::{FaceId, Mesh};
use subdiv_rules::VertexParams;

use crate::layout::{Patch, PatchLayout};
use crate::patches::irregular_faces;
use crate::tri::TriLayout;

type Uv = [f64; 2];

/// The unit square's corners (`subdiv_eval::Domain::Quad`).
const QUAD: [Uv; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
/// The barycentric triangle's corners (`subdiv_eval::Domain::Triangle`).
const TRIANGLE: [Uv; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];

fn mid(a: Uv, b: Uv) -> Uv {
    [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]
}

/// The lower-left corner of sub-face tile `k` of a Catmull-Clark face of `corners` corners (not
/// four): `subdiv_eval::Domain::SubFaces`' corner `k`, tiles in rows of `dim`.
fn tile_corner(corners: usize, k: usize) -> Uv {
    let dim = subdiv_rules::subface_tiles_per_row(corners as u32);
    let k = k as u32;
    [f64::from(k % dim), f64::from(k / dim)]
}

/// The rotation `r` with `corners[k] == face[(r + k) % len]` for every `k`, if there is one.
fn rotation(corners: &[u32], face: &[subdiv_mesh::VertexId]) -> Option<usize> {
    let len = face.len();
    (len == corners.len())
        .then(|| (0..len).find(|&r| (0..len).all(|k| corners[k] == face[(r + k) % len].0)))
        .flatten()
}

/// Per output point: its face and `(u, v)`, `u32::MAX` until written.
struct Params {
    face: Vec<u32>,
    uv: Vec<[f32; 2]>,
}

impl Params {
    fn new(n: usize) -> Params {
        Params {
            face: vec![u32::MAX; n],
            uv: vec![[0.0; 2]; n],
        }
    }

    fn put(&mut self, id: u32, face: u32, uv: Uv) {
        self.face[id as usize] = face;
        self.uv[id as usize] = [uv[0] as f32, uv[1] as f32];
    }

    /// The parameter points, or `None` where a point has no owner.
    fn finish(self) -> Option<VertexParams> {
        (!self.face.contains(&u32::MAX)).then_some(VertexParams {
            face: self.face,
            uv: self.uv,
        })
    }
}

impl PatchLayout {
    /// The parameter point of every output point (index: output id): the cage face and the
    /// `(u, v)` in its domain (`subdiv_eval::Domain`) of the point's owner patch, the point
    /// a tessellation of this layout writes the limit of. `mesh` is the cage the layout was
    /// made for (its positions do not matter).
    ///
    /// `None` where output points are not the limits of their owners' grid points, or where
    /// the layout does not match `mesh`: a cage with holes (its hidden patches), seams (their
    /// points are written from the seams' crease chains) or isolated vertices (output at their
    /// cage positions).
    pub fn point_params(&self, mesh: &Mesh) -> Option<VertexParams> {
        if self.patches.iter().any(|p| !p.visible)
            || !self.seams.groups().is_empty()
            || !self.isolated.is_empty()
        {
            return None;
        }
        let nv = mesh.num_vertices() as u32;
        // The irregular faces in face order: face point `nv + x` is the centre of `centres[x]`.
        let irregular = irregular_faces(mesh);
        let centres: Vec<FaceId> = mesh.faces().filter(|f| irregular[f.idx()]).collect();
        if nv + centres.len() as u32 != self.edge_base {
            return None;
        }
        let mut out = Params::new(self.num_points());
        for p in &self.patches {
            let (face, c) = match p.level {
                0 => self.cage_corners(mesh, p)?,
                _ => self.level1_corners(mesh, p, &centres)?,
            };
            let n = 1u32 << (self.depth - p.level);
            // Grid point `(i, j)` of the patch, bilinear between the corners' parameters.
            let at = |i: u32, j: u32| -> Uv {
                let (s, t) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                let w = [(1.0 - s) * (1.0 - t), s * (1.0 - t), s * t, (1.0 - s) * t];
                let coord = |a: usize| (0..4).map(|k| w[k] * c[k][a]).sum::<f64>();
                [coord(0), coord(1)]
            };
            for (k, (i, j)) in [(0, 0), (n, 0), (n, n), (0, n)].into_iter().enumerate() {
                if p.corner_owned[k] {
                    out.put(p.corners[k], face, at(i, j));
                }
            }
            for (k, side) in p.sides.iter().enumerate() {
                if side.owned {
                    for s in 1..n {
                        let (i, j) = crate::side_point(k, s, n);
                        out.put(side.id(s), face, at(i, j));
                    }
                }
            }
            for j in 1..n {
                for i in 1..n {
                    out.put(p.interior + (j - 1) * (n - 1) + (i - 1), face, at(i, j));
                }
            }
        }
        out.finish()
    }

    /// A level-0 patch's cage face and the parameters of its four corners.
    fn cage_corners(&self, mesh: &Mesh, p: &Patch) -> Option<(u32, [Uv; 4])> {
        if p.face.idx() >= mesh.num_faces() {
            return None;
        }
        let r = rotation(&p.corners, mesh.face_vertices(p.face))?;
        Some((p.face.0, std::array::from_fn(|k| QUAD[(r + k) % 4])))
    }

    /// A level-1 patch's cage face and the parameters of its four corners: vertex `k` of the
    /// face, the midpoint of edge `k`, the face's centre and the midpoint of edge `k - 1`.
    fn level1_corners(&self, mesh: &Mesh, p: &Patch, centres: &[FaceId]) -> Option<(u32, [Uv; 4])> {
        let nv = mesh.num_vertices() as u32;
        let [v, e, centre, e_prev] = p.corners;
        let f = *centres.get(centre.checked_sub(nv)? as usize)?;
        let vs = mesh.face_vertices(f);
        let len = vs.len();
        let k = vs.iter().position(|x| x.0 == v)?;
        // An edge midpoint's id: the middle one of its cage edge's `2^depth - 1` inner points.
        let m = 1u32 << self.depth;
        let hs: Vec<_> = mesh.face_halfedges(f).collect();
        let mid_id = |h: subdiv_mesh::HalfedgeId| self.edge_base + h.edge().0 * (m - 1) + m / 2 - 1;
        if e != mid_id(hs[k]) || e_prev != mid_id(hs[(k + len - 1) % len]) {
            return None;
        }
        let c = if len == 4 {
            let q = |x: usize| QUAD[x % 4];
            [q(k), mid(q(k), q(k + 1)), [0.5, 0.5], mid(q(k), q(k + 3))]
        } else {
            let [x, y] = tile_corner(len, k);
            [[x, y], [x + 0.5, y], [x + 0.5, y + 0.5], [x, y + 0.5]]
        };
        Some((f.0, c))
    }
}

impl TriLayout {
    /// The parameter point of every output point (index: output id): the cage triangle and
    /// the barycentric `(u, v)` in it (`subdiv_eval::Domain::Triangle`, corners at the face's
    /// vertices 0, 1, 2) of the point's owner patch. `mesh` is the cage the layout was made for
    /// (its positions do not matter).
    ///
    /// `None` where output points are not the limits of their owners' lattice points, or where
    /// the layout does not match `mesh`: a cage with holes (their hidden patches), seams (their
    /// points are written from the seams' crease chains) or isolated vertices (output at their
    /// cage positions).
    pub fn point_params(&self, mesh: &Mesh) -> Option<VertexParams> {
        if self.patches.iter().any(|p| !p.visible)
            || !self.seams.groups().is_empty()
            || !self.isolated.is_empty()
            || self.patches.len() != mesh.num_faces()
        {
            return None;
        }
        let n = 1u32 << self.depth;
        let mut out = Params::new(self.num_points());
        for (f, p) in mesh.faces().zip(&self.patches) {
            let r = rotation(&p.corners, mesh.face_vertices(f))?;
            let c: [Uv; 3] = std::array::from_fn(|k| TRIANGLE[(r + k) % 3]);
            for j in 0..=n {
                for i in 0..=n - j {
                    let (id, owned) = TriLayout::point_id(p, n, i, j);
                    if owned {
                        let (s, t) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                        let uv = std::array::from_fn(|a| {
                            c[0][a] + s * (c[1][a] - c[0][a]) + t * (c[2][a] - c[0][a])
                        });
                        out.put(id, f.0, uv);
                    }
                }
            }
        }
        out.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_eval::Domain;
    use subdiv_rules::Scheme;

    #[test]
    fn tiles_are_the_domains() {
        for corners in (3..=300).filter(|&n| n != 4) {
            let d = Domain::of(Scheme::CatmullClark, corners);
            for k in 0..corners {
                assert_eq!(
                    tile_corner(corners, k),
                    d.corner(k),
                    "{corners} corners, {k}"
                );
            }
        }
        let (q, t) = (
            Domain::of(Scheme::CatmullClark, 4),
            Domain::of(Scheme::Loop, 3),
        );
        assert!((0..4).all(|k| q.corner(k) == QUAD[k]));
        assert!((0..3).all(|k| t.corner(k) == TRIANGLE[k]));
    }
}
