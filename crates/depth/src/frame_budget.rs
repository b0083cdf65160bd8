//! Predictive frame-rate control (Funkhouser and Séquin 1993, the frame-rate control Settgast et
//! al. 2004 cite as their reference [16]): each frame, the per-face depths that minimise the
//! estimated screen-space error subject to the predicted frame time fitting the budget
//! ([`BudgetController`]), instead of feedback steps on the depths.
//!
//! - **Benefit** ([`face_errors`]): per face and depth, the pixels the frame would show wrong —
//!   the visible pixels whose drawn normal turns beyond the shading tolerance
//!   ([`OutlierTable`], the pixel-error mode's measurement) and, on the faces that may hold an
//!   outline (silhouette faces, faces at a boundary or hole, back faces not provably turned
//!   away), the pixels between the drawn and the true outline (its length on screen times the
//!   chord error projected to pixels).
//! - **Cost** ([`FaceCost`]): per face and depth, its triangles, and the limit points its block
//!   needs tessellated (and uploaded) when the cached block is coarser, priced by the
//!   [`FrameTimeModel`] fitted to the machine.
//! - **Choice** ([`BudgetController::choose`]): every face starts at its least depth; first the
//!   outlines: the faces that may hold one rise together, one level at a time while the whole
//!   level fits the budget, towards the least depth whose chord error stays within
//!   [`SILHOUETTE_PX`] on screen ([`silhouette_depths`]) (a wrong silhouette is the error a
//!   viewer sees first; raised face by face, a short budget would go to a few faces drawn finely
//!   while the rest of the outline stays coarse); then raises are taken greedily by error removed
//!   per predicted second (looking ahead over every deeper depth, so a step whose first level
//!   buys little but second a lot is seen), while the predicted frame time fits the budget.
//!   Back faces provably turned away ([`capped_back_faces`]) are never raised above their
//!   geometric depth; a frame's tessellation is part of its own cost, so a large raise spreads
//!   over a few frames instead of one slow one.
//! - **Feedback** ([`BudgetController::observe`]): the budget is the target shrunk by the
//!   model's recent bias, the median of the last [`WINDOW`] measured-over-predicted ratios,
//!   followed only as far as it strays beyond [`BIAS_BAND`]: one noisy frame moves no depth.
//! - **Hysteresis**: the previous frame's depths are kept while they fit the budget (within
//!   [`HOLD`]) and their estimated error is within [`HOLD`] of the new choice's: a still camera
//!   gives a still picture.

use std::collections::BinaryHeap;

use subdiv_mesh::Camera;

use crate::Depth;
use crate::assign::{Assignment, Class};
use crate::contour::contour_pixels;
use crate::frame_model::{FrameTimeModel, FrameWork};
use crate::pixel_error::{PatchErrors, outside_view, pixel_error_depth, screen_scale};
use crate::shading::{OutlierTable, Raise};
use crate::sphere::Sphere;

/// Frame times per bias estimate: the median of 9 cannot be moved by four outliers, and has a
/// third of one frame's noise; a lasting error of the model shows in it after 5 frames.
pub const WINDOW: usize = 9;

/// The budget follows the model's bias only as far as it strays beyond this band (log ratio,
/// `ln 1.02`): about twice the noise of the median of [`WINDOW`] frames whose times scatter by
/// ±4 %.
pub const BIAS_BAND: f64 = 0.019_802_627;

/// Hysteresis of the choice: the previous depths stay while their predicted time is within 3 %
/// over the budget and their estimated error within 3 % over the new choice's. With
/// [`BIAS_BAND`], the frame time settles within about 5 % of the target before noise, inside
/// the ±10 % band.
pub const HOLD: f64 = 0.03;

/// The chord error, in pixels on screen, within which [`BudgetController::choose`] first draws
/// every silhouette face: a quarter of a pixel, so that the drawn and the true silhouette cover
/// the same pixels but where they cross a pixel's edge.
pub const SILHOUETTE_PX: f32 = 0.25;

