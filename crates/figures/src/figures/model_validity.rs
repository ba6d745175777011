//! `model-validity` — where the rolling model holds (issue 34): over α × m/m0 for the paper's
//! body, whether the motion the inertial model computes stays rollable on a surface of
//! friction μ = 0.5 and μ = 1, or needs more friction (the body would slip), or needs the ramp
//! to pull (N ≤ 0: it would leave the ramp). The paper's experiments are marked: sin α ≈ 0.2,
//! m/m0 ≈ 0.025 (rubber-coated, viscous) and ≈ 2.5 (uncoated), SI §2H.
//!
//! Each cell runs the inertial model (DOP853, rtol 1e-9) from the default start (the body's
//! south pole on the ramp, at rest: the start of `simulate`) and from three random orientations
//! (seeded by `--seed`) over t ≤ 100 + 10 τ, τ = 1.4 m/m0 the drag relaxation time (so a heavy
//! body reaches its terminal motion), and follows the exact contact force
//! ([`crate::dynamics::ContactForce`]) along it: its smallest N/F, and the largest friction it
//! needs, |f_t|/N. A cell is classified by its worst start. In the viscous limit (m/m0 → 0) the
//! force is −F: N = cos α and μ_req = tan α, which is where the two dashed lines stand; inertia
//! adds the centre's acceleration on top, so the boundaries bend with m/m0.
//!
//! `--shard I/N` splits the runs (the grid's, then the two experiments'); `merge` classifies.

use anyhow::Result;
use serde::Serialize;

use super::{Computed, FigureData, FigureOptions};
use crate::analysis::studies::sphere::random_orientation;
use crate::chart::{Panel, Series, SeriesLabelPosition, Style};
use crate::dynamics::validity::ContactReport;
use crate::integrate::Method;
use crate::simulate::{InitialState, Model, Simulation, simulate};

/// The surfaces the map checks against: rubber on wood is about 0.5 to 1.
pub const SURFACES: [f64; 2] = [0.5, 1.0];

/// The paper's experiments (SI §2H): sin α ≈ 0.2, coated m/m0 ≈ 0.025 and uncoated ≈ 2.5.
pub const EXPERIMENTS: [(&str, f64, f64); 2] = [("coated", 0.2, 0.025), ("uncoated", 0.2, 2.5)];

/// Starts per cell: the default one and this many less one random orientations.
const STARTS: usize = 4;

/// What a run's contact force says about the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Needs μ ≤ 0.5: rolls on any ordinary surface.
    RollsAtHalf,
    /// Needs 0.5 < μ ≤ 1: rolls on a grippy surface, slips on a μ = 0.5 one.
    RollsAtOne,
    /// Needs μ > 1 but stays pressed on the ramp: slips on any ordinary surface.
    Slips,
    /// N ≤ 0 at some time: the body would leave the ramp.
    LeavesRamp,
}

impl Verdict {
    /// The verdict of one run's force report.
    ///
    /// # Example
    /// ```
    /// use rollphase_figures::dynamics::ContactForce;
    /// use rollphase_figures::dynamics::validity::{ContactLimits, ContactWatch};
    /// use rollphase_figures::figures::model_validity::Verdict;
    /// // A viscous body needs tan α: at α = 0.6, tan α = 0.68.
    /// let report = ContactWatch::new(ContactLimits::default(), 0.0, ContactForce::viscous(0.6)).report();
    /// assert_eq!(Verdict::of(&report), Verdict::RollsAtOne);
    /// ```
    pub fn of(r: &ContactReport) -> Self {
        if r.lift_off_t.is_some() || r.min_normal_force <= 0.0 {
            Verdict::LeavesRamp
        } else if r.max_friction_needed > SURFACES[1] {
            Verdict::Slips
        } else if r.max_friction_needed > SURFACES[0] {
            Verdict::RollsAtOne
        } else {
            Verdict::RollsAtHalf
        }
    }

    /// Its code in data.csv (0 to 3, worse upwards).
    fn code(self) -> f64 {
        self as u8 as f64
    }

