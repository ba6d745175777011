//! 2D panels drawn over the 3D views: lines of text and colour legends (a gradient bar with its
//! numbers), rasterised on the CPU with the bundled DejaVu Sans (ab_glyph) so that the same
//! pixels come out on every backend and in every PNG. Drawn by the renderer as textured quads.
//!
//! A line of text is rasterised once: its glyphs' coverage is kept ([`Font`]'s line cache) and
//! blended again wherever the same line is drawn at the same size and place. The app's overlay
//! changes a number or two a frame while its other lines stay, and rasterising every glyph of
//! every line anew was about 1.5 ms of each frame's main thread on a 2-core VM.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use ab_glyph::{Font as _, FontRef, PxScale, ScaleFont};

use super::types::{OverlayPanel, PanelItem};

/// A rasterised panel (sRGB RGBA, premultiplied by nothing: straight alpha).
#[derive(Debug, Clone, Default)]
pub struct PanelImage {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Pixels, row-major RGBA.
    pub rgba: Vec<u8>,
}

/// The bundled font, with the lines it has rasterised.
pub struct Font {
    font: FontRef<'static>,
    lines: Mutex<HashMap<LineKey, Arc<Stroke>>>,
}

/// Lines kept at most; past this the cache starts afresh (a frame draws a few dozen).
const LINES_KEPT: usize = 512;

/// A line as drawn: its text, size and where it starts (exactly: the glyphs' sub-pixel
/// positions, and so their coverage, depend on it to the last bit).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct LineKey {
    text: String,
    size_bits: u32,
    x_bits: u32,
    y_bits: u32,
}

/// A line's glyph coverage, pixel by pixel, in the order the glyphs draw it (overlapping glyphs
/// blend twice, as they did drawn directly).
type Stroke = Vec<(i64, i64, f32)>;

const FONT_BYTES: &[u8] = crate::assets::FONT;

impl Font {
    /// DejaVu Sans, bundled in `assets/fonts`.
    pub fn bundled() -> Self {
        // The bytes are a known-good font compiled into the binary; a parse failure would be a
        // build defect, caught by every rendering test.
        let font = FontRef::try_from_slice(FONT_BYTES).expect("bundled DejaVuSans.ttf parses");
        Self {
            font,
            lines: Mutex::new(HashMap::new()),
        }
    }

    /// Width of `text` in pixels at `size_px`.
    pub fn text_width(&self, text: &str, size_px: f32) -> f32 {
        let scaled = self.font.as_scaled(PxScale::from(size_px));
        let mut width = 0.0;
        let mut prev = None;
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = prev {
                width += scaled.kern(p, id);
            }
            width += scaled.h_advance(id);
            prev = Some(id);
        }
        width
    }

    /// Line height in pixels at `size_px`.
    pub fn line_height(&self, size_px: f32) -> f32 {
        let scaled = self.font.as_scaled(PxScale::from(size_px));
        scaled.ascent() - scaled.descent() + scaled.line_gap()
    }

    /// Draws `text` with its baseline-top at (x, y) into `img`, blending `color` by coverage.
    pub fn draw(
        &self,
        img: &mut PanelImage,
        x: f32,
        y: f32,
        text: &str,
        size_px: f32,
        color: [u8; 3],
    ) {
        let key = LineKey {
            text: text.to_string(),
            size_bits: size_px.to_bits(),
            x_bits: x.to_bits(),
            y_bits: y.to_bits(),
        };
        let cached = self
            .lines
            .lock()
            .ok()
            .and_then(|lines| lines.get(&key).cloned());
        let stroke = match cached {
            Some(stroke) => stroke,
            None => {
                let stroke = Arc::new(self.stroke(x, y, text, size_px));
                if let Ok(mut lines) = self.lines.lock() {
                    if lines.len() >= LINES_KEPT {
                        lines.clear();
                    }
                    lines.insert(key, stroke.clone());
                }
                stroke
            }
        };
        for &(px, py, coverage) in stroke.iter() {
            blend(img, px, py, color, coverage);
        }
    }

    /// The coverage of `text` drawn from (x, y).
    fn stroke(&self, x: f32, y: f32, text: &str, size_px: f32) -> Stroke {
        let mut stroke = Vec::new();
        let scale = PxScale::from(size_px);
        let scaled = self.font.as_scaled(scale);
        let baseline = y + scaled.ascent();
        let mut pen = x;
        let mut prev = None;
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = prev {
                pen += scaled.kern(p, id);
            }
            let glyph = id.with_scale_and_position(scale, ab_glyph::point(pen, baseline));
            pen += scaled.h_advance(id);
            prev = Some(id);
            if let Some(outline) = self.font.outline_glyph(glyph) {
                let bounds = outline.px_bounds();
                outline.draw(|gx, gy, coverage| {
                    let px = bounds.min.x as i64 + gx as i64;
                    let py = bounds.min.y as i64 + gy as i64;
                    stroke.push((px, py, coverage));
                });
            }
        }
        stroke
    }
}

