//! Frame-rate control by feedback (Funkhouser and Séquin 1993, as used in Settgast et al. 2004,
//! Section 3.1): "Starting with the tessellation depths assigned from geometric properties,
//! patches are moved to the neighbouring lower depth for decreasing detail and to the
//! neighbouring higher depth for increasing detail. We always start by adjusting the maximum
//! depth `maxsd` for rapid adjustment. The amount of adjustment is decreased as the frame rate
//! gets closer to the target frame rate."
//!
//! Two knobs, in that order: the cap (the adjusted `maxsd`), moved one level per decision while
//! the frame time is off by more than [`CAP_RATIO`]; then movable patches holding a signed
//! share of the frame's triangles moved one level (up: the highest
//! [`priority`](crate::priority) first; down: the lowest first), updated in proportion to the
//! remaining error so the steps shrink near the target.
//! Back faces are never raised.
//!
//! **Noise:** a frame time on a loaded machine can be off by a factor of two or more for one
//! frame (other processes, the first frame after a depth rise tessellating its new patches),
//! and by ±20 % for many. The controller therefore decides on the **median** of the last
//! [`WINDOW`] frame times measured *since its last change* (so every sample shows the current
//! depths), and does nothing until it has them: fewer than half the window being spikes moves
//! nothing, and the median estimates the typical frame time however far a spike
//! goes (the mean follows the spike). On top, **hysteresis**: once a
//! decision found the filtered time within [`TOLERANCE`] of the target the controller *holds*
//! and acts again only beyond [`HOLD`]; while not holding it acts down to [`TOLERANCE`]. Noise
//! that leaves the median inside the ±10 % band therefore reshuffles no patch (and no patch
//! cache), and a real change of load or view is corrected down to the paper's accuracy.
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
/// the paper reports (39-40 fps for a 40 fps target, Section 5). A controller that is not
/// holding acts until the filtered frame time is within it, then holds (see [`HOLD`]).
pub const TOLERANCE: f32 = 0.025_317_808; // ln(40 / 39)

/// Frame times per decision, the median taken over them: 5, so that two spikes among them (the
/// first frame after a change, tessellating its new patches, and one disturbance) cannot move
/// it, and a burst of load must last 3 frames to count. Far off target this costs 5 frames per
/// cap level, 10 from 4 times too slow.
pub const WINDOW: usize = 5;

/// Hysteresis band, as a log ratio: `ln 1.1`, the ±10 % within which Fig. 7 counts a frame on
/// target. A holding controller acts only when the filtered frame time leaves it, so noise of
/// the median inside it moves nothing.
pub const HOLD: f32 = 0.095_310_18; // ln(1.1)

/// Fraction of the model's correction applied per frame. The share update is a Newton step on
/// the cost model; if a share really costs `k` times what the model assumes, the error
/// shrinks by `|1 - GAIN k|` per frame, which converges for `0 < k < 2 / GAIN = 4`. The model
/// counts a patch at depth `d` as `4^d` triangles; an n-gon has `n/4` times that at `d >= 1`
/// and `n` times at depth 0 (`k` up to 2 for pentagons, 3 for hexagons), and the share of
/// triangles moved is the share of the frame's (`k = 1`) until the movable patches run out
/// (`k < 1`), so `GAIN = 2 / LEVEL_FACTOR` keeps
/// every such mismatch inside the range, at the cost of about two decisions per halving of the
/// error where the model is exact.
pub const GAIN: f32 = 2.0 / LEVEL_FACTOR;

/// Relative cost of moving patches holding a share `s` of the frame's triangles one level
/// (`s > 0`: up, the moved triangles multiply by `LEVEL_FACTOR`; `s < 0`: down, by
/// `1 / LEVEL_FACTOR`). Exact while enough patches are movable; beyond, the moves saturate
/// and the true slope is below the model's: within the convergence range of [`GAIN`].
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

/// Standard error of the median of [`WINDOW`] samples per unit of their median absolute
/// deviation: the MAD of normal noise is `0.6745 sigma`, and the median of `n` samples has
/// standard error `1.2533 sigma / sqrt(n)`, so `1.2533 / (0.6745 sqrt(5))`.
pub const MEDIAN_ERROR_PER_MAD: f32 = 0.831;

