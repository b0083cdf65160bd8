//! What the pixel-error mode measures once per Loop cage ([`subdiv_depth::PatchErrors`]), as
//! [`crate::patch_errors`] does for Catmull-Clark: for every triangle patch and depth, how far
//! the lattice triangles drawn at that depth stray from the limit surface and how far the
//! normals interpolated across them turn from the limit normals, and a cone bounding the
//! patch's limit normals.

use glam::Vec3;
use rayon::prelude::*;
use subdiv_depth::{NormalCone, PatchError, PatchErrors};
use subdiv_mesh::{FaceId, Mesh};
use subdiv_slate::{Depth, MAX_DEPTH, tri_lattice_index, tri_patch_lattice};
use subdiv_stitch::TriAssembler;

use crate::patch_error::{NORMAL_QUANTILE, SAMPLE_LEVELS, is_closed, touches_outline};

/// [`crate::patch_errors`] for a Loop cage: per triangle and depth `l <= max_depth`, the
/// largest distance between the limit surface and the lattice triangles drawn at depth `l`
/// (the gap along the limit normal, or the whole gap near the boundary and holes) and the
/// 99th percentile (`NORMAL_QUANTILE`) of the angle between limit and interpolated normals,
/// sampled on the patch's lattice at depth `max_depth + SAMPLE_LEVELS` (at most
/// [`MAX_DEPTH`]); and a cone containing the patch's limit normals, widened by the largest
/// angle between neighbouring samples.
pub fn patch_errors_loop(mesh: &Mesh, asm: &TriAssembler, max_depth: Depth) -> PatchErrors {
    let layout = asm.layout();
    let fine = (max_depth + SAMPLE_LEVELS).min(MAX_DEPTH);
    let faces: Vec<PatchError> = layout
        .patches
        .par_iter()
        .enumerate()
        .map_init(
            || (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new()),
            |(pos, nrm, sided, shade, angles), (f, p)| {
                tri_patch_lattice(mesh, layout, p, fine, pos, nrm, sided);
                shade.clone_from(nrm);
                for &(k, q) in sided.iter() {
                    shade[k as usize] = q;
                }
                let lat = Lattice {
                    n: 1 << fine,
                    pos,
                    nrm,
                    shade,
                };
                let outline = touches_outline(mesh, FaceId(f as u32));
                let levels = 0..=max_depth.min(fine);
                PatchError {
                    deviation: levels
                        .clone()
                        .map(|l| lat.triangle_deviation(fine - l, outline))
                        .collect(),
                    normal_error: levels
                        .map(|l| lat.normal_deviation(fine - l, angles))
                        .collect(),
                    normals: lat.normal_cone(),
                }
            },
        )
        .collect();
    PatchErrors {
        faces,
        closed: is_closed(mesh),
    }
}

/// One patch's limit points and normals on its triangular lattice of side `n`.
struct Lattice<'a> {
    n: u32,
    pos: &'a [[f32; 3]],
    nrm: &'a [[f32; 3]],
    /// What the renderer shades with: `nrm`, except this patch's one-sided normals.
    shade: &'a [[f32; 3]],
}

