//! Grid coordinates of a patch's sides: a depth-`d` patch is an `n x n` grid of quads
//! (`n = 2^d`) whose four sides run counter-clockwise from corner `k` to corner `k + 1`.

pub(super) use subdiv_slate::side_point;

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sides_round_trip() {
        for n in [1u32, 2, 4, 8] {
            let mut seen = 0;
            for j in 0..=n {
                for i in 0..=n {
                    if i > 0 && i < n && j > 0 && j < n {
                        continue;
                    }
                    seen += 1;
                    let (k, s) = side_of(i, j, n);
                    assert!(s < n, "corners start their side: ({i}, {j})");
                    assert_eq!(side_point(k, s, n), (i, j));
                    assert_eq!(side_of_on(k, i, j, n), (k, s));
                    // The end corner of a side has parameter n on it.
                    let (ei, ej) = side_point(k, n, n);
                    assert_eq!(side_of_on(k, ei, ej, n), (k, n));
                }
            }
            assert_eq!(seen, 4 * n, "border points of an {n}-grid");
        }
    }

    #[test]
    fn sides_run_counter_clockwise() {
        assert_eq!(side_point(0, 0, 4), (0, 0));
        assert_eq!(side_point(1, 0, 4), (4, 0));
        assert_eq!(side_point(2, 0, 4), (4, 4));
        assert_eq!(side_point(3, 0, 4), (0, 4));
        assert_eq!(side_point(3, 4, 4), (0, 0));
    }
}
