//! The app's plots (egui_plot) and the history they draw, accumulated from the samples the
//! simulation takes every [`PLOT_SAMPLE_DT`](crate::live::PLOT_SAMPLE_DT) and the snapshots the
//! UI receives: θ(t) and θ̇(θ) for a cylinder, the contact path on the (φ, θ) curvature map for
//! a sphere, the order parameter 1/T against α collected while the user sweeps α (a halted body
//! counts as 1/T = 0, separately for sweeps up and down, so hysteresis shows as two branches),
//! the crossing points of ∂Ω against m/m0 collected while the user sweeps the mass (3D, once the
//! crossings repeat: one branch per period-1 orbit, two where it has doubled), and the numerical
//! health against time.
//!
//! [`PlotHistory`] (in `live::history`, so the headless renderer collects the same data) is plain
//! data, tested without a window; [`plots_ui`] draws it as instruments: numbered ticks on every
//! axis at any size (`plot_axes`: `nice_marks`, `tick_label`), values under the pointer, and only the
//! health quantities the model has.

use egui::Color32;
use egui_plot::{HoverPosition, Line, Plot, PlotPoint, PlotPoints, Points, VLine};

use crate::colormap::{DIVERGING, sample};
use crate::dynamics::ModelKind;
use crate::geometry::Body;
use crate::geometry::sphere::{angles, direction};
use crate::live::Snapshot;
use crate::live::history::{Branch, PlotHistory, Regime};
use crate::view::CurvatureScale;

mod time_series;

use time_series::{bodies_ui, force_ui, health_measures, health_ui};

use super::plot_axes::{
    X_LABEL_POINTS, Y_LABEL_POINTS, label_spacing, rate_tick_label, tick_label, x_marks, y_marks,
};

/// Samples in the phase curve: the last 300 time units at every
/// [`PLOT_SAMPLE_DT`](crate::live::PLOT_SAMPLE_DT).
const PHASE_POINTS: usize = 3000;

/// The Gaussian curvature K on a (φ, θ) grid, for the contact-path plot of a sphere, drawn as
/// one texture: as 2592 heatmap cells it was re-tessellated and filled cell by cell every frame,
/// which on a CPU renderer cost about a third of the frame.
#[derive(Clone)]
pub struct CurvatureMap {
    values: Vec<f64>,
    cols: usize,
    rows: usize,
    scale: CurvatureScale,
    /// The map's colours as a texture, uploaded on first draw.
    texture: std::cell::OnceCell<egui::TextureHandle>,
}

impl std::fmt::Debug for CurvatureMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CurvatureMap")
            .field("cols", &self.cols)
            .field("rows", &self.rows)
            .field("uploaded", &self.texture.get().is_some())
            .finish()
    }
}

impl CurvatureMap {
    /// The map as an image, θ = π on the top row (the plot's θ axis points up).
    fn image(&self) -> egui::ColorImage {
        let mut pixels = Vec::with_capacity(self.cols * self.rows);
        for row in (0..self.rows).rev() {
            for col in 0..self.cols {
                let k = self.values[row * self.cols + col];
                let [r, g, b] = sample(&DIVERGING, self.scale.position(k as f32));
                pixels.push(Color32::from_rgb(r, g, b));
            }
        }
        egui::ColorImage::new([self.cols, self.rows], pixels)
    }

    /// The map's texture, uploaded once.
    fn texture(&self, ctx: &egui::Context) -> &egui::TextureHandle {
        self.texture.get_or_init(|| {
            ctx.load_texture("curvature-map", self.image(), egui::TextureOptions::LINEAR)
        })
    }

    /// The map of a 3D body (`None` for a cylinder), on a `cols`×`rows` grid; `scale` is the
    /// one the 3D view colours the body with, so the two agree.
    pub fn new(body: &Body, scale: CurvatureScale, cols: usize, rows: usize) -> Option<Self> {
        let Body::Sphere(s) = body else {
            return None;
        };
        let mut values = Vec::with_capacity(cols * rows);
        // Heatmap rows stack upwards from the heatmap's corner: row 0 is the smallest θ.
        for row in 0..rows {
            let theta = std::f64::consts::PI * (row as f64 + 0.5) / rows as f64;
            for col in 0..cols {
                let phi = -std::f64::consts::PI
                    + std::f64::consts::TAU * (col as f64 + 0.5) / cols as f64;
                values.push(s.surface(direction(theta, phi)).gaussian_curvature());
            }
        }
        Some(Self {
            values,
            cols,
            rows,
            scale,
            texture: std::cell::OnceCell::new(),
        })
    }
}