    fn label(self) -> &'static str {
        match self {
            Verdict::RollsAtHalf => "rolls on μ = 0.5 (needs μ ≤ 0.5)",
            Verdict::RollsAtOne => "rolls on μ = 1 only (0.5 < μ needed ≤ 1)",
            Verdict::Slips => "slips (needs μ > 1)",
            Verdict::LeavesRamp => "leaves the ramp (N ≤ 0)",
        }
    }

    fn color(self) -> (u8, u8, u8) {
        match self {
            Verdict::RollsAtHalf => (44, 160, 44),
            Verdict::RollsAtOne => (31, 119, 180),
            Verdict::Slips => (255, 127, 14),
            Verdict::LeavesRamp => (214, 39, 40),
        }
    }

    const ALL: [Verdict; 4] = [
        Verdict::RollsAtHalf,
        Verdict::RollsAtOne,
        Verdict::Slips,
        Verdict::LeavesRamp,
    ];
}

/// One of the paper's experiments, as the model sees it.
#[derive(Debug, Serialize)]
pub struct Experiment {
    /// "coated" or "uncoated".
    pub name: &'static str,
    /// α (rad), asin 0.2.
    pub alpha: f64,
    /// m/m0.
    pub mass_ratio: f64,
    /// Smallest N/F over its starts.
    pub min_normal_force: f64,
    /// Largest friction needed over its starts.
    pub max_friction_needed: f64,
    /// Its verdict.
    pub verdict: Verdict,
}

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// The body.
    pub body: String,
    /// α* of the body.
    pub alpha_star: f64,
    /// The α grid (rad).
    pub alphas: Vec<f64>,
    /// The m/m0 grid.
    pub masses: Vec<f64>,
    /// Starts per cell.
    pub starts: usize,
    /// Cells per verdict: rolls at μ = 0.5, rolls at μ = 1 only, slips, leaves the ramp.
    pub cells: [usize; 4],
    /// The paper's two experiments.
    pub experiments: Vec<Experiment>,
}

/// Runs the figure: computes it, then writes OUT/model-validity/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("model-validity")?;
    super::written(compute(opts)?, &dir, opts)
}