/// Weight of a window in the running noise estimate: 1/4, an average over about the last 4
/// windows (20 frames), since one window's own spread estimate from 5 samples is itself noisy
/// (a window of nearly equal frames would otherwise claim no noise and take a full step).
pub const NOISE_WEIGHT: f32 = 0.25;

/// The log of a window's median frame time, and the standard error of that median estimated
/// from the window's own spread (median absolute deviation of the logs).
fn filtered(v: &[f32; WINDOW]) -> (f32, f32) {
    let mut l = v.map(f32::ln);
    l.sort_unstable_by(f32::total_cmp);
    let m = l[WINDOW / 2];
    let mut dev = l.map(|x| (x - m).abs());
    dev.sort_unstable_by(f32::total_cmp);
    (m, MEDIAN_ERROR_PER_MAD * dev[WINDOW / 2])
}

/// The feedback controller.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameRateController {
    target: f32,
    max_depth: Depth,
    cap: Depth,
    share: f32,
    /// Frame times fed since the last change, oldest first (the first `seen` are valid).
    recent: [f32; WINDOW],
    seen: usize,
    /// On target: act only beyond [`HOLD`] (hysteresis).
    holding: bool,
    /// Running estimate of the variance of a window's log median (an exponential average of
    /// the windows' own estimates, weight [`NOISE_WEIGHT`]; `None` before the first window).
    noise_var: Option<f32>,
    /// The shares at which the moves run out of patches, up and down (from the last
    /// [`Self::apply`]; 1 before the first).
    reach: (f32, f32),
}

