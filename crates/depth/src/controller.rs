//! Frame-rate control by feedback (Funkhouser and Séquin 1993, as used in Settgast et al. 2004,
//! Section 3.1): "Starting with the tessellation depths assigned from geometric properties,
//! patches are moved to the neighbouring lower depth for decreasing detail and to the
//! neighbouring higher depth for increasing detail. We always start by adjusting the maximum
//! depth `maxsd` for rapid adjustment. The amount of adjustment is decreased as the frame rate
//! gets closer to the target frame rate."
//!
//! Two knobs, in that order: the cap (the adjusted `maxsd`), moved one level per decision while
//! the frame time is off by more than [`CAP_RATIO`]; then the movable patches holding a signed
//! share of their triangles moved one level (up: the highest [`priority`](crate::priority) first; down: the lowest
//! first), updated in proportion to the remaining error so the steps shrink near the target.
//! Back faces are never raised.
//!
//! **Noise:** a frame time on a loaded machine can be off by a factor of two or more for one
//! frame (other processes, the first frame after a depth rise tessellating its new patches). The
//! controller therefore looks at the last [`WINDOW`] frame times measured *since its last
//! change* (so every sample shows the current depths), does nothing until it has them, and acts
//! only when all of them are off the same way (all slower or all faster than the target), by the
//! one closest to the target: the smallest error the window proves. One outlier moves nothing;
//! noise that straddles the target moves nothing; a real offset moves by no more than it
//! certainly is.
//!
//! **Cost model** behind the constants: a frame's time is taken as proportional to its
//! triangles, and a patch at depth `d` has `2 * 4^d` of them, so one level costs a factor
//! [`LEVEL_FACTOR`] per patch.
//!
//! Pure and deterministic: the same frame times and assignments give the same depths.

use crate::Depth;
use crate::assign::{Assignment, Class, priority};

/// Triangles per patch grow by this factor per level (`2 * 4^d` for a quad at depth `d`).
pub const LEVEL_FACTOR: f32 = 4.0;

/// The cap moves while the frame time is off by more than this ratio, `sqrt(LEVEL_FACTOR)`.
/// One cap level changes the frame time by a factor of at most [`LEVEL_FACTOR`], so from a
/// ratio `r > 2` it lands above `r / 4 > 1/2`: closer to the target in log terms than `r`
/// (`|ln r - ln 4| < |ln r|` exactly when `r > 2`), and never past the opposite threshold, so
/// the cap cannot oscillate between two levels.
pub const CAP_RATIO: f32 = 2.0;

/// Dead band, as a log ratio of frame time to target: `ln(40/39)`, the steady-state accuracy
/// the paper reports (39-40 fps for a 40 fps target, Section 5). Within it nothing moves,
/// which keeps timer noise from reshuffling patches (and the patch cache) every frame.
pub const TOLERANCE: f32 = 0.025_317_808; // ln(40 / 39)

/// Frame times per decision: 3, the fewest of which one outlier cannot decide alone (with 2, an
/// outlier and a frame on the same side of the target would).
pub const WINDOW: usize = 3;

/// Fraction of the model's correction applied per frame. The share update is a Newton step on
/// the cost model; if a share really costs `k` times what the model assumes, the error
/// shrinks by `|1 - GAIN k|` per frame, which converges for `0 < k < 2 / GAIN = 4`. The model
/// counts a patch at depth `d` as `4^d` triangles; an n-gon has `n/4` times that at `d >= 1`
/// and `n` times at depth 0 (`k` up to 2 for pentagons, 3 for hexagons), and the share of
/// movable triangles is at most all of them (`k <= 1`), so `GAIN = 2 / LEVEL_FACTOR` keeps
/// every such mismatch inside the range, at the cost of about two frames per halving of the
/// error where the model is exact.
pub const GAIN: f32 = 2.0 / LEVEL_FACTOR;

/// Relative cost of moving patches holding a share `s` of the movable triangles one level
/// (`s > 0`: up, the moved triangles multiply by `LEVEL_FACTOR`; `s < 0`: down, by
/// `1 / LEVEL_FACTOR`), taking all triangles as movable. Where only a fraction `m` of them is,
/// the true slope is `m` times the model's: within the convergence range of [`GAIN`].
fn model(s: f32) -> f32 {
    if s >= 0.0 {
        1.0 + (LEVEL_FACTOR - 1.0) * s
    } else {
        1.0 + (1.0 - 1.0 / LEVEL_FACTOR) * s
    }
}

/// The share whose [`model`] cost is `c`.
fn model_inverse(c: f32) -> f32 {
    if c >= 1.0 {
        (c - 1.0) / (LEVEL_FACTOR - 1.0)
    } else {
        (c - 1.0) / (1.0 - 1.0 / LEVEL_FACTOR)
    }
}

/// The feedback controller.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameRateController {
    target: f32,
    max_depth: Depth,
    cap: Depth,
    share: f32,
    /// Frame times fed since the last change (the first `seen` are valid).
    recent: [f32; WINDOW],
    seen: usize,
}

