//! PNG charts for the command line's tables and figures: panels of line/marker series on linear
//! or logarithmic axes, drawn by plotters into a buffer and encoded by `image`, with the bundled
//! DejaVu Sans font (no system fontconfig). Output depends only on the data: same data, same bytes.
//! Not used by the physics core.

use std::path::Path;
use std::sync::Once;

use anyhow::{Context, Result};
use plotters::prelude::*;
use plotters::style::FontStyle;

/// Where a panel's legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesLabelPosition {
    /// Top right corner.
    UpperRight,
    /// Top left corner.
    UpperLeft,
    /// Bottom right corner.
    LowerRight,
    /// Bottom left corner.
    LowerLeft,
}

impl SeriesLabelPosition {
    fn to_plotters(self) -> plotters::chart::SeriesLabelPosition {
        use plotters::chart::SeriesLabelPosition as P;
        match self {
            Self::UpperRight => P::UpperRight,
            Self::UpperLeft => P::UpperLeft,
            Self::LowerRight => P::LowerRight,
            Self::LowerLeft => P::LowerLeft,
        }
    }
}

static FONT: &[u8] = crate::assets::FONT;
static REGISTER: Once = Once::new();

fn register_font() {
    REGISTER.call_once(|| {
        // The bundled font is a valid TrueType file; a failure would only mean missing labels.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// One data series.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Points (x, y); non-finite or, on log axes, non-positive points are skipped.
    pub points: Vec<(f64, f64)>,
    /// RGB colour.
    pub color: (u8, u8, u8),
    /// How the points are drawn.
    pub style: Style,
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A polyline.
    Line,
    /// Filled circles.
    Markers,
    /// A polyline with filled circles.
    LineMarkers,
    /// Consecutive point pairs as short arrows (a field of directions).
    Arrows,
    /// Consecutive point pairs as plain segments (contours).
    Segments,
}

/// One panel.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Title above the panel.
    pub title: String,
    /// x-axis label, with units.
    pub x_label: String,
    /// y-axis label, with units.
    pub y_label: String,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// The data.
    pub series: Vec<Series>,
    /// Where the legend goes. The axis range grows to leave it a band of its own, above (or
    /// below, for the lower corners) the data, so it never covers a point.
    pub legend: SeriesLabelPosition,
    /// One unit on x spans as many pixels as one unit on y (a circle stays round): for
    /// geometry such as the boundary of the SO(3) ball. Linear axes only.
    pub equal_aspect: bool,
}

/// A palette that stays distinguishable for up to eight series.
pub const PALETTE: [(u8, u8, u8); 8] = [
    (31, 119, 180),
    (214, 39, 40),
    (44, 160, 44),
    (255, 127, 14),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (23, 190, 207),
];

fn range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return if log { (1e-16, 1.0) } else { (0.0, 1.0) };
    }
    if log {
        let (a, b) = (lo.log10().floor(), hi.log10().ceil());
        (10f64.powf(a), 10f64.powf(if b > a { b } else { a + 1.0 }))
    } else {
        let pad = if hi > lo { 0.05 * (hi - lo) } else { 0.5 };
        (lo - pad, hi + pad)
    }
}

/// Draws `panels` in a grid of `cols` columns into a PNG file of `size` pixels, through the
/// output layer.
pub fn render_png(panels: &[Panel], cols: usize, size: (u32, u32), path: &Path) -> Result<()> {
    let png = png_bytes(panels, cols, size)?;
    Ok(crate::output::write_bytes(
        path,
        &png,
        &crate::output::Inputs::none(),
    )?)
}

