//! The regular patches' basis functions: the uniform bicubic B-spline (Catmull-Clark) and the
//! quartic three-direction box spline (Loop), with first and second derivatives and the
//! boundary rules that fold the weights of phantom points (reflections across an infinitely
//! sharp patch edge) onto the real ones.
//!
//! The forms are OpenSubdiv 3.5's (`far/patchBasis.cpp`: `evalBSplineCurve`,
//! `adjustBSplineBoundaryWeights`, `evalBoxSplineTriDerivWeights` — Stam's box spline basis in
//! bivariate monomials — and `adjustBoxSplineTriBoundaryWeights`), so a regular patch here and
//! in OpenSubdiv is the same polynomial of the same points.
//!
//! Point layouts. B-spline: point `(i, j)`, `-1 <= i, j <= 2`, at index `4 (j + 1) + (i + 1)`;
//! the patch is `[0, 1]^2` between points `(0, 0)` and `(1, 1)`. Box spline (lattice `(i, j)`,
//! the patch the triangle `(0, 0), (1, 0), (0, 1)`): indices 0..12 at `(0,-1) (1,-1) (2,-1)
//! (-1,0) (0,0) (1,0) (2,0) (-1,1) (0,1) (1,1) (-1,2) (0,2)`.

/// The weights of a patch's points for its value and derivatives at one parameter point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Weights<const N: usize> {
    pub p: [f64; N],
    pub ds: [f64; N],
    pub dt: [f64; N],
    pub dss: [f64; N],
    pub dst: [f64; N],
    pub dtt: [f64; N],
}

impl<const N: usize> Weights<N> {
    const ZERO: Self = Weights {
        p: [0.0; N],
        ds: [0.0; N],
        dt: [0.0; N],
        dss: [0.0; N],
        dst: [0.0; N],
        dtt: [0.0; N],
    };

    /// Applies `f` to every weight array in use (the second derivatives only with `second`).
    #[inline]
    fn each(&mut self, second: bool, mut f: impl FnMut(&mut [f64; N])) {
        f(&mut self.p);
        f(&mut self.ds);
        f(&mut self.dt);
        if second {
            f(&mut self.dss);
            f(&mut self.dst);
            f(&mut self.dtt);
        }
    }
}

/// The uniform cubic B-spline curve basis at `t` and its two derivatives.
#[inline]
fn bspline_curve(t: f64) -> ([f64; 4], [f64; 4], [f64; 4]) {
    let t2 = t * t;
    let t3 = t * t2;
    let p = [
        (1.0 - 3.0 * (t - t2) - t3) / 6.0,
        (4.0 - 6.0 * t2 + 3.0 * t3) / 6.0,
        (1.0 + 3.0 * (t + t2 - t3)) / 6.0,
        t3 / 6.0,
    ];
    let d = [
        -0.5 * t2 + t - 0.5,
        1.5 * t2 - 2.0 * t,
        -1.5 * t2 + t + 0.5,
        0.5 * t2,
    ];
    let dd = [1.0 - t, 3.0 * t - 2.0, 1.0 - 3.0 * t, t];
    (p, d, dd)
}

/// The bicubic B-spline weights at `(s, t)` with the phantom rows and columns of `boundary`
/// (bit `k`: patch side `k` is infinitely sharp; side 0 runs along `t = 0`, 1 along `s = 1`,
/// 2 along `t = 1`, 3 along `s = 0`) folded in. Second derivatives only with `second`.
pub(crate) fn bspline(s: f64, t: f64, boundary: u8, second: bool) -> Weights<16> {
    let (su, sd, sdd) = bspline_curve(s);
    let (tu, td, tdd) = bspline_curve(t);
    let mut w = Weights::<16>::ZERO;
    for j in 0..4 {
        for i in 0..4 {
            let k = 4 * j + i;
            w.p[k] = su[i] * tu[j];
            w.ds[k] = sd[i] * tu[j];
            w.dt[k] = su[i] * td[j];
            if second {
                w.dss[k] = sdd[i] * tu[j];
                w.dst[k] = sd[i] * td[j];
                w.dtt[k] = su[i] * tdd[j];
            }
        }
    }
    if boundary != 0 {
        w.each(second, |w| fold_bspline(boundary, w));
    }
    w
}