/// A plot that reads as an instrument: numbered ticks on both axes at any size, and the
/// values under the pointer named by the axes (`x` and `y`), with the series' name near a point.
fn instrument<'a>(plot: Plot<'a>, x: &'static str, y: &'static str) -> Plot<'a> {
    plot.x_grid_spacer(x_marks)
        .y_grid_spacer(y_marks)
        .custom_x_axes(vec![
            egui_plot::AxisHints::new_x()
                .formatter(tick_label)
                .label_spacing(label_spacing(X_LABEL_POINTS)),
        ])
        .custom_y_axes(vec![
            egui_plot::AxisHints::new_y()
                .formatter(tick_label)
                .label_spacing(label_spacing(Y_LABEL_POINTS)),
        ])
        .label_formatter(move |pos| {
            Some(match pos {
                HoverPosition::NearDataPoint {
                    plot_name,
                    position,
                    ..
                } => format!(
                    "{plot_name}\n{x} = {}\n{y} = {}",
                    hover_number(position.x),
                    hover_number(position.y)
                ),
                HoverPosition::Elsewhere { position } => format!(
                    "{x} = {}\n{y} = {}",
                    hover_number(position.x),
                    hover_number(position.y)
                ),
            })
        })
}

/// A hovered value with five significant digits.
fn hover_number(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e5) {
        format!("{v:.4e}")
    } else {
        format!(
            "{:.*}",
            (4 - v.abs().max(1e-300).log10().floor() as i64).max(0) as usize,
            v
        )
    }
}

/// The narrowest a plot is drawn, in points: where the plots panel cannot give each this
/// much, the force and then the health plot are left off (class mode at 1280×720 pushed them
/// off the window).
const MIN_PLOT_WIDTH: f32 = 190.0;

/// How a series shows in a plot's key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Swatch {
    /// A curve or a vertical line.
    Line,
    /// Points.
    Dot,
    /// Another body's points, where the scene's own are dots of nearby colours.
    Diamond,
}

/// One series in a plot's key.
type Key<'a> = (&'a str, Color32, Swatch);

/// Blue, orange, green, purple: the series of one plot, told apart (egui_plot's automatic
/// colours gave the pieces of one curve different colours that nothing explained).
const SERIES_COLORS: [Color32; 4] = [
    Color32::from_rgb(70, 140, 230),
    Color32::from_rgb(255, 150, 30),
    Color32::from_rgb(120, 200, 120),
    Color32::from_rgb(190, 120, 230),
];

/// Regimes besides the running one the 1/T plot names one by one; more are one series.
const MAX_NAMED_REGIMES: usize = 2;

/// The 1/T points of regimes other than the running one (another m/m0 or drag law): greys and
/// muted tones, apart from the running regime's blue and orange and the fit's green.
const OTHER_REGIME_COLORS: [Color32; 3] = [
    Color32::from_rgb(170, 170, 170),
    Color32::from_rgb(190, 120, 230),
    Color32::from_rgb(200, 170, 110),
];