fn blend(img: &mut PanelImage, x: i64, y: i64, color: [u8; 3], coverage: f32) {
    if x < 0 || y < 0 || x >= img.width as i64 || y >= img.height as i64 {
        return;
    }
    let i = ((y as u32 * img.width + x as u32) * 4) as usize;
    let a = coverage.clamp(0.0, 1.0);
    let dst_a = img.rgba[i + 3] as f32 / 255.0;
    let out_a = a + dst_a * (1.0 - a);
    for (k, &c) in color.iter().enumerate() {
        let dst = img.rgba[i + k] as f32;
        let v = if out_a > 0.0 {
            (c as f32 * a + dst * dst_a * (1.0 - a)) / out_a
        } else {
            0.0
        };
        img.rgba[i + k] = v.round().clamp(0.0, 255.0) as u8;
    }
    img.rgba[i + 3] = (out_a * 255.0).round() as u8;
}

fn item_size(item: &PanelItem, font: &Font) -> (u32, u32) {
    match item {
        PanelItem::Text { text, size_px, .. } => (
            font.text_width(text, *size_px).ceil() as u32,
            font.line_height(*size_px).ceil() as u32,
        ),
        PanelItem::ColorBar {
            width,
            height,
            labels,
            size_px,
            ..
        } => {
            // Labels are centred on their positions and may overhang the bar's ends.
            let overhang = labels
                .iter()
                .map(|(_, l)| font.text_width(l, *size_px).ceil() as u32)
                .max()
                .unwrap_or(0);
            (
                width + overhang,
                height + 4 + font.line_height(*size_px).ceil() as u32,
            )
        }
    }
}

