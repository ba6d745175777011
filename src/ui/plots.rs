//! The app's plots (egui_plot) and the history they draw, accumulated from the snapshots the
//! UI receives: θ(t) and θ̇(θ) for a cylinder, the contact path on the (φ, θ) curvature map for
//! a sphere, the order parameter 1/T against α collected while the user sweeps α (a halted body
//! counts as 1/T = 0, separately for sweeps up and down, so hysteresis shows as two branches),
//! the crossing points of ∂Ω against m/m0 collected while the user sweeps the mass (3D, once the
//! crossings repeat: one branch per period-1 orbit, two where it has doubled), and the numerical
//! health against time.
//!
//! [`PlotHistory`] is plain data, tested without a window; [`plots_ui`] draws it.

use std::collections::{BTreeMap, VecDeque};

use egui::Color32;
use egui_plot::{Heatmap, Legend, Line, Plot, PlotPoint, PlotPoints, Points, VLine};

use crate::colormap::{DIVERGING, sample};
use crate::geometry::Body;
use crate::geometry::sphere::{angles, direction};
use crate::sim::Snapshot;
use crate::view::CurvatureScale;

/// Samples kept per time series (older ones are dropped).
const MAX_SAMPLES: usize = 20_000;

/// Points per plotted time series (see [`PlotHistory::plotted`]).
pub const PLOT_POINTS: usize = 1000;

/// Width of the α bins of the 1/T sweep in ln α: 0.1 % of α (a slider step is far finer than
/// a user can resolve; one point per bin and direction keeps the newest measurement). Relative,
/// so that steps of 1 % of α* near a small α* (0.05 rad) stay apart, as the critical-angle
/// lesson needs.
const SWEEP_BIN: f64 = 1e-3;

/// One sample of the time series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Simulation time.
    pub t: f64,
    /// 2D: θ (unwrapped); 3D: the contact's polar angle θ.
    pub theta: f64,
    /// 2D: θ̇; 3D: |ω|.
    pub rate: f64,
    /// 3D: the contact's azimuth φ; 2D: 0.
    pub phi: f64,
    /// Worst ||q| − 1| so far.
    pub quat_norm_error: f64,
    /// Worst contact-normal error so far.
    pub contact_normal_error: f64,
    /// Worst |E + W − E(0)| so far.
    pub energy_drift: f64,
}

/// Which way α was last moved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Sweep {
    /// α increased (or not moved yet).
    Up,
    /// α decreased.
    Down,
}

/// What the plots show, accumulated from snapshots.
#[derive(Debug, Clone, Default)]
pub struct PlotHistory {
    samples: VecDeque<Sample>,
    /// (direction, α bin) → (α, 1/T).
    sweep: BTreeMap<(Sweep, i64), (f64, f64)>,
    last_alpha: Option<f64>,
    direction: Option<Sweep>,
    last_period: Option<f64>,
    /// (m/m0, polar angle of the crossing point with p_z ≥ 0) of settled ∂Ω crossings.
    crossings_by_mass: VecDeque<[f64; 2]>,
    last_crossing_t: Option<f64>,
}

/// Crossing points kept for the mass sweep.
const MAX_CROSSING_POINTS: usize = 5000;

impl PlotHistory {
    /// Clears the time series (a new run); the α sweep is kept, since it describes the body.
    pub fn clear_run(&mut self) {
        self.samples.clear();
        self.last_period = None;
    }

    /// Clears everything (a new body).
    pub fn clear_all(&mut self) {
        *self = Self::default();
    }

    /// Takes in one snapshot: a new sample if time moved on, and a sweep point when a new
    /// period was measured or the body halted.
    pub fn push(&mut self, snap: &Snapshot) {
        if self.samples.back().is_some_and(|s| snap.t <= s.t) {
            return;
        }
        let (theta, phi) = match snap.theta {
            Some(theta) => (theta, 0.0),
            None => angles(snap.contact_in_body),
        };
        self.samples.push_back(Sample {
            t: snap.t,
            theta,
            rate: snap.theta_dot.unwrap_or(snap.angular_speed),
            phi,
            quat_norm_error: snap.health.quat_norm_error,
            contact_normal_error: snap.health.contact_normal_error,
            energy_drift: snap.health.energy_drift,
        });
        while self.samples.len() > MAX_SAMPLES {
            self.samples.pop_front();
        }

        let alpha = snap.alpha_rad;
        if let Some(prev) = self.last_alpha
            && alpha != prev
        {
            self.direction = Some(if alpha > prev { Sweep::Up } else { Sweep::Down });
            // Periods measured before the change belong to the old α.
            self.last_period = snap.period;
        }
        self.last_alpha = Some(alpha);
        let direction = self.direction.unwrap_or(Sweep::Up);
        let bin = (alpha.ln() / SWEEP_BIN).round() as i64;
        if snap.halted {
            self.sweep.insert((direction, bin), (alpha, 0.0));
        } else if let Some(period) = snap.period
            && self.last_period != Some(period)
            && period > 0.0
        {
            self.sweep.insert((direction, bin), (alpha, 1.0 / period));
        }
        self.last_period = snap.period;

        if let Some((t, p)) = snap.last_crossing
            && self.last_crossing_t != Some(t)
            && snap.period_multiplicity.is_some()
            && snap.mass_ratio > 0.0
        {
            let p = if p.z < 0.0 { -p } else { p };
            self.crossings_by_mass
                .push_back([snap.mass_ratio, p.z.clamp(-1.0, 1.0).acos()]);
            while self.crossings_by_mass.len() > MAX_CROSSING_POINTS {
                self.crossings_by_mass.pop_front();
            }
            self.last_crossing_t = Some(t);
        }
    }