/// A plot under its key. The key is a row over the plot, outside what it plots: a legend in
/// a corner covered the fit curve or points when every corner had some, and jumped between
/// corners as the data grew. Swatches sit on grey, so a black curve's shows too. The key
/// takes the rows it needs of `height`; `plot` gets the rest.
fn keyed<R>(
    ui: &mut egui::Ui,
    width: f32,
    height: f32,
    keys: &[Key<'_>],
    plot: impl FnOnce(&mut egui::Ui, f32) -> R,
) -> R {
    ui.vertical(|ui| {
        let key = ui.allocate_ui_with_layout(
            egui::vec2(width, 0.0),
            egui::Layout::left_to_right(egui::Align::Center).with_main_wrap(true),
            |ui| {
                ui.set_width(width);
                ui.spacing_mut().item_spacing = egui::vec2(3.0, 1.0);
                for &(name, color, swatch) in keys {
                    // Each entry, its swatch and its name, is one piece a row break moves whole
                    // (a name wrapped on its own left "α" on one line and "down" on the next,
                    // or a swatch at a row's end without its name).
                    let font = egui::TextStyle::Small.resolve(ui.style());
                    // A name wider than the plot alone (the fit's formula at class mode's
                    // size) wraps within it, beside its swatch, rather than widen the panel
                    // past the window's edge.
                    let galley = ui.painter().layout(
                        name.to_string(),
                        font,
                        ui.visuals().text_color(),
                        (width - 22.0).max(40.0),
                    );
                    let size = egui::vec2(
                        14.0 + 3.0 + galley.size().x + 5.0,
                        galley.size().y.max(10.0),
                    );
                    let (entry, _) = ui.allocate_exact_size(size, egui::Sense::hover());
                    let rect = egui::Rect::from_center_size(
                        egui::pos2(entry.left() + 7.0, entry.center().y),
                        egui::vec2(14.0, 10.0),
                    );
                    ui.painter().galley(
                        egui::pos2(rect.right() + 3.0, entry.center().y - 0.5 * galley.size().y),
                        galley,
                        ui.visuals().text_color(),
                    );
                    let painter = ui.painter();
                    painter.rect_filled(rect, 2.0, Color32::from_gray(150));
                    match swatch {
                        Swatch::Line => {
                            painter.hline(
                                rect.x_range().shrink(2.0),
                                rect.center().y,
                                egui::Stroke::new(2.0, color),
                            );
                        }
                        Swatch::Dot => {
                            painter.circle_filled(rect.center(), 3.0, color);
                        }
                        Swatch::Diamond => {
                            let c = rect.center();
                            let corners = [(0.0, -4.0), (4.0, 0.0), (0.0, 4.0), (-4.0, 0.0)]
                                .map(|(x, y)| c + egui::vec2(x, y));
                            painter.add(egui::Shape::convex_polygon(
                                corners.to_vec(),
                                color,
                                egui::Stroke::NONE,
                            ));
                        }
                    }
                }
            },
        );
        // The top tick's label is centred on the plot's top edge: half of it stands above the
        // plot, where it touched the key's last row ("0.011" on the fit's name at class size).
        let tick_overhang = 0.5 * ui.text_style_height(&egui::TextStyle::Body) + 2.0;
        ui.add_space(tick_overhang);
        let key_height =
            key.response.rect.height() + tick_overhang + 2.0 * ui.spacing().item_spacing.y;
        plot(ui, (height - key_height).max(60.0))
    })
    .inner
}

/// Draws the plots that fit the body: 2D θ(t) and θ̇(θ); 3D the contact path on the curvature
/// map; both the 1/T sweep and the health. `alpha_star` marks the sweep plot; `height` is each
/// plot's height in points.
pub fn plots_ui(
    ui: &mut egui::Ui,
    history: &PlotHistory,
    snap: &Snapshot,
    map: Option<&CurvatureMap>,
    alpha_star: f64,
    height: f32,
) -> MapInput {
    let mut input = MapInput::default();
    let is_disk = snap.theta.is_some();
    let gap = ui.spacing().item_spacing.x;
    let fit = ((ui.available_width() + gap) / (MIN_PLOT_WIDTH + gap)).floor();
    // The other bodies' rate plot is one more: the health and force plots keep their places
    // after it where the panel is wide enough (at 1920 px it gives six ~300 px plots).
    let lanes = history.lanes() > 0 && snap.views.lanes;
    let extra = if lanes { 1.0 } else { 0.0 };
    let shown = fit.clamp(3.0 + extra, 5.0 + extra);
    let width = ((ui.available_width() - (shown - 1.0) * gap) / shown).max(120.0);
    ui.horizontal(|ui| {
        if is_disk {
            let theta_t: PlotPoints = history.plotted().map(|s| [s.t, s.theta]).collect();
            let theta_span = min_span(history.plotted().map(|s| s.theta), THETA_MIN_SPAN);
            let blue = SERIES_COLORS[0];
            keyed(
                ui,
                width,
                height,
                &[("θ(t), turned angle", blue, Swatch::Line)],
                |ui, plot_height| {
                    instrument(Plot::new("theta_t"), "t", "θ")
                        .width(width)
                        .height(plot_height)
                        .x_axis_label("t")
                        .y_axis_label("θ")
                        .include_y(theta_span.0)
                        .include_y(theta_span.1)
                        .show(ui, |p| p.line(Line::new("θ(t)", theta_t).color(blue)));
                },
            );
            // The phase curve as a line, broken where θ wraps at 2π: the newest samples at full
            // resolution (a periodic orbit retraces itself, and thinning cuts its peaks).
            let mut pieces: Vec<Vec<[f64; 2]>> = vec![Vec::new()];
            let mut prev: Option<f64> = None;
            for s in history.recent(PHASE_POINTS) {
                let theta = s.theta.rem_euclid(std::f64::consts::TAU);
                if prev.is_some_and(|q| (theta - q).abs() > std::f64::consts::PI) {
                    pieces.push(Vec::new());
                }
                if let Some(piece) = pieces.last_mut() {
                    piece.push([theta, s.rate]);
                }
                prev = Some(theta);
            }
            let rate_span = min_span(pieces.iter().flatten().map(|p| p[1]), RATE_MIN_SPAN);
            // "dθ/dt": the combining dot of θ̇ is lost on egui's rotated axis label. One colour
            // for every piece: they are one curve.
            let key = [("dθ/dt against θ, last 300 t", blue, Swatch::Line)];
            keyed(ui, width, height, &key, |ui, plot_height| {
                instrument(Plot::new("phase"), "θ", "dθ/dt")
                    .width(width)
                    .height(plot_height)
                    .x_axis_label("θ mod 2π")
                    .y_axis_label("dθ/dt")
                    .include_y(rate_span.0)
                    .include_y(rate_span.1)
                    .show(ui, |p| {
                        for piece in pieces.into_iter().filter(|piece| piece.len() > 1) {
                            p.line(
                                Line::new("dθ/dt (θ)", PlotPoints::from(piece))
                                    .color(blue)
                                    .width(1.5),
                            );
                        }
                    });
            });
        } else if !(history.has_crossings() || snap.views.lanes && history.has_lane_crossings()) {
            input = contact_map_ui(
                ui,
                snap,
                map,
                width * 2.0 + ui.spacing().item_spacing.x,
                height,
            );
        } else {
            input = contact_map_ui(ui, snap, map, width, height);
            crossings_ui(ui, history, snap, (width, height), PlotLook::ROW);
        }
        if lanes {
            bodies_ui(ui, history, snap, width, height);
        }
        sweep_ui(
            ui,
            history,
            snap,
            alpha_star,
            (width, height),
            PlotLook::ROW,
        );
        // A health plot with nothing to draw (no shown body's model has a constraint or a
        // conserved quantity: a viscous cylinder's) gives its place to the force plot.
        let health = health_measures(history, snap);
        if health && shown >= 4.0 + extra {
            health_ui(ui, history, snap, width, height);
        }
        if shown >= if health { 5.0 } else { 4.0 } + extra {
            force_ui(ui, history, snap, width, height);
        }
    });
    input
}

/// What the contact map reports back to the app: a click, and where the map is on screen.
#[derive(Debug, Clone, Copy, Default)]
pub struct MapInput {
    /// The body point (θ, φ) clicked this frame: θ in [0, π], φ in (−π, π].
    pub clicked: Option<(f64, f64)>,
    /// Plot ↔ screen coordinates of the map (`None` for a cylinder).
    pub transform: Option<egui_plot::PlotTransform>,
}

/// The body point (θ, φ) at a map position (x = φ, y = θ), folded into the body's ranges.
pub fn map_point(x: f64, y: f64) -> (f64, f64) {
    let theta = y.clamp(0.0, std::f64::consts::PI);
    let phi = (x + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    (theta, phi)
}

fn contact_map_ui(
    ui: &mut egui::Ui,
    snap: &Snapshot,
    map: Option<&CurvatureMap>,
    width: f32,
    height: f32,
) -> MapInput {
    // The paths drawn: the scene's own body's, and with the other bodies shown, each that is
    // the same body's (the map is of the scene's body), in its colour.
    let others: Vec<(usize, &Snapshot)> = if snap.views.lanes {
        snap.lanes
            .iter()
            .enumerate()
            .filter(|(_, l)| l.shares_body)
            .map(|(i, l)| (i + 1, l))
            .collect()
    } else {
        Vec::new()
    };
    let colour = |n: usize| {
        let [r, g, b] = crate::colormap::body_colour(n);
        Color32::from_rgb(r, g, b)
    };
    let (theta_now, phi_now) = angles(snap.contact_in_body);
    let ctx = ui.ctx().clone();
    // The map is the whole body, always: fixed bounds, and no pan or zoom, so a click names a
    // body point (it restarts the run from there).
    let yellow = Color32::from_rgb(255, 200, 0);
    let mut keys: Vec<Key<'_>> = if others.is_empty() {
        vec![
            ("contact path", Color32::BLACK, Swatch::Line),
            ("contact now", yellow, Swatch::Dot),
        ]
    } else {
        std::iter::once((snap.label.as_str(), colour(0), Swatch::Line))
            .chain(
                others
                    .iter()
                    .map(|&(n, l)| (l.label.as_str(), colour(n), Swatch::Line)),
            )
            .collect()
    };
    keys.push((
        "colour: curvature K",
        Color32::from_rgb(200, 70, 60),
        Swatch::Dot,
    ));
    let shown = keyed(ui, width, height, &keys, |ui, plot_height| {
        instrument(Plot::new("contact_map"), "φ", "θ")
            .width(width)
            .height(plot_height)
            .x_axis_label("φ (click: start here)")
            .y_axis_label("θ")
            .default_x_bounds(-std::f64::consts::PI, std::f64::consts::PI)
            .default_y_bounds(0.0, std::f64::consts::PI)
            .auto_bounds(false)
            .allow_drag(false)
            .allow_zoom(false)
            .allow_scroll(false)
            .allow_boxed_zoom(false)
            .allow_double_click_reset(false)
            .show(ui, |p| {
                if let Some(m) = map {
                    p.image(egui_plot::PlotImage::new(
                        "Gaussian curvature K",
                        m.texture(&ctx).id(),
                        PlotPoint::new(0.0, std::f64::consts::FRAC_PI_2),
                        egui::vec2(std::f32::consts::TAU, std::f32::consts::PI),
                    ));
                }
                if others.is_empty() {
                    for piece in map_pieces(&snap.body_trail) {
                        p.line(
                            Line::new("contact path", PlotPoints::from(piece))
                                .color(Color32::BLACK)
                                .width(1.5),
                        );
                    }
                    p.points(
                        Points::new("contact now", PlotPoints::from(vec![[phi_now, theta_now]]))
                            .color(yellow)
                            .radius(4.0),
                    );
                    return;
                }
                // Each body's path in its colour over a black edge, readable on the map's blues
                // and reds alike; its contact now a dot in its colour.
                for (n, body) in std::iter::once((0, snap)).chain(others.iter().copied()) {
                    let name = body.label.as_str();
                    for piece in map_pieces(&body.body_trail) {
                        p.line(
                            Line::new(name, PlotPoints::from(piece.clone()))
                                .color(Color32::BLACK)
                                .width(3.5),
                        );
                        p.line(
                            Line::new(name, PlotPoints::from(piece))
                                .color(colour(n))
                                .width(2.0),
                        );
                    }
                    let (theta, phi) = angles(body.contact_in_body);
                    p.points(
                        Points::new(name, PlotPoints::from(vec![[phi, theta]]))
                            .color(colour(n))
                            .radius(4.5),
                    );
                }
            })
    });
    let clicked = shown
        .response
        .clicked()
        .then(|| shown.response.interact_pointer_pos())
        .flatten()
        .map(|pos| {
            let v = shown.transform.value_from_position(pos);
            map_point(v.x, v.y)
        });
    MapInput {
        clicked,
        transform: Some(shown.transform),
    }
}

/// A contact path on the (φ, θ) map, split where φ wraps, so no line crosses the whole plot.
fn map_pieces(trail: &[glam::DVec3]) -> Vec<Vec<[f64; 2]>> {
    let mut pieces: Vec<Vec<[f64; 2]>> = vec![Vec::new()];
    let mut prev_phi: Option<f64> = None;
    for p in trail {
        let (theta, phi) = angles(*p);
        if prev_phi.is_some_and(|q| (phi - q).abs() > std::f64::consts::PI) {
            pieces.push(Vec::new());
        }
        if let Some(piece) = pieces.last_mut() {
            piece.push([phi, theta]);
        }
        prev_phi = Some(phi);
    }
    pieces.retain(|piece| piece.len() > 1);
    pieces
}

/// The lesson's plot alone (`presentation and class modes`), `width` × `height` points.
pub(super) fn lesson_plot(
    ui: &mut egui::Ui,
    plot: crate::scene::LessonPlot,
    history: &PlotHistory,
    snap: &Snapshot,
    size: (f32, f32),
    look: PlotLook,
) {
    match plot {
        crate::scene::LessonPlot::InversePeriod => {
            sweep_ui(ui, history, snap, snap.alpha_star, size, look);
        }
        crate::scene::LessonPlot::Crossings => crossings_ui(ui, history, snap, size, look),
        crate::scene::LessonPlot::None => {}
    }
}

/// How a sweep or crossing plot is drawn: in the row of plots, or large for a room.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct PlotLook {
    /// Marker radius, points.
    pub marker: f32,
    /// Values under the pointer (crosshair and label). Off in presentation and class modes
    /// until the pointer moves: a pointer left resting where the view was showed a stale
    /// tooltip for a whole lesson taught with a clicker.
    pub hover: bool,
    /// Space beside the data, as a fraction of the plot (a point at the largest m/m0 sat on
    /// the edge).
    pub margin: f32,
}

