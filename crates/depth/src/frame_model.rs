//! A frame's time predicted from the work it does ([`FrameTimeModel`]), the cost model of
//! predictive frame-rate control (Funkhouser and Séquin 1993, §4: "the time required to render
//! an object at a level of detail" estimated from the primitives it draws, here with the
//! coefficients fitted to the machine as it runs instead of measured once).
//!
//! A frame's time is taken as linear in what it does ([`FrameWork`]): a fixed part, the
//! triangles drawn (index emission, vertex and primitive work of the renderer), the limit
//! points tessellated, the vertices uploaded and the pixels covered. The coefficients are the
//! least-squares fit to the last [`HISTORY`] frames, each weighted [`FORGETTING`] times the
//! frame after it (so the fit follows the machine: another load, another renderer), refitted
//! every frame by solving the five normal equations. Three safeguards: a frame whose time lies
//! far off the prediction (a hiccup of the machine) is clipped to the noise band before it is
//! fitted, so one such frame moves the model little; a weak ridge pulls each coefficient
//! towards its prior, which decides the terms the frames do not excite (a controller that
//! tessellates nothing for a while still knows what tessellation costs); and coefficients stay
//! non-negative (work never saves time).

/// What a frame does, in the units the model is fitted in.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameWork {
    /// Triangles drawn.
    pub triangles: f64,
    /// Limit points tessellated (blocks recomputed).
    pub points: f64,
    /// Vertices uploaded (rewritten ranges of the vertex buffer).
    pub uploaded: f64,
    /// Pixels covered by the drawn surface.
    pub pixels: f64,
}

/// Number of terms of the model: the fixed part and the four of [`FrameWork`].
pub const TERMS: usize = 5;

impl FrameWork {
    /// The regressors, scaled so that a typical frame's are of order one (10^5 triangles,
    /// points and vertices, 10^6 pixels): well conditioned for the fit.
    #[inline]
    pub fn regressors(&self) -> [f64; TERMS] {
        [
            1.0,
            self.triangles * 1e-5,
            self.points * 1e-5,
            self.uploaded * 1e-5,
            self.pixels * 1e-6,
        ]
    }
}

/// Frames the fit remembers.
pub const HISTORY: usize = 128;

/// Weight of each frame relative to the frame after it: `0.98`, a memory of about 50 frames (a
/// few seconds): long enough to average single frames' noise out and to keep the slopes learnt
/// while the work varied through a stretch of frames that all do the same work; faster
/// changes of the machine are followed by the controller's bias feedback
/// ([`crate::BudgetController::observe`]).
pub const FORGETTING: f64 = 0.98;

/// Weight of the prior, as frames: the ridge counts as this many frames of scaled regressor 1
/// that all agree with the prior.
pub const PRIOR_FRAMES: f64 = 0.5;

/// Residuals beyond this many noise deviations are clipped before the fit (Huber's robust
/// regression): one frame of a busy machine moves the model as one slightly slow frame would.
pub const CLIP_DEVIATIONS: f64 = 2.5;

/// The predicted time of a frame, fitted online ([`FrameTimeModel::observe`]).
#[derive(Clone, Debug, PartialEq)]
pub struct FrameTimeModel {
    /// Seconds per unit of each regressor.
    theta: [f64; TERMS],
    prior: [f64; TERMS],
    /// The last frames: (regressors, seconds as fitted), oldest first.
    history: std::collections::VecDeque<([f64; TERMS], f64)>,
    /// Running mean absolute residual (seconds), the noise scale of the clipping.
    noise: f64,
    /// Frames fitted.
    seen: u64,
}

impl FrameTimeModel {
    /// A model starting from `prior` (seconds per regressor unit; see
    /// [`FrameWork::regressors`]).
    pub fn new(prior: [f64; TERMS]) -> FrameTimeModel {
        let prior = prior.map(|x| x.max(0.0));
        FrameTimeModel {
            theta: prior,
            prior,
            history: std::collections::VecDeque::with_capacity(HISTORY),
            noise: 0.0,
            seen: 0,
        }
    }

