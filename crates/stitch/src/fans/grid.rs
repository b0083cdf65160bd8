//! Grid coordinates of a patch's sides: a depth-`d` patch is an `n x n` grid of quads
//! (`n = 2^d`) whose four sides run counter-clockwise from corner `k` to corner `k + 1`.

/// Grid coordinates of the point at parameter `s` along side `k` of an `n`-grid (sides run
/// counter-clockwise from corner `k` to corner `k + 1`).
#[inline]
pub(super) fn side_point(k: usize, s: u32, n: u32) -> (u32, u32) {
    match k {
        0 => (s, 0),
        1 => (n, s),
        2 => (n - s, n),
        _ => (0, n - s),
    }
}

/// Side and parameter of a border point (corners belong to the side they start).
#[inline]
pub(super) fn side_of(i: u32, j: u32, n: u32) -> (usize, u32) {
    if j == 0 && i < n {
        (0, i)
    } else if i == n && j < n {
        (1, j)
    } else if j == n && i > 0 {
        (2, n - i)
    } else {
        (3, n - j)
    }
}

/// Parameter of a point known to lie on side `k` (corners included, either end).
#[inline]
pub(super) fn side_of_on(k: usize, i: u32, j: u32, n: u32) -> (usize, u32) {
    match k {
        0 => (0, i),
        1 => (1, j),
        2 => (2, n - i),
        _ => (3, n - j),
    }
}