impl PlotLook {
    /// The row of plots under the 3D view.
    pub const ROW: PlotLook = PlotLook {
        marker: 3.0,
        hover: true,
        margin: 0.05,
    };

    /// The lesson's plot on a projector: markers at least [`LESSON_MARKER_PX`] across at
    /// `pixels_per_point`.
    pub fn large(pixels_per_point: f32, hover: bool) -> PlotLook {
        PlotLook {
            marker: (0.5 * LESSON_MARKER_PX / pixels_per_point).max(3.0),
            hover,
            margin: 0.1,
        }
    }

    fn apply<'a>(self, plot: Plot<'a>) -> Plot<'a> {
        plot.show_x(self.hover)
            .show_y(self.hover)
            .show_crosshair(self.hover)
            .set_margin_fraction(egui::vec2(self.margin, self.margin))
    }
}

/// The least width of a marker on the lesson's plot, pixels: a back row sees a 10 px dot.
pub const LESSON_MARKER_PX: f32 = 12.0;

fn sweep_ui(
    ui: &mut egui::Ui,
    history: &PlotHistory,
    snap: &Snapshot,
    alpha_star: f64,
    (width, height): (f32, f32),
    look: PlotLook,
) {
    // The running regime's points are "α up" and "α down"; points taken under another m/m0
    // or drag law are series of their own, named, never mixed in (nor into the fit).
    let now = Regime::of(snap);
    let mut up_by = history.sweep_by_regime(Branch::Up);
    let mut down_by = history.sweep_by_regime(Branch::Down);
    let up = up_by.remove(&now).unwrap_or_default();
    let down = down_by.remove(&now).unwrap_or_default();
    let others: Vec<(String, Vec<[f64; 2]>)> = {
        let mut regimes: Vec<Regime> = up_by.keys().chain(down_by.keys()).cloned().collect();
        regimes.sort();
        regimes.dedup();
        let named: Vec<(String, Vec<[f64; 2]>)> = regimes
            .into_iter()
            .map(|r| {
                let mut points = up_by.remove(&r).unwrap_or_default();
                points.extend(down_by.remove(&r).unwrap_or_default());
                (r.label(), points)
            })
            .collect();
        // A mass sweep leaves a regime per m/m0: past a few, one grey series says how many
        // (a key per regime once buried the plot under 28 of them).
        if named.len() > MAX_NAMED_REGIMES {
            let count = named.len();
            vec![(
                format!("{count} other m/m0 or drag laws"),
                named.into_iter().flat_map(|(_, p)| p).collect(),
            )]
        } else {
            named
        }
    };
    // The √ law is the viscous cylinder's; with inertia the branches follow other laws.
    let sqrt_law = match snap.model {
        ModelKind::DiskViscous => true,
        ModelKind::DiskInertial | ModelKind::SphereViscous | ModelKind::SphereInertial => false,
    };
    let fit = (sqrt_law && alpha_star > 0.0)
        .then(|| {
            let all: Vec<[f64; 2]> = up.iter().chain(&down).copied().collect();
            crate::analysis::fit::sqrt_law(&all, alpha_star)
        })
        .flatten();
    let fit_curve: Option<(String, Vec<[f64; 2]>)> = fit.map(|(a, b)| {
        let curve = (1..=120)
            .map(|i| {
                let alpha = alpha_star * (1.0 + 0.5 * (i as f64 / 120.0).powi(2));
                [alpha, 1.0 / (a / (alpha - alpha_star).sqrt() + b)]
            })
            .collect();
        (format!("T = {a:.3}/√(α−α*) + {b:.1}"), curve)
    });
    let (red, blue, orange, green) = (
        Color32::from_rgb(220, 60, 60),
        SERIES_COLORS[0],
        SERIES_COLORS[1],
        SERIES_COLORS[2],
    );
    // Every key always, so none moves when a series gains its first point.
    let mut keys = vec![
        ("α*", red, Swatch::Line),
        ("α now", Color32::GRAY, Swatch::Line),
        ("α up", blue, Swatch::Dot),
        ("α down", orange, Swatch::Dot),
    ];
    if let Some((name, _)) = &fit_curve {
        keys.push((name, green, Swatch::Line));
    }
    let other_color = |i: usize| OTHER_REGIME_COLORS[i % OTHER_REGIME_COLORS.len()];
    for (i, (label, _)) in others.iter().enumerate() {
        keys.push((label, other_color(i), Swatch::Dot));
    }
    let bodies = other_bodies_sweeps(history, snap);
    for body in &bodies {
        keys.push((&body.label, body.colour, Swatch::Diamond));
    }
    keyed(ui, width, height, &keys, |ui, plot_height| {
        look.apply(instrument(Plot::new("sweep"), "α", "1/T"))
            .custom_y_axes(vec![
                egui_plot::AxisHints::new_y()
                    .formatter(rate_tick_label)
                    .label_spacing(label_spacing(Y_LABEL_POINTS)),
            ])
            .width(width)
            .height(plot_height)
            .x_axis_label("α (rad)")
            .y_axis_label("1/T")
            .include_y(0.0)
            .include_y(rate_top(
                up.iter()
                    .chain(&down)
                    .chain(others.iter().flat_map(|o| &o.1))
                    .chain(bodies.iter().flat_map(|b| &b.points)),
            ))
            .show(ui, |p| {
                p.vline(VLine::new("α*", alpha_star).color(red));
                p.vline(VLine::new("α now", snap.alpha_rad).color(Color32::GRAY));
                if let Some((name, curve)) = &fit_curve {
                    p.line(Line::new(name, PlotPoints::from(curve.clone())).color(green));
                }
                p.points(
                    Points::new("α up", PlotPoints::from(up))
                        .color(blue)
                        .radius(look.marker),
                );
                p.points(
                    Points::new("α down", PlotPoints::from(down))
                        .color(orange)
                        .radius(look.marker),
                );
                for (i, (label, points)) in others.iter().enumerate() {
                    p.points(
                        Points::new(label.as_str(), PlotPoints::from(points.clone()))
                            .color(other_color(i))
                            .radius(look.marker),
                    );
                }
                for body in &bodies {
                    if body.alpha_star > 0.0 {
                        let name = format!("α* of {}", body.label);
                        p.vline(VLine::new(name, body.alpha_star).color(body.colour));
                    }
                    p.points(
                        Points::new(body.label.as_str(), PlotPoints::from(body.points.clone()))
                            .color(body.colour)
                            .shape(egui_plot::MarkerShape::Diamond)
                            .radius(look.marker * 1.4),
                    );
                }
            });
    });
}