/// OpenSubdiv's `adjustBSplineBoundaryWeights`: a phantom row or column is the reflection
/// `2 b - i` of the boundary row `b` across from the inner row `i`.
fn fold_bspline(boundary: u8, w: &mut [f64; 16]) {
    if boundary & 1 != 0 {
        for i in 0..4 {
            w[i + 8] -= w[i];
            w[i + 4] += 2.0 * w[i];
            w[i] = 0.0;
        }
    }
    if boundary & 2 != 0 {
        for i in (0..16).step_by(4) {
            w[i + 1] -= w[i + 3];
            w[i + 2] += 2.0 * w[i + 3];
            w[i + 3] = 0.0;
        }
    }
    if boundary & 4 != 0 {
        for i in 0..4 {
            w[i + 4] -= w[i + 12];
            w[i + 8] += 2.0 * w[i + 12];
            w[i + 12] = 0.0;
        }
    }
    if boundary & 8 != 0 {
        for i in (0..16).step_by(4) {
            w[i + 2] -= w[i];
            w[i + 1] += 2.0 * w[i];
            w[i] = 0.0;
        }
    }
}

/// The bivariate monomials up to degree 4: `1, s, t, ss, st, tt, sss, sst, stt, ttt, ssss,
/// ssst, sstt, sttt, tttt`.
#[inline]
fn monomials(s: f64, t: f64) -> [f64; 15] {
    let mut m = [0.0; 15];
    m[0] = 1.0;
    m[1] = s;
    m[2] = t;
    m[3] = s * s;
    m[4] = s * t;
    m[5] = t * t;
    m[6] = m[3] * s;
    m[7] = m[4] * s;
    m[8] = m[4] * t;
    m[9] = m[5] * t;
    m[10] = m[6] * s;
    m[11] = m[7] * s;
    m[12] = m[3] * m[5];
    m[13] = m[8] * t;
    m[14] = m[9] * t;
    m
}

/// The box spline's value weights.
#[rustfmt::skip]
fn box_value(m: &[f64; 15], w: &mut [f64; 12]) {
    let s = 1.0 / 12.0;
    w[0]  = s * (1.0 - 2.0*m[1] - 4.0*m[2] + 6.0*m[4] + 6.0*m[5] + 2.0*m[6] - 6.0*m[8] - 4.0*m[9] - m[10] - 2.0*m[11] + 2.0*m[13] + m[14]);
    w[1]  = s * (1.0 + 2.0*m[1] - 2.0*m[2] - 6.0*m[4] - 4.0*m[6] + 6.0*m[8] + 2.0*m[9] + 2.0*m[10] + 4.0*m[11] - 2.0*m[13] - m[14]);
    w[2]  = s * (2.0*m[6] - m[10] - 2.0*m[11]);
    w[3]  = s * (1.0 - 4.0*m[1] - 2.0*m[2] + 6.0*m[3] + 6.0*m[4] - 4.0*m[6] - 6.0*m[7] + 2.0*m[9] + m[10] + 2.0*m[11] - 2.0*m[13] - m[14]);
    w[4]  = s * (6.0 - 12.0*m[3] - 12.0*m[4] - 12.0*m[5] + 8.0*m[6] + 12.0*m[7] + 12.0*m[8] + 8.0*m[9] - m[10] - 2.0*m[11] - 2.0*m[13] - m[14]);
    w[5]  = s * (1.0 + 4.0*m[1] + 2.0*m[2] + 6.0*m[3] + 6.0*m[4] - 4.0*m[6] - 6.0*m[7] - 12.0*m[8] - 4.0*m[9] - m[10] - 2.0*m[11] + 4.0*m[13] + 2.0*m[14]);
    w[6]  = s * (m[10] + 2.0*m[11]);
    w[7]  = s * (1.0 - 2.0*m[1] + 2.0*m[2] - 6.0*m[4] + 2.0*m[6] + 6.0*m[7] - 4.0*m[9] - m[10] - 2.0*m[11] + 4.0*m[13] + 2.0*m[14]);
    w[8]  = s * (1.0 + 2.0*m[1] + 4.0*m[2] + 6.0*m[4] + 6.0*m[5] - 4.0*m[6] - 12.0*m[7] - 6.0*m[8] - 4.0*m[9] + 2.0*m[10] + 4.0*m[11] - 2.0*m[13] - m[14]);
    w[9]  = s * (2.0*m[6] + 6.0*m[7] + 6.0*m[8] + 2.0*m[9] - m[10] - 2.0*m[11] - 2.0*m[13] - m[14]);
    w[10] = s * (2.0*m[9] - 2.0*m[13] - m[14]);
    w[11] = s * (2.0*m[13] + m[14]);
}

