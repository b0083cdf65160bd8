//! One frame: every block's sums over its face's support, eight points at a time, and the unit
//! normals `du x dv`.
//!
//! The sums run in registers of eight lanes (one point each): per support vertex, nine
//! multiply-adds (position, `d/du` and `d/dv`, three coordinates each) against the vertex's
//! coordinates broadcast. Where the CPU has AVX2 and FMA (detected once, at run time) the same
//! code is compiled for them and the multiply-adds are fused; elsewhere they are a product and
//! a sum, so the last bits of a point may differ between the two kinds of CPU (not between
//! runs, thread counts or frames on one machine).

use std::sync::OnceLock;

use glam::Vec3;
use rayon::prelude::*;
use subdiv_mesh::Mesh;

use crate::StencilError;
use crate::table::{BLOCK_FLOATS, Group, LANES, NO_POINT, StencilTable};

/// Groups one task takes at least (a face's points are a few dozen: tasks of a few hundred).
const MIN_GROUPS_PER_TASK: usize = 16;

/// The frame's output, written through raw pointers by the tasks: every point is the target of
/// exactly one lane of one block (the table's targets are distinct, checked in range before).
struct Out {
    pos: *mut [f32; 3],
    nrm: *mut [f32; 3],
}

// SAFETY: tasks write disjoint elements (distinct targets) of buffers that outlive them.
unsafe impl Sync for Out {}
// SAFETY: as above.
unsafe impl Send for Out {}

