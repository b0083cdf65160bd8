//! The shading bound of the pixel-error mode, in screen space (beyond Settgast et al.).
//!
//! What the quality benchmark reports, and what a viewer sees, is the 99th percentile over the
//! *image's* pixels of the angle between the drawn normal and the true one
//! (`shading_deg_p99`). A per-patch percentile over parameter samples overspends: a semi-sharp
//! crease turns the limit normal by tens of degrees within a strip far narrower than a pixel,
//! which no drawn depth resolves, and holding every patch along it to the tolerance sends them
//! all to the deepest depth although the strips cover a negligible share of the image.
//!
//! So the bound is allotted over the whole visible surface:
//!
//! - **Once per cage** ([`ShadingError`], measured by [`crate::patch_errors`]): each face is cut
//!   into small *area elements* (centre, mean limit normal, world area), and for every depth the
//!   world area of each element where the normal interpolated across the drawn triangles turns
//!   further than the tolerance from the limit normal (its *outlier area*) — both normals
//!   averaged over blocks of 1, 2, 4, … sample cells, since a pixel shows the mean normal of its
//!   footprint: a strip far narrower than a pixel moves that mean only by its share of it.
//! - **Per frame** ([`raise_for_shading`]): each element's world area becomes pixels by the
//!   projected-area density of a pinhole camera ([`ScreenArea::density`]), `f² · cos θ · d / Z³` (solid angle
//!   `A cos θ / d²` times `f² / cos³ α` pixels per steradian at off-axis angle `α`, `cos α =
//!   Z / d`), zero for elements behind the eye, off screen, or facing away on a closed surface
//!   (hidden there), and times the share of the element's splat that a coarse depth buffer of
//!   all elements leaves visible ([`ScreenArea::visible_density`]). Each element's outlier area is read at the largest block that fits in
//!   a pixel there. The visible pixels `V` and each face's outlier pixels at every depth follow.
//!   Starting from the silhouette depths, faces are raised greedily — the raise with the most
//!   outlier pixels removed per added triangle first, looking ahead over every deeper depth —
//!   until the outlier pixels are at most [`MODELLED_SHARE`] × 1 % of `V`. The pixels
//!   straddling a silhouette, which no area element sees, join the count as the *contour term*
//!   ([`crate::contour`]): a silhouette face's contour pixels are outliers at every depth where
//!   the normal's turn across one drawn triangle exceeds the tolerance.
//!
//! With at most 1 % of the covered pixels beyond the tolerance, their 99th percentile is within
//! it. Half of that 1 % is left for what the model does not see: occlusion beyond the coarse
//! depth buffer's resolution, pixels along silhouettes and folds where the two renders show
//! different surfaces, and elements only partly on screen.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use glam::{Mat4, Vec2, Vec3};
use rayon::prelude::*;
use subdiv_mesh::Camera;

use crate::Depth;
use crate::contour::contour_turns;
use crate::pixel_error::{PatchError, PatchErrors};

/// The share of the visible pixels whose shading error may exceed the tolerance: 1 %, as the
/// benchmark's 99th percentile.
pub const OUTLIER_SHARE: f32 = 0.01;

/// The part of [`OUTLIER_SHARE`] the modelled normal error may spend: one half, the other left
/// for what the model does not see (see the module documentation).
pub const MODELLED_SHARE: f32 = 0.5;

/// A small piece of a face's limit surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaElement {
    /// Area-weighted centre.
    pub centre: Vec3,
    /// Unit mean limit normal (zero when the normals cancel).
    pub normal: Vec3,
    /// World area.
    pub area: f32,
    /// Edge length of one sample cell of the element (`sqrt(area / cells)`): the unit of the
    /// footprint scales of [`ShadingError::outlier_area`].
    pub cell: f32,
}

