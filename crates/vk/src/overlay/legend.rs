//! Colour legends of the depth palette and the DoI heat map, in the top-right corner.
//!
//! The colours repeat those of `shaders/mesh.frag` (`depth_colour`, `heat_colour`), unlit; the
//! tests below pin both tables.

use super::{Overlay, PANEL, TEXT, font};
use crate::scene::Shading;

/// Most depth levels listed (deeper ones are cut off, the palette cycles after 8 anyway).
const MAX_LEVELS: i32 = 12;
/// Steps of the heat-map bar.
const HEAT_STEPS: u32 = 32;

/// The palette of [`Shading::Depth`]: colour of depth `level` (cycled after 8), as in
/// `mesh.frag`.
pub(crate) fn depth_colour(level: i32) -> [f32; 3] {
    match level.rem_euclid(8) {
        0 => [0.20, 0.35, 0.90],
        1 => [0.10, 0.75, 0.85],
        2 => [0.20, 0.80, 0.25],
        3 => [0.95, 0.90, 0.15],
        4 => [1.00, 0.55, 0.10],
        5 => [0.90, 0.15, 0.15],
        6 => [0.85, 0.25, 0.80],
        _ => [0.55, 0.30, 0.75],
    }
}

/// The heat map of [`Shading::Doi`] at `t` in 0..1 (blue, cyan, green, yellow, red), as in
/// `mesh.frag`.
pub(crate) fn heat_colour(t: f32) -> [f32; 3] {
    let c = |centre: f32| (1.5 - (4.0 * t - centre).abs()).clamp(0.0, 1.0);
    [c(3.0), c(2.0), c(1.0)]
}

/// The legend of `shading` for scalars in `range` (depths: `min..=max` rounded; DoI: the
/// heat map's range) in an image of `size` pixels; empty for the other shadings.
pub fn legend(shading: Shading, range: (f32, f32), size: [u32; 2]) -> Overlay {
    let scale = super::text_scale(size);
    match shading {
        Shading::Depth => depth_legend(range, size, scale),
        Shading::Doi => heat_legend(range, size, scale),
        _ => Overlay::default(),
    }
}

fn rgba([r, g, b]: [f32; 3]) -> [f32; 4] {
    [r, g, b, 1.0]
}

/// Title "depth", then one swatch and number per depth level, top to bottom.
fn depth_legend(range: (f32, f32), size: [u32; 2], scale: u32) -> Overlay {
    let s = scale as f32;
    let lo = range.0.round().max(0.0) as i32;
    let hi = (range.1.round() as i32).clamp(lo, lo + MAX_LEVELS - 1);
    let labels: Vec<String> = (lo..=hi).map(|d| format!("  {d}")).collect();
    let mut lines: Vec<&str> = vec!["depth"];
    lines.extend(labels.iter().map(String::as_str));
    let [w, h] = Overlay::text_size(&lines, scale);
    let pad = 3.0 * s;
    let x = size[0] as f32 - w - 2.0 * pad - 4.0 * s;
    let y = 4.0 * s;
    let mut o = Overlay::default();
    o.rect(x, y, w + 2.0 * pad, h + 2.0 * pad, PANEL);
    let line = font::LINE_H as f32 * s;
    o.text(x + pad, y + pad, scale, TEXT, lines[0]);
    for (i, (d, label)) in (lo..=hi).zip(&labels).enumerate() {
        let top = y + pad + (i + 1) as f32 * line;
        let side = font::GLYPH_H as f32 * s;
        o.rect(x + pad, top, side, side, rgba(depth_colour(d)));
        o.text(x + pad, top, scale, TEXT, label);
    }
    o
}

/// Title "DoI", a vertical heat bar (high at the top) with the range's ends as labels.
fn heat_legend(range: (f32, f32), size: [u32; 2], scale: u32) -> Overlay {
    let s = scale as f32;
    let (lo, hi) = range;
    let top_label = format!("{hi:.3}");
    let bottom_label = format!("{lo:.3}");
    let bar_w = 8.0 * s;
    let bar_h = 64.0 * s;
    let label_w = Overlay::text_size(&[&top_label, &bottom_label, "DoI"], scale)[0];
    let pad = 3.0 * s;
    let line = font::LINE_H as f32 * s;
    let w = bar_w + pad + label_w;
    let h = line + bar_h;
    let x = size[0] as f32 - w - 2.0 * pad - 4.0 * s;
    let y = 4.0 * s;
    let mut o = Overlay::default();
    o.rect(x, y, w + 2.0 * pad, h + 2.0 * pad, PANEL);
    o.text(x + pad, y + pad, scale, TEXT, "DoI");
    let bar_top = y + pad + line;
    let step = bar_h / HEAT_STEPS as f32;
    for i in 0..HEAT_STEPS {
        // Row i from the top shows the value at the middle of its step, high values on top.
        let t = 1.0 - (i as f32 + 0.5) / HEAT_STEPS as f32;
        o.rect(
            x + pad,
            bar_top + i as f32 * step,
            bar_w,
            step,
            rgba(heat_colour(t)),
        );
    }
    let label_x = x + pad + bar_w + pad;
    o.text(label_x, bar_top, scale, TEXT, &top_label);
    let glyph_h = font::GLYPH_H as f32 * s;
    o.text(
        label_x,
        bar_top + bar_h - glyph_h,
        scale,
        TEXT,
        &bottom_label,
    );
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shader_colours_are_pinned() {
        // Must equal `depth_colour` and `heat_colour` of shaders/mesh.frag.
        let frag = include_str!("../shaders/mesh.frag");
        for level in 0..8 {
            let [r, g, b] = depth_colour(level);
            let line = format!("vec3({r:.2}, {g:.2}, {b:.2})");
            assert!(frag.contains(&line), "mesh.frag lacks {line}");
        }
        assert_eq!(depth_colour(9), depth_colour(1));
        assert!(frag.contains("clamp(1.5 - abs(4.0 * t - 3.0), 0.0, 1.0)"));
        assert_eq!(heat_colour(0.0), [0.0, 0.0, 0.5]);
        assert_eq!(heat_colour(0.5), [0.5, 1.0, 0.5]);
        assert_eq!(heat_colour(1.0), [0.5, 0.0, 0.0]);
    }

    #[test]
    fn legends_sit_in_the_top_right_corner() {
        let size = [640, 480];
        let depth = legend(Shading::Depth, (0.0, 3.0), size);
        // Panel, title, four swatches with labels.
        let swatches = depth
            .rects
            .iter()
            .filter(|r| r.color != TEXT && r.color != PANEL)
            .count();
        assert_eq!(swatches, 4);
        let heat = legend(Shading::Doi, (0.25, 2.0), size);
        for o in [&depth, &heat] {
            let panel = o.rects[0];
            assert!(panel.max[0] <= 640.0 && panel.min[0] > 320.0, "{panel:?}");
            assert!(panel.min[1] >= 0.0 && panel.max[1] < 240.0, "{panel:?}");
        }
        assert!(legend(Shading::Smooth, (0.0, 1.0), size).is_empty());
    }
}
