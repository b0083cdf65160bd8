//! How far two tessellations of the same surface with the same points lie apart: what a path
//! that agrees with another to rounding (not to the bit) is checked with.

/// The largest distance between corresponding points of `a` and `b` over `size` (the cage's
/// size), and the largest angle (radians) between corresponding normals where both are
/// non-zero; a normal zero in one and not in the other counts as `PI`.
pub fn max_deviation(
    (a_pos, a_nrm): (&[[f32; 3]], &[[f32; 3]]),
    (b_pos, b_nrm): (&[[f32; 3]], &[[f32; 3]]),
    size: f32,
) -> (f32, f32) {
    assert_eq!(a_pos.len(), b_pos.len(), "point counts differ");
    assert_eq!(a_nrm.len(), b_nrm.len(), "normal counts differ");
    let sub = |p: &[f32; 3], q: &[f32; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let dot = |p: &[f32; 3], q: &[f32; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    let mut dist = 0.0f32;
    for (p, q) in a_pos.iter().zip(b_pos) {
        let d = sub(p, q);
        dist = dist.max(dot(&d, &d).sqrt() / size);
    }
    // Angles as atan2(|n x m|, n . m) in f64: exact near zero (an acos of an f32 dot is
    // no finer than 5e-4 there).
    let mut angle = 0.0f64;
    for (n, m) in a_nrm.iter().zip(b_nrm) {
        let (n, m) = (n.map(f64::from), m.map(f64::from));
        let c = [
            n[1] * m[2] - n[2] * m[1],
            n[2] * m[0] - n[0] * m[2],
            n[0] * m[1] - n[1] * m[0],
        ];
        let zero = |v: &[f64; 3]| v.iter().all(|&x| x == 0.0);
        let a = match (zero(&n), zero(&m)) {
            (false, false) => {
                let sin = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
                sin.atan2(n[0] * m[0] + n[1] * m[1] + n[2] * m[2])
            }
            (true, true) => 0.0,
            _ => std::f64::consts::PI,
        };
        angle = angle.max(a);
    }
    (dist, angle as f32)
}
