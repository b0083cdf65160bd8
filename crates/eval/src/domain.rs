//! How a face's points are named: OpenSubdiv 3.5 `Bfr::Parameterization`.
//!
//! - A quad (Catmull-Clark) is the unit square: corner `k` at `(0,0), (1,0), (1,1), (0,1)`,
//!   `u` along edge 0 (corner 0 to 1), `v` along edge 3 reversed (corner 0 to 3).
//! - A triangle (Loop) is barycentric: corner 0 at `(0,0)`, 1 at `(1,0)`, 2 at `(0,1)`,
//!   `u, v >= 0`, `u + v <= 1`.
//! - Any other face (Catmull-Clark) is split into quad *sub-faces*, one per corner (its level-1
//!   quads): sub-face `k` is the tile `[x, x + 1/2] x [y, y + 1/2]` with `x = k % d`,
//!   `y = k / d` and `d = 2` for 3 and 4 corners, 3 for 5..=9, `1 + floor(sqrt(n - 1))`
//!   beyond; inside it, `u` runs from corner `k` along edge `k` to its midpoint and `v` from
//!   corner `k` along edge `k - 1` (backwards) to its midpoint, and `(x + 1/2, y + 1/2)` is the
//!   face's centre. Derivatives are taken with respect to these `(u, v)`, so a sub-face's
//!   derivatives are twice those in its normalised `[0, 1]^2` (Ptex) coordinates.

use subdiv_rules::Scheme;

/// The parameter domain of one face ([`Domain::of`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Domain {
    /// The unit square of a Catmull-Clark quad.
    Quad,
    /// The barycentric triangle of a Loop triangle.
    Triangle,
    /// The quad sub-faces of a Catmull-Clark face of `corners` corners (not four), `dim` tiles
    /// a row.
    SubFaces {
        /// The face's corners (and sub-faces).
        corners: u32,
        /// Tiles per row.
        dim: u32,
    },
}

impl Domain {
    /// The domain of a face of `corners` corners under `scheme` (a Loop face is a triangle:
    /// the caller checks).
    pub fn of(scheme: Scheme, corners: usize) -> Domain {
        match scheme {
            Scheme::Loop => Domain::Triangle,
            Scheme::CatmullClark | Scheme::Bilinear if corners == 4 => Domain::Quad,
            Scheme::CatmullClark | Scheme::Bilinear => {
                let n = corners as u32;
                let dim = subdiv_rules::subface_tiles_per_row(n);
                Domain::SubFaces { corners: n, dim }
            }
        }
    }

