//! The row loop of the separable regular step, written once for any [`SplitRows`] kernels:
//! the scalar rules of `subdiv-rules` ([`Scalar`]) or their AVX2 form
//! ([`wide::split`](crate::wide)), which give the same bits.

use glam::Vec3A;
use subdiv_rules::catmark;

/// The three row operations of the regular step, as `catmark::split_row`,
/// `catmark::split_rows_mid` and `catmark::split_rows_even` define them.
pub(crate) trait SplitRows {
    /// `catmark::split_row`.
    fn row(&self, row: &[Vec3A], out: &mut [Vec3A]);
    /// `catmark::split_rows_mid`.
    fn mid(&self, a: &[Vec3A], b: &[Vec3A], out: &mut [Vec3A]);
    /// `catmark::split_rows_even`.
    fn even(&self, a: &[Vec3A], b: &[Vec3A], c: &[Vec3A], out: &mut [Vec3A]);
}

/// The rules of `subdiv-rules` themselves.
pub(crate) struct Scalar;

impl SplitRows for Scalar {
    #[inline(always)]
    fn row(&self, row: &[Vec3A], out: &mut [Vec3A]) {
        catmark::split_row(row, out);
    }
    #[inline(always)]
    fn mid(&self, a: &[Vec3A], b: &[Vec3A], out: &mut [Vec3A]) {
        catmark::split_rows_mid(a, b, out);
    }
    #[inline(always)]
    fn even(&self, a: &[Vec3A], b: &[Vec3A], c: &[Vec3A], out: &mut [Vec3A]) {
        catmark::split_rows_even(a, b, c, out);
    }
}

/// The regular step's rows: the `ss x ss` source positions `src` into the `ds x ds` positions
/// `dst` (`ds = 2 ss - 3`) through three split rows of `ds` points in `split`.
///
/// Storage row y of dst is level coordinate y - 1: odd coordinates (even y) lie between split
/// rows r - 1 and r, even ones (odd y) at split row r - 1. The three slots hold split rows
/// r - 2, r - 1 and r, rotated after each source row.
#[inline(always)]
pub(crate) fn regular_rows<K: SplitRows>(
    k: &K,
    src: &[Vec3A],
    ss: usize,
    dst: &mut [Vec3A],
    ds: usize,
    split: &mut [Vec3A],
) {
    let (s0, rest) = split[..3 * ds].split_at_mut(ds);
    let (s1, s2) = rest.split_at_mut(ds);
    let mut slots: [&mut [Vec3A]; 3] = [s0, s1, s2];
    let mut rows = src[..ss * ss].chunks_exact(ss);
    let mut out = dst[..ds * ds].chunks_exact_mut(ds);
    if let (Some(r0), Some(r1)) = (rows.next(), rows.next()) {
        k.row(r0, slots[0]);
        k.row(r1, slots[1]);
        if let Some(o) = out.next() {
            k.mid(slots[0], slots[1], o);
        }
    }
    for row in rows {
        k.row(row, slots[2]);
        if let Some(o) = out.next() {
            k.even(slots[0], slots[1], slots[2], o);
        }
        if let Some(o) = out.next() {
            k.mid(slots[1], slots[2], o);
        }
        slots.rotate_left(1);
    }
}
