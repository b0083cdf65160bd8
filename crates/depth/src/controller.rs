//! Frame-rate control by feedback (Funkhouser and Séquin 1993, as used in Settgast et al. 2004,
//! Section 3.1): measured frame times move patches one depth down (too slow) or up (too fast).
//! The cap `maxsd` moves first for rapid changes; near the target only a fraction of the patches
//! moves, and that fraction shrinks as the frame rate approaches the target.
//!
//! Pure and deterministic: the same sequence of frame times gives the same depths.

/// The feedback controller.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameRateController {
    target: f32,
    max_depth: u8,
    cap: u8,
    shift: f32,
    /// Relative error band within which nothing changes.
    pub tolerance: f32,
    /// Relative error beyond which the cap moves (rapid adjustment).
    pub coarse: f32,
    /// Gain of the fine adjustment.
    pub gain: f32,
}

impl FrameRateController {
    /// A controller aiming at `target_fps`, for depths up to `max_depth`.
    ///
    /// ```
    /// use subdiv_depth::FrameRateController;
    /// let mut c = FrameRateController::new(30.0, 5);
    /// c.update(0.2); // 5 fps: far too slow, the cap drops at once
    /// assert_eq!(c.cap(), 4);
    /// let mut d = vec![5, 3, 1];
    /// c.apply(&mut d);
    /// assert_eq!(d[0], 4);
    /// ```
    pub fn new(target_fps: f32, max_depth: u8) -> FrameRateController {
        FrameRateController {
            target: 1.0 / target_fps.max(1e-3),
            max_depth,
            cap: max_depth,
            shift: 0.0,
            tolerance: 0.04,
            coarse: 0.6,
            gain: 0.35,
        }
    }

    /// Changes the target frame rate.
    pub fn set_target_fps(&mut self, fps: f32) {
        self.target = 1.0 / fps.max(1e-3);
    }
    /// The target frame rate.
    pub fn target_fps(&self) -> f32 {
        1.0 / self.target
    }
    /// The current depth cap (the adjusted `maxsd`).
    pub fn cap(&self) -> u8 {
        self.cap
    }
    /// The fraction of patches currently moved one level (negative: down).
    pub fn shift(&self) -> f32 {
        self.shift
    }

    /// Feeds the time the last frame took (seconds).
    pub fn update(&mut self, frame_time: f32) {
        if !(frame_time.is_finite() && frame_time > 0.0) {
            return;
        }
        let e = frame_time / self.target - 1.0; // > 0: too slow
        if e.abs() <= self.tolerance {
            return;
        }
        if e > self.coarse && self.cap > 0 {
            self.cap -= 1;
            self.shift = 0.0;
            return;
        }
        if e < -self.coarse / (1.0 + self.coarse) && self.cap < self.max_depth {
            self.cap += 1;
            self.shift = 0.0;
            return;
        }
        // Fine adjustment, proportional to the (log) error: smaller steps near the target.
        let step = (-self.gain * (1.0 + e).ln()).clamp(-0.25, 0.25);
        self.shift += step;
        if self.shift > 1.0 {
            if self.cap < self.max_depth {
                self.cap += 1;
                self.shift -= 1.0;
            } else {
                self.shift = 1.0;
            }
        } else if self.shift < -1.0 {
            if self.cap > 0 {
                self.cap -= 1;
                self.shift += 1.0;
            } else {
                self.shift = -1.0;
            }
        }
    }

    /// Applies the control to geometric depths: the cap, then a fraction `|shift|` of the patches
    /// (chosen by a fixed hash of their index, so the choice is stable between frames) moved one
    /// level down or up.
    pub fn apply(&self, depth: &mut [u8]) {
        let frac = self.shift.abs();
        for (i, d) in depth.iter_mut().enumerate() {
            let mut v = (*d).min(self.cap);
            if hash01(i as u32) < frac {
                if self.shift < 0.0 {
                    v = v.saturating_sub(1);
                } else {
                    v = (v + 1).min(self.cap);
                }
            }
            *d = v;
        }
    }
}

/// A fixed pseudo-random number in [0, 1) per index.
#[inline]
fn hash01(i: u32) -> f32 {
    let mut x = i.wrapping_mul(0x9E37_79B9) ^ 0x85EB_CA6B;
    x ^= x >> 16;
    x = x.wrapping_mul(0x7FEB_352D);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846C_A68B);
    x ^= x >> 16;
    (x >> 8) as f32 / (1u32 << 24) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Frame time of a scene whose cost is proportional to its triangles.
    fn cost(depths: &[u8], seconds_per_triangle: f32) -> f32 {
        depths
            .iter()
            .map(|&d| 2.0 * 4f32.powi(d as i32))
            .sum::<f32>()
            * seconds_per_triangle
    }

    fn run(
        geometric: &[u8],
        target_fps: f32,
        start_fps_guess: &mut FrameRateController,
        spt: f32,
        frames: usize,
    ) -> Vec<f32> {
        let mut fps = Vec::new();
        let c = start_fps_guess;
        c.set_target_fps(target_fps);
        for _ in 0..frames {
            let mut d = geometric.to_vec();
            c.apply(&mut d);
            let t = cost(&d, spt);
            fps.push(1.0 / t);
            c.update(t);
        }
        fps
    }

    #[test]
    fn converges_within_70_frames() {
        // 2320 patches (40 helmets) with geometric depths 0..4.
        let geometric: Vec<u8> = (0..2320u32).map(|i| (i % 5) as u8).collect();
        let spt = 1e-7;
        let full = 1.0 / cost(&geometric, spt);
        for target in [full * 1.8, full * 3.0, full * 0.9, full * 6.0] {
            let mut c = FrameRateController::new(target, 4);
            let fps = run(&geometric, target, &mut c, spt, 120);
            let ok = (70..120).all(|i| (fps[i] / target - 1.0).abs() <= 0.10);
            assert!(
                ok,
                "target {target:.1}: fps from frame 70: {:?}",
                &fps[70..80]
            );
        }
        // Switching targets between two levels (the paper's 14-15 -> 39-40 fps experiment).
        let mut c = FrameRateController::new(1.0, 4);
        let low = full * 1.2;
        let high = full * 3.5;
        run(&geometric, low, &mut c, spt, 80);
        let fps = run(&geometric, high, &mut c, spt, 80);
        assert!(
            (70..80).all(|i| (fps[i] / high - 1.0).abs() <= 0.10),
            "{:?}",
            &fps[60..80]
        );
    }

    #[test]
    fn deterministic_and_bounded() {
        let mut a = FrameRateController::new(60.0, 5);
        let mut b = a.clone();
        for t in [0.05, 0.03, 0.02, 0.017, 0.016, 0.01, 0.2, f32::NAN, -1.0] {
            a.update(t);
            b.update(t);
        }
        assert_eq!(a, b);
        assert!(a.cap() <= 5 && a.shift().abs() <= 1.0);
        let mut d = vec![9u8; 10];
        a.apply(&mut d);
        assert!(d.iter().all(|&x| x <= a.cap()));
    }
}