/// The box spline's first-derivative weights (`d/ds`, `d/dt`).
#[rustfmt::skip]
fn box_first(m: &[f64; 15], ws: &mut [f64; 12], wt: &mut [f64; 12]) {
    let s = 1.0 / 6.0;
    ws[0]  = s * (-1.0 + 3.0*m[2] + 3.0*m[3] - 3.0*m[5] - 2.0*m[6] - 3.0*m[7] + m[9]);
    ws[1]  = s * (1.0 - 3.0*m[2] - 6.0*m[3] + 3.0*m[5] + 4.0*m[6] + 6.0*m[7] - m[9]);
    ws[2]  = s * (3.0*m[3] - 2.0*m[6] - 3.0*m[7]);
    ws[3]  = s * (-2.0 + 6.0*m[1] + 3.0*m[2] - 6.0*m[3] - 6.0*m[4] + 2.0*m[6] + 3.0*m[7] - m[9]);
    ws[4]  = s * (-12.0*m[1] - 6.0*m[2] + 12.0*m[3] + 12.0*m[4] + 6.0*m[5] - 2.0*m[6] - 3.0*m[7] - m[9]);
    ws[5]  = s * (2.0 + 6.0*m[1] + 3.0*m[2] - 6.0*m[3] - 6.0*m[4] - 6.0*m[5] - 2.0*m[6] - 3.0*m[7] + 2.0*m[9]);
    ws[6]  = s * (2.0*m[6] + 3.0*m[7]);
    ws[7]  = s * (-1.0 - 3.0*m[2] + 3.0*m[3] + 6.0*m[4] - 2.0*m[6] - 3.0*m[7] + 2.0*m[9]);
    ws[8]  = s * (1.0 + 3.0*m[2] - 6.0*m[3] - 12.0*m[4] - 3.0*m[5] + 4.0*m[6] + 6.0*m[7] - m[9]);
    ws[9]  = s * (3.0*m[3] + 6.0*m[4] + 3.0*m[5] - 2.0*m[6] - 3.0*m[7] - m[9]);
    ws[10] = s * (-m[9]);
    ws[11] = s * m[9];

    wt[0]  = s * (-2.0 + 3.0*m[1] + 6.0*m[2] - 6.0*m[4] - 6.0*m[5] - m[6] + 3.0*m[8] + 2.0*m[9]);
    wt[1]  = s * (-1.0 - 3.0*m[1] + 6.0*m[4] + 3.0*m[5] + 2.0*m[6] - 3.0*m[8] - 2.0*m[9]);
    wt[2]  = s * (-m[6]);
    wt[3]  = s * (-1.0 + 3.0*m[1] - 3.0*m[3] + 3.0*m[5] + m[6] - 3.0*m[8] - 2.0*m[9]);
    wt[4]  = s * (-6.0*m[1] - 12.0*m[2] + 6.0*m[3] + 12.0*m[4] + 12.0*m[5] - m[6] - 3.0*m[8] - 2.0*m[9]);
    wt[5]  = s * (1.0 + 3.0*m[1] - 3.0*m[3] - 12.0*m[4] - 6.0*m[5] - m[6] + 6.0*m[8] + 4.0*m[9]);
    wt[6]  = s * m[6];
    wt[7]  = s * (1.0 - 3.0*m[1] + 3.0*m[3] - 6.0*m[5] - m[6] + 6.0*m[8] + 4.0*m[9]);
    wt[8]  = s * (2.0 + 3.0*m[1] + 6.0*m[2] - 6.0*m[3] - 6.0*m[4] - 6.0*m[5] + 2.0*m[6] - 3.0*m[8] - 2.0*m[9]);
    wt[9]  = s * (3.0*m[3] + 6.0*m[4] + 3.0*m[5] - m[6] - 3.0*m[8] - 2.0*m[9]);
    wt[10] = s * (3.0*m[5] - 3.0*m[8] - 2.0*m[9]);
    wt[11] = s * (3.0*m[8] + 2.0*m[9]);
}