impl FrameRateController {
    /// A controller aiming at `target_fps`, for depths up to `max_depth`.
    ///
    /// ```
    /// use subdiv_depth::{Assignment, Class, FrameRateController};
    /// let mut c = FrameRateController::new(30.0, 5);
    /// for _ in 0..3 {
    ///     c.update(0.2); // 5 fps: six times too slow, the cap drops first (after 3 frames)
    /// }
    /// assert_eq!((c.cap(), c.share()), (4, 0.0));
    /// let mut a = Assignment {
    ///     depth: vec![5, 3, 1],
    ///     active: vec![true; 3],
    ///     class: vec![Class::Front; 3],
    ///     radius: vec![100.0; 3],
    ///     curvature: vec![2; 3],
    /// };
    /// c.apply(&mut a);
    /// assert_eq!(a.depth, [4, 3, 1]);
    /// ```
    pub fn new(target_fps: f32, max_depth: Depth) -> FrameRateController {
        FrameRateController {
            target: 1.0 / target_fps.max(1e-3),
            max_depth,
            cap: max_depth,
            share: 0.0,
            recent: [0.0; WINDOW],
            seen: 0,
        }
    }

    /// Changes the target frame rate.
    pub fn set_target_fps(&mut self, fps: f32) {
        self.target = 1.0 / fps.max(1e-3);
    }
    /// Frame times kept for the next decision (fewer than 3, `WINDOW`).
    pub fn pending(&self) -> usize {
        self.seen
    }
    /// The target frame rate.
    pub fn target_fps(&self) -> f32 {
        1.0 / self.target
    }
    /// The current depth cap (the adjusted `maxsd`).
    pub fn cap(&self) -> Depth {
        self.cap
    }
    /// The share of the movable patches' triangles currently moved one level (negative: down).
    pub fn share(&self) -> f32 {
        self.share
    }

    /// Feeds the time the last frame took (seconds). Once 3 valid times (`WINDOW`) are in since
    /// the last change, and on every later frame over the last 3: if all are slower than the
    /// target the fastest of them decides, if all are faster the slowest, else nothing moves; a
    /// change starts a new window.
    pub fn update(&mut self, frame_time: f32) {
        if !(frame_time.is_finite() && frame_time > 0.0) {
            return;
        }
        self.recent[self.seen] = frame_time;
        self.seen += 1;
        if self.seen < WINDOW {
            return;
        }
        let mut w = self.recent;
        w.sort_unstable_by(f32::total_cmp);
        let (fastest, slowest) = (w[0], w[WINDOW - 1]);
        let before = (self.cap, self.share);
        if fastest > self.target {
            self.decide(fastest);
        } else if slowest < self.target {
            self.decide(slowest);
        }
        // A change invalidates the window (its frames show the old depths); otherwise slide.
        if (self.cap, self.share) != before {
            self.seen = 0;
        } else {
            self.recent.copy_within(1.., 0);
            self.seen = WINDOW - 1;
        }
    }

    /// One decision on a (filtered) frame time.
    fn decide(&mut self, frame_time: f32) {
        let r = frame_time / self.target; // > 1: too slow
        if r.ln().abs() <= TOLERANCE {
            return;
        }
        // `maxsd` first, for rapid adjustment.
        if r > CAP_RATIO && self.cap > 0 {
            self.cap -= 1;
            self.share = 0.0;
            return;
        }
        if r < 1.0 / CAP_RATIO && self.cap < self.max_depth {
            self.cap += 1;
            self.share = 0.0;
            return;
        }
        // Then the share: the model's share for the cost that would meet the target, damped.
        let want = model_inverse(model(self.share) / r);
        let next = self.share + GAIN * (want - self.share);
        self.share = if next > 1.0 && self.cap < self.max_depth {
            self.cap += 1;
            0.0
        } else if next < -1.0 && self.cap > 0 {
            self.cap -= 1;
            0.0
        } else {
            next.clamp(-1.0, 1.0)
        };
    }

    /// Applies the control to a frame's geometric depths: every depth capped at [`Self::cap`],
    /// then `|share|` of the movable patches moved one level. Up: the non-back patches below
    /// the cap, highest [`priority`] first. Down: the patches above depth 0, lowest priority
    /// first. Priorities are taken at the capped depths; ties go to the lower face index.
    pub fn apply(&self, a: &mut Assignment) {
        for d in &mut a.depth {
            *d = (*d).min(self.cap);
        }
        if self.share == 0.0 {
            return;
        }
        let up = self.share > 0.0;
        let mut movable: Vec<(f32, usize, f32)> = (0..a.depth.len())
            .filter(|&f| {
                if up {
                    a.class[f] != Class::Back && a.depth[f] < self.cap
                } else {
                    a.depth[f] > 0
                }
            })
            .map(|f| {
                let p = priority(a.radius[f], a.curvature[f], a.depth[f]);
                (p, f, LEVEL_FACTOR.powi(a.depth[f] as i32))
            })
            .collect();
        movable.sort_unstable_by(|x, y| {
            let by_priority = if up {
                y.0.total_cmp(&x.0)
            } else {
                x.0.total_cmp(&y.0)
            };
            by_priority.then(x.1.cmp(&y.1))
        });
        // The share counts triangles, not patches, so the cost model holds whatever depths the
        // prioritised patches have.
        let budget = self.share.abs() * movable.iter().map(|m| m.2).sum::<f32>();
        let mut moved = 0.0;
        for &(_, f, tris) in &movable {
            if moved >= budget {
                break;
            }
            moved += tris;
            if up {
                a.depth[f] += 1;
            } else {
                a.depth[f] -= 1;
            }
        }
    }
}

#[cfg(test)]
#[path = "controller_tests.rs"]
mod tests;
