//! The interior limits of a slate eight points at a time (AVX2, `x86_64` only), bit for bit
//! what the scalar loop of [`Worker::limit_interior`](crate::worker::Worker) computes.
//!
//! The masks are the regular Catmull-Clark limit masks in their separable form (Settgast et al.
//! §3.2 evaluate them per grid point; `catmark::limit_row_sums` and
//! `catmark::limit_regular_from_sums` are the scalar definitions this kernel repeats). The data
//! is laid out SoA: each table row is transposed once (`x`, `y`, `z` arrays), its row sums are
//! formed in that layout, and every output row combines three rows of sums for eight points per
//! iteration, then interleaves the positions and normals back into the `[f32; 3]` output.
//!
//! **Invariant: the same bits as the scalar path.** Every lane performs the scalar path's IEEE
//! operations on the same operands in the same order (additions and products of two operands
//! commute exactly; no fused multiply-add is used, and Rust never contracts). A row of `m >= 8`
//! points is covered by blocks at `0, 8, 16, ...` and a last block at `m - 8`, which recomputes
//! (identically) the points it shares with the block before instead of masking; a row of seven
//! (grid size 8) takes one block whose eighth lane, the border point after the row, is computed
//! from the table's outer column and dropped. Shorter rows are the caller's (scalar) business.

use std::sync::atomic::{AtomicBool, Ordering};

use glam::Vec3A;

mod split;

pub(crate) use split::split_rows;

/// Whether the SIMD paths may be taken (see [`set_simd`]).
static SIMD: AtomicBool = AtomicBool::new(true);

/// Lets the slate tessellator take its SIMD paths where the CPU has them (`true`, the default)
/// or makes it take the scalar paths everywhere (`false`): for tests and measurements, since
/// the output is the same bits either way. Takes effect from the next patch; patches running
/// meanwhile may take either path.
pub fn set_simd(on: bool) {
    SIMD.store(on, Ordering::Relaxed);
}

/// Whether this CPU has AVX2 (detected once; `std` caches it).
#[inline]
fn cpu_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Whether the AVX2 paths run: the CPU has AVX2 and [`set_simd`] allows it.
#[inline]
pub(crate) fn available() -> bool {
    SIMD.load(Ordering::Relaxed) && cpu_avx2()
}

/// Floats of scratch [`interior_rows`] needs for grid size `n`.
pub(crate) fn scratch_len(n: usize) -> usize {
    6 * (n + 2) + 3 * 48 * n.saturating_sub(1).div_ceil(8)
}

/// Where the interior limits go: point `(i, j)`, `1 <= i, j <= n - 1`, at index
/// `first + (j - 1) * stride + (i - 1)` of `pos` and `nrm`.
pub(crate) struct InteriorOut<'a> {
    /// Limit positions.
    pub pos: &'a mut [[f32; 3]],
    /// Limit normals.
    pub nrm: &'a mut [[f32; 3]],
    /// Index of point `(1, 1)`.
    pub first: usize,
    /// Index distance between rows (at least `n - 1`).
    pub stride: usize,
}

impl InteriorOut<'_> {
    /// `true` if every interior point of a grid of size `n >= 2` lies inside both buffers.
    pub(crate) fn fits(&self, n: usize) -> bool {
        let m = n - 1;
        let end = self.first + (m - 1) * self.stride + m;
        self.stride >= m && end <= self.pos.len() && end <= self.nrm.len()
    }
}