/// The box spline's second-derivative weights (`d2/ds2`, `d2/dsdt`, `d2/dt2`).
#[rustfmt::skip]
fn box_second(m: &[f64; 15], wss: &mut [f64; 12], wst: &mut [f64; 12], wtt: &mut [f64; 12]) {
    wss[0]  = m[1] - m[3] - m[4];
    wss[1]  = -2.0*m[1] + 2.0*m[3] + 2.0*m[4];
    wss[2]  = m[1] - m[3] - m[4];
    wss[3]  = 1.0 - 2.0*m[1] - m[2] + m[3] + m[4];
    wss[4]  = -2.0 + 4.0*m[1] + 2.0*m[2] - m[3] - m[4];
    wss[5]  = 1.0 - 2.0*m[1] - m[2] - m[3] - m[4];
    wss[6]  = m[3] + m[4];
    wss[7]  = m[1] + m[2] - m[3] - m[4];
    wss[8]  = -2.0*m[1] - 2.0*m[2] + 2.0*m[3] + 2.0*m[4];
    wss[9]  = m[1] + m[2] - m[3] - m[4];
    wss[10] = 0.0;
    wss[11] = 0.0;

    wtt[0]  = 1.0 - m[1] - 2.0*m[2] + m[4] + m[5];
    wtt[1]  = m[1] + m[2] - m[4] - m[5];
    wtt[2]  = 0.0;
    wtt[3]  = m[2] - m[4] - m[5];
    wtt[4]  = -2.0 + 2.0*m[1] + 4.0*m[2] - m[4] - m[5];
    wtt[5]  = -2.0*m[1] - 2.0*m[2] + 2.0*m[4] + 2.0*m[5];
    wtt[6]  = 0.0;
    wtt[7]  = -2.0*m[2] + 2.0*m[4] + 2.0*m[5];
    wtt[8]  = 1.0 - m[1] - 2.0*m[2] - m[4] - m[5];
    wtt[9]  = m[1] + m[2] - m[4] - m[5];
    wtt[10] = m[2] - m[4] - m[5];
    wtt[11] = m[4] + m[5];

    let h = 0.5;
    wst[0]  = h * (1.0 - 2.0*m[2] - m[3] + m[5]);
    wst[1]  = h * (-1.0 + 2.0*m[2] + 2.0*m[3] - m[5]);
    wst[2]  = h * (-m[3]);
    wst[3]  = h * (1.0 - 2.0*m[1] + m[3] - m[5]);
    wst[4]  = h * (-2.0 + 4.0*m[1] + 4.0*m[2] - m[3] - m[5]);
    wst[5]  = h * (1.0 - 2.0*m[1] - 4.0*m[2] - m[3] + 2.0*m[5]);
    wst[6]  = h * m[3];
    wst[7]  = h * (-1.0 + 2.0*m[1] - m[3] + 2.0*m[5]);
    wst[8]  = h * (1.0 - 4.0*m[1] - 2.0*m[2] + 2.0*m[3] - m[5]);
    wst[9]  = h * (2.0*m[1] + 2.0*m[2] - m[3] - m[5]);
    wst[10] = h * (-m[5]);
    wst[11] = h * m[5];
}

/// The box spline weights at `(s, t)` with OpenSubdiv's 5-bit boundary mask folded in: the
/// low 3 bits are the infinitely sharp patch edges (edge `k` from corner `k` to `k + 1`); the
/// upper 2 bits say how to read them: 0 edges, 1 vertices (corner `k` on a sharp line that
/// runs along no patch edge), 2 one edge and its opposite vertex.
pub(crate) fn box_spline(s: f64, t: f64, boundary: u8, second: bool) -> Weights<12> {
    let m = monomials(s, t);
    let mut w = Weights::<12>::ZERO;
    box_value(&m, &mut w.p);
    box_first(&m, &mut w.ds, &mut w.dt);
    if second {
        box_second(&m, &mut w.dss, &mut w.dst, &mut w.dtt);
    }
    if boundary != 0 {
        w.each(second, |w| fold_box(boundary, w));
    }
    w
}