/// Rasterises a panel.
pub fn rasterise(panel: &OverlayPanel, font: &Font) -> PanelImage {
    let sizes: Vec<(u32, u32)> = panel.items.iter().map(|i| item_size(i, font)).collect();
    let inner_w = sizes.iter().map(|s| s.0).max().unwrap_or(0);
    let inner_h: u32 = sizes.iter().map(|s| s.1 + 2).sum();
    if inner_w == 0 || inner_h == 0 {
        return PanelImage::default();
    }
    let width = inner_w + 2 * panel.padding;
    let height = inner_h + 2 * panel.padding;
    let mut img = PanelImage {
        width,
        height,
        rgba: panel.background.repeat((width * height) as usize),
    };
    // Rounded corners: coverage falls off outside the corner circles. Elsewhere the distance
    // to the clamped centre is at most radius − 0.5, so the coverage is 1 and the pixel keeps
    // the background as filled; only the corner squares are worked out.
    let radius = panel.padding.min(8) as f32;
    let corner = (radius.ceil() as u32).min(width).min(height);
    let columns = (0..corner).chain(width.saturating_sub(corner).max(corner)..width);
    for x in columns {
        let rows = (0..corner).chain(height.saturating_sub(corner).max(corner)..height);
        for y in rows {
            let cx = (x as f32 + 0.5).clamp(radius, width as f32 - radius);
            let cy = (y as f32 + 0.5).clamp(radius, height as f32 - radius);
            let d = ((x as f32 + 0.5 - cx).powi(2) + (y as f32 + 0.5 - cy).powi(2)).sqrt();
            let cover = (radius + 0.5 - d).clamp(0.0, 1.0);
            let i = ((y * width + x) * 4 + 3) as usize;
            img.rgba[i] = (panel.background[3] as f32 * cover).round() as u8;
        }
    }
    let mut y = panel.padding as f32;
    for (item, (_, h)) in panel.items.iter().zip(&sizes) {
        let x = panel.padding as f32;
        match item {
            PanelItem::Text {
                text,
                size_px,
                color,
            } => font.draw(&mut img, x, y, text, *size_px, *color),
            PanelItem::ColorBar {
                width,
                height,
                colors,
                labels,
                size_px,
            } => {
                let overhang = (item_size(item, font).0 - width) as f32 / 2.0;
                let x0 = x + overhang;
                for bx in 0..*width {
                    let c = crate::colormap::sample(colors, bx as f32 / (*width - 1).max(1) as f32);
                    for by in 0..*height {
                        blend(
                            &mut img,
                            (x0 as u32 + bx) as i64,
                            (y as u32 + by) as i64,
                            c,
                            1.0,
                        );
                    }
                }
                for (pos, label) in labels {
                    let w = font.text_width(label, *size_px);
                    let lx = x0 + pos.clamp(0.0, 1.0) * (*width as f32) - w / 2.0;
                    let tick_x = (x0 + pos.clamp(0.0, 1.0) * (*width - 1) as f32) as i64;
                    for ty in 0..4 {
                        blend(
                            &mut img,
                            tick_x,
                            (y as u32 + height + ty) as i64,
                            [230; 3],
                            1.0,
                        );
                    }
                    font.draw(
                        &mut img,
                        lx,
                        y + *height as f32 + 4.0,
                        label,
                        *size_px,
                        [235; 3],
                    );
                }
            }
        }
        y += (*h + 2) as f32;
    }
    img
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::types::Anchor;

    fn panel(lines: &[&str]) -> OverlayPanel {
        OverlayPanel {
            anchor: Anchor::TopLeft(0, 0),
            background: [20, 20, 30, 200],
            padding: 6,
            items: lines
                .iter()
                .map(|t| PanelItem::Text {
                    text: (*t).to_string(),
                    size_px: 17.0,
                    color: [230, 230, 230],
                })
                .collect(),
        }
    }

    #[test]
    fn a_line_drawn_again_from_the_cache_is_the_same_pixels() {
        let font = Font::bundled();
        let first = rasterise(&panel(&["t = 3.73", "α = 0.30000 rad", "Wavy ƒ fj"]), &font);
        let lines = font.lines.lock().unwrap().len();
        assert_eq!(lines, 3);
        let again = rasterise(&panel(&["t = 3.73", "α = 0.30000 rad", "Wavy ƒ fj"]), &font);
        assert_eq!(first.rgba, again.rgba);
        assert_eq!(
            font.lines.lock().unwrap().len(),
            3,
            "nothing new rasterised"
        );
        // A fresh font (no cache) draws the same bytes.
        let fresh = rasterise(
            &panel(&["t = 3.73", "α = 0.30000 rad", "Wavy ƒ fj"]),
            &Font::bundled(),
        );
        assert_eq!(first.rgba, fresh.rgba);
        // One line changed: one line more in the cache.
        rasterise(&panel(&["t = 3.74", "α = 0.30000 rad", "Wavy ƒ fj"]), &font);
        assert_eq!(font.lines.lock().unwrap().len(), 4);
    }

    #[test]
    fn the_line_cache_stays_bounded() {
        let font = Font::bundled();
        for k in 0..3 * LINES_KEPT {
            rasterise(&panel(&[&format!("t = {k}")]), &font);
        }
        assert!(font.lines.lock().unwrap().len() <= LINES_KEPT);
    }
}
