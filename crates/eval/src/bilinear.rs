//! Bilinear interpolation over a face in its parameterisation: the bilinear scheme's limit
//! surface (the cage's own bilinear patches) and the linear face-varying option's values.
//!
//! A quad is the bilinear patch of its corners; any other face (a bilinear triangle too) is
//! split at its centre and edge midpoints into one quad per corner, `(0, 0)` at the corner,
//! `(1, 0)` at the midpoint of the edge to the next corner, `(1, 1)` at the centre and `(0, 1)`
//! at the midpoint of the edge from the previous corner, as OpenSubdiv's bilinear refinement
//! splits it and `Bfr` parameterises its sub-faces. A Loop triangle is linear over its corners.

use std::iter::Sum;
use std::ops::{Add, Div, Mul, Sub};

/// Value, `d/ds`, `d/dt` and `d2/dsdt` at `(s, t)` of sub-face `sub` (normalised coordinates,
/// [`crate::Domain::locate`]) of a face of `n` corners whose corner `k` is `corner(k)`;
/// `triangle`: Loop's barycentric triangle (then `d2/dsdt` is zero). The second derivatives
/// along `s` and `t` are zero.
pub(crate) fn over_face<T>(
    corner: impl Fn(usize) -> T,
    n: usize,
    triangle: bool,
    sub: usize,
    s: f64,
    t: f64,
) -> [T; 4]
where
    T: Copy + Add<Output = T> + Sub<Output = T> + Mul<f64, Output = T> + Div<f64, Output = T> + Sum,
{
    let c = |k: usize| corner(k % n);
    if triangle {
        let (a, b, d) = (c(0), c(1), c(2));
        return [a + (b - a) * s + (d - a) * t, b - a, d - a, a * 0.0];
    }
    let q = if n == 4 {
        [c(0), c(1), c(2), c(3)]
    } else {
        let centre = (0..n).map(c).sum::<T>() / n as f64;
        let k = sub;
        [
            c(k),
            (c(k) + c(k + 1)) * 0.5,
            centre,
            (c(k + n - 1) + c(k)) * 0.5,
        ]
    };
    let p = q[0] * ((1.0 - s) * (1.0 - t))
        + q[1] * (s * (1.0 - t))
        + q[2] * (s * t)
        + q[3] * ((1.0 - s) * t);
    let ds = (q[1] - q[0]) * (1.0 - t) + (q[2] - q[3]) * t;
    let dt = (q[3] - q[0]) * (1.0 - s) + (q[2] - q[1]) * s;
    let dst = q[0] - q[1] + q[2] - q[3];
    [p, ds, dt, dst]
}