/// Draws `panels` in a grid of `cols` columns as the bytes of a PNG of `size` pixels.
pub fn png_bytes(panels: &[Panel], cols: usize, size: (u32, u32)) -> Result<Vec<u8>> {
    register_font();
    let (w, h) = size;
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE)
            .map_err(|e| anyhow::anyhow!("drawing: {e}"))?;
        let rows = panels.len().div_ceil(cols.max(1));
        let areas = root.split_evenly((rows, cols.max(1)));
        for (panel, area) in panels.iter().zip(areas.iter()) {
            draw_panel(panel, area).map_err(|e| anyhow::anyhow!("drawing {}: {e}", panel.title))?;
        }
        root.present()
            .map_err(|e| anyhow::anyhow!("drawing: {e}"))?;
    }
    let img = image::RgbImage::from_raw(w, h, buf).context("image buffer size")?;
    let mut png = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .context("cannot encode the chart as PNG")?;
    Ok(png)
}

/// Tick text: powers of ten as 1e-5 on log axes, short decimals on linear ones.
fn tick(v: f64, log: bool) -> String {
    if log {
        let e = v.log10().round();
        if (v.log10() - e).abs() < 1e-6 {
            return format!("1e{}", e as i64);
        }
        return format!("{v:.0e}");
    }
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.to_string() }
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Pixels of one legend entry and of the legend's frame.
const LEGEND_ROW_PX: f64 = 20.0;
const LEGEND_FRAME_PX: f64 = 16.0;

/// The size in pixels of the plotting area `draw_panel` gets inside `area` (measured by laying
/// the same chart out on a scratch bitmap, so caption and label areas count exactly).
fn plot_pixels(p: &Panel, area: &Area) -> (f64, f64) {
    let (w, h) = area.dim_in_pixel();
    let mut scratch = vec![0u8; (w * h * 3) as usize];
    let root = BitMapBackend::with_buffer(&mut scratch, (w, h)).into_drawing_area();
    let chart = chart_builder(p, &root).build_cartesian_2d(0.0..1.0, 0.0..1.0);
    match chart {
        Ok(c) => {
            let (pw, ph) = c.plotting_area().dim_in_pixel();
            (f64::from(pw.max(1)), f64::from(ph.max(1)))
        }
        Err(_) => (f64::from(w.max(1)), f64::from(h.max(1))),
    }
}

fn chart_builder<'a, 'b>(p: &Panel, area: &'a Area<'b>) -> ChartBuilder<'a, 'b, BitMapBackend<'b>> {
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(&p.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(42)
        .y_label_area_size(82);
    builder
}

/// Grows (lo, hi) so that the data fill `1 − free` of it, the free part at the top (`top`) or
/// the bottom; in log10 space on log axes.
fn make_room((lo, hi): (f64, f64), free: f64, top: bool, log: bool) -> (f64, f64) {
    let (a, b) = if log {
        (lo.log10(), hi.log10())
    } else {
        (lo, hi)
    };
    let span = (b - a) / (1.0 - free);
    let (a, b) = if top { (a, a + span) } else { (b - span, b) };
    if log {
        (10f64.powf(a), 10f64.powf(b))
    } else {
        (a, b)
    }
}

/// Widens one axis about its centre so that units on x and y span equal pixels.
fn equal_aspect(x: (f64, f64), y: (f64, f64), (pw, ph): (f64, f64)) -> ((f64, f64), (f64, f64)) {
    let (sx, sy) = ((x.1 - x.0) / pw, (y.1 - y.0) / ph);
    let widen = |(lo, hi): (f64, f64), px: f64, scale: f64| {
        let (c, half) = (0.5 * (lo + hi), 0.5 * scale * px);
        (c - half, c + half)
    };
    if sx > sy {
        (x, widen(y, ph, sx))
    } else {
        (widen(x, pw, sy), y)
    }
}

