//! What the pixel-error mode measures once per Loop cage ([`PatchErrors`]), as
//! [`crate::patch_errors`] does for Catmull-Clark: for every triangle patch and depth, how far
//! the lattice triangles drawn at that depth stray from the limit surface, where the normals
//! interpolated across them turn further than the shading tolerance from the limit normals (per
//! area element, [`ShadingError`]), and a cone bounding the patch's limit normals. The patches
//! are the triangular slates' lattices ([`tri_patch_lattice`]).

use glam::Vec3;
use rayon::prelude::*;
use subdiv_mesh::{FaceId, Mesh};
use subdiv_slate::{Depth, MAX_DEPTH, TriLayout, tri_lattice_index, tri_patch_lattice};

use crate::patch_error::{ELEMENTS_PER_SIDE, SAMPLE_LEVELS, Scratch, touches_outline};
use crate::{AreaElement, NormalCone, PatchError, PatchErrors, ShadingError};

/// [`crate::patch_errors`] for a Loop cage (`layout`: its triangular slates' layout, any depth):
/// per triangle and depth `l <= max_depth`, the
/// largest distance between the limit surface and the lattice triangles drawn at depth `l`
/// (the gap along the limit normal, or the whole gap near the boundary and holes) and, per area
/// element, the world area where the angle between limit and interpolated normals exceeds
/// `shading_tolerance` (radians), sampled on the patch's lattice at depth
/// `max_depth + SAMPLE_LEVELS` (at most [`MAX_DEPTH`]); and a cone containing the patch's limit
/// normals, widened by the largest angle between neighbouring samples.
pub fn patch_errors_tri(
    mesh: &Mesh,
    layout: &TriLayout,
    max_depth: Depth,
    shading_tolerance: f32,
) -> PatchErrors {
    let fine = (max_depth + SAMPLE_LEVELS).min(MAX_DEPTH);
    // Footprint scales: blocks of 1, 2, 4, ... fine cells up to an element, as for quads.
    let scales = (fine as usize).saturating_sub(1).max(1);
    let faces: Vec<PatchError> = layout
        .patches()
        .par_iter()
        .enumerate()
        .map_init(
            || {
                (
                    Vec::new(),
                    Vec::new(),
                    Vec::new(),
                    Vec::new(),
                    Scratch::default(),
                )
            },
            |(pos, nrm, sided, shade, cells), (f, p)| {
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
                let elements = lat.elements();
                let per = (max_depth as usize + 1) * scales;
                let mut outlier_area = vec![0.0f32; elements.len() * per];
                let mut at_depth = vec![0.0f32; elements.len() * scales];
                if shading_tolerance < std::f32::consts::PI {
                    lat.cell_sums(cells);
                }
                for l in levels.clone() {
                    lat.outlier_areas(fine - l, shading_tolerance, scales, cells, &mut at_depth);
                    for (k, e) in at_depth.chunks(scales).enumerate() {
                        let at = k * per + l as usize * scales;
                        outlier_area[at..at + scales].copy_from_slice(e);
                    }
                }
                PatchError {
                    deviation: levels
                        .map(|l| lat.triangle_deviation(fine - l, outline))
                        .collect(),
                    shading: ShadingError {
                        elements,
                        outlier_area,
                        scales,
                        // A triangle patch draws 4^d triangles at depth d.
                        weight: 0.5,
                    },
                    normals: lat.normal_cone(),
                    outline,
                }
            },
        )
        .collect();
    PatchErrors {
        faces,
        closed: mesh.is_closed(),
        shading_tolerance,
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

    /// The triangles of cell `(i, j)` (`i + j < n`): the up triangle `(i, j), (i + 1, j),
    /// (i, j + 1)` and, below the hypotenuse, the down triangle `(i + 1, j), (i + 1, j + 1),
    /// (i, j + 1)`, as sample indices. The cells form a square array (a sheared grid of
    /// parallelograms), so blocks of `2^s × 2^s` cells are footprints as for quads.
    #[inline]
    fn cell(&self, i: u32, j: u32) -> ([usize; 3], Option<[usize; 3]>) {
        let idx = |a: u32, b: u32| tri_lattice_index(self.n, a, b) as usize;
        let up = [idx(i, j), idx(i + 1, j), idx(i, j + 1)];
        let down = (i + j + 2 <= self.n).then(|| [idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        (up, down)
    }

    /// World area of the triangle with these sample indices.
    #[inline]
    fn area(&self, t: [usize; 3]) -> f32 {
        let p = t.map(|k| Vec3::from(self.pos[k]));
        0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length()
    }

    /// Elements per side: [`ELEMENTS_PER_SIDE`], or one per cell on coarser lattices.
    #[inline]
    fn elements_per_side(&self) -> u32 {
        (ELEMENTS_PER_SIDE as u32).min(self.n)
    }

    /// The element holding cell `(i, j)`: the blocks `(i e / n, j e / n)` below the hypotenuse
    /// (`e (e + 1) / 2` of them, none empty), numbered as a lattice of side `e - 1`.
    #[inline]
    fn element_of(&self, i: u32, j: u32) -> usize {
        let e = self.elements_per_side();
        tri_lattice_index(e - 1, i * e / self.n, j * e / self.n) as usize
    }

    /// The lattice's area elements: per block of cells, the area-weighted centre, the mean
    /// limit normal, the area and the edge of a cell of equal area.
    fn elements(&self) -> Vec<AreaElement> {
        let e = self.elements_per_side() as usize;
        let mut acc = vec![(Vec3::ZERO, Vec3::ZERO, 0.0f32, 0.0f32); e * (e + 1) / 2];
        for j in 0..self.n {
            for i in 0..self.n - j {
                let (up, down) = self.cell(i, j);
                let k = &mut acc[self.element_of(i, j)];
                for t in std::iter::once(up).chain(down) {
                    let a = self.area(t);
                    let centre = t.iter().map(|&s| Vec3::from(self.pos[s])).sum::<Vec3>() / 3.0;
                    let normal: Vec3 = t.iter().map(|&s| Vec3::from(self.nrm[s])).sum();
                    k.0 += centre * a;
                    k.1 += normal.normalize_or_zero() * a;
                    k.2 += a;
                    // Two triangles make one parallelogram cell.
                    k.3 += 0.5;
                }
            }
        }
        acc.into_iter()
            .map(|(c, n, a, cells)| AreaElement {
                centre: if a > 0.0 { c / a } else { c },
                normal: n.normalize_or_zero(),
                area: a,
                cell: (a / cells.max(0.5)).sqrt(),
            })
            .collect()
    }

    /// Per cell of [`Lattice::cell`] (an `n × n` array, row-major; zero where the lattice has
    /// none) its area and the area-weighted sum of its triangles' unit limit normals (from
    /// `shade`), into `c.cell_area` and `c.cell_truth`: what [`Lattice::outlier_areas`] needs
    /// of the limit at every depth.
    fn cell_sums(&self, c: &mut Scratch) {
        let n = self.n as usize;
        c.unit_normals(self.shade);
        c.cell_truth.clear();
        c.cell_truth.resize(n * n, Vec3::ZERO);
        c.cell_area.clear();
        c.cell_area.resize(n * n, 0.0);
        let Scratch {
            interp: unit,
            cell_truth,
            cell_area,
            ..
        } = c;
        self.cell_triangles(|at, t, a| {
            cell_truth[at] += t.iter().map(|&s| unit[s]).sum::<Vec3>() * a;
            cell_area[at] += a;
        });
    }

    /// Every triangle `t` of every cell of [`Lattice::cell`] with the cell's index `at` in an
    /// `n × n` array (row-major) and the triangle's area `a`, up before down.
    fn cell_triangles(&self, mut f: impl FnMut(usize, [usize; 3], f32)) {
        let n = self.n as usize;
        for j in 0..self.n {
            for i in 0..self.n - j {
                let (up, down) = self.cell(i, j);
                let at = j as usize * n + i as usize;
                for t in std::iter::once(up).chain(down) {
                    f(at, t, self.area(t));
                }
            }
        }
    }

    /// The outlier areas of the lattice's elements at `shift` (the quad grid's measure, over
    /// the cells of [`Lattice::cell`]): per cell the area-weighted sums of the limit normals
    /// (from `shade`) and of the normals interpolated across the drawn triangles, then
    /// `Scratch::outliers_by_block`.
    fn outlier_areas(
        &self,
        shift: Depth,
        tolerance: f32,
        scales: usize,
        c: &mut Scratch,
        out: &mut [f32],
    ) {
        out.fill(0.0);
        if tolerance >= std::f32::consts::PI {
            return;
        }
        let cos_tol = tolerance.cos();
        let n = self.n as usize;
        c.interp.clear();
        c.interp.resize(self.nrm.len(), Vec3::ZERO);
        self.samples(|k, i, j| {
            let on: Vec3 = self
                .holder(shift, i, j)
                .iter()
                .map(|&(q, w)| Vec3::from(self.shade[q]) * w)
                .sum();
            c.interp[k] = on.normalize_or_zero();
        });
        c.truth.clone_from(&c.cell_truth);
        c.area.clone_from(&c.cell_area);
        c.drawn.clear();
        c.drawn.resize(n * n, Vec3::ZERO);
        let (drawn, interp) = (&mut c.drawn, &c.interp);
        self.cell_triangles(|at, t, a| {
            drawn[at] += t.iter().map(|&s| interp[s]).sum::<Vec3>() * a;
        });
        let per_side = self.elements_per_side() as usize;
        c.outliers_by_block(
            n,
            (per_side, per_side * (per_side + 1) / 2),
            scales,
            cos_tol,
            |i, j| self.element_of(i as u32, j as u32),
            out,
        );
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
        let path = subdiv_test_support::shape(&format!("{name}.obj"));
        Mesh::from_soup(&parse_obj(&std::fs::read_to_string(path).unwrap()).unwrap()).unwrap()
    }

    #[test]
    fn deviations_fall_with_depth_and_bound_a_dense_check() {
        let mesh = fixture("loop_icosahedron");
        let layout = TriLayout::new(&mesh, 1).unwrap();
        let e = patch_errors_tri(&mesh, &layout, 3, 2f32.to_radians());
        assert!(e.closed);
        assert_eq!(e.faces.len(), mesh.num_faces());
        // Depth-l lattice points against the depth-(l + 2) limit points of the same patch:
        // the measured deviation is the largest such gap.
        let (mut pos, mut nrm, mut sided) = (Vec::new(), Vec::new(), Vec::new());
        let p = &layout.patches()[0];
        tri_patch_lattice(&mesh, &layout, p, 5, &mut pos, &mut nrm, &mut sided);
        for f in &e.faces {
            let d = &f.deviation;
            assert_eq!(d.len(), 4);
            assert!(d.windows(2).all(|w| w[1] < w[0]), "{d:?}");
            // Outlier area per depth (summed over elements, finest footprint) never grows.
            let sh = &f.shading;
            let per = 4 * sh.scales;
            let by_depth: Vec<f32> = (0..4)
                .map(|l| {
                    (0..sh.elements.len())
                        .map(|k| sh.outlier_area[k * per + l * sh.scales])
                        .sum()
                })
                .collect();
            assert!(by_depth.windows(2).all(|w| w[1] <= w[0]), "{by_depth:?}");
            assert!(
                by_depth[0] > 0.0 && by_depth[3] < by_depth[0],
                "{by_depth:?}"
            );
            let area: f32 = sh.elements.iter().map(|e| e.area).sum();
            assert!(area > 0.0 && sh.elements.iter().all(|e| e.area > 0.0));
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
        let layout = TriLayout::new(&mesh, 1).unwrap();
        let e = patch_errors_tri(&mesh, &layout, 2, 2f32.to_radians());
        assert!(!e.closed);
        for f in &e.faces {
            assert!(f.shading.outlier_area.iter().all(|&a| a == 0.0), "{f:?}");
            assert!((f.normals.axis - Vec3::Z).length() < 1e-5);
            // The boundary curve leaves the chord triangles: a real gap, falling with depth.
            assert!(f.deviation.windows(2).all(|w| w[1] <= w[0]), "{f:?}");
        }
    }
}