/// The shading data of one cage face, for one tolerance.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShadingError {
    /// The face's area elements.
    pub elements: Vec<AreaElement>,
    /// Per element `k`, depth `l` and footprint scale `s` (`(k * depths + l) * scales + s`,
    /// `depths = max_depth + 1`): the world area of element `k` where the interpolated normal
    /// at depth `l`, averaged over blocks of `2^s × 2^s` sample cells, is further than the
    /// tolerance from the limit normal averaged alike. A pixel shows the mean normal of its
    /// footprint, so a strip narrower than a pixel counts only as far as it moves that mean.
    pub outlier_area: Vec<f32>,
    /// Footprint scales per element and depth.
    pub scales: usize,
    /// Triangles drawn for the face at depth `d`: `2 · weight · 4^d` (1 for a quad patch,
    /// `n / 4` for an n-gon's `n` level-1 patches).
    pub weight: f32,
}

impl ShadingError {
    /// Depths the table covers (`max_depth + 1`).
    #[inline]
    fn depths(&self) -> usize {
        self.outlier_area.len() / (self.elements.len() * self.scales).max(1)
    }

    /// The largest footprint scale whose blocks fit in a pixel at `density` pixels per world
    /// area for element `e`.
    #[inline]
    fn scale(&self, e: &AreaElement, density: f32) -> usize {
        // A pixel's footprint is 1 / sqrt(density) world units on a side.
        let cells = 1.0 / (density.sqrt() * e.cell);
        if cells.is_nan() || cells < 2.0 {
            return 0;
        }
        (cells.log2().floor() as usize).min(self.scales.saturating_sub(1))
    }

    /// Triangles drawn at depth `d`.
    #[inline]
    fn triangles(&self, d: usize) -> f32 {
        2.0 * self.weight * (1u64 << (2 * d)) as f32
    }
}

/// What [`ScreenArea::density`] needs of a camera, computed once per frame.
#[derive(Clone, Copy, Debug)]
pub struct ScreenArea {
    view: Mat4,
    focal: f32,
    size: Vec2,
    closed: bool,
}

impl ScreenArea {
    /// For `camera`; `closed`: the surface has no boundary or holes, so what faces away is
    /// hidden.
    pub fn new(camera: &Camera, closed: bool) -> ScreenArea {
        ScreenArea {
            view: camera.view_matrix(),
            focal: camera.focal_pixels(),
            size: Vec2::new(camera.width as f32, camera.height as f32),
            closed,
        }
    }

    /// Pixels covered by a world area of 1 at element `e` (see the module documentation); zero
    /// when hidden: behind the eye, centre off screen, or facing away on a closed surface.
    #[inline]
    pub fn density(&self, e: &AreaElement) -> f32 {
        self.splat(e).map_or(0.0, |s| s.density)
    }

    /// Where element `e` lands on screen, or `None` when hidden (see [`Self::density`]).
    #[inline]
    fn splat(&self, e: &AreaElement) -> Option<Splat> {
        // View space: the eye at the origin looking down -Z.
        let c = self.view.transform_point3(e.centre);
        let z = -c.z;
        let d = c.length();
        if z <= 1e-6 * d {
            return None;
        }
        let pixel = Vec2::new(c.x, -c.y) * (self.focal / z) + self.size * 0.5;
        if pixel.cmplt(Vec2::ZERO).any() || pixel.cmpgt(self.size).any() {
            return None;
        }
        // Cosine between the normal and the direction to the eye.
        let facing = -self.view.transform_vector3(e.normal).dot(c) / d;
        let cos = if self.closed { facing } else { facing.abs() };
        if cos <= 0.0 {
            return None;
        }
        let density = self.focal * self.focal * cos * d / (z * z * z);
        Some(Splat {
            pixel,
            // Half the side of a square of the element's projected area.
            half: 0.5 * (e.area * density).sqrt(),
            z,
            density,
        })
    }

    /// The cells of the occlusion grid (cell size [`OCCLUSION_CELL`] pixels) a splat covers.
    #[inline]
    fn cells(&self, s: &Splat) -> (std::ops::Range<usize>, std::ops::Range<usize>, usize) {
        let cols = (self.size.x / OCCLUSION_CELL).ceil().max(1.0) as usize;
        let rows = (self.size.y / OCCLUSION_CELL).ceil().max(1.0) as usize;
        let cell = |v: f32, n: usize| ((v / OCCLUSION_CELL).max(0.0) as usize).min(n - 1);
        let x = cell(s.pixel.x - s.half, cols)..cell(s.pixel.x + s.half, cols) + 1;
        let y = cell(s.pixel.y - s.half, rows)..cell(s.pixel.y + s.half, rows) + 1;
        (x, y, cols)
    }

