//! The app's plots (egui_plot) and the history they draw, accumulated from the samples the
//! simulation takes every [`PLOT_SAMPLE_DT`](crate::sim::PLOT_SAMPLE_DT) and the snapshots the
//! UI receives: θ(t) and θ̇(θ) for a cylinder, the contact path on the (φ, θ) curvature map for
//! a sphere, the order parameter 1/T against α collected while the user sweeps α (a halted body
//! counts as 1/T = 0, separately for sweeps up and down, so hysteresis shows as two branches),
//! the crossing points of ∂Ω against m/m0 collected while the user sweeps the mass (3D, once the
//! crossings repeat: one branch per period-1 orbit, two where it has doubled), and the numerical
//! health against time.
//!
//! [`PlotHistory`] (in `sim::history`, so the headless renderer collects the same data) is plain
//! data, tested without a window; [`plots_ui`] draws it as instruments: numbered ticks on every
//! axis at any size ([`nice_marks`], [`tick_label`]), values under the pointer, and only the
//! health quantities the model has.

use egui::Color32;
use egui_plot::{
    GridInput, GridMark, HoverPosition, Legend, Line, Plot, PlotPoint, PlotPoints, Points, VLine,
};

use crate::colormap::{DIVERGING, sample};
use crate::geometry::Body;
use crate::geometry::sphere::{angles, direction};
use crate::sim::Snapshot;
pub use crate::sim::history::{PLOT_POINTS, PlotHistory, Sample, Sweep};
use crate::view::CurvatureScale;

/// Samples in the phase curve: the last 300 time units at every
/// [`PLOT_SAMPLE_DT`](crate::sim::PLOT_SAMPLE_DT).
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

/// The closest x tick numbers may be, in points.
const X_LABEL_SPACING: f32 = 45.0;

/// The step of rung `k` of the 1-2-5 ladder: …, 0.1, 0.2, 0.5, 1, 2, 5, 10, … (k = 0 is 1).
fn rung(k: i32) -> f64 {
    [1.0, 2.0, 5.0][k.rem_euclid(3) as usize] * 10f64.powi(k.div_euclid(3))
}

/// Grid marks on the 1-2-5 ladder (egui_plot's default has steps of 10× only, so a narrow range
/// such as α from 0.0489 to 0.0499 got one labelled tick, or none): marks at the finest rung
/// at least `base_step_size`, each with the coarsest of the next six rungs that divides it, so
/// that some rung falls 2–2.5× under the label spacing and every axis shows several numbers.
pub fn nice_marks(input: GridInput) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    if !(lo.is_finite() && hi.is_finite() && hi > lo && input.base_step_size > 0.0) {
        return Vec::new();
    }
    let mut k = input.base_step_size.log10().floor() as i32 * 3 - 3;
    while rung(k) < input.base_step_size {
        k += 1;
    }
    let fine = rung(k);
    let first = (lo / fine).ceil() as i64;
    let last = (hi / fine).floor() as i64;
    if last - first > 10_000 {
        return Vec::new();
    }
    (first..=last)
        .map(|i| {
            let value = i as f64 * fine;
            let step_size = (0..7)
                .rev()
                .map(|j| rung(k + j))
                .find(|&s| {
                    let q = value / s;
                    (q - q.round()).abs() < 1e-6
                })
                .unwrap_or(fine);
            GridMark { value, step_size }
        })
        .collect()
}

/// A tick's number with as many decimals as its step needs (a step of 0.0005 shows 0.0495, not
/// egui_plot's rounded 0.050), and as the finest ticks of the visible `range` need, so that
/// all of an axis's numbers have the same decimals (0.0490 beside 0.0492, not 0.049).
pub fn tick_label(mark: GridMark, range: &std::ops::RangeInclusive<f64>) -> String {
    let decimals = |step: f64| (-step.log10() - 1e-9).ceil().max(0.0) as usize;
    let width = range.end() - range.start();
    let finest = if width.is_finite() && width > 0.0 {
        decimals(width / 5.0)
    } else {
        0
    };
    format!(
        "{:.*}",
        decimals(mark.step_size).max(finest).min(12),
        mark.value
    )
}