/// Whether face `f` may hold an outline on screen: a silhouette face (its vertex normals turn
/// from facing the eye to facing away), one at the boundary or a hole of an open surface
/// (whose own edge is an outline from any side), or a back face whose limit normals are not
/// all provably turned away ([`crate::PatchError::faces_away`]): on a coarse cage the vertex classes
/// call a face back whose limit surface still turns to the eye and draws part of the outline.
fn holds_contour(
    camera: &Camera,
    errors: &PatchErrors,
    spheres: &[Sphere],
    a: &Assignment,
    f: usize,
) -> bool {
    match a.class[f] {
        Class::Silhouette => true,
        _ if errors.faces[f].outline => true,
        Class::Back => !errors.faces[f].faces_away(camera, &spheres[f]),
        Class::Front => false,
    }
}

/// Per face: whether the predictive control keeps it at or below its geometric depth: the back
/// faces ([`Class::Back`]) whose limit normals all provably face away from the eye. The other
/// back faces may hold part of the outline ([`holds_contour`]) and are raised like any face.
pub fn capped_back_faces(
    camera: &Camera,
    errors: &PatchErrors,
    spheres: &[Sphere],
    a: &Assignment,
) -> Vec<bool> {
    (0..a.class.len())
        .map(|f| a.class[f] == Class::Back && !holds_contour(camera, errors, spheres, a, f))
        .collect()
}

/// Per face: the least depth whose chord error is within [`SILHOUETTE_PX`] on screen, for the
/// active faces in view that may hold an outline (silhouette faces, faces at the boundary or a
/// hole; [`pixel_error_depth`]); 0 for the others.
pub fn silhouette_depths(
    camera: &Camera,
    errors: &PatchErrors,
    spheres: &[Sphere],
    a: &Assignment,
    max_depth: Depth,
) -> Vec<Depth> {
    (0..a.class.len())
        .map(|f| {
            if a.active[f]
                && holds_contour(camera, errors, spheres, a, f)
                && !outside_view(camera, &spheres[f])
            {
                pixel_error_depth(
                    camera,
                    &spheres[f],
                    &errors.faces[f],
                    SILHOUETTE_PX,
                    max_depth,
                )
            } else {
                0
            }
        })
        .collect()
}

/// Per face and depth `0..=max_depth`: the estimated pixels shown wrong (see the module
/// documentation), row-major (`f * (max_depth + 1) + d`). Inactive faces, faces outside the view
/// and (on a closed surface) hidden faces have none.
pub fn face_errors(
    camera: &Camera,
    errors: &PatchErrors,
    spheres: &[Sphere],
    a: &Assignment,
    max_depth: Depth,
) -> Vec<f32> {
    let levels = max_depth as usize + 1;
    let contour: Vec<f32> = (0..a.class.len())
        .map(|f| {
            if holds_contour(camera, errors, spheres, a, f) {
                contour_pixels(a.radius[f])
            } else {
                0.0
            }
        })
        .collect();
    let table = OutlierTable::new(camera, errors, &a.active, &contour, max_depth);
    let mut out = table.rows;
    for (f, e) in errors.faces.iter().enumerate() {
        let row = &mut out[f * levels..(f + 1) * levels];
        if !a.active[f] || outside_view(camera, &spheres[f]) {
            row.fill(0.0);
            continue;
        }
        if contour[f] > 0.0 {
            let scale = screen_scale(camera, &spheres[f]);
            for (d, o) in row.iter_mut().enumerate() {
                let dev = e.deviation.get(d).copied().unwrap_or(0.0) * scale;
                *o += contour[f] * dev.min(a.radius[f]);
            }
        }
    }
    out
}

/// What a face costs at a depth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceCost {
    /// Triangles per depth unit: a face draws `2 · weight · 4^d` triangles and tessellates
    /// `weight · (2^d + 1)²` points (a quad patch 1; an n-gon's level-1 patches `n / 4`; a Loop
    /// triangle `1 / 2`).
    pub weight: f32,
    /// The depth of the face's cached block (`None`: none): tessellation is free up to it.
    pub cached: Option<Depth>,
}

impl FaceCost {
    /// The work of drawing the face at depth `d` this frame.
    #[inline]
    pub fn work(&self, d: Depth) -> FrameWork {
        let w = self.weight as f64;
        let n = (1u64 << d) as f64;
        let points = if self.cached.is_some_and(|c| c >= d) {
            0.0
        } else {
            w * (n + 1.0) * (n + 1.0)
        };
        FrameWork {
            triangles: 2.0 * w * n * n,
            points,
            uploaded: points,
            pixels: 0.0,
        }
    }
}

