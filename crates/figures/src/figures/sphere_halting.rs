//! `sphere-halting` — SI §2D–2E: the halting loops of viscous 3D rolling and their stability, on
//! the default body at α = 0.5, 0.75 and 0.9 α*.
//!
//! The rest states Q = tan α, their linear stability and its check by simulation are computed
//! in the core ([`crate::analysis::rest::halting`], where the method is described); this file writes
//! the segments and draws them on the body's (φ, θ) chart.

use anyhow::Result;
use glam::DVec3;
use serde::Serialize;

use super::{FigureData, FigureOptions, progress};
use crate::analysis::critical_angle;
use crate::analysis::rest::halting::{QualityGrid, halting_loops};
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::geometry::Body;
use crate::geometry::sphere::angles;

/// Per-α result.
#[derive(Debug, Clone, Serialize)]
pub struct LevelResult {
    /// α/α*.
    pub alpha_over_alpha_star: f64,
    /// α.
    pub alpha: f64,
    /// Loop segments found.
    pub segments: usize,
    /// Fraction of loop points classified stable.
    pub stable_fraction: f64,
    /// Perturbed stable points that came back to rest nearby / tried.
    pub stable_confirmed: [usize; 2],
    /// Perturbed unstable points that left / tried.
    pub unstable_confirmed: [usize; 2],
}

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// The body: the paper's by default, or `--seed`, or `--shape`.
    pub body: String,
    /// Seed. (null for a `--shape` file).
    pub seed: Option<u64>,
    /// α*.
    pub alpha_star: f64,
    /// Per α.
    pub levels: Vec<LevelResult>,
}

/// Runs the figure: computes it, then writes OUT/sphere-halting/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("sphere-halting")?;
    compute(opts)?.write_to(&dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<FigureData<Summary>> {
    opts.no_alpha("sphere-halting", "α/α* over its levels")?;
    let fig = opts.sphere("sphere-halting")?;
    let (body, seed) = (fig.body.clone(), fig.seed);
    let ca = critical_angle(&Body::Sphere(body.clone()));
    super::refuse_perfect_sphere(
        "sphere-halting",
        ca.alpha_star,
        "it has no rest point on any tilted plane, so there are no halting loops Q = tan α; it \
         rolls from every orientation",
    )?;
    let (nt, np) = if opts.quick { (91, 181) } else { (181, 361) };
    let grid = QualityGrid::new(&body, nt, np);
    let mut levels = Vec::new();
    let mut series = Vec::new();
    let mut rows = Vec::new();
    for (li, f) in [0.5, 0.75, 0.9].into_iter().enumerate() {
        let alpha = f * ca.alpha_star;
        let bar = progress(0, "stability");
        let loops = halting_loops(&body, &grid, alpha, &|total| {
            bar.set_length(total as u64);
            bar.inc(1);
        })?;
        bar.finish_and_clear();
        let (mut stable_pts, mut unstable_pts) = (Vec::new(), Vec::new());
        for seg in &loops.segments {
            let target = if seg.stable {
                &mut stable_pts
            } else {
                &mut unstable_pts
            };
            target.push(seg.from);
            target.push(seg.to);
            let ((p0, t0), (p1, t1)) = (seg.from, seg.to);
            rows.push(vec![
                alpha,
                0.5 * (p0 + p1),
                0.5 * (t0 + t1),
                if seg.stable { 1.0 } else { 0.0 },
            ]);
        }
        levels.push(LevelResult {
            alpha_over_alpha_star: f,
            alpha,
            segments: loops.segments.len(),
            stable_fraction: loops.stable_fraction(),
            stable_confirmed: loops.stable_confirmed,
            unstable_confirmed: loops.unstable_confirmed,
        });
        let shade = 0.45 + 0.25 * li as f64;
        let tint = |c: (u8, u8, u8)| {
            (
                (c.0 as f64 * shade) as u8,
                (c.1 as f64 * shade) as u8,
                (c.2 as f64 * shade) as u8,
            )
        };
        series.push(Series {
            label: format!("stable, α = {f} α*"),
            points: stable_pts,
            color: tint(PALETTE[2]),
            style: Style::Segments,
        });
        series.push(Series {
            label: format!("unstable, α = {f} α*"),
            points: unstable_pts,
            color: tint(PALETTE[1]),
            style: Style::Segments,
        });
    }
    let (t_star, p_star) = angles(DVec3::from_array(ca.direction));
    series.push(Series {
        label: "max Q (rests only up to α*)".into(),
        points: vec![(p_star, t_star)],
        color: (0, 0, 0),
        style: Style::Markers,
    });
    let csv_header = "alpha,phi,theta,stable";
    let summary = Summary {
        body: fig.label,
        seed,
        alpha_star: ca.alpha_star,
        levels,
    };
    let panel = Panel {
        title: format!(
            "halting loops Q = tan α on the body (α* = {:.4}) and their stability",
            ca.alpha_star
        ),
        x_label: "contact azimuth φ (rad)".into(),
        y_label: "contact polar angle θ (rad)".into(),
        log_x: false,
        log_y: false,
        series,
        legend: SeriesLabelPosition::UpperRight,
        equal_aspect: false,
    };
    Ok(FigureData {
        panels: vec![panel],
        columns: 1,
        size: (1300, 760),
        header: csv_header,
        rows,
        summary,
    })
}