/// Another body's 1/T points on the ramp, drawn in its colour with its α*.
struct BodySweep {
    label: String,
    colour: Color32,
    points: Vec<[f64; 2]>,
    alpha_star: f64,
}

/// The 1/T points of each other body shown (`[[bodies]]`, with the view's "the other bodies"
/// on) that has any: a ramp at 9° shows the designed 10° cylinder at rest (1/T = 0) and the
/// smooth one rolling.
fn other_bodies_sweeps(history: &PlotHistory, snap: &Snapshot) -> Vec<BodySweep> {
    if !snap.views.lanes {
        return Vec::new();
    }
    snap.lanes
        .iter()
        .enumerate()
        .filter_map(|(i, lane)| {
            let h = history.lane(i + 1)?;
            let mut points = h.sweep(Branch::Up);
            points.extend(h.sweep(Branch::Down));
            let [r, g, b] = crate::colormap::body_colour(i + 1);
            (!points.is_empty()).then(|| BodySweep {
                label: lane.label.clone(),
                colour: Color32::from_rgb(r, g, b),
                points,
                alpha_star: lane.alpha_star,
            })
        })
        .collect()
}

/// The least top of the 1/T axis (1/t0): a plot holding only halts (1/T = 0) was centred on
/// 0, half of it negative 1/T; rolling bodies here turn at 0.005–0.1.
pub const RATE_MIN_TOP: f64 = 0.01;