/// The frame-time budget optimiser (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct BudgetController {
    /// Seconds per frame aimed at.
    target: f64,
    /// Log ratios measured / predicted of the last frames, oldest first (`seen` valid).
    recent: [f64; WINDOW],
    seen: usize,
    /// The bias (log ratio) the budget is corrected by.
    bias: f64,
    /// The previous frame's choice.
    previous: Vec<Depth>,
}

/// One frame's choice problem.
pub struct Choice<'a> {
    /// Per face and depth: estimated error ([`face_errors`]).
    pub errors: &'a [f32],
    /// Per face: its cost ([`FaceCost`]).
    pub costs: &'a [FaceCost],
    /// The frame's classification and geometric depths ([`crate::assign`]): inactive faces are
    /// not drawn.
    pub assignment: &'a Assignment,
    /// Per face: never raised above its depth in `assignment` (the back faces turned away from
    /// the eye, [`capped_back_faces`]).
    pub capped: &'a [bool],
    /// Per face: its least depth.
    pub min_depth: &'a [Depth],
    /// Per face: the depth it is raised to first, as far as the budget allows
    /// ([`silhouette_depths`]; empty: none).
    pub first: &'a [Depth],
    /// The deepest depth.
    pub max_depth: Depth,
    /// The frame's work outside the faces (its pixels).
    pub fixed: FrameWork,
}

impl Choice<'_> {
    fn levels(&self) -> usize {
        self.max_depth as usize + 1
    }

    /// The least and the greatest depth face `f` may take.
    fn range(&self, f: usize) -> (Depth, Depth) {
        let lo = self.min_depth[f].min(self.max_depth);
        let hi = if self.capped[f] {
            self.assignment.depth[f].clamp(lo, self.max_depth)
        } else {
            self.max_depth
        };
        (lo, hi)
    }

    fn error(&self, f: usize, d: Depth) -> f64 {
        self.errors[f * self.levels() + d as usize] as f64
    }

    fn cost(&self, model: &FrameTimeModel, f: usize, d: Depth) -> f64 {
        if !self.assignment.active[f] {
            return 0.0;
        }
        predicted_work_cost(model, &self.costs[f].work(d))
    }

    /// Predicted seconds and estimated error of `depth`.
    fn evaluate(&self, model: &FrameTimeModel, depth: &[Depth]) -> (f64, f64) {
        let mut time = model.predict(&self.fixed);
        let mut error = 0.0;
        for (f, &d) in depth.iter().enumerate() {
            if self.assignment.active[f] {
                time += self.cost(model, f, d);
                error += self.error(f, d);
            }
        }
        (time, error)
    }

    /// The best raise of face `f` from `d` that costs at most `room` seconds.
    fn best_raise(&self, model: &FrameTimeModel, f: usize, d: Depth, room: f64) -> Option<Raise> {
        let (_, hi) = self.range(f);
        let (e0, c0) = (self.error(f, d), self.cost(model, f, d));
        (d + 1..=hi)
            .filter_map(|to| {
                let gain = e0 - self.error(f, to);
                let cost = self.cost(model, f, to) - c0;
                (gain > 0.0 && cost <= room).then(|| Raise {
                    ratio: gain / cost.max(1e-12),
                    face: f,
                    from: d,
                    to,
                })
            })
            .max()
    }
}

/// The work-dependent part of a prediction: the model's prediction less its fixed part.
fn predicted_work_cost(model: &FrameTimeModel, w: &FrameWork) -> f64 {
    model.predict(w) - model.predict(&FrameWork::default())
}

impl BudgetController {
    /// A controller aiming at `target_fps`.
    pub fn new(target_fps: f32) -> BudgetController {
        BudgetController {
            target: 1.0 / f64::from(target_fps.max(1e-3)),
            recent: [0.0; WINDOW],
            seen: 0,
            bias: 0.0,
            previous: Vec::new(),
        }
    }

    /// The target frame rate.
    pub fn target_fps(&self) -> f32 {
        (1.0 / self.target) as f32
    }

    /// Changes the target (the next choice aims at it at once).
    pub fn set_target_fps(&mut self, fps: f32) {
        self.target = 1.0 / f64::from(fps.max(1e-3));
    }