    /// The settled crossing points of ∂Ω as (m/m0, polar angle), oldest first.
    pub fn crossings_by_mass(&self) -> Vec<[f64; 2]> {
        self.crossings_by_mass.iter().copied().collect()
    }

    /// The samples, oldest first.
    pub fn samples(&self) -> impl Iterator<Item = &Sample> {
        self.samples.iter()
    }

    /// At most about [`PLOT_POINTS`] evenly spaced samples, the newest always included: a
    /// plot a few hundred pixels wide shows no more, and every point drawn costs tessellation
    /// and fill time (on a CPU renderer the full series doubled the frame time).
    pub fn plotted(&self) -> impl Iterator<Item = &Sample> {
        let n = self.samples.len();
        let stride = n.div_ceil(PLOT_POINTS).max(1);
        // Count from the newest sample so it is always drawn.
        let offset = (n + stride - 1) % stride;
        self.samples.iter().skip(offset).step_by(stride)
    }

    /// The sweep points (α, 1/T) of one direction, by α.
    pub fn sweep(&self, direction: Sweep) -> Vec<[f64; 2]> {
        self.sweep
            .iter()
            .filter(|((d, _), _)| *d == direction)
            .map(|(_, &(a, f))| [a, f])
            .collect()
    }
}

/// The Gaussian curvature K on a (φ, θ) grid, for the contact-path plot of a sphere.
#[derive(Debug, Clone)]
pub struct CurvatureMap {
    values: Vec<f64>,
    cols: usize,
    rows: usize,
    scale: CurvatureScale,
}

impl CurvatureMap {
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
        })
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
    let width = ((ui.available_width() - 3.0 * ui.spacing().item_spacing.x) / 4.0).max(120.0);
    ui.horizontal(|ui| {
        if is_disk {
            let theta_t: PlotPoints = history.plotted().map(|s| [s.t, s.theta]).collect();
            Plot::new("theta_t")
                .width(width)
                .height(height)
                .x_axis_label("t")
                .y_axis_label("θ")
                .show(ui, |p| p.line(Line::new("θ(t)", theta_t)));
            let phase: PlotPoints = history
                .plotted()
                .map(|s| [s.theta.rem_euclid(std::f64::consts::TAU), s.rate])
                .collect();
            Plot::new("phase")
                .width(width)
                .height(height)
                .x_axis_label("θ mod 2π")
                .y_axis_label("θ̇")
                .show(ui, |p| p.points(Points::new("θ̇(θ)", phase).radius(1.0)));
        } else if history.crossings_by_mass.is_empty() {
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
        health_ui(ui, history, width, height);
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
    // The map is the whole body, always: fixed bounds, and no pan or zoom, so a click names a
    // body point (it restarts the run from there).
    let shown = Plot::new("contact_map")
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
                let scale = m.scale;
                let heat = Heatmap::new(m.values.clone(), m.cols)
                    .at(PlotPoint::new(-std::f64::consts::PI, 0.0))
                    .tile_size(
                        (std::f64::consts::TAU / m.cols as f64) as f32,
                        (std::f64::consts::PI / m.rows as f64) as f32,
                    )
                    .show_labels(false)
                    .custom_mapping(Box::new(move |k| {
                        let [r, g, b] = sample(&DIVERGING, scale.position(k as f32));
                        Color32::from_rgb(r, g, b)
                    }))
                    .name("Gaussian curvature K");
                p.heatmap(heat);
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
    Plot::new("sweep")
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
    Plot::new("crossings_by_mass")
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

fn health_ui(ui: &mut egui::Ui, history: &PlotHistory, width: f32, height: f32) {
    let log = |v: f64| v.max(1e-17).log10();
    let series = |f: &dyn Fn(&Sample) -> f64| -> PlotPoints<'static> {
        history.plotted().map(|s| [s.t, log(f(s))]).collect()
    };
    let marks: Vec<[f64; 2]> = history
        .plotted()
        .flat_map(|s| {
            [s.quat_norm_error, s.contact_normal_error, s.energy_drift].map(|v| [s.t, log(v)])
        })
        .collect();
    let labels = ["||q|−1|", "contact normal", "|E+W−E₀|"];
    let corner = legend_corner(&marks, &[[f64::NAN, -16.0]], &labels, [width, height]);
    Plot::new("health")
        .width(width)
        .height(height)
        .legend(Legend::default().position(corner))
        .x_axis_label("t")
        .y_axis_label("log₁₀ error")
        .include_y(-16.0)
        .show(ui, |p| {
            p.line(Line::new("||q|−1|", series(&|s| s.quat_norm_error)));
            p.line(Line::new(
                "contact normal",
                series(&|s| s.contact_normal_error),
            ));
            p.line(Line::new("|E+W−E₀|", series(&|s| s.energy_drift)));
        });
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