    /// Per element of `elements` (flattened over faces by the caller): its visible pixels per
    /// world area, [`Self::density`] times the share of its splat not behind a nearer element
    /// (a coarse depth buffer of element centres, [`OCCLUSION_CELL`] pixels per cell; an element
    /// is visible in a cell when its depth is within its own size of the cell's nearest).
    pub fn visible_density<'a>(
        &self,
        elements: impl Iterator<Item = &'a AreaElement> + Clone,
        out: &mut Vec<f32>,
    ) {
        let mut both = Vec::new();
        self.densities(elements, &mut both);
        out.clear();
        out.extend(both.iter().map(|&(visible, _)| visible));
    }

    /// [`Self::visible_density`] and [`Self::density`] of every element, as pairs (each splat
    /// computed once; splats and visible shares in parallel).
    pub fn densities<'a>(
        &self,
        elements: impl Iterator<Item = &'a AreaElement>,
        out: &mut Vec<(f32, f32)>,
    ) {
        let cols = (self.size.x / OCCLUSION_CELL).ceil().max(1.0) as usize;
        let rows = (self.size.y / OCCLUSION_CELL).ceil().max(1.0) as usize;
        let elements: Vec<&AreaElement> = elements.collect();
        let splats: Vec<Option<(Splat, f32)>> = elements
            .par_iter()
            .with_min_len(PAR_ELEMENTS)
            .map(|e| self.splat(e).map(|s| (s, 2.0 * e.area.sqrt())))
            .collect();
        let mut nearest = vec![f32::INFINITY; cols * rows];
        for (s, _) in splats.iter().flatten() {
            let (xs, ys, cols) = self.cells(s);
            for y in ys {
                for z in &mut nearest[y * cols + xs.start..y * cols + xs.end] {
                    *z = z.min(s.z);
                }
            }
        }
        splats
            .par_iter()
            .with_min_len(PAR_ELEMENTS)
            .map(|splat| {
                let Some((s, slack)) = splat else {
                    return (0.0, 0.0);
                };
                let (xs, ys, cols) = self.cells(s);
                let (mut seen, mut all) = (0usize, 0usize);
                for y in ys {
                    for &z in &nearest[y * cols + xs.start..y * cols + xs.end] {
                        all += 1;
                        seen += usize::from(s.z <= z + slack);
                    }
                }
                (s.density * seen as f32 / all.max(1) as f32, s.density)
            })
            .collect_into_vec(out);
    }
}

/// Elements per parallel task of [`ScreenArea::densities`], and faces per task of
/// [`OutlierTable::new`]'s rows (16 elements each): enough work per task to outweigh handing
/// it out.
const PAR_ELEMENTS: usize = 1024;
const PAR_FACES: usize = 64;

/// Cell size of the occlusion grid of [`ScreenArea::visible_density`], in pixels: elements are
/// a few pixels wide where the shading bound matters.
pub const OCCLUSION_CELL: f32 = 2.0;

/// An element on screen.
struct Splat {
    pixel: Vec2,
    half: f32,
    z: f32,
    density: f32,
}

/// One candidate raise of a face, ordered by its gain per unit of cost (outlier pixels per
/// added triangle here, estimated error per predicted second in [`crate::frame_budget`]); ties
/// go to the lower face index, so the choice is deterministic.
pub(crate) struct Raise {
    pub(crate) ratio: f64,
    pub(crate) face: usize,
    pub(crate) from: Depth,
    pub(crate) to: Depth,
}