/// The top the 1/T plot includes: its largest point, at least [`RATE_MIN_TOP`].
pub fn rate_top<'a>(points: impl Iterator<Item = &'a [f64; 2]>) -> f64 {
    points
        .map(|p| p[1])
        .filter(|r| r.is_finite())
        .fold(RATE_MIN_TOP, f64::max)
}

/// The least span the crossing plot shows, in radians of polar angle. A settled orbit's
/// crossings repeat to the settling test's 1e-3 (and to 1e-6 once converged): autoscaled to
/// that jitter, one branch looked like two while the period-doubling lesson said "still period
/// 1". Doubled branches lie 0.1–0.2 rad apart, far outside it.
pub const CROSSING_MIN_SPAN: f64 = 0.05;

/// The least span of θ in the θ(t) plot: a halted cylinder's θ moves by 1e-11, which
/// autoscaled showed as noise labelled with eleven decimals.
pub const THETA_MIN_SPAN: f64 = 0.5;
/// The least span of dθ/dt in the phase plot ([`THETA_MIN_SPAN`]).
pub const RATE_MIN_SPAN: f64 = 0.01;

/// The y range the crossing plot includes: the crossings' own, widened about its middle to
/// [`CROSSING_MIN_SPAN`] (nothing to include when there are no crossings).
pub fn crossing_span(points: &[[f64; 2]]) -> (f64, f64) {
    min_span(points.iter().map(|p| p[1]), CROSSING_MIN_SPAN)
}

