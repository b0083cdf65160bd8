//! What the pixel-error mode measures once per cage ([`PatchErrors`]): for every cage face and
//! depth, how far the triangles drawn at that depth stray from the limit surface and where the
//! normals interpolated across them turn further than the shading tolerance from the limit
//! normals (per area element, [`ShadingError`]), and a cone bounding the face's limit normals.
//! The patches are the slates' (Settgast et al. 2004, Section 3.2: [`PatchGrids`] tessellates
//! each on its own), sampled [`SAMPLE_LEVELS`] deeper than the deepest drawn depth.

use std::cell::RefCell;

use glam::Vec3;
use rayon::prelude::*;
use subdiv_mesh::{FaceId, Mesh};
use subdiv_slate::{Depth, MAX_DEPTH, PatchGrids, PatchSet};

use crate::{AreaElement, NormalCone, PatchError, PatchErrors, ShadingError};

/// Levels beyond the deepest drawn depth at which the limit surface is sampled: at `+2` every
/// drawn quad of the deepest depth holds a 5 × 5 grid of samples (corners, edge quarter points,
/// the points around its triangles' centroids), enough to find the worst point of a smooth
/// patch's deviation from its two triangles.
pub const SAMPLE_LEVELS: Depth = 2;

/// Area elements per side of a patch (at most one per sample cell): 4 × 4 per patch, small
/// enough that the view changes little across one (its projected-area density is taken at its
/// centre, [`crate::ScreenArea::density`]), few enough to weigh per frame.
pub const ELEMENTS_PER_SIDE: usize = 4;

/// Measures, for each cage face of `mesh` (whose patches are `set`) and depth `l <= max_depth`, the largest distance between the
/// limit surface and the triangles drawn at depth `l` (each grid quad split along its
/// `(i, j)`–`(i + 1, j + 1)` diagonal, as `subdiv-stitch` draws it; the gap along the limit
/// normal, or the whole gap near the cage's boundary and holes, see `Grid::triangle_deviation`)
/// and, per area element ([`ELEMENTS_PER_SIDE`]² per patch), the world area where the angle
/// between limit and interpolated normals exceeds `shading_tolerance` (radians), sampled on the
/// depth `max_depth + SAMPLE_LEVELS` grid (at most [`MAX_DEPTH`]) of every patch of the face; and
/// a cone containing the face's limit normals, widened by the largest angle between neighbouring
/// samples (normals between samples lean no further than that for a smooth patch).
pub fn patch_errors(
    mesh: &Mesh,
    set: &PatchSet,
    max_depth: Depth,
    shading_tolerance: f32,
) -> PatchErrors {
    let fine = (max_depth + SAMPLE_LEVELS).min(MAX_DEPTH);
    let depths = max_depth as usize + 1;
    // Footprint scales: blocks of 1, 2, 4, ... fine cells up to a quad patch's element.
    let scales = (fine as usize).saturating_sub(1).max(1);
    let per_patch: Vec<PatchMeasure> = set
        .patches()
        .par_iter()
        .map_init(
            || {
                let buffers = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
                (
                    PatchGrids::new(mesh, set, fine),
                    buffers,
                    RefCell::new(Scratch::default()),
                )
            },
            |(grids, (pos, nrm, shade, sided), scratch), p| {
                // Level-1 patches are one level coarser than their face.
                let l_fine = fine - p.level;
                let n = 1usize << l_fine;
                pos.resize((n + 1) * (n + 1), [0.0f32; 3]);
                nrm.resize((n + 1) * (n + 1), [0.0f32; 3]);
                grids.grid(p, l_fine, pos, nrm, sided);
                // What the renderer shades this patch with: its own side's normal on creases.
                shade.clone_from(nrm);
                for &(k, q) in sided.iter() {
                    shade[k as usize] = q;
                }
                let grid = Grid { n, pos, nrm, shade };
                let outline = touches_outline(mesh, set.units()[p.unit as usize].face);
                let shift_of = |ld: Depth| match ld.checked_sub(p.level) {
                    Some(l) if l <= l_fine => Some(l_fine - l),
                    _ => None,
                };
                let deviation = (0..=max_depth)
                    .map(|ld| {
                        shift_of(ld).map_or(f32::INFINITY, |s| grid.triangle_deviation(s, outline))
                    })
                    .collect();
                let elements = grid.elements();
                let table = ShadingTable {
                    max_depth,
                    tolerance: shading_tolerance,
                    scales,
                };
                let outlier = table.measure(&grid, &elements, &shift_of, &mut scratch.borrow_mut());
                PatchMeasure {
                    deviation,
                    elements,
                    outlier,
                    cone: grid.normal_cone(),
                }
            },
        )
        .collect();
    let mut faces = vec![
        PatchError {
            deviation: vec![0.0; depths],
            shading: ShadingError::default(),
            normals: NormalCone::ANY,
            outline: false,
        };
        mesh.num_faces()
    ];
    for (f, e) in faces.iter_mut().enumerate() {
        e.outline = touches_outline(mesh, subdiv_mesh::FaceId(f as u32));
    }
    let mut cones: Vec<Vec<NormalCone>> = vec![Vec::new(); mesh.num_faces()];
    for (p, m) in set.patches().iter().zip(per_patch) {
        let f = set.units()[p.unit as usize].face.idx();
        for (o, d) in faces[f].deviation.iter_mut().zip(m.deviation) {
            *o = o.max(d);
        }
        let sh = &mut faces[f].shading;
        sh.scales = scales;
        sh.elements.extend(m.elements);
        sh.outlier_area.extend(m.outlier);
        // A level-1 patch draws a quarter of a quad patch's triangles at the face's depth.
        sh.weight += 0.25f32.powi(p.level as i32);
        cones[f].push(m.cone);
    }
    for (face, c) in faces.iter_mut().zip(&cones) {
        face.normals = merge_cones(c);
    }
    PatchErrors {
        faces,
        closed: mesh.is_closed(),
        shading_tolerance,
    }
}