impl PartialEq for Raise {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Raise {}
impl PartialOrd for Raise {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Raise {
    fn cmp(&self, o: &Self) -> Ordering {
        // Ties go to the lower face index, so the result is deterministic.
        self.ratio
            .total_cmp(&o.ratio)
            .then_with(|| o.face.cmp(&self.face))
    }
}

/// The best raise of face `f` from depth `d`: the deeper depth with the most outlier pixels
/// removed per added triangle (none when no deeper depth removes any).
fn best_raise(f: usize, d: Depth, outliers: &[f32], e: &ShadingError, max: Depth) -> Option<Raise> {
    let now = outliers[d as usize];
    (d + 1..=max)
        .filter_map(|to| {
            let gain = now - outliers[to as usize];
            let cost = e.triangles(to as usize) - e.triangles(d as usize);
            (gain > 0.0).then(|| Raise {
                ratio: f64::from(gain / cost.max(f32::MIN_POSITIVE)),
                face: f,
                from: d,
                to,
            })
        })
        .max()
}

/// Per face and depth, the outlier pixels a frame would show (see the module documentation):
/// the visible pixels of each face whose drawn normal turns further than the tolerance from
/// the limit normal at each depth, its contour term included; and the frame's visible pixels.
#[derive(Clone, Debug, Default)]
pub struct OutlierTable {
    /// Depths per face (`max_depth + 1`).
    pub levels: usize,
    /// `rows[f * levels + d]`: outlier pixels of face `f` at depth `d` (0 for inactive faces).
    pub rows: Vec<f32>,
    /// Visible pixels of the active faces (each element's projected area times the share of its
    /// splat no nearer element hides).
    pub visible: f64,
    /// Per face: its visible pixels.
    pub face_visible: Vec<f32>,
}

impl OutlierTable {
    /// The outlier pixels of face `f` at each depth.
    #[inline]
    pub fn row(&self, f: usize) -> &[f32] {
        &self.rows[f * self.levels..(f + 1) * self.levels]
    }