impl Lattice<'_> {
    /// The drawn triangle of the lattice with `2^shift` samples per side that holds sample
    /// `(i, j)`: its three corners (sample indices) and the sample's barycentric weights. A
    /// sample that is a corner of the coarser lattice has weight 1 on itself.
    #[inline]
    fn holder(&self, shift: Depth, i: u32, j: u32) -> [(usize, f32); 3] {
        let s = 1u32 << shift;
        let nc = self.n >> shift;
        let (a, b, ru, rv) = (i >> shift, j >> shift, i & (s - 1), j & (s - 1));
        let idx = |a: u32, b: u32| tri_lattice_index(self.n, a * s, b * s) as usize;
        let w = |x: u32| x as f32 / s as f32;
        if a + b == nc {
            let k = idx(a, b);
            [(k, 1.0), (k, 0.0), (k, 0.0)]
        } else if ru + rv <= s {
            // Up triangle (a, b), (a + 1, b), (a, b + 1).
            [
                (idx(a, b), w(s - ru - rv)),
                (idx(a + 1, b), w(ru)),
                (idx(a, b + 1), w(rv)),
            ]
        } else {
            // Down triangle (a + 1, b), (a + 1, b + 1), (a, b + 1).
            [
                (idx(a + 1, b), w(s - rv)),
                (idx(a + 1, b + 1), w(ru + rv - s)),
                (idx(a, b + 1), w(s - ru)),
            ]
        }
    }

    /// Calls `f(sample index, i, j)` for every sample.
    #[inline]
    fn samples(&self, mut f: impl FnMut(usize, u32, u32)) {
        for j in 0..=self.n {
            for i in 0..=self.n - j {
                f(tri_lattice_index(self.n, i, j) as usize, i, j);
            }
        }
    }

    /// Largest distance of a sample from the point of the same parameters on the coarser
    /// lattice's triangles: along the limit normal inside the surface, the whole gap where the
    /// face reaches the boundary or a hole (`outline`), as [`crate::patch_errors`] measures.
    fn triangle_deviation(&self, shift: Depth, outline: bool) -> f32 {
        let at = |k: usize| Vec3::from(self.pos[k]);
        let mut worst = 0.0f32;
        self.samples(|k, i, j| {
            let on: Vec3 = self
                .holder(shift, i, j)
                .iter()
                .map(|&(c, w)| at(c) * w)
                .sum();
            let gap = at(k) - on;
            let d = if outline {
                gap.length()
            } else {
                gap.dot(Vec3::from(self.nrm[k])).abs()
            };
            worst = worst.max(d);
        });
        worst
    }

    /// The 99th percentile (`NORMAL_QUANTILE`) of the angle (radians) between a sample's shading
    /// normal and the one interpolated at its parameters across the coarser lattice's triangles.
    fn normal_deviation(&self, shift: Depth, angles: &mut Vec<f32>) -> f32 {
        let nrm = |k: usize| Vec3::from(self.shade[k]);
        angles.clear();
        self.samples(|k, i, j| {
            let on: Vec3 = self
                .holder(shift, i, j)
                .iter()
                .map(|&(c, w)| nrm(c) * w)
                .sum();
            let (m, t) = (on.normalize_or_zero(), nrm(k).normalize_or_zero());
            if m != Vec3::ZERO && t != Vec3::ZERO {
                angles.push(m.dot(t).clamp(-1.0, 1.0).acos());
            }
        });
        if angles.is_empty() {
            return 0.0;
        }
        let rank = ((NORMAL_QUANTILE * angles.len() as f32).ceil() as usize).clamp(1, angles.len());
        *angles.select_nth_unstable_by(rank - 1, f32::total_cmp).1
    }

    /// A cone around the lattice's normals, widened by the largest angle between neighbours.
    fn normal_cone(&self) -> NormalCone {
        let normal = |k: usize| Vec3::from(self.nrm[k]);
        let mut margin = 0.0f32;
        self.samples(|k, i, j| {
            let right = (i + j < self.n).then(|| tri_lattice_index(self.n, i + 1, j));
            let up = (i + j < self.n).then(|| tri_lattice_index(self.n, i, j + 1));
            for m in [right, up].into_iter().flatten() {
                let cos = normal(k).dot(normal(m as usize)).clamp(-1.0, 1.0);
                margin = margin.max(cos.acos());
            }
        });
        NormalCone::bounding((0..self.nrm.len()).map(normal), margin)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_mesh::parse_obj;

    fn fixture(name: &str) -> Mesh {
        let path = format!(
            "{}/../../fixtures/reference/shapes/{name}.obj",
            env!("CARGO_MANIFEST_DIR")
        );
        Mesh::from_soup(&parse_obj(&std::fs::read_to_string(path).unwrap()).unwrap()).unwrap()
    }

    #[test]
    fn deviations_fall_with_depth_and_bound_a_dense_check() {
        let mesh = fixture("loop_icosahedron");
        let asm = TriAssembler::new(&mesh, 3).unwrap();
        let e = patch_errors_loop(&mesh, &asm, 3);
        assert!(e.closed);
        assert_eq!(e.faces.len(), mesh.num_faces());
        // Depth-l lattice points against the depth-(l + 2) limit points of the same patch:
        // the measured deviation is the largest such gap.
        let layout = asm.layout();
        let (mut pos, mut nrm, mut sided) = (Vec::new(), Vec::new(), Vec::new());
        let p = &layout.patches[0];
        tri_patch_lattice(&mesh, layout, p, 5, &mut pos, &mut nrm, &mut sided);
        for f in &e.faces {
            let d = &f.deviation;
            assert_eq!(d.len(), 4);
            assert!(d.windows(2).all(|w| w[1] < w[0]), "{d:?}");
            let a = &f.normal_error;
            assert!(a.windows(2).all(|w| w[1] < w[0]), "{a:?}");
            let half = f.normals.cos.acos().to_degrees();
            assert!(half > 5.0 && half < 90.0, "{half}");
        }
        // The centre of patch 0 at depth 5 lies off the depth-0 triangle by at most the
        // recorded deviation, and by more than a third of it (a sphere-like bulge).
        let n = 32;
        let c = Vec3::from(pos[tri_lattice_index(n, 11, 11) as usize]);
        let corners = [(0, 0), (n, 0), (0, n)]
            .map(|(i, j)| Vec3::from(pos[tri_lattice_index(n, i, j) as usize]));
        let plane_n = (corners[1] - corners[0])
            .cross(corners[2] - corners[0])
            .normalize();
        let off = (c - corners[0]).dot(plane_n).abs();
        assert!(off <= e.faces[0].deviation[0] * 1.001 && off > e.faces[0].deviation[0] / 3.0);
    }

    #[test]
    fn flat_open_patches_have_no_normal_error() {
        let mesh = Mesh::from_soup(
            &parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n").unwrap(),
        )
        .unwrap();
        let asm = TriAssembler::new(&mesh, 2).unwrap();
        let e = patch_errors_loop(&mesh, &asm, 2);
        assert!(!e.closed);
        for f in &e.faces {
            assert!(f.normal_error.iter().all(|&a| a < 1e-3), "{f:?}");
            assert!((f.normals.axis - Vec3::Z).length() < 1e-5);
            // The boundary curve leaves the chord triangles: a real gap, falling with depth.
            assert!(f.deviation.windows(2).all(|w| w[1] <= w[0]), "{f:?}");
        }
    }
}
