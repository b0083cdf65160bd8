//! The viewer's on-screen display: the HUD (frame rate, triangles, depth cap, frame-rate
//! control with its target, measured and predicted frame time, mode) in the top-left corner and the colour legend of the depth and DoI shadings in
//! the top-right one, drawn with Vulkan as an [`Overlay`] over the frame.

use super::FrameControl;
use crate::overlay::{self, Overlay};
use crate::scene::{self, RenderMesh, RenderOptions, Shading};

/// What the HUD shows for one frame.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct HudState {
    /// Whether the HUD is on (`I`).
    pub show: bool,
    /// Smoothed frame rate while frames run back to back; `None` while the viewer redraws
    /// only on changes (then the frame's CPU time is shown instead).
    pub fps: Option<f32>,
    /// CPU time of the previous frame in milliseconds.
    pub work_ms: f32,
    /// Triangles drawn.
    pub triangles: usize,
    /// The source's subdivision depth cap, if it has one.
    pub depth_cap: Option<u32>,
    /// The frame-rate control and its target frame rate.
    pub control: FrameControl,
    pub target_fps: f32,
    /// The previous frame's measured time in milliseconds while frames run back to back.
    pub measured_ms: Option<f32>,
    /// The source's prediction of this frame's time in milliseconds.
    pub predicted_ms: Option<f32>,
    /// Shading and the overlays that are on.
    pub shading: Shading,
    pub wire: bool,
    pub silhouettes: bool,
    pub frozen: bool,
}

impl HudState {
    /// The HUD's text lines.
    pub fn lines(&self) -> Vec<String> {
        let rate = match self.fps {
            Some(fps) => format!("fps {fps:.1}"),
            None => format!("frame {:.1} ms (idle)", self.work_ms),
        };
        let cap = self
            .depth_cap
            .map_or_else(|| String::from("-"), |d| d.to_string());
        let target = if self.control.is_on() {
            let t = self.target_fps;
            format!(
                "{} control, target {t:.0} fps {:.1} ms",
                self.control.name(),
                1e3 / t
            )
        } else {
            String::from("control off")
        };
        let time = match (self.measured_ms, self.predicted_ms) {
            (Some(m), Some(p)) => format!("frame {m:.1} ms, predicted {p:.1} ms"),
            (Some(m), None) => format!("frame {m:.1} ms"),
            (None, Some(p)) => format!("predicted {p:.1} ms"),
            (None, None) => String::from("frame time -"),
        };
        let mut mode = format!("mode {}", self.shading.name());
        for (on, name) in [
            (self.wire, " +wire"),
            (self.silhouettes, " +silhouettes"),
            (self.frozen, " +frozen"),
        ] {
            if on {
                mode.push_str(name);
            }
        }
        vec![
            rate,
            format!("triangles {}", self.triangles),
            format!("depth cap {cap}"),
            target,
            time,
            mode,
        ]
    }
}

/// The HUD (when on) and the legend (when `options.legend`) over a frame of `size` pixels
/// showing `mesh`.
pub(super) fn overlay(
    state: &HudState,
    mesh: &RenderMesh<'_>,
    options: &RenderOptions,
    size: [u32; 2],
) -> Overlay {
    let mut o = Overlay::default();
    let scale = overlay::text_scale(size);
    if state.show {
        let lines = state.lines();
        let refs: Vec<&str> = lines.iter().map(String::as_str).collect();
        let margin = 4.0 * scale as f32;
        o.panel(margin, margin, scale, &refs);
    }
    if options.legend {
        let range = scene::scalar_range(mesh, options);
        o.extend(overlay::legend(options.shading, range, size));
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hud_lines_name_every_quantity() {
        let mut state = HudState {
            show: true,
            fps: Some(59.94),
            work_ms: 3.0,
            triangles: 1234,
            depth_cap: Some(4),
            control: FrameControl::Budget,
            target_fps: 30.0,
            measured_ms: Some(33.41),
            predicted_ms: Some(32.0),
            shading: Shading::Depth,
            wire: true,
            silhouettes: false,
            frozen: true,
        };
        assert_eq!(
            state.lines(),
            [
                "fps 59.9",
                "triangles 1234",
                "depth cap 4",
                "budget control, target 30 fps 33.3 ms",
                "frame 33.4 ms, predicted 32.0 ms",
                "mode depth +wire +frozen"
            ]
        );
        state.fps = None;
        state.control = FrameControl::Off;
        state.depth_cap = None;
        state.measured_ms = None;
        state.predicted_ms = None;
        let lines = state.lines();
        assert_eq!(lines[0], "frame 3.0 ms (idle)");
        assert_eq!(lines[2], "depth cap -");
        assert_eq!(lines[3], "control off");
        assert_eq!(lines[4], "frame time -");
        let mesh = RenderMesh::default();
        let options = RenderOptions::default();
        assert!(!overlay(&state, &mesh, &options, [640, 480]).is_empty());
        state.show = false;
        assert!(overlay(&state, &mesh, &options, [640, 480]).is_empty());
    }

    #[test]
    fn c_cycles_off_budget_paper() {
        let mut c = FrameControl::Off;
        let seen: Vec<&str> = (0..4)
            .map(|_| {
                c = c.next();
                c.name()
            })
            .collect();
        assert_eq!(seen, ["budget", "paper", "off", "budget"]);
        assert!(!FrameControl::Off.is_on() && FrameControl::Paper.is_on());
    }
}