    /// The table for `camera`: `active[f]` is whether face `f` is drawn (missing entries count
    /// as drawn); `contour_px[f]` the length in pixels of the contour through face `f` (0 when
    /// it holds none; missing entries count 0), whose visible share counts as outlier pixels at
    /// the depths where the face's contour turn exceeds the tolerance ([`crate::contour`]);
    /// depths `0..=max_depth`.
    pub fn new(
        camera: &Camera,
        errors: &PatchErrors,
        active: &[bool],
        contour_px: &[f32],
        max_depth: Depth,
    ) -> OutlierTable {
        let levels = max_depth as usize + 1;
        let faces = &errors.faces;
        let screen = ScreenArea::new(camera, errors.closed);
        let is_active = |f: usize| active.get(f).copied().unwrap_or(true);
        let mut densities = Vec::new();
        screen.densities(
            faces
                .iter()
                .enumerate()
                .filter(|&(f, _)| is_active(f))
                .flat_map(|(_, p)| &p.shading.elements),
            &mut densities,
        );
        // Where each active face's elements start among the densities.
        let mut starts = vec![0usize; faces.len()];
        let mut at = 0;
        for (f, p) in faces.iter().enumerate() {
            starts[f] = at;
            if is_active(f) {
                at += p.shading.elements.len();
            }
        }
        let tolerance = errors.shading_tolerance;
        let mut rows = vec![0.0f32; faces.len() * levels];
        let mut face_visible = vec![0.0f32; faces.len()];
        rows.par_chunks_mut(levels)
            .zip(face_visible.par_iter_mut())
            .enumerate()
            .with_min_len(PAR_FACES)
            .for_each_init(
                || vec![0.0f32; levels],
                |turns, (f, (row, seen))| {
                    if is_active(f) {
                        let p = &faces[f];
                        let n = p.shading.elements.len();
                        let d = densities.get(starts[f]..starts[f] + n).unwrap_or(&[]);
                        let contour = contour_px.get(f).copied().unwrap_or(0.0);
                        *seen = face_row(p, d, contour, tolerance, row, turns);
                    }
                },
            );
        // Summed in face and element order, as the frame's visible pixels always are.
        let mut visible = 0.0f64;
        for (f, p) in faces.iter().enumerate().filter(|&(f, _)| is_active(f)) {
            let d = densities.get(starts[f]..).unwrap_or(&[]);
            for (el, &(density, _)) in p.shading.elements.iter().zip(d) {
                if density != 0.0 {
                    visible += (el.area * density) as f64;
                }
            }
        }
        OutlierTable {
            levels,
            rows,
            visible,
            face_visible,
        }
    }
}

/// Face `p`'s outlier pixels at each depth into `row` (zeroed), from its elements' visible and
/// projected densities `d` and its contour's length in pixels; returns its visible pixels.
/// `turns`: scratch, one entry per depth.
fn face_row(
    p: &PatchError,
    d: &[(f32, f32)],
    contour: f32,
    tolerance: f32,
    row: &mut [f32],
    turns: &mut [f32],
) -> f32 {
    let e = &p.shading;
    let depths = e.depths();
    // Projected and visible pixels of the face, for the visible share of its contour.
    let (mut projected, mut seen) = (0.0f32, 0.0f32);
    for (k, (el, &(density, raw))) in e.elements.iter().zip(d).enumerate() {
        if density == 0.0 {
            continue;
        }
        seen += el.area * density;
        projected += el.area * raw;
        let s = e.scale(el, density);
        let areas = &e.outlier_area[k * depths * e.scales..(k + 1) * depths * e.scales];
        for (o, a) in row.iter_mut().zip(areas.chunks(e.scales)) {
            *o += a[s] * density;
        }
    }
    if contour > 0.0 && seen > 0.0 && tolerance < std::f32::consts::PI {
        let pixels = contour * (seen / projected.max(seen));
        contour_turns(p, turns);
        for (o, &t) in row.iter_mut().zip(turns.iter()) {
            if t > tolerance {
                *o += pixels;
            }
        }
    }
    seen
}

/// Raises `depth` (one entry per face, the silhouette depths) until the outlier pixels of the
/// frame are at most [`MODELLED_SHARE`] × [`OUTLIER_SHARE`] of its visible pixels, greedily by
/// outlier pixels removed per added triangle (see the module documentation). `active[f]` is
/// whether face `f` is drawn; `contour_px[f]` the length in pixels of the contour through face
/// `f` (0 when it holds none; missing entries count 0), whose visible share counts as outlier
/// pixels at the depths where the face's contour turn exceeds the tolerance
/// ([`crate::contour`]); depths never exceed `max_depth`. Returns the estimated share of outlier
/// pixels after the raise.
pub fn raise_for_shading(
    camera: &Camera,
    errors: &PatchErrors,
    active: &[bool],
    contour_px: &[f32],
    depth: &mut [Depth],
    max_depth: Depth,
) -> f32 {
    let faces = &errors.faces;
    let t = OutlierTable::new(camera, errors, active, contour_px, max_depth);
    let is_active = |f: usize| active.get(f).copied().unwrap_or(true);
    let levels = t.levels;
    let mut outlier: f64 = (0..faces.len())
        .filter(|&f| is_active(f))
        .map(|f| t.row(f)[(depth[f] as usize).min(levels - 1)] as f64)
        .sum();
    let visible = t.visible;
    let budget = (MODELLED_SHARE * OUTLIER_SHARE) as f64 * visible;
    if outlier > budget {
        let mut heap: BinaryHeap<Raise> = (0..faces.len())
            .filter_map(|f| best_raise(f, depth[f], t.row(f), &faces[f].shading, max_depth))
            .collect();
        while outlier > budget
            && let Some(r) = heap.pop()
        {
            if depth[r.face] != r.from {
                continue;
            }
            let row = t.row(r.face);
            outlier -= (row[r.from as usize] - row[r.to as usize]) as f64;
            depth[r.face] = r.to;
            if let Some(next) = best_raise(r.face, r.to, row, &faces[r.face].shading, max_depth) {
                heap.push(next);
            }
        }
    }
    if visible > 0.0 {
        (outlier.max(0.0) / visible) as f32
    } else {
        0.0
    }
}

#[cfg(test)]
#[path = "shading_tests.rs"]
mod tests;
