//! The viewer's on-screen display: the HUD (frame rate, triangles, depth cap, target frame
//! rate, mode) in the top-left corner and the colour legend of the depth and DoI shadings in
//! the top-right one, drawn with Vulkan as an [`Overlay`] over the frame.

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
    /// Target frame rate with frame-rate control on; `None`: control off.
    pub target_fps: Option<f32>,
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
        let target = self.target_fps.map_or_else(
            || String::from("target fps off"),
            |t| format!("target fps {t:.0}"),
        );
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
            target_fps: Some(30.0),
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
                "target fps 30",
                "mode depth +wire +frozen"
            ]
        );
        state.fps = None;
        state.target_fps = None;
        state.depth_cap = None;
        let lines = state.lines();
        assert_eq!(lines[0], "frame 3.0 ms (idle)");
        assert_eq!(lines[2], "depth cap -");
        assert_eq!(lines[3], "target fps off");
        let mesh = RenderMesh::default();
        let options = RenderOptions::default();
        assert!(!overlay(&state, &mesh, &options, [640, 480]).is_empty());
        state.show = false;
        assert!(overlay(&state, &mesh, &options, [640, 480]).is_empty());
    }
}