/// How [`patch_errors`] lays out a patch's outlier areas ([`ShadingError::outlier_area`]).
struct ShadingTable {
    max_depth: Depth,
    tolerance: f32,
    scales: usize,
}

impl ShadingTable {
    /// The outlier areas of `grid`'s `elements`: element-major, then depth, then footprint
    /// scale. `shift_of(depth)` is how many grid levels lie below a drawn depth (`None`: the
    /// patch cannot be drawn there, a level-1 patch at depth 0, and the whole element counts).
    fn measure(
        &self,
        grid: &Grid<'_>,
        elements: &[AreaElement],
        shift_of: &dyn Fn(Depth) -> Option<Depth>,
        scratch: &mut Scratch,
    ) -> Vec<f32> {
        let scales = self.scales;
        let per = (self.max_depth as usize + 1) * scales;
        let mut outlier = vec![0.0f32; elements.len() * per];
        let mut at_depth = vec![0.0f32; elements.len() * scales];
        // What every depth compares with: the cells' areas and limit normal sums.
        if self.tolerance < std::f32::consts::PI {
            grid.cell_sums(scratch);
        }
        for ld in 0..=self.max_depth {
            match shift_of(ld) {
                Some(shift) => {
                    grid.outlier_areas(shift, self.tolerance, scales, scratch, &mut at_depth)
                }
                None => {
                    for (o, k) in at_depth.iter_mut().zip((0..).map(|x| x / scales)) {
                        *o = elements[k].area;
                    }
                }
            }
            for (k, e) in at_depth.chunks(scales).enumerate() {
                let at = k * per + ld as usize * scales;
                outlier[at..at + scales].copy_from_slice(e);
            }
        }
        outlier
    }
}

/// Reused buffers of the outlier measure (`Grid::outlier_areas`, and the triangle lattice's in
/// `patch_error_tri`): the interpolated normal per sample, and per cell of a square array of
/// side `n` (row-major) the area-weighted sums of the limit and the interpolated normals and
/// the cell's area (zero for cells a triangular lattice lacks). `cell_truth` and `cell_area`
/// keep a patch's level-0 limit sums and areas for all its depths (`Grid::cell_sums`,
/// `Lattice::cell_sums`).
#[derive(Default)]
pub(crate) struct Scratch {
    pub(crate) interp: Vec<Vec3>,
    pub(crate) truth: Vec<Vec3>,
    pub(crate) drawn: Vec<Vec3>,
    pub(crate) area: Vec<f32>,
    pub(crate) cell_truth: Vec<Vec3>,
    pub(crate) cell_area: Vec<f32>,
}

impl Scratch {
    /// `shade`'s normals made unit length (zero where they vanish), into `interp`.
    pub(crate) fn unit_normals(&mut self, shade: &[[f32; 3]]) {
        self.interp.clear();
        self.interp
            .extend(shade.iter().map(|&q| Vec3::from(q).normalize_or_zero()));
    }