    /// The default prior: 5 ms a frame, 10 ms per 10^5 triangles, 5 ms per 10^5 points,
    /// 1 ms per 10^5 uploaded vertices, 5 ms per 10^6 pixels; deliberately dear (a slow
    /// software renderer), so that control starts coarse and refines as it learns.
    pub fn with_default_prior() -> FrameTimeModel {
        FrameTimeModel::new([5e-3, 10e-3, 5e-3, 1e-3, 5e-3])
    }

    /// The coefficients, seconds per regressor unit ([`FrameWork::regressors`]).
    pub fn coefficients(&self) -> [f64; TERMS] {
        self.theta
    }

    /// The predicted time of a frame doing `w`, in seconds.
    #[inline]
    pub fn predict(&self, w: &FrameWork) -> f64 {
        dot(&self.theta, &w.regressors())
    }

    /// Frames fitted so far.
    pub fn frames(&self) -> u64 {
        self.seen
    }

    /// The running noise scale: mean absolute residual, seconds.
    pub fn noise(&self) -> f64 {
        self.noise
    }

    /// Fits a frame that did `w` in `seconds` (ignored unless positive and finite).
    pub fn observe(&mut self, w: &FrameWork, seconds: f64) {
        if !(seconds.is_finite() && seconds > 0.0) {
            return;
        }
        let x = w.regressors();
        let predicted = dot(&self.theta, &x);
        let mut residual = seconds - predicted;
        // Clip to the noise band (one deviation is about 1.25 mean absolute residuals, and at
        // least 2 % of the prediction) once a noise scale is known.
        if self.seen >= 5 {
            let sigma = (1.25 * self.noise).max(0.02 * predicted.abs());
            let limit = CLIP_DEVIATIONS * sigma;
            residual = residual.clamp(-limit, limit);
        }
        let abs = (seconds - predicted).abs();
        self.noise = if self.seen == 0 {
            abs
        } else {
            // The residual counted at most three times the scale: a hiccup widens the band a
            // little, a lasting change (every residual large) widens it by a fifth a frame.
            let capped = abs.min(3.0 * self.noise.max(0.01 * predicted.abs()));
            0.9 * self.noise + 0.1 * capped
        };
        if self.history.len() == HISTORY {
            self.history.pop_front();
        }
        self.history.push_back((x, predicted + residual));
        self.seen += 1;
        self.fit();
    }

    /// Refits the coefficients to the history: weighted least squares with the ridge towards
    /// the prior, non-negative (a coefficient that comes out negative is fixed at 0 and the
    /// rest refitted).
    fn fit(&mut self) {
        let mut a = [[0.0; TERMS]; TERMS];
        let mut b = [0.0; TERMS];
        let mut w = 1.0;
        for (x, t) in self.history.iter().rev() {
            for i in 0..TERMS {
                b[i] += w * x[i] * t;
                for j in 0..TERMS {
                    a[i][j] += w * x[i] * x[j];
                }
            }
            w *= FORGETTING;
        }
        for i in 0..TERMS {
            a[i][i] += PRIOR_FRAMES;
            b[i] += PRIOR_FRAMES * self.prior[i];
        }
        let mut free = [true; TERMS];
        for _ in 0..TERMS {
            let Some(theta) = solve(&a, &b, &free) else {
                return;
            };
            match (0..TERMS).find(|&k| free[k] && theta[k] < 0.0) {
                Some(k) => free[k] = false,
                None => {
                    self.theta = theta;
                    return;
                }
            }
        }
    }
}

/// Solves `a θ = b` over the free coefficients (the others 0) by Gaussian elimination with
/// partial pivoting; `None` if singular.
fn solve(
    a: &[[f64; TERMS]; TERMS],
    b: &[f64; TERMS],
    free: &[bool; TERMS],
) -> Option<[f64; TERMS]> {
    let idx: Vec<usize> = (0..TERMS).filter(|&k| free[k]).collect();
    let n = idx.len();
    let mut m: Vec<Vec<f64>> = idx
        .iter()
        .map(|&i| {
            let mut row: Vec<f64> = idx.iter().map(|&j| a[i][j]).collect();
            row.push(b[i]);
            row
        })
        .collect();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| m[i][c].abs().total_cmp(&m[j][c].abs()))?;
        if m[p][c].abs() < 1e-300 {
            return None;
        }
        m.swap(c, p);
        let pivot = m[c].clone();
        for (r, row) in m.iter_mut().enumerate() {
            if r != c {
                let f = row[c] / pivot[c];
                for (x, &y) in row[c..].iter_mut().zip(&pivot[c..]) {
                    *x -= f * y;
                }
            }
        }
    }
    let mut theta = [0.0; TERMS];
    for (r, &i) in idx.iter().enumerate() {
        theta[i] = m[r][n] / m[r][r];
    }
    Some(theta)
}

