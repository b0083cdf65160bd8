//! The regular step's row operations two points per AVX2 register: a `Vec3A` fills half of one,
//! so the AoS rows of the table are processed as they are, without transposition, and every
//! lane does the scalar rule's operations in its order (the same bits, `w` lane included).

use glam::Vec3A;

/// The regular step's rows (see `step::rows::regular_rows`) with the AVX2 kernels; `false`
/// (nothing done) on a CPU without AVX2.
pub(crate) fn split_rows(
    src: &[Vec3A],
    ss: usize,
    dst: &mut [Vec3A],
    ds: usize,
    split: &mut [Vec3A],
) -> bool {
    if !super::available() {
        return false;
    }
    #[cfg(target_arch = "x86_64")]
    // SAFETY: AVX2 is available (checked above).
    unsafe {
        avx2::step(src, ss, dst, ds, split)
    };
    true
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::*;

    use glam::Vec3A;

    use crate::step::rows::{SplitRows, regular_rows};

    /// Proof that AVX2 is available: made only inside [`step`], whose caller guarantees it.
    pub(super) struct Avx2(());

    /// `step::rows::regular_rows` with [`Avx2`]'s kernels.
    ///
    /// # Safety
    /// AVX2.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn step(
        src: &[Vec3A],
        ss: usize,
        dst: &mut [Vec3A],
        ds: usize,
        split: &mut [Vec3A],
    ) {
        regular_rows(&Avx2(()), src, ss, dst, ds, split);
    }

    const HALF: f32 = 0.5;
    const SIX: f32 = 6.0;
    const EIGHTH: f32 = 0.125;

    /// `catmark::split_row` of the `l >= 3` points at `p` into `2 l - 3` at `o`.
    ///
    /// # Safety
    /// AVX2; `p` readable for `4 l` floats, `o` writable for `4 (2 l - 3)`.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn split_row(p: *const f32, l: usize, o: *mut f32) {
        let (half, six, eighth) = (
            _mm256_set1_ps(HALF),
            _mm256_set1_ps(SIX),
            _mm256_set1_ps(EIGHTH),
        );
        let windows = l - 2;
        let mut k = 0;
        // SAFETY (every block): window `k` reads points `k ..= k + 2 <= l - 1` and writes
        // outputs `2 k`, `2 k + 1 <= 2 l - 5`; two windows at once read up to point `k + 3`
        // and write up to output `2 k + 3` (`k + 2 <= windows`); the last output is `2 l - 4`.
        while k + 2 <= windows {
            // SAFETY: windows `k`, `k + 1` (see above).
            unsafe {
                let a = _mm256_loadu_ps(p.add(4 * k));
                let b = _mm256_loadu_ps(p.add(4 * k + 4));
                let c = _mm256_loadu_ps(p.add(4 * k + 8));
                // Edge points `(w0 + w1) / 2` and vertex points `((w0 + w2) + 6 w1) / 8` of
                // windows `k` and `k + 1`, then interleaved.
                let e = _mm256_mul_ps(_mm256_add_ps(a, b), half);
                let v = _mm256_add_ps(_mm256_add_ps(a, c), _mm256_mul_ps(b, six));
                let v = _mm256_mul_ps(v, eighth);
                _mm256_storeu_ps(o.add(8 * k), _mm256_permute2f128_ps::<0x20>(e, v));
                _mm256_storeu_ps(o.add(8 * k + 8), _mm256_permute2f128_ps::<0x31>(e, v));
            }
            k += 2;
        }
        let (half, six, eighth) = (_mm_set1_ps(HALF), _mm_set1_ps(SIX), _mm_set1_ps(EIGHTH));
        if k < windows {
            // SAFETY: window `k` (see above).
            unsafe {
                let a = _mm_loadu_ps(p.add(4 * k));
                let b = _mm_loadu_ps(p.add(4 * k + 4));
                let c = _mm_loadu_ps(p.add(4 * k + 8));
                let v = _mm_add_ps(_mm_add_ps(a, c), _mm_mul_ps(b, six));
                _mm_storeu_ps(o.add(8 * k), _mm_mul_ps(_mm_add_ps(a, b), half));
                _mm_storeu_ps(o.add(8 * k + 4), _mm_mul_ps(v, eighth));
            }
        }
        // SAFETY: points `l - 2`, `l - 1`, output `2 l - 4` (see above).
        unsafe {
            let a = _mm_loadu_ps(p.add(4 * (l - 2)));
            let b = _mm_loadu_ps(p.add(4 * (l - 1)));
            _mm_storeu_ps(o.add(4 * (2 * l - 4)), _mm_mul_ps(_mm_add_ps(a, b), half));
        }
    }

    /// `out[i] = f(a[i], b[i], c[i])` over `len` points, two at a time, for an `f` made of
    /// lane-wise operations (the same in 128 and 256 bits).
    ///
    /// # Safety
    /// AVX2; `a`, `b`, `c` readable and `o` writable for `4 len` floats.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn lanes(
        a: *const f32,
        b: *const f32,
        c: *const f32,
        o: *mut f32,
        len: usize,
        f8: impl Fn(__m256, __m256, __m256) -> __m256,
        f4: impl Fn(__m128, __m128, __m128) -> __m128,
    ) {
        let mut i = 0;
        // SAFETY (every block): points `i .. i + 4 <= len`, then `i`, `i + 1 < len`, then the
        // last one, `i < len`.
        while i + 4 <= len {
            // SAFETY: points `i .. i + 4` (see above).
            unsafe {
                for h in [0, 2] {
                    let (x, y, z) = (
                        _mm256_loadu_ps(a.add(4 * (i + h))),
                        _mm256_loadu_ps(b.add(4 * (i + h))),
                        _mm256_loadu_ps(c.add(4 * (i + h))),
                    );
                    _mm256_storeu_ps(o.add(4 * (i + h)), f8(x, y, z));
                }
            }
            i += 4;
        }
        if i + 2 <= len {
            // SAFETY: points `i`, `i + 1` (see above).
            unsafe {
                let (x, y, z) = (
                    _mm256_loadu_ps(a.add(4 * i)),
                    _mm256_loadu_ps(b.add(4 * i)),
                    _mm256_loadu_ps(c.add(4 * i)),
                );
                _mm256_storeu_ps(o.add(4 * i), f8(x, y, z));
            }
            i += 2;
        }
        if i < len {
            // SAFETY: point `i` (see above).
            unsafe {
                let (x, y, z) = (
                    _mm_loadu_ps(a.add(4 * i)),
                    _mm_loadu_ps(b.add(4 * i)),
                    _mm_loadu_ps(c.add(4 * i)),
                );
                _mm_storeu_ps(o.add(4 * i), f4(x, y, z));
            }
        }
    }

    impl SplitRows for Avx2 {
        #[inline(always)]
        fn row(&self, row: &[Vec3A], out: &mut [Vec3A]) {
            let l = row.len();
            assert!(
                l >= 3 && out.len() + 3 == 2 * l,
                "split_row: output must hold 2 * len - 3 points"
            );
            // SAFETY: `Avx2` exists only where AVX2 does; lengths as `split_row` needs them.
            unsafe { split_row(row.as_ptr().cast(), l, out.as_mut_ptr().cast()) }
        }

        #[inline(always)]
        fn mid(&self, a: &[Vec3A], b: &[Vec3A], out: &mut [Vec3A]) {
            let len = out.len().min(a.len()).min(b.len());
            let (pa, pb) = (a.as_ptr().cast(), b.as_ptr().cast());
            // `(a + b) / 2`. SAFETY: AVX2 (the token); `len` points in every slice.
            unsafe {
                lanes(
                    pa,
                    pb,
                    pb,
                    out.as_mut_ptr().cast(),
                    len,
                    |a, b, _| _mm256_mul_ps(_mm256_add_ps(a, b), _mm256_set1_ps(HALF)),
                    |a, b, _| _mm_mul_ps(_mm_add_ps(a, b), _mm_set1_ps(HALF)),
                )
            }
        }

        #[inline(always)]
        fn even(&self, a: &[Vec3A], b: &[Vec3A], c: &[Vec3A], out: &mut [Vec3A]) {
            let len = out.len().min(a.len()).min(b.len()).min(c.len());
            // `((a + c) + 6 b) / 8`. SAFETY: AVX2 (the token); `len` points in every slice.
            unsafe {
                lanes(
                    a.as_ptr().cast(),
                    b.as_ptr().cast(),
                    c.as_ptr().cast(),
                    out.as_mut_ptr().cast(),
                    len,
                    |a, b, c| {
                        let s = _mm256_add_ps(
                            _mm256_add_ps(a, c),
                            _mm256_mul_ps(b, _mm256_set1_ps(SIX)),
                        );
                        _mm256_mul_ps(s, _mm256_set1_ps(EIGHTH))
                    },
                    |a, b, c| {
                        let s = _mm_add_ps(_mm_add_ps(a, c), _mm_mul_ps(b, _mm_set1_ps(SIX)));
                        _mm_mul_ps(s, _mm_set1_ps(EIGHTH))
                    },
                )
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3A;

    use super::*;
    use crate::step::rows::{Scalar, regular_rows};

    #[test]
    fn two_points_per_register_equal_the_scalar_rules_bit_for_bit() {
        if !super::super::cpu_avx2() {
            eprintln!("no AVX2 on this CPU: the wide path is not used, nothing to compare");
            return;
        }
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f32 / (1u64 << 24) as f32 - 0.5
        };
        // Every source stride a table has (`n + 3`, n = 1..=32) and odd ones between.
        for ss in 4..=35 {
            let ds = 2 * ss - 3;
            for scale in [1.0f32, 3.7e-3, 1.9e7] {
                let src: Vec<Vec3A> = (0..ss * ss)
                    .map(|k| {
                        let (i, j) = ((k % ss) as f32, (k / ss) as f32);
                        Vec3A::new(i + next(), j + next(), next()) * scale
                    })
                    .collect();
                let mut want = vec![Vec3A::ZERO; ds * ds];
                let mut got = vec![Vec3A::splat(f32::NAN); ds * ds];
                let mut split = vec![Vec3A::ZERO; 3 * ds];
                regular_rows(&Scalar, &src, ss, &mut want, ds, &mut split);
                assert!(split_rows(&src, ss, &mut got, ds, &mut split));
                for (k, (w, g)) in want.iter().zip(&got).enumerate() {
                    let bits = |v: &Vec3A| v.to_array().map(f32::to_bits);
                    assert_eq!(bits(w), bits(g), "stride {ss} scale {scale} point {k}");
                }
            }
        }
    }
}