    /// The frame time the choices aim at: the target shrunk by the model's bias (seconds).
    pub fn budget(&self) -> f64 {
        self.target / self.bias.exp()
    }

    /// Feeds the last frame's measured and predicted times (seconds).
    pub fn observe(&mut self, measured: f64, predicted: f64) {
        if !(measured.is_finite() && measured > 0.0 && predicted.is_finite() && predicted > 0.0) {
            return;
        }
        if self.seen == WINDOW {
            self.recent.copy_within(1.., 0);
            self.seen -= 1;
        }
        self.recent[self.seen] = (measured / predicted).ln();
        self.seen += 1;
        if self.seen < WINDOW {
            return;
        }
        let mut v = self.recent;
        v.sort_unstable_by(f64::total_cmp);
        // Dead-zone tracking: the bias follows the median only as far as it strays beyond
        // the band, so noise that crosses the band moves the budget by little.
        let median = v[WINDOW / 2];
        let off = median - self.bias;
        if off.abs() > BIAS_BAND {
            self.bias += off - BIAS_BAND.copysign(off);
        }
    }

    /// Chooses this frame's depths into `depth` (one per face) and returns the chosen work
    /// (fixed part included) as the model predicts it.
    pub fn choose(
        &mut self,
        c: &Choice<'_>,
        model: &FrameTimeModel,
        depth: &mut [Depth],
    ) -> FrameWork {
        let n = depth.len();
        let budget = self.budget();
        for (f, d) in depth.iter_mut().enumerate() {
            *d = c.range(f).0;
        }
        let (mut time, _) = c.evaluate(model, depth);
        // The outlines first, one level at a time for all of them together, as far as the
        // whole level fits: raised face by face instead, the budget would go to a few outline
        // faces drawn finely while the rest of the outline stays at its least depth.
        let goal: Vec<Depth> = (0..n)
            .map(|f| {
                let (lo, hi) = c.range(f);
                match c.first.get(f) {
                    Some(&to) if c.assignment.active[f] => to.clamp(lo, hi),
                    _ => lo,
                }
            })
            .collect();
        loop {
            let step: Vec<usize> = (0..n).filter(|&f| depth[f] < goal[f]).collect();
            let cost: f64 = step
                .iter()
                .map(|&f| c.cost(model, f, depth[f] + 1) - c.cost(model, f, depth[f]))
                .sum();
            if step.is_empty() || time + cost > budget {
                break;
            }
            time += cost;
            for f in step {
                depth[f] += 1;
            }
        }
        let mut heap: BinaryHeap<Raise> = (0..n)
            .filter(|&f| c.assignment.active[f])
            .filter_map(|f| c.best_raise(model, f, depth[f], budget - time))
            .collect();
        while let Some(r) = heap.pop() {
            if depth[r.face] != r.from {
                continue;
            }
            let step = c.cost(model, r.face, r.to) - c.cost(model, r.face, r.from);
            if time + step > budget {
                // A smaller raise of this face may still fit.
                if let Some(s) = c.best_raise(model, r.face, r.from, budget - time) {
                    heap.push(s);
                }
                continue;
            }
            time += step;
            depth[r.face] = r.to;
            if let Some(next) = c.best_raise(model, r.face, r.to, budget - time) {
                heap.push(next);
            }
        }
        // Hysteresis: keep the previous depths while they still fit and are nearly as good.
        if self.previous.len() == n {
            let prev: Vec<Depth> = (0..n)
                .map(|f| {
                    let (lo, hi) = c.range(f);
                    self.previous[f].clamp(lo, hi)
                })
                .collect();
            let (t_prev, e_prev) = c.evaluate(model, &prev);
            let (_, e_new) = c.evaluate(model, depth);
            if t_prev <= budget * (1.0 + HOLD) && e_prev <= e_new * (1.0 + HOLD) + 1e-6 {
                depth.copy_from_slice(&prev);
            }
        }
        self.previous.clear();
        self.previous.extend_from_slice(depth);
        let mut work = c.fixed;
        for (f, &d) in depth.iter().enumerate() {
            if c.assignment.active[f] {
                let w = c.costs[f].work(d);
                work.triangles += w.triangles;
                work.points += w.points;
                work.uploaded += w.uploaded;
            }
        }
        work
    }
}

#[cfg(test)]
#[path = "frame_budget_tests.rs"]
mod tests;