fn draw_panel(p: &Panel, area: &Area) -> std::result::Result<(), Box<dyn std::error::Error>> {
    let xs = p.series.iter().flat_map(|s| s.points.iter().map(|q| q.0));
    let ys = p.series.iter().flat_map(|s| s.points.iter().map(|q| q.1));
    let (mut x0, mut x1) = range(xs, p.log_x);
    let (mut y0, mut y1) = range(ys, p.log_y);
    let pixels = plot_pixels(p, area);
    let labels = p.series.iter().filter(|s| !s.label.is_empty()).count();
    if labels > 0 {
        let free = (labels as f64 * LEGEND_ROW_PX + LEGEND_FRAME_PX) / pixels.1;
        if free < 0.6 {
            let top = !matches!(
                p.legend,
                SeriesLabelPosition::LowerLeft | SeriesLabelPosition::LowerRight
            );
            (y0, y1) = make_room((y0, y1), free, top, p.log_y);
        }
    }
    if p.equal_aspect && !p.log_x && !p.log_y {
        ((x0, x1), (y0, y1)) = equal_aspect((x0, x1), (y0, y1), pixels);
    }
    let mut builder = chart_builder(p, area);
    let keep = |x: f64, y: f64| {
        x.is_finite() && y.is_finite() && (!p.log_x || x > 0.0) && (!p.log_y || y > 0.0)
    };
    macro_rules! body {
        ($chart:expr) => {{
            let mut chart = $chart;
            let fx = |v: &f64| tick(*v, p.log_x);
            let fy = |v: &f64| tick(*v, p.log_y);
            chart
                .configure_mesh()
                .x_label_formatter(&fx)
                .y_label_formatter(&fy)
                .x_desc(p.x_label.as_str())
                .y_desc(p.y_label.as_str())
                .label_style(("sans-serif", 14))
                .axis_desc_style(("sans-serif", 15))
                .draw()?;
            for s in &p.series {
                let color = RGBColor(s.color.0, s.color.1, s.color.2);
                if matches!(s.style, Style::Arrows | Style::Segments) {
                    let segs: Vec<Vec<(f64, f64)>> = s
                        .points
                        .chunks_exact(2)
                        .filter(|c| keep(c[0].0, c[0].1) && keep(c[1].0, c[1].1))
                        .map(|c| vec![c[0], c[1]])
                        .collect();
                    let heads: Vec<(f64, f64)> = segs.iter().map(|c| c[1]).collect();
                    let anno = chart.draw_series(
                        segs.into_iter()
                            .map(|c| PathElement::new(c, color.stroke_width(1))),
                    )?;
                    if !s.label.is_empty() {
                        anno.label(s.label.as_str()).legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2))
                        });
                    }
                    chart.draw_series(
                        heads.into_iter().map(|h| Circle::new(h, 2, color.filled())),
                    )?;
                    continue;
                }
                let pts: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .copied()
                    .filter(|(x, y)| keep(*x, *y))
                    .collect();
                let labelled = !s.label.is_empty();
                if matches!(s.style, Style::Line | Style::LineMarkers) {
                    let anno =
                        chart.draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))?;
                    if labelled && s.style == Style::Line {
                        anno.label(s.label.as_str()).legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(3))
                        });
                    }
                }
                if matches!(s.style, Style::Markers | Style::LineMarkers) {
                    let anno = chart.draw_series(
                        pts.iter()
                            .map(|&(x, y)| Circle::new((x, y), 4, color.filled())),
                    )?;
                    if labelled {
                        anno.label(s.label.as_str())
                            .legend(move |(x, y)| Circle::new((x + 8, y), 5, color.filled()));
                    }
                }
            }
            if p.series.iter().any(|s| !s.label.is_empty()) {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .label_font(("sans-serif", 14))
                    .position(p.legend.to_plotters())
                    .draw()?;
            }
        }};
    }
    match (p.log_x, p.log_y) {
        (true, true) => {
            body!(builder.build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?)
        }
        (true, false) => body!(builder.build_cartesian_2d((x0..x1).log_scale(), y0..y1)?),
        (false, true) => body!(builder.build_cartesian_2d(x0..x1, (y0..y1).log_scale())?),
        (false, false) => body!(builder.build_cartesian_2d(x0..x1, y0..y1)?),
    }
    Ok(())
}