/// A plot that reads as an instrument: numbered ticks on both axes at any size, and the
/// values under the pointer named by the axes (`x` and `y`), with the series' name near a point.
fn instrument<'a>(plot: Plot<'a>, x: &'static str, y: &'static str) -> Plot<'a> {
    plot.x_grid_spacer(nice_marks)
        .y_grid_spacer(nice_marks)
        // Numbers from 45 points apart (egui_plot's x axis wants 60, which a 180-point plot
        // over a 1-2-5 step may not have twice).
        .custom_x_axes(vec![
            egui_plot::AxisHints::new_x()
                .formatter(tick_label)
                .label_spacing(X_LABEL_SPACING..=65.0),
        ])
        .y_axis_formatter(tick_label)
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
    let width = ((ui.available_width() - 4.0 * ui.spacing().item_spacing.x) / 5.0).max(120.0);
    ui.horizontal(|ui| {
        if is_disk {
            let theta_t: PlotPoints = history.plotted().map(|s| [s.t, s.theta]).collect();
            instrument(Plot::new("theta_t"), "t", "θ")
                .width(width)
                .height(height)
                .x_axis_label("t")
                .y_axis_label("θ")
                .show(ui, |p| p.line(Line::new("θ(t)", theta_t)));
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
            // "dθ/dt": the combining dot of θ̇ is lost on egui's rotated axis label.
            instrument(Plot::new("phase"), "θ", "dθ/dt")
                .width(width)
                .height(height)
                .x_axis_label("θ mod 2π")
                .y_axis_label("dθ/dt")
                .show(ui, |p| {
                    for piece in pieces.into_iter().filter(|piece| piece.len() > 1) {
                        p.line(Line::new("dθ/dt (θ)", PlotPoints::from(piece)).width(1.5));
                    }
                });
        } else if !history.has_crossings() {
            input = contact_map_ui(
                ui,
                snap,
                map,
                width * 2.0 + ui.spacing().item_spacing.x,
                height,
            );
        } else {
            input = contact_map_ui(ui, snap, map, width, height);
            crossings_ui(ui, history, snap, width, height);
        }
        sweep_ui(ui, history, snap, alpha_star, width, height);
        health_ui(ui, history, snap.health.measured, width, height);
        force_ui(ui, history, snap, width, height);
    });
    input
}