    /// From the per-cell sums: per element and footprint scale (into `out`,
    /// `out[k * scales + s]`), the area of the aligned blocks of `2^s × 2^s` cells whose mean
    /// interpolated normal is further than `acos(cos_tol)` from their mean limit normal (what a
    /// pixel of that footprint shows: a pixel's normal is the mean over its samples), credited
    /// to the element `element_of(i, j)` holding the block's first cell. `per_side` is
    /// elements per side and how many there are; scales beyond an element's size repeat the
    /// element-sized blocks' result. Sums `2 × 2` blocks in place, level by level.
    pub(crate) fn outliers_by_block(
        &mut self,
        n: usize,
        (per_side, elements): (usize, usize),
        scales: usize,
        cos_tol: f32,
        element_of: impl Fn(usize, usize) -> usize,
        out: &mut [f32],
    ) {
        let (tr, dr, ar) = (&mut self.truth, &mut self.drawn, &mut self.area);
        let mut side = n;
        let mut block = 1usize;
        for s in 0..scales {
            if block > n / per_side {
                // Larger than the element: repeat the element-sized blocks' result.
                for k in 0..elements {
                    out[k * scales + s] = out[k * scales + s - 1];
                }
                continue;
            }
            if s > 0 {
                let half = side / 2;
                for j in 0..half {
                    for i in 0..half {
                        let q = [(0, 0), (1, 0), (0, 1), (1, 1)]
                            .map(|(x, y)| (2 * j + y) * side + 2 * i + x);
                        let to = j * half + i;
                        tr[to] = q.iter().map(|&k| tr[k]).sum();
                        dr[to] = q.iter().map(|&k| dr[k]).sum();
                        ar[to] = q.iter().map(|&k| ar[k]).sum();
                    }
                }
                side = half;
            }
            for j in 0..side {
                for i in 0..side {
                    let b = j * side + i;
                    let (t, m) = (tr[b], dr[b]);
                    let len = t.length() * m.length();
                    if ar[b] > 0.0 && len > 0.0 && t.dot(m) < len * cos_tol {
                        out[element_of(i * block, j * block) * scales + s] += ar[b];
                    }
                }
            }
            block *= 2;
        }
    }
}

/// What [`patch_errors`] measures of one patch.
struct PatchMeasure {
    /// Chord error per depth.
    deviation: Vec<f32>,
    /// The patch's area elements.
    elements: Vec<AreaElement>,
    /// Outlier area per element and depth (element-major).
    outlier: Vec<f32>,
    /// Bounds the patch's limit normals.
    cone: NormalCone,
}

/// Whether face `f` shares a vertex with the cage's boundary or with a hole (so the surface's
/// own edge may be an outline on screen near it).
pub(crate) fn touches_outline(mesh: &Mesh, f: FaceId) -> bool {
    mesh.face_vertices(f).iter().any(|&v| {
        mesh.outgoing(v).any(|h| {
            let g = mesh.face(h);
            !g.is_some() || mesh.is_hole(g) || !mesh.face(h.twin()).is_some()
        })
    })
}

/// One patch's limit points and normals on an `(n + 1)²` grid.
struct Grid<'a> {
    n: usize,
    pos: &'a [[f32; 3]],
    /// Limit normals (the mean of the sides' where the surface has a crease or a corner).
    nrm: &'a [[f32; 3]],
    /// The normals the renderer shades this patch with: `nrm`, except this patch's own side's
    /// normal at crease and corner points.
    shade: &'a [[f32; 3]],
}

