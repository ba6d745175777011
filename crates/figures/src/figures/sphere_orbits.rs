//! `sphere-orbits` — paper Fig. 3c: the order parameter 1/T versus α for 6 initial orientations
//! of the paper's body by default (viscous). Each run starts afresh at each α and is followed until it
//! halts or settles on a closed orbit, detected by event location on SO(3): successive crossings
//! of ∂Ω repeat ([`crate::analysis::orbits::sphere_orbits::settle`]). Closed orbits are identified by
//! their point on ∂Ω (antipodes identified); the paper finds that all runs collapse onto two
//! stable periodic orbits.

use anyhow::Result;
use glam::DVec3;
use serde::Serialize;

use super::{Computed, FigureData, FigureOptions};
use crate::analysis::critical_angle;
use crate::analysis::orbits::sphere_orbits::{
    SETTLED_ON_SAME_ORBIT, Settle, Settlement, boundary_distance, cluster_antipodal, settle,
};
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::dynamics::Ramp;
use crate::geometry::Body;

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// The body: the paper's by default, or `--seed`, or `--shape`.
    pub body: String,
    /// Seed. (null for a `--shape` file).
    pub seed: Option<u64>,
    /// α*.
    pub alpha_star: f64,
    /// Most distinct closed orbits seen at one α (the paper: 2).
    pub distinct_orbits: usize,
    /// Runs (orientation × α) that neither halted nor closed in time.
    pub undecided: usize,
    /// Orbit label per run and α (−1: halts).
    pub labels: Vec<Vec<i64>>,
}

use crate::analysis::studies::sphere::random_orientation;

/// Runs the figure: computes it, then writes OUT/sphere-orbits/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("sphere-orbits")?;
    super::written(compute(opts)?, &dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<Computed<FigureData<Summary>>> {
    opts.no_alpha("sphere-orbits", "α from 0.3 α* to 0.5")?;
    let fig = opts.sphere("sphere-orbits")?;
    let (body, seed) = (fig.body.clone(), fig.seed);
    let a_star = critical_angle(&Body::Sphere(body.clone())).alpha_star;
    let runs = 6;
    let na = if opts.quick { 5 } else { 24 };
    let alphas: Vec<f64> = (0..na)
        .map(|i| a_star * 0.3 + (0.5 - a_star * 0.3) * i as f64 / (na - 1) as f64)
        .collect();
    let jobs: Vec<(usize, usize)> = (0..runs)
        .flat_map(|r| (0..na).map(move |a| (r, a)))
        .collect();
    let fates = super::all_runs!(opts.ensemble(
        "sphere-orbits",
        jobs.len(),
        "orbits",
        |k| -> Result<Settlement> {
            let (r, a) = jobs[k];
            let ramp = Ramp::new(alphas[a], 0.0)?;
            let q0 = random_orientation(&body, opts.seed, r);
            Ok(settle(
                &body,
                &ramp,
                q0,
                &Settle {
                    t_max: 4000.0,
                    ..Settle::default()
                },
            )?
            .0)
        }
    ));
    // Label orbits at each α by clustering their ∂Ω points; keep labels consistent across α by
    // matching each cluster to the nearest cluster of the previous α.
    let mut labels = vec![vec![-1i64; na]; runs];
    let mut previous: Vec<DVec3> = Vec::new();
    let mut distinct = 0;
    let mut rows = Vec::new();
    for a in 0..na {
        let pts: Vec<(usize, DVec3)> = (0..runs)
            .filter_map(|r| match &fates[r * na + a] {
                Settlement::Periodic { point, .. } => Some((r, DVec3::from_array(*point))),
                _ => None,
            })
            .collect();
        let clusters = cluster_antipodal(
            &pts.iter().map(|p| p.1).collect::<Vec<_>>(),
            SETTLED_ON_SAME_ORBIT,
        );
        distinct = distinct.max(clusters.len());
        let mut reps: Vec<DVec3> = Vec::new();
        for (c, _) in &clusters {
            // Nearest previous representative keeps the label; otherwise a new label.
            let label = previous
                .iter()
                .enumerate()
                .filter(|(_, p)| boundary_distance(**p, *c) < 0.3)
                .min_by(|x, y| boundary_distance(*x.1, *c).total_cmp(&boundary_distance(*y.1, *c)))
                .map(|(i, _)| i)
                .unwrap_or(previous.len() + reps.len());
            reps.push(*c);
            for (r, p) in &pts {
                if boundary_distance(*p, *c) < SETTLED_ON_SAME_ORBIT {
                    labels[*r][a] = label as i64;
                }
            }
        }
        previous = reps;
        for r in 0..runs {
            let (inv_t, k) = match &fates[r * na + a] {
                Settlement::Periodic { period, .. } => (1.0 / period, labels[r][a] as f64),
                Settlement::Halts { .. } => (0.0, -1.0),
                Settlement::Undecided { .. } => (f64::NAN, -2.0),
            };
            rows.push(vec![r as f64, alphas[a], inv_t, k]);
        }
    }
    let csv_header = "run,alpha,inverse_period,orbit_label";
    let undecided = fates
        .iter()
        .filter(|f| matches!(f, Settlement::Undecided { .. }))
        .count();
    let summary = Summary {
        body: fig.label,
        seed,
        alpha_star: a_star,
        distinct_orbits: distinct,
        undecided,
        labels: labels.clone(),
    };
    let mut series = Vec::new();
    for r in 0..runs {
        series.push(Series {
            label: format!("orientation {r}"),
            points: rows
                .iter()
                .filter(|row| row[0] == r as f64 && row[2].is_finite())
                .map(|row| (row[1], row[2]))
                .collect(),
            color: PALETTE[r % PALETTE.len()],
            style: Style::LineMarkers,
        });
    }
    series.push(Series {
        label: "α*".into(),
        points: vec![(a_star, 0.0), (a_star, 0.06)],
        color: (0, 0, 0),
        style: Style::Line,
    });
    let panel = Panel {
        title: format!(
            "1/T of 6 orientations (viscous): {} distinct closed orbits",
            distinct
        ),
        x_label: "ramp angle α (rad)".into(),
        y_label: "1/T, T the orbit period (1/t0)".into(),
        log_x: false,
        log_y: false,
        series,
        legend: SeriesLabelPosition::UpperLeft,
        equal_aspect: false,
    };
    Ok(Computed::Figure(FigureData {
        panels: vec![panel],
        columns: 1,
        size: (1000, 700),
        header: csv_header,
        rows,
        summary,
    }))
}