#[cfg(test)]
thread_local! {
    /// Tests run the portable kernel too (this machine's CPU may have AVX2 and FMA): set on
    /// the thread that calls `apply`, which decides the kernel for the frame.
    pub(crate) static PORTABLE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether the fused AVX2 kernel runs here.
fn fused() -> bool {
    static FUSED: OnceLock<bool> = OnceLock::new();
    #[cfg(test)]
    if PORTABLE.with(|p| p.get()) {
        return false;
    }
    *FUSED.get_or_init(|| {
        #[cfg(target_arch = "x86_64")]
        {
            std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    })
}

impl StencilTable {
    /// Writes the limit position and unit normal (`du x dv`, zero where the derivatives are
    /// parallel) of every point of the table for the points of `mesh` (the cage the table was
    /// made for, moved) into `positions` and
    /// `normals` (one element per point). Runs on the current rayon pool; the result does not
    /// depend on the thread count.
    pub fn apply(
        &self,
        mesh: &Mesh,
        positions: &mut [[f32; 3]],
        normals: &mut [[f32; 3]],
    ) -> Result<(), StencilError> {
        let cage = mesh.positions();
        if cage.len() != self.num_vertices() {
            return Err(StencilError::Params(format!(
                "a cage of {} vertices for a table made for {}",
                cage.len(),
                self.num_vertices()
            )));
        }
        if positions.len() != self.num_points() || normals.len() != self.num_points() {
            return Err(StencilError::Params(format!(
                "{} positions and {} normals for a table of {} points",
                positions.len(),
                normals.len(),
                self.num_points()
            )));
        }
        let out = Out {
            pos: positions.as_mut_ptr(),
            nrm: normals.as_mut_ptr(),
        };
        let fused = fused();
        self.groups
            .par_iter()
            .with_min_len(MIN_GROUPS_PER_TASK)
            .for_each_init(Vec::new, |scratch, g| {
                if fused {
                    #[cfg(target_arch = "x86_64")]
                    // SAFETY: the CPU has AVX2 and FMA (`fused`); `Out` as in `group`.
                    unsafe {
                        self.group_fused(g, cage, &out, scratch)
                    }
                } else {
                    self.group::<false>(g, cage, &out, scratch);
                }
            });
        Ok(())
    }

    /// [`StencilTable::group`] with the sums in AVX2 registers, fused.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn group_fused(&self, g: &Group, cage: &[Vec3], out: &Out, scratch: &mut Vec<f32>) {
        self.group::<true>(g, cage, out, scratch);
    }

    /// The points of one face: its support gathered once, then block after block.
    #[inline(always)]
    fn group<const FUSED: bool>(
        &self,
        g: &Group,
        cage: &[Vec3],
        out: &Out,
        scratch: &mut Vec<f32>,
    ) {
        let s = g.len as usize;
        scratch.clear();
        scratch.resize(3 * s, 0.0);
        let (sx, rest) = scratch.split_at_mut(s);
        let (sy, sz) = rest.split_at_mut(s);
        let support = &self.support[g.support as usize..][..s];
        // Sums about the face's first support vertex: the derivative weights sum to 0 and the
        // position weights to 1, so the sums are the same maps with less cancellation.
        let origin = support.first().map_or(Vec3::ZERO, |&v| cage[v as usize]);
        for (j, &v) in support.iter().enumerate() {
            let p = cage[v as usize] - origin;
            (sx[j], sy[j], sz[j]) = (p.x, p.y, p.z);
        }
        let per_block = s * BLOCK_FLOATS;
        let weights = &self.weights[g.weights..][..g.blocks as usize * per_block];
        let targets = &self.targets[g.first_block as usize * LANES..][..g.blocks as usize * LANES];
        for (w, t) in weights
            .chunks_exact(per_block)
            .zip(targets.chunks_exact(LANES))
        {
            #[cfg(target_arch = "x86_64")]
            if FUSED {
                // SAFETY: `FUSED` is only instantiated from `group_fused`, which runs where
                // the CPU has AVX2 and FMA.
                let (p, n) = unsafe { fused::block(w, sx, sy, sz) };
                write(&p, &n, origin, t, out);
                continue;
            }
            let acc = sums(w, sx, sy, sz);
            let n = normals(&acc);
            write(&[acc[0], acc[1], acc[2]], &n, origin, t, out);
        }
    }
}

/// The nine sums of one block: rows 0-2 the position, 3-5 `d/du`, 6-8 `d/dv`.
#[inline(always)]
fn sums(w: &[f32], sx: &[f32], sy: &[f32], sz: &[f32]) -> [[f32; LANES]; 9] {
    let mut acc = [[0.0f32; LANES]; 9];
    for (((wb, &x), &y), &z) in w.chunks_exact(BLOCK_FLOATS).zip(sx).zip(sy).zip(sz) {
        for k in 0..3 {
            let wk = &wb[k * LANES..][..LANES];
            for l in 0..LANES {
                acc[3 * k][l] += wk[l] * x;
                acc[3 * k + 1][l] += wk[l] * y;
                acc[3 * k + 2][l] += wk[l] * z;
            }
        }
    }
    acc
}

/// Unit normals `du x dv` of a block's lanes (zero where the derivatives are parallel).
#[inline(always)]
fn normals(a: &[[f32; LANES]; 9]) -> [[f32; LANES]; 3] {
    let mut n = [[0.0f32; LANES]; 3];
    for l in 0..LANES {
        let cx = a[4][l] * a[8][l] - a[5][l] * a[7][l];
        let cy = a[5][l] * a[6][l] - a[3][l] * a[8][l];
        let cz = a[3][l] * a[7][l] - a[4][l] * a[6][l];
        let len2 = cx * cx + cy * cy + cz * cz;
        // `len2 > 0.0 && len2.is_finite()` in one unsigned compare: the positive finite floats
        // are the bit patterns 1..=0x7f7f_ffff.
        let ok = len2.to_bits().wrapping_sub(1) < 0x7f7f_ffff;
        let inv = if ok { 1.0 / len2.sqrt() } else { 0.0 };
        n[0][l] = cx * inv;
        n[1][l] = cy * inv;
        n[2][l] = cz * inv;
    }
    n
}

/// Every point of a block: its position (`origin` added back) and normal written out.
#[inline(always)]
fn write(p: &[[f32; LANES]; 3], n: &[[f32; LANES]; 3], origin: Vec3, targets: &[u32], out: &Out) {
    for (l, &t) in targets.iter().enumerate() {
        if t == NO_POINT {
            break;
        }
        // SAFETY: `t` is below the point count (the table's targets are the points `0..n`,
        // `apply` checked both buffers hold `n`), and no other lane of any block targets it.
        unsafe {
            *out.pos.add(t as usize) = [p[0][l] + origin.x, p[1][l] + origin.y, p[2][l] + origin.z];
            *out.nrm.add(t as usize) = [n[0][l], n[1][l], n[2][l]];
        }
    }
}

/// The block's sums and normals in AVX2 registers, the multiply-adds fused.
#[cfg(target_arch = "x86_64")]
mod fused {
    use std::arch::x86_64::*;

    use crate::table::{BLOCK_FLOATS, LANES};

    /// Positions and unit normals of one block (see [`super::sums`], [`super::normals`]).
    ///
    /// # Safety
    /// The CPU must have AVX2 and FMA; `w` holds `BLOCK_FLOATS` floats per support vertex.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn block(
        w: &[f32],
        sx: &[f32],
        sy: &[f32],
        sz: &[f32],
    ) -> ([[f32; LANES]; 3], [[f32; LANES]; 3]) {
        assert!(w.len() >= sx.len() * BLOCK_FLOATS && sy.len() == sx.len() && sz.len() == sx.len());
        let z0 = _mm256_setzero_ps();
        let (mut p0, mut p1, mut p2) = (z0, z0, z0);
        let (mut u0, mut u1, mut u2) = (z0, z0, z0);
        let (mut v0, mut v1, mut v2) = (z0, z0, z0);
        let wp = w.as_ptr();
        for j in 0..sx.len() {
            // SAFETY: `j * BLOCK_FLOATS + 24 <= w.len()` (asserted above).
            let (wa, wu, wv) = unsafe {
                let at = wp.add(j * BLOCK_FLOATS);
                (
                    _mm256_loadu_ps(at),
                    _mm256_loadu_ps(at.add(LANES)),
                    _mm256_loadu_ps(at.add(2 * LANES)),
                )
            };
            let x = _mm256_set1_ps(sx[j]);
            let y = _mm256_set1_ps(sy[j]);
            let z = _mm256_set1_ps(sz[j]);
            p0 = _mm256_fmadd_ps(wa, x, p0);
            p1 = _mm256_fmadd_ps(wa, y, p1);
            p2 = _mm256_fmadd_ps(wa, z, p2);
            u0 = _mm256_fmadd_ps(wu, x, u0);
            u1 = _mm256_fmadd_ps(wu, y, u1);
            u2 = _mm256_fmadd_ps(wu, z, u2);
            v0 = _mm256_fmadd_ps(wv, x, v0);
            v1 = _mm256_fmadd_ps(wv, y, v1);
            v2 = _mm256_fmadd_ps(wv, z, v2);
        }
        let cx = _mm256_sub_ps(_mm256_mul_ps(u1, v2), _mm256_mul_ps(u2, v1));
        let cy = _mm256_sub_ps(_mm256_mul_ps(u2, v0), _mm256_mul_ps(u0, v2));
        let cz = _mm256_sub_ps(_mm256_mul_ps(u0, v1), _mm256_mul_ps(u1, v0));
        let len2 = _mm256_add_ps(
            _mm256_add_ps(_mm256_mul_ps(cx, cx), _mm256_mul_ps(cy, cy)),
            _mm256_mul_ps(cz, cz),
        );
        // Positive and finite (NaN compares false).
        let ok = _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GT_OQ>(len2, z0),
            _mm256_cmp_ps::<_CMP_LT_OQ>(len2, _mm256_set1_ps(f32::INFINITY)),
        );
        let inv = _mm256_and_ps(ok, _mm256_div_ps(_mm256_set1_ps(1.0), _mm256_sqrt_ps(len2)));
        let mut p = [[0.0f32; LANES]; 3];
        let mut n = [[0.0f32; LANES]; 3];
        for (dst, v) in p.iter_mut().zip([p0, p1, p2]) {
            // SAFETY: `dst` holds eight floats.
            unsafe { _mm256_storeu_ps(dst.as_mut_ptr(), v) };
        }
        for (dst, c) in n.iter_mut().zip([cx, cy, cz]) {
            // SAFETY: as above.
            unsafe { _mm256_storeu_ps(dst.as_mut_ptr(), _mm256_mul_ps(c, inv)) };
        }
        (p, n)
    }
}