/// The range of `values` widened about its middle to at least `least`, so that a plot does not
/// magnify rounding into structure; `(NaN, NaN)` (nothing to include) for no finite value.
pub fn min_span(values: impl Iterator<Item = f64>, least: f64) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|y| y.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
            (a.min(y), b.max(y))
        });
    if lo > hi {
        return (f64::NAN, f64::NAN);
    }
    let half = 0.5 * least.max(hi - lo);
    let mid = 0.5 * (lo + hi);
    (mid - half, mid + half)
}

/// The settled crossings of ∂Ω against m/m0 (the orbit diagram), with the run's m/m0. With the
/// other bodies shown, each body's points are in its colour under its name: the doubling
/// lesson's bodies at m/m0 = 2 and 4.5 show one point and two.
fn crossings_ui(
    ui: &mut egui::Ui,
    history: &PlotHistory,
    snap: &Snapshot,
    (width, height): (f32, f32),
    look: PlotLook,
) {
    let bodies = if snap.views.lanes {
        1 + snap.lanes.len()
    } else {
        1
    };
    let (series, labels, colours): (Vec<Vec<[f64; 2]>>, Vec<String>, Vec<Color32>) = if bodies == 1
    {
        // One body: the points measured under the running drag law, and those of each other
        // law apart, named (at one m/m0 another law is another orbit, not a branch of this one).
        let now = snap.drag_law.label();
        let by_law = history.crossings_by_law();
        let mut series = vec![
            by_law
                .iter()
                .find(|(law, _)| *law == now)
                .map(|(_, points)| points.clone())
                .unwrap_or_default(),
        ];
        let mut labels = vec!["∂Ω crossings, settled".to_string()];
        let mut colours = vec![SERIES_COLORS[0]];
        for (i, (law, points)) in by_law.into_iter().filter(|(l, _)| *l != now).enumerate() {
            series.push(points);
            labels.push(law);
            colours.push(OTHER_REGIME_COLORS[i % OTHER_REGIME_COLORS.len()]);
        }
        (series, labels, colours)
    } else {
        // The bodies' names alone: the plot's title says they are crossings, and a room's
        // large text has no width to spare.
        let labels = std::iter::once(&snap.label)
            .chain(snap.lanes.iter().map(|l| &l.label))
            .cloned()
            .collect();
        let colours = (0..bodies)
            .map(|n| {
                let [r, g, b] = crate::colormap::body_colour(n);
                Color32::from_rgb(r, g, b)
            })
            .collect();
        let series = (0..bodies).map(|n| history.crossings_of_body(n)).collect();
        (series, labels, colours)
    };
    let colour = |n: usize| colours[n];
    let mut keys: Vec<Key<'_>> = labels
        .iter()
        .enumerate()
        .map(|(n, label)| (label.as_str(), colour(n), Swatch::Dot))
        .collect();
    keys.push(("m/m0 now", Color32::GRAY, Swatch::Line));
    let all: Vec<[f64; 2]> = series.iter().flatten().copied().collect();
    let (lo, hi) = crossing_span(&all);
    keyed(ui, width, height, &keys, |ui, plot_height| {
        look.apply(instrument(
            Plot::new("crossings_by_mass"),
            "m/m0",
            "polar angle (rad)",
        ))
        .width(width)
        .height(plot_height)
        .x_axis_label("m/m0")
        .y_axis_label("polar angle (rad)")
        .include_y(lo)
        .include_y(hi)
        // m/m0 from 0 to at least 1: with every point at one m/m0 (a lesson's first step, at
        // 0) the axis otherwise spanned −0.02 … 0.02, negative masses included.
        .include_x(0.0)
        .include_x(1.0)
        .show(ui, |p| {
            p.vline(VLine::new("m/m0 now", snap.mass_ratio).color(Color32::GRAY));
            for (n, points) in series.into_iter().enumerate() {
                p.points(
                    Points::new(labels[n].as_str(), PlotPoints::from(points))
                        .color(colour(n))
                        .radius(look.marker),
                );
            }
        });
    });
}