impl FrameRateController {
    /// A controller aiming at `target_fps`, for depths up to `max_depth`.
    ///
    /// ```
    /// use subdiv_depth::{Assignment, Class, FrameRateController};
    /// let mut c = FrameRateController::new(30.0, 5);
    /// for _ in 0..5 {
    ///     c.update(0.2); // 5 fps: six times too slow, the cap drops first (after 5 frames)
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
            holding: false,
            noise_var: None,
            reach: (1.0, 1.0),
        }
    }

    /// Changes the target frame rate (the controller acts again down to [`TOLERANCE`]).
    pub fn set_target_fps(&mut self, fps: f32) {
        self.target = 1.0 / fps.max(1e-3);
        self.holding = false;
    }
    /// Frame times kept since the last change (at most 5, [`WINDOW`]).
    pub fn pending(&self) -> usize {
        self.seen
    }
    /// Whether the controller holds (the last decision found the target met within
    /// [`TOLERANCE`]; it acts again only beyond [`HOLD`]).
    pub fn holding(&self) -> bool {
        self.holding
    }
    /// The target frame rate.
    pub fn target_fps(&self) -> f32 {
        1.0 / self.target
    }
    /// The current depth cap (the adjusted `maxsd`).
    pub fn cap(&self) -> Depth {
        self.cap
    }
    /// The share of the frame's triangles (before the move) currently moved one level
    /// (negative: down).
    pub fn share(&self) -> f32 {
        self.share
    }

    /// Feeds the time the last frame took (seconds). Once 5 valid times ([`WINDOW`]) are in
    /// since the last change, every frame decides on the median of the last 5; a change starts
    /// a new window.
    pub fn update(&mut self, frame_time: f32) {
        if !(frame_time.is_finite() && frame_time > 0.0) {
            return;
        }
        if self.seen == WINDOW {
            self.recent.copy_within(1.., 0);
            self.seen -= 1;
        }
        self.recent[self.seen] = frame_time;
        self.seen += 1;
        if self.seen < WINDOW {
            return;
        }
        let before = (self.cap, self.share);
        let (log_time, window_noise) = filtered(&self.recent);
        let var = window_noise * window_noise;
        let var = match self.noise_var {
            Some(v) => v + NOISE_WEIGHT * (var - v),
            None => var,
        };
        self.noise_var = Some(var);
        self.decide(log_time, var.sqrt());
        // A change invalidates the window: its frames show the old depths.
        if (self.cap, self.share) != before {
            self.seen = 0;
        }
    }

    /// One decision on a filtered frame time (its log, and the standard error of that log).
    fn decide(&mut self, log_time: f32, noise: f32) {
        let err = log_time - self.target.ln(); // > 0: too slow
        let r = err.exp();
        let band = if self.holding { HOLD } else { TOLERANCE };
        if err.abs() <= band {
            self.holding = true;
            return;
        }
        self.holding = false;
        // `maxsd` first, for rapid adjustment, when the error is beyond CAP_RATIO by more than
        // its standard error (a noisy window near the threshold does not move a whole level).
        let far = err.abs() > CAP_RATIO.ln() + noise;
        if far && r > 1.0 && self.cap > 0 {
            self.cap -= 1;
            self.share = 0.0;
            return;
        }
        if far && r < 1.0 && self.cap < self.max_depth {
            self.cap += 1;
            self.share = 0.0;
            return;
        }
        // Then the share: the model's share for the cost that would meet the target, damped,
        // and shrunk by the error's signal-to-noise ratio (`err^2 / (err^2 + noise^2)`, the
        // weight of a measurement with that noise in a running average): far off the step is
        // nearly GAIN of the correction, inside the noise it is a small one, so successive
        // windows average the noise out instead of chasing it.
        let want = model_inverse(model(self.share) / r);
        let weight = err * err / (err * err + noise * noise);
        let next = self.share + GAIN * weight * (want - self.share);
        // Beyond the share that moves every movable patch, the cap takes over. Raising it starts
        // at the fewest triangles the new cap allows (every patch above depth 0 one level down,
        // share -1), which is about where the old cap with share 0 was: the cost stays
        // continuous instead of jumping by the whole level (share 0 at the new cap). Lowering
        // it from share -1 to the new cap's share 0 is continuous already.
        let (hi, lo) = (self.reach.0, -self.reach.1);
        self.share = if next > hi && self.cap < self.max_depth {
            self.cap += 1;
            -1.0
        } else if next < lo && self.cap > 0 {
            self.cap -= 1;
            0.0
        } else {
            next.clamp(lo, hi)
        };
    }

    /// Applies the control to a frame's geometric depths: every depth capped at [`Self::cap`],
    /// then movable patches holding `|share|` of the drawn (active) faces' triangles moved one
    /// level, as many as there are. Up: the drawn non-back patches below the cap, highest
    /// [`priority`] first. Down: the drawn patches above depth 0, lowest priority first.
    /// Priorities are taken at the capped depths; ties go to the lower face index. Records how
    /// far the share can go before the moves run out (the next decision moves the cap beyond).
    pub fn apply(&mut self, a: &mut Assignment) {
        for d in &mut a.depth {
            *d = (*d).min(self.cap);
        }
        let cap = self.cap;
        let raisable = |f: usize| a.active[f] && a.class[f] != Class::Back && a.depth[f] < cap;
        let lowerable = |f: usize| a.active[f] && a.depth[f] > 0;
        let tris = |f: usize| LEVEL_FACTOR.powi(a.depth[f] as i32);
        let (mut drawn, mut up, mut down) = (0.0f32, 0.0f32, 0.0f32);
        for f in (0..a.depth.len()).filter(|&f| a.active[f]) {
            drawn += tris(f);
            up += if raisable(f) { tris(f) } else { 0.0 };
            down += if lowerable(f) { tris(f) } else { 0.0 };
        }
        self.reach = if drawn > 0.0 {
            (up / drawn, down / drawn)
        } else {
            (0.0, 0.0)
        };
        if self.share == 0.0 {
            return;
        }
        let raise = self.share > 0.0;
        let mut movable: Vec<(f32, usize, f32)> = (0..a.depth.len())
            .filter(|&f| if raise { raisable(f) } else { lowerable(f) })
            .map(|f| {
                (
                    priority(a.radius[f], a.curvature[f], a.depth[f]),
                    f,
                    tris(f),
                )
            })
            .collect();
        movable.sort_unstable_by(|x, y| {
            let by_priority = if raise {
                y.0.total_cmp(&x.0)
            } else {
                x.0.total_cmp(&y.0)
            };
            by_priority.then(x.1.cmp(&y.1))
        });
        // The share counts the frame's triangles, not patches, so the cost model holds whatever
        // depths the prioritised patches have and however few of them are movable.
        let budget = self.share.abs() * drawn;
        let mut moved = 0.0;
        for &(_, f, t) in &movable {
            if moved >= budget {
                break;
            }
            moved += t;
            if raise {
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