impl Grid<'_> {
    #[inline]
    fn at(&self, i: usize, j: usize) -> Vec3 {
        Vec3::from(self.pos[j * (self.n + 1) + i])
    }

    /// Largest distance of a sample from the triangles of the coarser grid with `step` samples
    /// per quad side: quad `(a, b, c, e)` drawn as `(a, b, c)` and `(a, c, e)`, each sample
    /// against the triangle point of the same parameters. Inside the surface only the part of
    /// that gap along the limit normal counts: at a silhouette the normal lies across the line
    /// of sight, so the outline moves by the normal part, while the part along the surface
    /// slides points within it and moves nothing on screen. Where the face reaches the cage's
    /// boundary or a hole (`outline`), the surface's own edge is an outline too, and the whole
    /// gap counts.
    fn triangle_deviation(&self, shift: Depth, outline: bool) -> f32 {
        let step = 1usize << shift;
        // `x * inv` is `x / step` exactly: `step` is a power of two.
        let inv = 1.0 / step as f32;
        let w = self.n + 1;
        let mut worst = 0.0f32;
        for j0 in (0..self.n).step_by(step) {
            for i0 in (0..self.n).step_by(step) {
                let a = self.at(i0, j0);
                let b = self.at(i0 + step, j0);
                let c = self.at(i0 + step, j0 + step);
                let e = self.at(i0, j0 + step);
                for j in j0..=j0 + step {
                    for i in i0..=i0 + step {
                        let u = (i - i0) as f32 * inv;
                        let v = (j - j0) as f32 * inv;
                        let on = if v <= u {
                            a * (1.0 - u) + b * (u - v) + c * v
                        } else {
                            a * (1.0 - v) + c * u + e * (v - u)
                        };
                        let gap = self.at(i, j) - on;
                        let d = if outline {
                            gap.length()
                        } else {
                            gap.dot(Vec3::from(self.nrm[j * w + i])).abs()
                        };
                        worst = worst.max(d);
                    }
                }
            }
        }
        worst
    }

    /// The normal interpolated at each sample's parameters across the coarser grid's triangles
    /// (as [`Grid::triangle_deviation`] splits the quads) from their corners' normals in
    /// `shade`, normalised: the renderer's smooth shading, into `out` (row-major).
    fn interpolated_normals(&self, shift: Depth, out: &mut Vec<Vec3>) {
        let step = 1usize << shift;
        // `x * inv` is `x / step` exactly: `step` is a power of two.
        let inv = 1.0 / step as f32;
        let w = self.n + 1;
        let nrm = |i: usize, j: usize| Vec3::from(self.shade[j * w + i]);
        out.clear();
        for j in 0..w {
            // The quad holding sample (i, j): the last row and column belong to the last quad.
            let j0 = (j / step * step).min(self.n - step);
            for i in 0..w {
                let i0 = (i / step * step).min(self.n - step);
                let a = nrm(i0, j0);
                let b = nrm(i0 + step, j0);
                let c = nrm(i0 + step, j0 + step);
                let e = nrm(i0, j0 + step);
                let u = (i - i0) as f32 * inv;
                let v = (j - j0) as f32 * inv;
                let on = if v <= u {
                    a * (1.0 - u) + b * (u - v) + c * v
                } else {
                    a * (1.0 - v) + c * u + e * (v - u)
                };
                out.push(on.normalize_or_zero());
            }
        }
    }

    /// Elements per side: [`ELEMENTS_PER_SIDE`], or one per cell on coarser grids.
    #[inline]
    fn elements_per_side(&self) -> usize {
        ELEMENTS_PER_SIDE.min(self.n)
    }

    /// The element holding cell `(i, j)`.
    #[inline]
    fn element_of(&self, i: usize, j: usize) -> usize {
        let e = self.elements_per_side();
        (j * e / self.n) * e + i * e / self.n
    }

    /// World area of cell `(i, j)` (half the cross product of its diagonals).
    #[inline]
    fn cell_area(&self, i: usize, j: usize) -> f32 {
        let d0 = self.at(i + 1, j + 1) - self.at(i, j);
        let d1 = self.at(i, j + 1) - self.at(i + 1, j);
        0.5 * d0.cross(d1).length()
    }

    /// The grid's area elements: per block of cells, the area-weighted centre, the mean limit
    /// normal and the area.
    fn elements(&self) -> Vec<AreaElement> {
        let e = self.elements_per_side();
        let w = self.n + 1;
        let cells = ((self.n / e) * (self.n / e)) as f32;
        let mut acc = vec![(Vec3::ZERO, Vec3::ZERO, 0.0f32); e * e];
        for j in 0..self.n {
            for i in 0..self.n {
                let a = self.cell_area(i, j);
                let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                let centre = corners.iter().map(|&(x, y)| self.at(x, y)).sum::<Vec3>() * 0.25;
                let normal: Vec3 = corners
                    .iter()
                    .map(|&(x, y)| Vec3::from(self.nrm[y * w + x]))
                    .sum();
                let k = &mut acc[self.element_of(i, j)];
                k.0 += centre * a;
                k.1 += normal.normalize_or_zero() * a;
                k.2 += a;
            }
        }
        acc.into_iter()
            .map(|(c, n, a)| AreaElement {
                centre: if a > 0.0 { c / a } else { c },
                normal: n.normalize_or_zero(),
                area: a,
                cell: (a / cells).sqrt(),
            })
            .collect()
    }

    /// Per cell (row-major) its area and the sum of its corners' unit limit normals (from
    /// `shade`) times that area, into `scratch.cell_area` and `scratch.cell_truth`: the
    /// level 0 of [`Grid::outlier_areas`] that is the same at every depth.
    fn cell_sums(&self, scratch: &mut Scratch) {
        let w = self.n + 1;
        scratch.unit_normals(self.shade);
        let Scratch {
            interp: unit,
            cell_truth,
            cell_area,
            ..
        } = scratch;
        cell_truth.clear();
        cell_area.clear();
        for j in 0..self.n {
            for i in 0..self.n {
                let a = self.cell_area(i, j);
                let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                let t: Vec3 = corners.iter().map(|&(x, y)| unit[y * w + x]).sum();
                cell_truth.push(t * a);
                cell_area.push(a);
            }
        }
    }

    /// Per element and footprint scale (into `out`, `out[k * scales + s]`): the world area
    /// where the mean interpolated normal at `shift` turns further than `tolerance` (radians)
    /// from the mean limit normal (both from `shade`, so a crease's sides are compared with
    /// their own normals), the means taken over aligned blocks of `2^s × 2^s` cells — what a
    /// pixel of that footprint shows, since a pixel's normal is the mean over its samples. Scales
    /// beyond the element's size repeat its largest block. `scratch` is scratch space.
    fn outlier_areas(
        &self,
        shift: Depth,
        tolerance: f32,
        scales: usize,
        scratch: &mut Scratch,
        out: &mut [f32],
    ) {
        out.fill(0.0);
        if tolerance >= std::f32::consts::PI {
            return;
        }
        let cos_tol = tolerance.cos();
        self.interpolated_normals(shift, &mut scratch.interp);
        let w = self.n + 1;
        // Level 0: per cell, the area-weighted sums of both normals (corner means) and its area
        // (the limit's and the area from `cell_sums`).
        let Scratch {
            interp,
            truth: tr,
            drawn: dr,
            area: ar,
            cell_truth,
            cell_area,
        } = scratch;
        tr.clone_from(cell_truth);
        ar.clone_from(cell_area);
        dr.clear();
        for j in 0..self.n {
            for i in 0..self.n {
                let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                let m: Vec3 = corners.iter().map(|&(x, y)| interp[y * w + x]).sum();
                dr.push(m * cell_area[j * self.n + i]);
            }
        }
        let per_side = self.elements_per_side();
        scratch.outliers_by_block(
            self.n,
            (per_side, per_side * per_side),
            scales,
            cos_tol,
            |i, j| self.element_of(i, j),
            out,
        );
    }

    /// A cone around the grid's normals, widened by the largest angle between neighbours.
    fn normal_cone(&self) -> NormalCone {
        let w = self.n + 1;
        let normal = |k: usize| Vec3::from(self.nrm[k]);
        let mut margin = 0.0f32;
        for j in 0..w {
            for i in 0..w {
                let k = j * w + i;
                for m in [(i + 1 < w).then(|| k + 1), (j + 1 < w).then(|| k + w)]
                    .into_iter()
                    .flatten()
                {
                    let cos = normal(k).dot(normal(m)).clamp(-1.0, 1.0);
                    margin = margin.max(cos.acos());
                }
            }
        }
        NormalCone::bounding((0..w * w).map(normal), margin)
    }
}

/// A cone containing every given cone: around the normalised sum of their axes, as wide as the
/// farthest of them reaches.
fn merge_cones(cones: &[NormalCone]) -> NormalCone {
    if cones.iter().any(|c| c.cos <= -1.0) || cones.is_empty() {
        return NormalCone::ANY;
    }
    let axis = cones
        .iter()
        .map(|c| c.axis)
        .sum::<Vec3>()
        .normalize_or_zero();
    if axis == Vec3::ZERO {
        return NormalCone::ANY;
    }
    let half = cones
        .iter()
        .map(|c| axis.dot(c.axis).clamp(-1.0, 1.0).acos() + c.cos.clamp(-1.0, 1.0).acos())
        .fold(0.0f32, f32::max);
    if half >= std::f32::consts::PI {
        NormalCone::ANY
    } else {
        NormalCone {
            axis,
            cos: half.cos(),
        }
    }
}

#[cfg(test)]
mod tests;