/// The interior limits of the grid of size `n` whose table has row stride `stride` and holds
/// point `(i, j)` at `positions[(j + 1) * stride + i + 1]`, plus `origin`, into `out`; pushes onto
/// `bad` (in row order) the points whose tangents are degenerate (their output is left to the
/// caller to overwrite). Needs [`available`] and `n >= 8`; `scratch` holds at least
/// [`scratch_len`]`(n)` floats.
pub(crate) fn interior_rows(
    positions: &[Vec3A],
    stride: usize,
    n: usize,
    origin: Vec3A,
    scratch: &mut [f32],
    out: &mut InteriorOut<'_>,
    bad: &mut Vec<(i32, i32)>,
) {
    assert!(cpu_avx2(), "interior_rows needs AVX2");
    assert!(n >= 8 && stride >= n + 3, "grid too small for eight lanes");
    assert!(positions.len() >= (n + 2) * stride, "table too small");
    assert!(scratch.len() >= scratch_len(n), "scratch too small");
    assert!(out.fits(n), "output too small");
    #[cfg(target_arch = "x86_64")]
    // SAFETY: AVX2 is available (asserted), and the asserts above are the bounds
    // `avx2::interior_rows` relies on.
    unsafe {
        avx2::interior_rows(positions, stride, n, origin, scratch, out, bad)
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::*;

    use glam::Vec3A;

    use super::InteriorOut;

    /// Block starts covering `0..len` (`len >= 8`) with eight lanes: `0, 8, ...`, the last at
    /// `len - 8`.
    #[inline(always)]
    fn blocks(len: usize) -> impl Iterator<Item = usize> {
        (0..len.div_ceil(8)).map(move |b| (b * 8).min(len - 8))
    }

    /// Transposes the `len >= 8` points at `src` into `x`, `y`, `z`.
    ///
    /// # Safety
    /// AVX2; `src` readable for `len` points (16-byte aligned, as `Vec3A` is), `x`, `y`, `z`
    /// writable for `len` floats.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn transpose(src: *const Vec3A, len: usize, x: *mut f32, y: *mut f32, z: *mut f32) {
        for s in blocks(len) {
            // SAFETY: `s + 8 <= len`: every access lies in the ranges the caller guarantees.
            unsafe {
                let p = src.add(s) as *const f32;
                let pair = |a: usize| {
                    let lo = _mm_load_ps(p.add(4 * a));
                    let hi = _mm_load_ps(p.add(4 * (a + 4)));
                    _mm256_insertf128_ps::<1>(_mm256_castps128_ps256(lo), hi)
                };
                // [p0 | p4], [p1 | p5], [p2 | p6], [p3 | p7], then a 4x4 transpose per lane.
                let (r0, r1, r2, r3) = (pair(0), pair(1), pair(2), pair(3));
                let t0 = _mm256_unpacklo_ps(r0, r1);
                let t1 = _mm256_unpacklo_ps(r2, r3);
                let t2 = _mm256_unpackhi_ps(r0, r1);
                let t3 = _mm256_unpackhi_ps(r2, r3);
                _mm256_storeu_ps(x.add(s), _mm256_shuffle_ps::<0b01_00_01_00>(t0, t1));
                _mm256_storeu_ps(y.add(s), _mm256_shuffle_ps::<0b11_10_11_10>(t0, t1));
                _mm256_storeu_ps(z.add(s), _mm256_shuffle_ps::<0b01_00_01_00>(t2, t3));
            }
        }
    }

    /// Floats of one block of row sums: `b` x, y, z then `a` x, y, z, eight lanes each.
    const BLOCK: usize = 48;

    /// Block starts of the row sums and limits of a row of `cnt >= 7` interior points:
    /// [`blocks`], and for seven points the one block at 0 (its eighth lane is dropped).
    #[inline(always)]
    fn sum_blocks(cnt: usize) -> impl Iterator<Item = usize> {
        (0..cnt.div_ceil(8)).map(move |b| (b * 8).min(cnt.max(8) - 8))
    }

    /// Table row `j` transposed into `px` (`x`, `y`, `z`, `n + 2` floats each: columns `0` to
    /// `n + 1`).
    ///
    /// # Safety
    /// AVX2; the bounds of [`interior_rows`]; `px` writable for `3 * (n + 2)` floats.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn transpose_row(positions: &[Vec3A], stride: usize, n: usize, j: usize, px: *mut f32) {
        let len = n + 2;
        // SAFETY: row `j <= n + 1` of the table spans `(j + 1) * stride + 1 ..= + n + 1`, inside
        // `positions` (`(n + 2) * stride` points, `stride >= n + 3`).
        unsafe {
            let src = positions.as_ptr().add((j + 1) * stride + 1);
            transpose(src, len, px, px.add(len), px.add(2 * len));
        }
    }

    /// `catmark::limit_row_sums` of the transposed row `px`, by blocks: block `k` (the points
    /// of `sum_blocks(n - 1)`'s `k`-th start) at `sums + k * BLOCK`, each coordinate's
    /// `b = (w[i] + w[i + 2]) + w[i + 1] * 4` and `a = w[i + 2] - w[i]`.
    ///
    /// The loads are unaligned, so they must not read a row transposed just before: a load
    /// that straddles two recent stores waits for them to leave the store buffer (on the
    /// pawn at depth 5 that stall was a sixth of the kernel's cycles).
    ///
    /// # Safety
    /// AVX2; `n >= 8`; `px` readable for `3 * (n + 2)` floats, `sums` writable for
    /// `BLOCK * (n - 1).div_ceil(8)`.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn row_sums(px: *const f32, n: usize, sums: *mut f32) {
        let (len, cnt) = (n + 2, n - 1);
        let four = _mm256_set1_ps(4.0);
        // SAFETY: block starts `s <= cnt.max(8) - 8 <= n - 8` read `px` below
        // `c * len + s + 10 <= (c + 1) * len` and write block `k < cnt.div_ceil(8)`.
        unsafe {
            for (k, s) in sum_blocks(cnt).enumerate() {
                let out = sums.add(k * BLOCK);
                for c in 0..3 {
                    let w = px.add(c * len + s);
                    let w0 = _mm256_loadu_ps(w);
                    let w1 = _mm256_loadu_ps(w.add(1));
                    let w2 = _mm256_loadu_ps(w.add(2));
                    let b = _mm256_add_ps(_mm256_add_ps(w0, w2), _mm256_mul_ps(w1, four));
                    _mm256_storeu_ps(out.add(8 * c), b);
                    _mm256_storeu_ps(out.add(8 * (3 + c)), _mm256_sub_ps(w2, w0));
                }
            }
        }
    }

    /// Interleaves eight points given as `x`, `y`, `z` into 24 floats at `dst`.
    ///
    /// # Safety
    /// AVX2; `dst` writable for 24 floats.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn store3(dst: *mut f32, x: __m256, y: __m256, z: __m256) {
        // Each permuted vector holds in every lane the element that lane takes in one of the
        // three outputs (x y z x y z x y | z x y z x y z x | y z x y z x y z).
        let xp = _mm256_permutevar8x32_ps(x, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5));
        let yp = _mm256_permutevar8x32_ps(y, _mm256_setr_epi32(5, 0, 3, 6, 1, 4, 7, 2));
        let zp = _mm256_permutevar8x32_ps(z, _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
        let o0 = _mm256_blend_ps::<0x24>(_mm256_blend_ps::<0x92>(xp, yp), zp);
        let o1 = _mm256_blend_ps::<0x49>(_mm256_blend_ps::<0x24>(xp, yp), zp);
        let o2 = _mm256_blend_ps::<0x92>(_mm256_blend_ps::<0x49>(xp, yp), zp);
        // SAFETY: 24 floats at `dst` are writable (the caller's guarantee).
        unsafe {
            _mm256_storeu_ps(dst, o0);
            _mm256_storeu_ps(dst.add(8), o1);
            _mm256_storeu_ps(dst.add(16), o2);
        }
    }

    /// Positions and normals of the block of row sums at `s0`, `s1`, `s2` (table rows
    /// `j - 1`, `j`, `j + 1`) into `pos` and `nrm` (24 floats each), and the mask of its lanes
    /// with non-degenerate tangents.
    ///
    /// # Safety
    /// AVX2; `s0`, `s1`, `s2` readable for `BLOCK` floats, `pos` and `nrm` writable for 24.
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn limit_block(
        s: [*const f32; 3],
        origin: [__m256; 3],
        pos: *mut f32,
        nrm: *mut f32,
    ) -> u32 {
        // SAFETY: every load lies in the `BLOCK` floats at `s[0]`, `s[1]`, `s[2]`.
        let ld = |r: usize, c: usize| unsafe { _mm256_loadu_ps(s[r].add(8 * c)) };
        let four = _mm256_set1_ps(4.0);
        // `catmark::limit_regular_from_sums` per coordinate, tangents first (fewer live
        // registers): `t1 = (a0 + a2) + a1 * 4`, `t2 = b2 - b0`.
        let t1 = |c: usize| {
            let a = _mm256_add_ps(ld(0, 3 + c), ld(2, 3 + c));
            _mm256_add_ps(a, _mm256_mul_ps(ld(1, 3 + c), four))
        };
        let t2 = |c: usize| _mm256_sub_ps(ld(2, c), ld(0, c));
        let (ux, uy, uz) = (t1(0), t1(1), t1(2));
        let (vx, vy, vz) = (t2(0), t2(1), t2(2));
        // `t1.cross(t2)` and its squared length, as glam orders them.
        let cx = _mm256_sub_ps(_mm256_mul_ps(uy, vz), _mm256_mul_ps(uz, vy));
        let cy = _mm256_sub_ps(_mm256_mul_ps(uz, vx), _mm256_mul_ps(ux, vz));
        let cz = _mm256_sub_ps(_mm256_mul_ps(ux, vy), _mm256_mul_ps(uy, vx));
        let len2 = _mm256_add_ps(
            _mm256_add_ps(_mm256_mul_ps(cx, cx), _mm256_mul_ps(cy, cy)),
            _mm256_mul_ps(cz, cz),
        );
        // `0 < len2 <= f32::MAX` (false for NaN): the scalar path's bit test.
        let ok = _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GT_OQ>(len2, _mm256_setzero_ps()),
            _mm256_cmp_ps::<_CMP_LE_OQ>(len2, _mm256_set1_ps(f32::MAX)),
        );
        let r = _mm256_div_ps(_mm256_set1_ps(1.0), _mm256_sqrt_ps(len2));
        // SAFETY: 24 floats at `nrm` and at `pos` (the caller's guarantee).
        unsafe {
            store3(
                nrm,
                _mm256_mul_ps(cx, r),
                _mm256_mul_ps(cy, r),
                _mm256_mul_ps(cz, r),
            )
        };
        // `((b0 + b2) + b1 * 4) * (1 / 36) + origin`.
        let inv36 = _mm256_set1_ps((1.0f64 / 36.0) as f32);
        let p = |c: usize| {
            let b = _mm256_add_ps(ld(0, c), ld(2, c));
            let b = _mm256_add_ps(b, _mm256_mul_ps(ld(1, c), four));
            _mm256_add_ps(_mm256_mul_ps(b, inv36), origin[c])
        };
        // SAFETY: as above.
        unsafe { store3(pos, p(0), p(1), p(2)) };
        _mm256_movemask_ps(ok) as u32
    }

    /// See [`super::interior_rows`].
    ///
    /// # Safety
    /// AVX2; `n >= 8`, `stride >= n + 3`, `positions.len() >= (n + 2) * stride`,
    /// `scratch.len() >= scratch_len(n)`, `out.fits(n)`.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn interior_rows(
        positions: &[Vec3A],
        stride: usize,
        n: usize,
        origin: Vec3A,
        scratch: &mut [f32],
        out: &mut InteriorOut<'_>,
        bad: &mut Vec<(i32, i32)>,
    ) {
        let cnt = n - 1;
        let base = scratch.as_mut_ptr();
        // Scratch: two transposed table rows (`3 * (n + 2)` floats each; row `r` goes to
        // `px[r % 2]`, transposed one output row before its sums are formed), then three slots
        // of row sums (`BLOCK * cnt.div_ceil(8)` floats each), `scratch_len(n)` in all.
        let slot_len = BLOCK * cnt.div_ceil(8);
        // SAFETY: offsets inside the scratch (see above).
        let px = [0, 1].map(|b| unsafe { base.add(3 * (n + 2) * b) });
        // SAFETY: as above.
        let mut slots = [0, 1, 2].map(|s| unsafe { base.add(6 * (n + 2) + slot_len * s) });
        // SAFETY: the caller's bounds; rows 0, 1 and 2 exist (`n >= 8`).
        unsafe {
            transpose_row(positions, stride, n, 0, px[0]);
            transpose_row(positions, stride, n, 1, px[1]);
            row_sums(px[0], n, slots[0]);
            transpose_row(positions, stride, n, 2, px[0]);
            row_sums(px[1], n, slots[1]);
        }
        let o = [origin.x, origin.y, origin.z].map(|c| _mm256_set1_ps(c));
        let pos = out.pos.as_mut_ptr() as *mut f32;
        let nrm = out.nrm.as_mut_ptr() as *mut f32;
        for j in 1..n {
            // SAFETY: table rows `j + 1 <= n` (transposed last iteration) and `j + 2`
            // (into the buffer of row `j`, whose sums are formed); the slot holds `slot_len`
            // floats.
            unsafe {
                row_sums(px[(j + 1) % 2], n, slots[2]);
                if j + 2 <= n {
                    transpose_row(positions, stride, n, j + 2, px[j % 2]);
                }
            }
            let row = out.first + (j - 1) * out.stride;
            // Lanes below `checked` were tested by an earlier block of this row.
            let mut checked = 0;
            for (k, x) in sum_blocks(cnt).enumerate() {
                let at = k * BLOCK;
                let i = 3 * (row + x);
                // SAFETY: block `k` lies in each slot.
                let s = unsafe { [slots[0].add(at), slots[1].add(at), slots[2].add(at)] };
                let s = s.map(|p| p as *const f32);
                let mask = if cnt >= 8 {
                    // SAFETY: the output points `row + x .. + 8` lie in the row
                    // (`x + 8 <= cnt`), inside the buffers (`out.fits(n)`).
                    unsafe { limit_block(s, o, pos.add(i), nrm.add(i)) }
                } else {
                    // Seven points: eight lanes into a buffer, the first seven copied out.
                    let (mut p8, mut n8) = ([0.0f32; 24], [0.0f32; 24]);
                    // SAFETY: 24 floats each in `p8` and `n8`; the output points `row ..
                    // row + cnt` lie inside the buffers (`out.fits(n)`).
                    unsafe {
                        let mask = limit_block(s, o, p8.as_mut_ptr(), n8.as_mut_ptr());
                        std::ptr::copy_nonoverlapping(p8.as_ptr(), pos.add(i), 3 * cnt);
                        std::ptr::copy_nonoverlapping(n8.as_ptr(), nrm.add(i), 3 * cnt);
                        (mask | (0xff << cnt)) & 0xff
                    }
                };
                if mask != 0xff {
                    for l in 0..8 {
                        if mask & (1 << l) == 0 && x + l >= checked {
                            bad.push((x as i32 + l as i32 + 1, j as i32));
                        }
                    }
                }
                checked = x + 8;
            }
            slots.rotate_left(1);
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3A;

    use super::*;
    use crate::worker::Worker;

    use subdiv_test_support::Rng;

    /// A table of grid size `n` whose points lie on a bumpy surface of scale `scale`, with some
    /// exceptional points (`kind`): coincident rows (zero tangents), overflowing and NaN ones.
    fn fill(w: &mut Worker, n: usize, scale: f32, kind: u32, rng: &mut Rng) {
        let t = &mut w.t[w.cur];
        t.grid_size = n;
        t.stride = n + 3;
        for j in 0..n + 3 {
            for i in 0..n + 3 {
                let (x, y) = (i as f32, j as f32);
                let z = rng.next_f32() - 0.5;
                let mut p = Vec3A::new(x + 0.3 * z, y - 0.2 * z, z * z) * scale;
                match kind {
                    // Three coincident rows: degenerate tangents below, at and above them.
                    1 if (5..8).contains(&j) => p = Vec3A::splat(scale),
                    // A flat patch: tangents exactly in the plane.
                    2 => p.z = 0.0,
                    3 if rng.next_f32() < 0.02 => p.x = 3.0e38,
                    4 if rng.next_f32() < 0.02 => p.y = f32::NAN,
                    _ => {}
                }
                t.positions[j * t.stride + i] = p;
            }
        }
        w.origin32 = Vec3A::new(rng.next_f32(), -rng.next_f32(), 100.0 * rng.next_f32()) * scale;
    }

    #[test]
    fn eight_lanes_equal_the_scalar_loop_bit_for_bit() {
        if !cpu_avx2() {
            eprintln!("no AVX2 on this CPU: the wide path is not used, nothing to compare");
            return;
        }
        let mut w = Worker::new(5);
        let mut rng = Rng::xorshift_star(0x9e37_79b9_7f4a_7c15);
        let mut scratch = vec![0.0; scratch_len(32)];
        let mut cases = 0;
        for n in 8..=32 {
            for (kind, scale) in [
                (0, 1.0),
                (0, 1e-6),
                (0, 3e-12),
                (0, 1e6),
                (1, 1.0),
                (2, 0.5),
            ]
            .into_iter()
            .chain([(3, 1.0), (4, 1.0)])
            {
                fill(&mut w, n, scale, kind, &mut rng);
                let (m, stride) = (n - 1, n + 2);
                let len = (m - 1) * stride + m + 3;
                let mut buf = [vec![[0.0f32; 3]; len], vec![[0.0f32; 3]; len]];
                let mut wide = [vec![[0.0f32; 3]; len], vec![[0.0f32; 3]; len]];
                let (mut bad, mut bad_wide) = (Vec::new(), Vec::new());
                let [p, q] = &mut buf;
                let mut out = InteriorOut {
                    pos: p,
                    nrm: q,
                    first: 3,
                    stride,
                };
                w.limit_interior_scalar(&mut out, &mut bad);
                let [p, q] = &mut wide;
                let mut out = InteriorOut {
                    pos: p,
                    nrm: q,
                    first: 3,
                    stride,
                };
                let t = &w.t[w.cur];
                let o = w.origin32;
                interior_rows(
                    &t.positions,
                    t.stride,
                    n,
                    o,
                    &mut scratch,
                    &mut out,
                    &mut bad_wide,
                );
                assert_eq!(bad, bad_wide, "n {n} kind {kind} scale {scale}");
                if kind == 1 {
                    assert!(!bad.is_empty(), "coincident rows give degenerate tangents");
                }
                // Points the scalar loop wrote (not degenerate) carry the same bits; nothing
                // outside the interior rows is written.
                for k in 0..len {
                    let (i, j) = ((k + stride - 3) % stride + 1, (k + stride - 3) / stride);
                    let interior = k >= 3 && i <= m && j >= 1 && j <= m;
                    let skip = interior && bad.contains(&(i as i32, j as i32));
                    if !interior {
                        assert_eq!(wide[0][k], [0.0; 3], "n {n} index {k} written");
                    } else if !skip {
                        let bits = |v: [f32; 3]| v.map(f32::to_bits);
                        assert_eq!(bits(buf[0][k]), bits(wide[0][k]), "n {n} ({i}, {j})");
                        assert_eq!(bits(buf[1][k]), bits(wide[1][k]), "n {n} ({i}, {j})");
                        cases += 1;
                    }
                }
            }
        }
        assert!(cases > 10_000, "{cases} points compared");
    }
}