/// The contact force against time: N/F and the friction rolling needs, with the scene's μ
/// (when it has one) and N = 0 as the lines the model must stay within.
fn force_ui(ui: &mut egui::Ui, history: &PlotHistory, snap: &Snapshot, width: f32, height: f32) {
    let normal: Vec<[f64; 2]> = history.plotted().map(|s| [s.t, s.normal_force]).collect();
    // Where N ≤ 0 no friction holds the body: drawn as a gap, not a line off to infinity.
    let needed: Vec<[f64; 2]> = history
        .plotted()
        .map(|s| [s.t, s.friction_needed])
        .filter(|p| p[1].is_finite())
        .collect();
    let friction = snap.contact.friction;
    let red = Color32::from_rgb(230, 60, 50);
    let labels = ["N/F", "μ needed", "surface μ"];
    let corner = legend_corner(
        &[normal.clone(), needed.clone()].concat(),
        &[[f64::NAN, 0.0]],
        &labels,
        [width, height],
    );
    instrument(Plot::new("contact_force"), "t", "force / F")
        .width(width)
        .height(height)
        .legend(Legend::default().position(corner))
        .x_axis_label("t")
        .y_axis_label("N/F, μ needed")
        .include_y(0.0)
        .show(ui, |p| {
            // Colours apart from the surface's red line: N orange, μ needed blue.
            p.line(
                Line::new(labels[0], PlotPoints::from(normal))
                    .color(Color32::from_rgb(255, 150, 30)),
            );
            p.line(
                Line::new(labels[1], PlotPoints::from(needed))
                    .color(Color32::from_rgb(70, 140, 230)),
            );
            p.hline(egui_plot::HLine::new("N = 0", 0.0).color(Color32::GRAY));
            if let Some(mu) = friction {
                p.hline(egui_plot::HLine::new(labels[2], mu).color(red));
            }
        });
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
    // Split the path where φ wraps, so no line crosses the whole plot.
    let mut pieces: Vec<Vec<[f64; 2]>> = vec![Vec::new()];
    let mut prev_phi: Option<f64> = None;
    for p in &snap.body_trail {
        let (theta, phi) = angles(*p);
        if prev_phi.is_some_and(|q| (phi - q).abs() > std::f64::consts::PI) {
            pieces.push(Vec::new());
        }
        if let Some(piece) = pieces.last_mut() {
            piece.push([phi, theta]);
        }
        prev_phi = Some(phi);
    }
    let (theta_now, phi_now) = angles(snap.contact_in_body);
    let ctx = ui.ctx().clone();
    // The map is the whole body, always: fixed bounds, and no pan or zoom, so a click names a
    // body point (it restarts the run from there).
    let shown = instrument(Plot::new("contact_map"), "φ", "θ")
        .width(width)
        .height(height)
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
            for piece in pieces.into_iter().filter(|piece| piece.len() > 1) {
                p.line(
                    Line::new("contact path", PlotPoints::from(piece))
                        .color(Color32::BLACK)
                        .width(1.5),
                );
            }
            p.points(
                Points::new("contact now", PlotPoints::from(vec![[phi_now, theta_now]]))
                    .color(Color32::from_rgb(255, 200, 0))
                    .radius(4.0),
            );
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

fn sweep_ui(
    ui: &mut egui::Ui,
    history: &PlotHistory,
    snap: &Snapshot,
    alpha_star: f64,
    width: f32,
    height: f32,
) {
    let up = history.sweep(Sweep::Up);
    let down = history.sweep(Sweep::Down);
    // The √ law is the viscous cylinder's; with inertia the branches follow other laws.
    let fit = (snap.theta.is_some() && snap.mass_ratio == 0.0 && alpha_star > 0.0)
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
    let mut marks: Vec<[f64; 2]> = up.iter().chain(&down).copied().collect();
    let mut labels = vec!["α*", "α now"];
    // egui_plot lists only the series that have points.
    if !up.is_empty() {
        labels.push("α increasing");
    }
    if !down.is_empty() {
        labels.push("α decreasing");
    }
    if let Some((name, curve)) = &fit_curve {
        marks.extend(curve.iter().step_by(10));
        labels.push(name);
    }
    let spans = [[alpha_star, 0.0], [snap.alpha_rad, 0.0]];
    let corner = legend_corner(&marks, &spans, &labels, [width, height]);
    instrument(Plot::new("sweep"), "α", "1/T")
        .width(width)
        .height(height)
        .legend(Legend::default().position(corner))
        .x_axis_label("α (rad)")
        .y_axis_label("1/T")
        .include_y(0.0)
        .show(ui, |p| {
            p.vline(VLine::new("α*", alpha_star).color(Color32::from_rgb(220, 60, 60)));
            p.vline(VLine::new("α now", snap.alpha_rad).color(Color32::GRAY));
            if let Some((name, curve)) = fit_curve {
                p.line(
                    Line::new(name, PlotPoints::from(curve))
                        .color(Color32::from_rgb(120, 200, 120)),
                );
            }
            p.points(
                Points::new("α increasing", PlotPoints::from(up))
                    .color(Color32::from_rgb(60, 130, 230))
                    .radius(3.0),
            );
            p.points(
                Points::new("α decreasing", PlotPoints::from(down))
                    .color(Color32::from_rgb(240, 150, 30))
                    .radius(3.0),
            );
        });
}

/// Where a plot's legend hides the least of what it plots: the corner whose legend-sized box
/// covers the fewest of `marks`. The plot frames the marks and the points of `spans` (lines and
/// included values it also shows; a NaN coordinate leaves that axis alone) with egui_plot's 5 %
/// margin; the legend of `labels` is sized as egui draws it (16 points a row, about 6.5 per
/// character) in a widget of `size` points, of which the axes take about 60 by 30. Ties go to
/// the top right (egui_plot's default), then the bottom right, the top left, the bottom left.
fn legend_corner(
    marks: &[[f64; 2]],
    spans: &[[f64; 2]],
    labels: &[&str],
    size: [f32; 2],
) -> egui_plot::Corner {
    use egui_plot::Corner;
    let widest = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    let legend = [
        25.0 + 6.5 * widest as f64,
        12.0 + 16.0 * labels.len() as f64,
    ];
    let area = [f64::from(size[0]) - 60.0, f64::from(size[1]) - 30.0];
    let share = [0, 1].map(|k| (legend[k] / area[k].max(1.0)).min(1.0));
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in marks.iter().chain(spans) {
        for k in 0..2 {
            if p[k].is_finite() {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    // Where a mark sits, 0 to 1 across each axis (a flat axis puts it in the middle).
    let unit = |v: f64, k: usize| {
        if hi[k] > lo[k] {
            0.05 + 0.9 * (v - lo[k]) / (hi[k] - lo[k])
        } else {
            0.5
        }
    };
    let covered = |right: bool, top: bool| {
        marks
            .iter()
            .filter(|p| {
                let (x, y) = (unit(p[0], 0), unit(p[1], 1));
                let in_x = if right {
                    x >= 1.0 - share[0]
                } else {
                    x <= share[0]
                };
                let in_y = if top {
                    y >= 1.0 - share[1]
                } else {
                    y <= share[1]
                };
                in_x && in_y
            })
            .count()
    };
    [
        (Corner::RightTop, true, true),
        (Corner::RightBottom, true, false),
        (Corner::LeftTop, false, true),
        (Corner::LeftBottom, false, false),
    ]
    .into_iter()
    .min_by_key(|&(_, right, top)| covered(right, top))
    .map_or(Corner::RightTop, |(corner, _, _)| corner)
}

fn crossings_ui(
    ui: &mut egui::Ui,
    history: &PlotHistory,
    snap: &Snapshot,
    width: f32,
    height: f32,
) {
    let points = history.crossings_by_mass();
    let labels = ["m/m0 now", "settled crossings"];
    let spans = [[snap.mass_ratio, f64::NAN]];
    let corner = legend_corner(&points, &spans, &labels, [width, height]);
    instrument(Plot::new("crossings_by_mass"), "m/m0", "polar angle")
        .width(width)
        .height(height)
        .legend(Legend::default().position(corner))
        .x_axis_label("m/m0")
        .y_axis_label("∂Ω crossing, polar angle")
        .show(ui, |p| {
            p.vline(VLine::new("m/m0 now", snap.mass_ratio).color(Color32::GRAY));
            p.points(
                Points::new("settled crossings", PlotPoints::from(points))
                    .color(Color32::from_rgb(60, 130, 230))
                    .radius(2.0),
            );
        });
}

fn health_ui(
    ui: &mut egui::Ui,
    history: &PlotHistory,
    measured: crate::sim::Measured,
    width: f32,
    height: f32,
) {
    let log = |v: f64| v.max(1e-17).log10();
    // Only what the running model has (flat lines at the floor said nothing).
    let quantities = crate::sim::history::health_quantities(measured);
    if quantities.is_empty() {
        ui.allocate_ui(egui::vec2(width, height), |ui| {
            ui.vertical_centered(|ui| {
                ui.add_space(height * 0.35);
                ui.label("health: this model has no constraint or conserved quantity to drift");
                ui.label(egui::RichText::new("(θ is integrated directly)").weak());
            });
        });
        return;
    }
    let marks: Vec<[f64; 2]> = history
        .plotted()
        .flat_map(|s| {
            quantities
                .iter()
                .map(|q| [s.t, log((q.value)(s))])
                .collect::<Vec<_>>()
        })
        .collect();
    let labels: Vec<&str> = quantities.iter().map(|q| q.label).collect();
    let corner = legend_corner(&marks, &[[f64::NAN, -16.0]], &labels, [width, height]);
    instrument(Plot::new("health"), "t", "log₁₀ error")
        .width(width)
        .height(height)
        .legend(Legend::default().position(corner))
        .x_axis_label("t")
        .y_axis_label("log₁₀ error")
        .include_y(-16.0)
        .show(ui, |p| {
            for q in &quantities {
                let points: PlotPoints = history
                    .plotted()
                    .map(|s| [s.t, log((q.value)(s))])
                    .collect();
                p.line(Line::new(q.label, points));
            }
        });
}

#[cfg(test)]
mod axis_tests {
    use super::{nice_marks, tick_label};
    use egui_plot::GridInput;

    /// The labelled ticks of an axis `pixels` long over `bounds`, as egui_plot labels them: a
    /// mark whose step spans more than the x-axis label spacing.
    fn labelled(bounds: (f64, f64), pixels: f64) -> Vec<String> {
        let per_point = (bounds.1 - bounds.0) / pixels;
        // egui_plot asks for steps of at least 8 points.
        let marks = nice_marks(GridInput {
            bounds,
            base_step_size: 8.0 * per_point,
        });
        marks
            .iter()
            .filter(|m| m.step_size / per_point > f64::from(super::X_LABEL_SPACING))
            .map(|m| tick_label(*m, &(bounds.0..=bounds.1)))
            .collect()
    }

    #[test]
    fn every_axis_gets_several_numbers_at_any_range_and_size() {
        for bounds in [
            (0.0489, 0.0499),
            (0.0, 1.0),
            (-16.0, -15.2),
            (0.0, 2000.0),
            (0.1, 6.3),
        ] {
            for pixels in [180.0, 320.0, 900.0] {
                let ticks = labelled(bounds, pixels);
                assert!(ticks.len() >= 2, "{bounds:?} over {pixels} px: {ticks:?}");
                // Distinct numbers: enough decimals for the step.
                let mut unique = ticks.clone();
                unique.dedup();
                assert_eq!(unique, ticks, "{bounds:?}");
            }
        }
        // The case of the issue: α from α* = 0.0489 to 0.0499 on a 300 px plot.
        let ticks = labelled((0.0489, 0.0499), 300.0);
        assert!(ticks.contains(&"0.0490".to_string()), "{ticks:?}");
        // Nothing for a broken range.
        assert!(
            nice_marks(GridInput {
                bounds: (1.0, f64::NAN),
                base_step_size: 0.1
            })
            .is_empty()
        );
    }
}

#[cfg(test)]
mod tests {
    use super::legend_corner;
    use egui_plot::Corner;

    /// A plot's size in the app at 1600×900 with the controls shown.
    const SIZE: [f32; 2] = [320.0, 170.0];

    #[test]
    fn the_critical_angle_lessons_legend_leaves_the_fit_and_its_points_visible() {
        // α* = 0.0489; the periods the lesson measures, and its √-law fit. The top right holds
        // the 1.3 α* point and the top left the fit's steep rise (which the legend hid when it
        // was fixed there); the bottom right is empty.
        let a_star: f64 = 0.0489;
        let mut marks: Vec<[f64; 2]> = [
            (0.9, 0.0),
            (1.003, 613.09),
            (1.01, 385.92),
            (1.03, 265.97),
            (1.1, 182.95),
            (1.3, 125.07),
        ]
        .iter()
        .map(|&(r, t)| [r * a_star, if t > 0.0 { 1.0 / t } else { 0.0 }])
        .collect();
        marks.extend((1..=120).step_by(10).map(|i| {
            let alpha = a_star * (1.0 + 0.5 * (i as f64 / 120.0).powi(2));
            [alpha, 1.0 / (6.26 / (alpha - a_star).sqrt() + 98.8)]
        }));
        let labels = ["α*", "α now", "α increasing", "T = 6.260/√(α−α*) + 98.8"];
        let spans = [[a_star, 0.0], [1.3 * a_star, 0.0]];
        assert_eq!(
            legend_corner(&marks, &spans, &labels, SIZE),
            Corner::RightBottom
        );
    }

    #[test]
    fn the_doubled_branch_is_not_hidden_under_the_legend() {
        // The period-doubling lesson's crossings: one branch at m/m0 = 2, two at 4.5 and 6. The
        // upper branch sat under egui_plot's default top-right legend.
        let marks = [
            [2.0, 1.22],
            [4.5, 1.17],
            [4.5, 1.38],
            [6.0, 1.17],
            [6.0, 1.38],
        ];
        let labels = ["m/m0 now", "settled crossings"];
        let corner = legend_corner(&marks, &[[6.0, f64::NAN]], &labels, SIZE);
        assert_eq!(corner, Corner::LeftTop);
    }

    #[test]
    fn the_legend_goes_to_the_one_empty_corner() {
        let labels = ["a", "b", "c"];
        let filled = |skip: usize| -> Vec<[f64; 2]> {
            let corners = [[1.0, 1.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]];
            let mut marks = vec![[0.5, 0.5]];
            marks.extend(
                corners
                    .iter()
                    .enumerate()
                    .filter(|&(i, _)| i != skip)
                    .map(|(_, &c)| c),
            );
            marks
        };
        let expected = [
            Corner::RightTop,
            Corner::RightBottom,
            Corner::LeftTop,
            Corner::LeftBottom,
        ];
        for (skip, want) in expected.into_iter().enumerate() {
            assert_eq!(legend_corner(&filled(skip), &[], &labels, SIZE), want);
        }
        // Nothing plotted: egui_plot's own default.
        assert_eq!(legend_corner(&[], &[], &labels, SIZE), Corner::RightTop);
    }
}