/// The time window of a run at m/m0: long enough for the drag relaxation τ = 1.4 m/m0 to end.
fn window(mass: f64) -> f64 {
    100.0 + 10.0 * 1.4 * mass
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<Computed<FigureData<Summary>>> {
    opts.no_alpha("model-validity", "α over 0.05 … 1.2 rad")?;
    let fig = opts.sphere("model-validity")?;
    let body = crate::geometry::Body::Sphere(fig.body.clone());
    let alpha_star = super::sphere_alpha_star(&fig.body);
    let (n_a, n_m, starts) = if opts.quick {
        (6, 5, 1)
    } else {
        (24, 17, STARTS)
    };
    // Rounded to 12 digits so the grid reads 0.05, 0.1, … in data.csv, not 0.15000000000000002.
    let alphas: Vec<f64> = (1..=n_a)
        .map(|i| (1.2e12 * i as f64 / n_a as f64).round() / 1e12)
        .collect();
    let masses: Vec<f64> = (0..n_m)
        .map(|i| 10f64.powf(-2.0 + 4.0 * i as f64 / (n_m - 1) as f64))
        .collect();
    // The grid's cells, then the experiments', each from `starts` starts.
    let mut jobs: Vec<(f64, f64, usize)> = Vec::new();
    for &a in &alphas {
        for &m in &masses {
            jobs.extend((0..starts).map(|o| (a, m, o)));
        }
    }
    let grid_jobs = jobs.len();
    for (_, sin_alpha, m) in EXPERIMENTS {
        jobs.extend((0..starts).map(|o| (f64::asin(sin_alpha), m, o)));
    }
    let reports = super::all_runs!(opts.ensemble(
        "model-validity",
        jobs.len(),
        "runs",
        |k| -> Result<ContactReport> {
            let (alpha, mass, o) = jobs[k];
            let initial = if o == 0 {
                InitialState::at_rest(&body)
            } else {
                InitialState::Sphere {
                    q0: random_orientation(&fig.body, opts.seed, o - 1),
                    omega0: glam::DVec3::ZERO,
                }
            };
            let sim = Simulation::new(alpha, window(mass))
                .model(Model::Inertial { mass_ratio: mass })
                .method(Method::dop853(1e-9))
                .initial(initial)
                .samples(2);
            let (_, summary) = simulate(&body, &sim)?;
            summary
                .contact
                .ok_or_else(|| anyhow::anyhow!("a run reports its contact force"))
        },
    ));
    if reports.len() != jobs.len() {
        anyhow::bail!("model-validity: the runs came back in the wrong number");
    }
    // The worst start of each cell.
    let worst = |rs: &[ContactReport]| -> (Verdict, f64, f64) {
        let v = rs
            .iter()
            .map(Verdict::of)
            .max()
            .unwrap_or(Verdict::RollsAtHalf);
        let n = rs
            .iter()
            .map(|r| r.min_normal_force)
            .fold(f64::INFINITY, f64::min);
        let mu = rs.iter().map(|r| r.max_friction_needed).fold(0.0, f64::max);
        (v, n, mu)
    };
    let mut rows = Vec::with_capacity(grid_jobs);
    let mut points: [Vec<(f64, f64)>; 4] = Default::default();
    let mut cells = [0usize; 4];
    for (cell, rs) in reports[..grid_jobs].chunks(starts).enumerate() {
        let (alpha, mass, _) = jobs[cell * starts];
        let (verdict, _, _) = worst(rs);
        cells[verdict as usize] += 1;
        points[verdict as usize].push((alpha, mass));
        for (o, r) in rs.iter().enumerate() {
            rows.push(vec![
                alpha,
                mass,
                o as f64,
                r.min_normal_force,
                r.max_normal_force,
                r.max_friction_needed,
                r.lift_off_t.unwrap_or(f64::NAN),
                Verdict::of(r).code(),
                verdict.code(),
            ]);
        }
    }
    let experiments: Vec<Experiment> = EXPERIMENTS
        .iter()
        .zip(reports[grid_jobs..].chunks(starts))
        .map(|(&(name, sin_alpha, mass), rs)| {
            let (verdict, min_normal_force, max_friction_needed) = worst(rs);
            Experiment {
                name,
                alpha: sin_alpha.asin(),
                mass_ratio: mass,
                min_normal_force,
                max_friction_needed,
                verdict,
            }
        })
        .collect();
    let panel = chart(
        points,
        &masses,
        alpha_star,
        &format!(
            "where rolling holds: {}, worst of {starts} start(s) per cell",
            fig.label
        ),
    );
    let summary = Summary {
        body: fig.label,
        alpha_star,
        alphas,
        masses,
        starts,
        cells,
        experiments,
    };
    Ok(Computed::Figure(FigureData {
        panels: vec![panel],
        columns: 1,
        size: (1100, 800),
        header: "alpha,mass_ratio,start,min_normal_force,max_normal_force,max_friction_needed,\
                 lift_off_t,verdict,cell_verdict",
        rows,
        summary,
    }))
}

/// The map: each cell's verdict as a coloured point, α* and the viscous limit's lines, and the
/// paper's experiments.
fn chart(points: [Vec<(f64, f64)>; 4], masses: &[f64], alpha_star: f64, title: &str) -> Panel {
    let mut series: Vec<Series> = Verdict::ALL
        .iter()
        .zip(points)
        .filter(|(_, p)| !p.is_empty())
        .map(|(v, p)| Series {
            label: v.label().into(),
            points: p,
            color: v.color(),
            style: Style::Markers,
        })
        .collect();
    let (m_lo, m_hi) = (masses[0], masses[masses.len() - 1]);
    let vertical = |x: f64| vec![(x, m_lo), (x, m_hi)];
    series.push(Series {
        label: format!("α* = {alpha_star:.3} (rests below, from some starts)"),
        points: vertical(alpha_star),
        color: (120, 120, 120),
        style: Style::Line,
    });
    series.push(Series {
        label: "viscous limit: tan α = 0.5 and tan α = 1".into(),
        points: [vertical(0.5f64.atan()), vertical(1f64.atan())].concat(),
        color: (0, 0, 0),
        style: Style::Segments,
    });
    series.push(Series {
        label: "the paper's experiments (sin α = 0.2; m/m0 ≈ 0.025 coated, 2.5 uncoated)".into(),
        points: EXPERIMENTS.iter().map(|&(_, s, m)| (s.asin(), m)).collect(),
        color: (0, 0, 0),
        style: Style::Markers,
    });
    Panel {
        title: title.to_string(),
        x_label: "ramp angle α (rad)".into(),
        y_label: "m/m0".into(),
        log_x: false,
        log_y: true,
        series,
        legend: SeriesLabelPosition::UpperLeft,
        equal_aspect: false,
    }
}