    /// The `(u, v)` of corner `k`.
    pub fn corner(&self, k: usize) -> [f64; 2] {
        match *self {
            Domain::Quad => [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]][k & 3],
            Domain::Triangle => [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]][k % 3],
            Domain::SubFaces { dim, .. } => {
                let k = k as u32;
                [f64::from(k % dim), f64::from(k / dim)]
            }
        }
    }

    /// The `(u, v)` at `t` in `[0, 1]` along edge `k` (from corner `k` to corner `k + 1`).
    pub fn edge_point(&self, k: usize, t: f64) -> [f64; 2] {
        match *self {
            Domain::Quad => match k & 3 {
                0 => [t, 0.0],
                1 => [1.0, t],
                2 => [1.0 - t, 1.0],
                _ => [0.0, 1.0 - t],
            },
            Domain::Triangle => match k % 3 {
                0 => [t, 0.0],
                1 => [1.0 - t, t],
                _ => [0.0, 1.0 - t],
            },
            Domain::SubFaces { corners, .. } => {
                if t < 0.5 {
                    let [u, v] = self.corner(k);
                    [u + t, v]
                } else {
                    let [u, v] = self.corner((k + 1) % corners as usize);
                    [u, v + 1.0 - t]
                }
            }
        }
    }

    /// The `(u, v)` of the face's centre.
    pub fn centre(&self) -> [f64; 2] {
        match self {
            Domain::Triangle => [1.0 / 3.0, 1.0 / 3.0],
            _ => [0.5, 0.5],
        }
    }

    /// Where `(u, v)` lies: the sub-face (0 for quads and triangles) and the normalised
    /// coordinates in it (`[0, 1]^2`, or the triangle), or `None` outside the domain. Points
    /// on a boundary between tiles belong to one of them; the domain is closed.
    pub fn locate(&self, u: f64, v: f64) -> Option<(usize, f64, f64)> {
        if !(u.is_finite() && v.is_finite()) {
            return None;
        }
        match *self {
            Domain::Quad => {
                ((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)).then_some((0, u, v))
            }
            Domain::Triangle => (u >= 0.0 && v >= 0.0 && u + v <= 1.0).then_some((0, u, v)),
            Domain::SubFaces { corners, dim } => {
                if u < 0.0 || v < 0.0 {
                    return None;
                }
                let (x, y) = (u.floor(), v.floor());
                let (fu, fv) = (u - x, v - y);
                // A point on the far edge of a tile (fraction exactly 1/2) is that tile's.
                if fu > 0.5 || fv > 0.5 {
                    return None;
                }
                let (x, y) = (x as u64, y as u64);
                if x >= u64::from(dim) {
                    return None;
                }
                let k = y * u64::from(dim) + x;
                (k < u64::from(corners)).then_some((k as usize, 2.0 * fu, 2.0 * fv))
            }
        }
    }

    /// Derivatives with respect to `(u, v)` are this times those in the normalised
    /// coordinates of [`Domain::locate`].
    pub fn derivative_scale(&self) -> f64 {
        match self {
            Domain::SubFaces { .. } => 2.0,
            _ => 1.0,
        }
    }

    /// The point of the domain at `r = (r0, r1, r2)` in `[0, 1)^3`: uniformly distributed in
    /// the domain's area when `r` is (the sub-face from `r2`).
    pub fn sample(&self, r: [f64; 3]) -> [f64; 2] {
        match *self {
            Domain::Quad => [r[0], r[1]],
            Domain::Triangle if r[0] + r[1] > 1.0 => [1.0 - r[0], 1.0 - r[1]],
            Domain::Triangle => [r[0], r[1]],
            Domain::SubFaces { corners, .. } => {
                let k = ((r[2] * f64::from(corners)) as usize).min(corners as usize - 1);
                let [x, y] = self.corner(k);
                [x + 0.5 * r[0], y + 0.5 * r[1]]
            }
        }
    }

    /// A short name of the domain for messages.
    pub fn describe(&self) -> String {
        match self {
            Domain::Quad => "the unit square".into(),
            Domain::Triangle => "the triangle u, v >= 0, u + v <= 1".into(),
            Domain::SubFaces { corners, dim } => format!(
                "the {corners} sub-face tiles [x, x + 0.5] x [y, y + 0.5] (x = k % {dim}, y = k / {dim}, k < {corners})"
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bfr_tile_dimensions_and_coordinates() {
        let d = |n| match Domain::of(Scheme::CatmullClark, n) {
            Domain::SubFaces { dim, .. } => dim,
            _ => 0,
        };
        assert_eq!([d(3), d(5), d(9), d(10), d(16), d(17)], [2, 3, 3, 4, 4, 5]);
        let pent = Domain::of(Scheme::CatmullClark, 5);
        assert_eq!(pent.corner(4), [1.0, 1.0]);
        // Edge 1 from corner 1 (tile (1, 0)) to corner 2 (tile (2, 0)).
        assert_eq!(pent.edge_point(1, 0.25), [1.25, 0.0]);
        assert_eq!(pent.edge_point(1, 0.75), [2.0, 0.25]);
        assert_eq!(pent.locate(1.25, 0.5), Some((1, 0.5, 1.0)));
        assert_eq!(pent.locate(1.75, 0.0), None);
        assert_eq!(pent.locate(2.25, 1.25), None);
        assert_eq!(pent.locate(1.5, 1.5), Some((4, 1.0, 1.0)));
        assert_eq!(Domain::Quad.locate(1.0, 1.0), Some((0, 1.0, 1.0)));
        assert_eq!(Domain::Quad.locate(1.0, 1.0 + 1e-12), None);
        assert_eq!(Domain::Triangle.locate(0.6, 0.5), None);
        assert_eq!(Domain::Triangle.locate(f64::NAN, 0.0), None);
    }
}
