//! Grid coordinates of a patch's sides: a depth-`d` patch is an `n x n` grid of quads
//! (`n = 2^d`) whose four sides run counter-clockwise from corner `k` to corner `k + 1`. The one
//! home of that convention for the slates and for `subdiv-stitch`'s fans.

/// Grid coordinates of the point at parameter `s` along side `k` of an `n`-grid (sides run
/// counter-clockwise from corner `k` to corner `k + 1`).
#[inline]
pub fn side_point(k: usize, s: u32, n: u32) -> (u32, u32) {
    match k {
        0 => (s, 0),
        1 => (n, s),
        2 => (n - s, n),
        _ => (0, n - s),
    }
}