#[cfg(test)]
mod look_tests {
    use super::{LESSON_MARKER_PX, PlotLook, RATE_MIN_TOP, rate_top};

    #[test]
    fn a_1_over_t_plot_of_halts_alone_shows_no_negative_half() {
        // Only halts: the axis runs from 0 to the least top, not about 0.
        assert_eq!(rate_top([[0.2, 0.0], [0.21, 0.0]].iter()), RATE_MIN_TOP);
        assert_eq!(rate_top([[0.2, 0.0], [0.3, 0.05]].iter()), 0.05);
        assert_eq!(rate_top([[0.2, f64::NAN]].iter()), RATE_MIN_TOP);
    }

    #[test]
    fn the_lesson_plots_markers_are_large_enough_for_a_room_at_any_zoom() {
        for ppp in [1.0, 1.25, 1.6, 1.8, 2.2, 3.0] {
            let look = PlotLook::large(ppp, false);
            assert!(
                2.0 * look.marker * ppp >= LESSON_MARKER_PX,
                "{ppp}: {look:?}"
            );
            assert!(!look.hover && look.margin > PlotLook::ROW.margin);
        }
        const { assert!(LESSON_MARKER_PX >= 10.0) };
    }
}

#[cfg(test)]
mod tests {
    use super::{CROSSING_MIN_SPAN, crossing_span};

    #[test]
    fn the_crossing_plot_never_magnifies_a_settled_orbits_jitter_into_branches() {
        // Period 1 at three masses, jittering by 1e-6: shown over at least the minimum span,
        // centred on them.
        let settled = [[2.0, 1.220_000], [3.0, 1.220_001], [4.0, 1.219_999]];
        let (lo, hi) = crossing_span(&settled);
        assert!((hi - lo - CROSSING_MIN_SPAN).abs() < 1e-12);
        assert!((0.5 * (lo + hi) - 1.22).abs() < 1e-6);
        // Doubled branches 0.21 apart keep their own span.
        let doubled = [[4.5, 1.17], [4.5, 1.38], [6.0, 1.17], [6.0, 1.38]];
        let (lo, hi) = crossing_span(&doubled);
        assert!((lo - 1.17).abs() < 1e-12 && (hi - 1.38).abs() < 1e-12);
        // Nothing yet: nothing included.
        assert!(crossing_span(&[]).0.is_nan());
    }
}