/// The boundary bits of [`box_spline`]: which patch edges and which corners carry a sharp line.
fn box_bits(mask: u8) -> (u8, u8) {
    let (upper, lower) = ((mask >> 3) & 3, mask & 7);
    match upper {
        1 => (0, lower),
        2 => (lower, ((lower & 1) << 2) | (lower >> 1)),
        _ => (lower, 0),
    }
}

/// Moves weight `from` onto the points of `plus` (each `+w`, `plus[k]` twice where listed
/// twice) and `minus` (`-w`), then clears it: a phantom point `p = a + b - c`.
#[inline]
fn fold(w: &mut [f64; 12], from: usize, a: usize, b: usize, c: usize) {
    let x = w[from];
    w[a] += x;
    w[b] += x;
    w[c] -= x;
}

/// OpenSubdiv's `adjustBoxSplineTriBoundaryWeights`: the three phantom points beyond each
/// sharp edge and the two beyond each sharp line through a corner, as `B1 + (B0 - I0)`-style
/// reflections of real points.
fn fold_box(mask: u8, w: &mut [f64; 12]) {
    let (e, v) = box_bits(mask);
    let (e0, e1, e2) = (e & 1 != 0, e & 2 != 0, e & 4 != 0);
    if e0 {
        if e2 {
            fold(w, 0, 4, 4, 8)
        } else {
            fold(w, 0, 4, 3, 7)
        }
        fold(w, 1, 4, 5, 8);
        if e1 {
            fold(w, 2, 5, 5, 8)
        } else {
            fold(w, 2, 5, 6, 9)
        }
        w[0] = 0.0;
        w[1] = 0.0;
        w[2] = 0.0;
    }
    if e1 {
        if e0 {
            fold(w, 6, 5, 5, 4)
        } else {
            fold(w, 6, 5, 2, 1)
        }
        fold(w, 9, 5, 8, 4);
        if e2 {
            fold(w, 11, 8, 8, 4)
        } else {
            fold(w, 11, 8, 10, 7)
        }
        w[6] = 0.0;
        w[9] = 0.0;
        w[11] = 0.0;
    }
    if e2 {
        if e1 {
            fold(w, 10, 8, 8, 5)
        } else {
            fold(w, 10, 8, 11, 9)
        }
        fold(w, 7, 8, 4, 5);
        if e0 {
            fold(w, 3, 4, 4, 5)
        } else {
            fold(w, 3, 4, 0, 1)
        }
        w[10] = 0.0;
        w[7] = 0.0;
        w[3] = 0.0;
    }
    if v & 1 != 0 {
        fold(w, 3, 4, 7, 8);
        fold(w, 0, 4, 1, 5);
        w[3] = 0.0;
        w[0] = 0.0;
    }
    if v & 2 != 0 {
        fold(w, 2, 5, 1, 4);
        fold(w, 6, 5, 9, 8);
        w[2] = 0.0;
        w[6] = 0.0;
    }
    if v & 4 != 0 {
        fold(w, 11, 8, 9, 5);
        fold(w, 10, 8, 7, 4);
        w[11] = 0.0;
        w[10] = 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both bases are partitions of unity (derivatives sum to zero), with and without folds,
    /// and reproduce linear functions with their exact derivatives.
    #[test]
    fn partition_of_unity_and_linear_precision() {
        let pts: Vec<(f64, f64)> = vec![(0.0, 0.0), (0.3, 0.6), (1.0, 0.0), (0.25, 0.25)];
        let quad_xy = |k: usize| ((k % 4) as f64 - 1.0, (k / 4) as f64 - 1.0);
        let tri_ij = [
            (0., -1.),
            (1., -1.),
            (2., -1.),
            (-1., 0.),
            (0., 0.),
            (1., 0.),
            (2., 0.),
            (-1., 1.),
            (0., 1.),
            (1., 1.),
            (-1., 2.),
            (0., 2.),
        ];
        for &(s, t) in &pts {
            for mask in [0u8, 1, 5, 15, 6] {
                let w = bspline(s, t, mask, true);
                let sum = |a: &[f64; 16]| a.iter().sum::<f64>();
                assert!((sum(&w.p) - 1.0).abs() < 1e-14);
                for a in [&w.ds, &w.dt, &w.dss, &w.dst, &w.dtt] {
                    assert!(sum(a).abs() < 1e-13);
                }
                // f = 2x - 3y + 1.
                let f = |k: usize| {
                    let (x, y) = quad_xy(k);
                    2.0 * x - 3.0 * y + 1.0
                };
                let val = |a: &[f64; 16]| (0..16).map(|k| a[k] * f(k)).sum::<f64>();
                assert!((val(&w.p) - (2.0 * s - 3.0 * t + 1.0)).abs() < 1e-13);
                assert!((val(&w.ds) - 2.0).abs() < 1e-13 && (val(&w.dt) + 3.0).abs() < 1e-13);
                assert!(val(&w.dss).abs() < 1e-12 && val(&w.dst).abs() < 1e-12);
            }
            if s + t > 1.0 {
                continue;
            }
            for mask in [0u8, 1, 2, 4, 3, 7, 8 + 1, 8 + 6, 16 + 1, 16 + 2] {
                let w = box_spline(s, t, mask, true);
                let f = |k: usize| 2.0 * tri_ij[k].0 - 3.0 * tri_ij[k].1 + 1.0;
                let val = |a: &[f64; 12]| (0..12).map(|k| a[k] * f(k)).sum::<f64>();
                assert!((w.p.iter().sum::<f64>() - 1.0).abs() < 1e-14, "{mask}");
                assert!(
                    (val(&w.p) - (2.0 * s - 3.0 * t + 1.0)).abs() < 1e-13,
                    "{mask}"
                );
                assert!((val(&w.ds) - 2.0).abs() < 1e-13 && (val(&w.dt) + 3.0).abs() < 1e-13);
                assert!(val(&w.dss).abs() < 1e-12 && val(&w.dtt).abs() < 1e-12);
            }
        }
    }

    /// The derivative weights are the derivatives of the value weights (central differences).
    #[test]
    fn derivatives_match_differences() {
        let h = 1e-5;
        for &(s, t) in &[(0.3, 0.4), (0.1, 0.7), (0.5, 0.2)] {
            for mask in [0u8, 9] {
                let w = bspline(s, t, mask, true);
                let (a, b) = (bspline(s + h, t, mask, true), bspline(s - h, t, mask, true));
                let (c, d) = (bspline(s, t + h, mask, true), bspline(s, t - h, mask, true));
                for k in 0..16 {
                    assert!(((a.p[k] - b.p[k]) / (2.0 * h) - w.ds[k]).abs() < 1e-8);
                    assert!(((c.p[k] - d.p[k]) / (2.0 * h) - w.dt[k]).abs() < 1e-8);
                    assert!(((a.ds[k] - b.ds[k]) / (2.0 * h) - w.dss[k]).abs() < 1e-7);
                    assert!(((c.ds[k] - d.ds[k]) / (2.0 * h) - w.dst[k]).abs() < 1e-7);
                    assert!(((c.dt[k] - d.dt[k]) / (2.0 * h) - w.dtt[k]).abs() < 1e-7);
                }
            }
            for mask in [0u8, 1, 8 + 2] {
                let w = box_spline(s, t, mask, true);
                let (a, b) = (
                    box_spline(s + h, t, mask, true),
                    box_spline(s - h, t, mask, true),
                );
                let (c, d) = (
                    box_spline(s, t + h, mask, true),
                    box_spline(s, t - h, mask, true),
                );
                for k in 0..12 {
                    assert!(((a.p[k] - b.p[k]) / (2.0 * h) - w.ds[k]).abs() < 1e-8);
                    assert!(((c.p[k] - d.p[k]) / (2.0 * h) - w.dt[k]).abs() < 1e-8);
                    assert!(((a.ds[k] - b.ds[k]) / (2.0 * h) - w.dss[k]).abs() < 1e-7);
                    assert!(((c.ds[k] - d.ds[k]) / (2.0 * h) - w.dst[k]).abs() < 1e-7);
                    assert!(((c.dt[k] - d.dt[k]) / (2.0 * h) - w.dtt[k]).abs() < 1e-7);
                }
            }
        }
    }
}