#[inline]
fn dot(a: &[f64; TERMS], b: &[f64; TERMS]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use subdiv_test_support::Rng;

    /// A machine whose frames cost 4 ms plus 30 ms per 10^5 triangles plus 8 ms per 10^5
    /// points, with multiplicative noise of a few percent and an occasional hiccup.
    fn machine(w: &FrameWork, rng: &mut Rng) -> f64 {
        let t = 4e-3 + 30e-3 * w.triangles * 1e-5 + 8e-3 * w.points * 1e-5;
        let noise = 1.0 + 0.04 * rng.unit() as f64;
        let hiccup = if rng.chance(3) { 2.5 } else { 1.0 };
        t * noise * hiccup
    }

    fn work(rng: &mut Rng) -> FrameWork {
        FrameWork {
            triangles: 2e4 + rng.next_f64() * 3e5,
            points: if rng.chance(30) {
                rng.next_f64() * 1e5
            } else {
                0.0
            },
            uploaded: 0.0,
            pixels: 3e5,
        }
    }

    #[test]
    fn the_fit_learns_the_machine_and_shrugs_off_hiccups() {
        let mut rng = Rng::splitmix(7);
        let mut m = FrameTimeModel::with_default_prior();
        for _ in 0..300 {
            let w = work(&mut rng);
            m.observe(&w, machine(&w, &mut rng));
        }
        // Prediction within 10 % of the noiseless cost over the range of work.
        for tris in [2e4, 1e5, 3e5] {
            let w = FrameWork {
                triangles: tris,
                pixels: 3e5,
                ..FrameWork::default()
            };
            let truth = 4e-3 + 30e-3 * tris * 1e-5;
            let p = m.predict(&w);
            assert!((p / truth - 1.0).abs() < 0.1, "{tris}: {p} vs {truth}");
        }
        // One huge hiccup moves the prediction by little.
        let w = FrameWork {
            triangles: 1e5,
            pixels: 3e5,
            ..FrameWork::default()
        };
        let before = m.predict(&w);
        m.observe(&w, 10.0 * before);
        let after = m.predict(&w);
        assert!(after / before < 1.1, "{before} -> {after}");
        assert!(m.coefficients().iter().all(|&c| c >= 0.0));
    }

    #[test]
    fn the_fit_follows_a_change_of_machine() {
        let mut rng = Rng::splitmix(11);
        let mut m = FrameTimeModel::with_default_prior();
        for i in 0..400 {
            let w = work(&mut rng);
            // After frame 200 the machine is twice as slow (another load).
            let slow = if i >= 200 { 2.0 } else { 1.0 };
            m.observe(&w, slow * machine(&w, &mut rng));
        }
        let w = FrameWork {
            triangles: 2e5,
            pixels: 3e5,
            ..FrameWork::default()
        };
        let truth = 2.0 * (4e-3 + 30e-3 * 2.0);
        assert!(
            (m.predict(&w) / truth - 1.0).abs() < 0.08,
            "{}",
            m.predict(&w)
        );
    }

    #[test]
    fn repeated_work_does_not_wind_the_model_up() {
        // A controller holding its target: the same work every frame, then one change.
        let mut rng = Rng::splitmix(3);
        let mut m = FrameTimeModel::with_default_prior();
        for _ in 0..100 {
            let w = work(&mut rng);
            m.observe(&w, machine(&w, &mut rng));
        }
        let w = FrameWork {
            triangles: 1e5,
            pixels: 3e5,
            ..FrameWork::default()
        };
        for _ in 0..2000 {
            m.observe(&w, 4e-3 + 30e-3);
        }
        // A new workload is still predicted sensibly.
        let other = FrameWork {
            triangles: 2e5,
            pixels: 3e5,
            ..FrameWork::default()
        };
        let truth = 4e-3 + 60e-3;
        assert!(
            (m.predict(&other) / truth - 1.0).abs() < 0.25,
            "{}",
            m.predict(&other)
        );
    }
}
