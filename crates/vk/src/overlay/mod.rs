//! Screen-space overlays drawn over a frame: the viewer's HUD and the colour legends of the
//! depth and DoI shadings. An [`Overlay`] is a list of axis-aligned, alpha-blended rectangles
//! in pixels (origin top-left, y down); text is built from the crate's own 5×7 bitmap font
//! ([`font`]), one rectangle per run of lit pixels in a glyph row.
//!
//! Plain data: nothing here touches Vulkan. The frame recipe draws the rectangles last, with
//! blending and without depth test, into the colour target only.

pub mod font;
mod legend;

pub use legend::legend;

/// One filled rectangle: pixels `min.x..max.x` × `min.y..max.y`, straight (non-premultiplied)
/// RGBA colour in 0..1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlayRect {
    /// Top-left corner in pixels.
    pub min: [f32; 2],
    /// Bottom-right corner in pixels (exclusive).
    pub max: [f32; 2],
    /// RGBA colour; alpha blends with the frame below.
    pub color: [f32; 4],
}

/// Rectangles drawn over a frame, in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overlay {
    /// The rectangles, drawn first to last.
    pub rects: Vec<OverlayRect>,
}

impl Overlay {
    /// Whether there is nothing to draw.
    pub fn is_empty(&self) -> bool {
        self.rects.is_empty()
    }

    /// Adds a filled rectangle at (`x`, `y`) of `w` × `h` pixels.
    pub fn rect(&mut self, x: f32, y: f32, w: f32, h: f32, color: [f32; 4]) {
        if w > 0.0 && h > 0.0 {
            self.rects.push(OverlayRect {
                min: [x, y],
                max: [x + w, y + h],
                color,
            });
        }
    }

    /// Adds `text` with its top-left corner at (`x`, `y`), each font pixel `scale` × `scale`
    /// screen pixels; returns the width drawn. One line (`\n` is drawn as `?`).
    pub fn text(&mut self, x: f32, y: f32, scale: u32, color: [f32; 4], text: &str) -> f32 {
        let s = scale.max(1) as f32;
        let mut pen = x;
        for c in text.chars() {
            for (row, bits) in font::glyph(c).iter().enumerate() {
                let top = y + row as f32 * s;
                let mut col = 0u32;
                while col < font::GLYPH_W {
                    let lit = |col: u32| bits & (1 << (font::GLYPH_W - 1 - col)) != 0;
                    if !lit(col) {
                        col += 1;
                        continue;
                    }
                    let start = col;
                    while col < font::GLYPH_W && lit(col) {
                        col += 1;
                    }
                    let left = pen + start as f32 * s;
                    self.rect(left, top, (col - start) as f32 * s, s, color);
                }
            }
            pen += font::ADVANCE as f32 * s;
        }
        pen - x
    }

    /// Size in pixels of `lines` of text at `scale` ([`Overlay::text`] per line, advancing
    /// by [`font::LINE_H`]).
    pub fn text_size(lines: &[&str], scale: u32) -> [f32; 2] {
        let s = scale.max(1) as f32;
        let chars = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0);
        let w = (chars as f32 * font::ADVANCE as f32 - 1.0).max(0.0) * s;
        let h = (lines.len() as f32 * font::LINE_H as f32 - 2.0).max(0.0) * s;
        [w, h]
    }

    /// A block of text lines on a translucent dark panel with its top-left corner at (`x`,
    /// `y`) (the viewer's HUD).
    pub fn panel(&mut self, x: f32, y: f32, scale: u32, lines: &[&str]) {
        let s = scale.max(1) as f32;
        let pad = 3.0 * s;
        let [w, h] = Self::text_size(lines, scale);
        self.rect(x, y, w + 2.0 * pad, h + 2.0 * pad, PANEL);
        for (i, line) in lines.iter().enumerate() {
            let top = y + pad + i as f32 * font::LINE_H as f32 * s;
            self.text(x + pad, top, scale, TEXT, line);
        }
    }

    /// Appends `other`'s rectangles (drawn after this overlay's).
    pub fn extend(&mut self, other: Overlay) {
        self.rects.extend(other.rects);
    }
}

/// Panel colour: dark, translucent.
pub const PANEL: [f32; 4] = [0.06, 0.06, 0.08, 0.72];
/// Text colour on panels.
pub const TEXT: [f32; 4] = [1.0, 1.0, 1.0, 1.0];

/// Text scale for an image of `size` pixels: 2 from 480 pixels high, else 1.
pub fn text_scale(size: [u32; 2]) -> u32 {
    if size[1] >= 480 && size[0] >= 480 {
        2
    } else {
        1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_one_rect_per_run_of_lit_pixels() {
        let mut o = Overlay::default();
        let w = o.text(10.0, 20.0, 2, TEXT, "1-");
        assert_eq!(w, 2.0 * 6.0 * 2.0);
        // '1': one run in each of its seven rows; '-': one run of five.
        assert_eq!(o.rects.len(), 8);
        let dash = o.rects[7];
        assert_eq!(dash.min, [10.0 + 12.0, 20.0 + 3.0 * 2.0]);
        assert_eq!(dash.max, [10.0 + 12.0 + 10.0, 20.0 + 4.0 * 2.0]);
        assert_eq!(Overlay::text_size(&["1-", "abc"], 1), [17.0, 16.0]);
    }

    #[test]
    fn panel_covers_its_text() {
        let mut o = Overlay::default();
        o.panel(4.0, 4.0, 1, &["fps 60.0", "triangles 12"]);
        let panel = o.rects[0];
        assert_eq!(panel.color, PANEL);
        for r in &o.rects[1..] {
            assert!(r.min[0] >= panel.min[0] && r.max[0] <= panel.max[0]);
            assert!(r.min[1] >= panel.min[1] && r.max[1] <= panel.max[1]);
        }
    }
}
