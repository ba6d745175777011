//! `sphere-bifurcation` — beyond paper Fig. 4e: the orbit diagram of 3D inertial rolling in
//! m/m0, the Floquet multipliers of its period-1 orbits, and the masses where they flip.
//!
//! On the paper's body at α = 0.15 (by default), for each m/m0 on a grid:
//! 1. **Direct simulation.** From several orientations released from rest, the body rolls at
//!    least to `t_min`, then on until its late crossings close a cycle (or it rests), at most to
//!    `t_cap` = 10 `t_min`; the crossings of ∂Ω in the run's last `t_min`/2 are the attractor's
//!    points. The attractor's period k is the smallest k with p_n ≈ p_{n−k} ≈ p_{n−2k}
//!    ([`crate::analysis::orbits::sphere_orbits::settled_cycle`], antipodes identified; a cycle of k ≥ 2 must also be steady). The
//!    diagram plots each late crossing against m: one branch per period-1 orbit, two where it
//!    has doubled. Runs within ~0.01 of a flip can stay undecided to the cap (the summary's
//!    `undecided_runs`): there the multiplier is so near −1 that the orbit attracts too slowly.
//! 2. **Floquet multipliers.** Each period-1 orbit found at the lowest inertial mass is
//!    continued in m as a fixed point of the return map on ∂Ω (5 dimensions: the boundary point
//!    and ω), by Newton's method with a central-difference Jacobian
//!    ([`crate::analysis::orbits::sphere_return_map`]); its multipliers are that Jacobian's eigenvalues
//!    (nalgebra). Where the most negative real multiplier passes −1 the orbit flips; the flip
//!    mass m_c is located by bisection.
//! 3. **Cross-check.** Each doubling window seen in the simulations (`onset_mass`, the first grid
//!    mass with a period-2 attractor near that orbit, and `end_mass`, the first after it without
//!    one) is compared with the flips, and near onset the squared alternation amplitude
//!    |p_n − p_{n−1}|² is fitted against m: it grows linearly from its own m_c at a
//!    supercritical flip.
//!
//! Every step is computed in the core ([`crate::analysis::orbits::orbit_diagram`]); this figure shards
//! step 1, shows progress, and writes and draws. `--shard I/N` splits the direct simulations
//! (step 1, the bulk of the work); `merge` runs steps 2 and 3.

use anyhow::{Result, anyhow};
use serde::Serialize;

use super::shard::{Fields, Record};
use super::{
    Computed, FigureData, FigureOptions, PAPER_ALPHA, par_map, progress, sphere_alpha_star,
};
use crate::analysis::orbits::orbit_diagram::{
    DirectRuns, OrbitDiagramError, RunWindow, continue_orbit, direct_run, doubling_windows,
    flip_brackets, locate_flip_in, orbit_diagram, period_one_seeds,
};
use crate::analysis::orbits::orbit_diagram::{
    DoublingWindow, Flip, LateRun, MAX_K, MassRow, OrbitBranch,
};
use crate::analysis::studies::sphere::random_orientation;
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::dynamics::Ramp;

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// The body: the paper's by default, or `--seed`, or `--shape`.
    pub body: String,
    /// Its α*.
    pub alpha_star: f64,
    /// α.
    pub alpha: f64,
    /// Orientations per mass.
    pub starts: usize,
    /// Every run goes on at least this long…
    pub t_min: f64,
    /// …then until its late crossings close a cycle of k ≤ 4 or it comes to rest, at most this
    /// long. The crossings of a run's last t_min/2 are the attractor's.
    pub t_cap: f64,
    /// Runs still without a cycle at t_cap (not at rest), over all masses.
    pub undecided_runs: usize,
    /// The longest any run went on.
    pub longest_run: f64,
    /// The orbit diagram, per grid mass.
    pub masses: Vec<MassRow>,
    /// The period-1 orbits continued in m, with their multipliers.
    pub orbits: Vec<OrbitBranch>,
    /// Every flip found.
    pub flips: Vec<Flip>,
    /// The windows of period 2 seen in the simulations, with the flips bracketing them.
    pub period_doubling: Vec<DoublingWindow>,
}

impl Record for LateRun {
    fn encode(&self, out: &mut Vec<f64>) {
        self.crossings.encode(out);
        self.omegas.encode(out);
        self.period.encode(out);
        self.t_end.encode(out);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let run = LateRun {
            crossings: Record::decode(f)?,
            omegas: Record::decode(f)?,
            period: Record::decode(f)?,
            t_end: Record::decode(f)?,
        };
        if !(run.t_end.is_finite() && run.t_end >= 0.0) {
            return Err(anyhow!("the run's end time {} is not a time", run.t_end));
        }
        // What the reduction relies on: a cycle of 1..=MAX_K crossings, finite ω.
        if let Some(k) = run.period
            && !(1..=MAX_K).contains(&k)
        {
            return Err(anyhow!("period multiplicity {k} is not 1 to {MAX_K}"));
        }
        if !run.omegas.iter().all(|w| w.is_finite()) {
            return Err(anyhow!("an angular velocity is not finite"));
        }
        Ok(run)
    }
}

/// Runs the figure: computes it, then writes OUT/sphere-bifurcation/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("sphere-bifurcation")?;
    super::written(compute(opts)?, &dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<Computed<FigureData<Summary>>> {
    let fig = opts.sphere("sphere-bifurcation")?;
    let body = fig.body;
    let alpha_star = sphere_alpha_star(&body);
    let alpha = opts.single_alpha("sphere-bifurcation", PAPER_ALPHA)?;
    let (n_mass, starts, t_min) = if opts.quick {
        (25, 4, 1500.0)
    } else {
        (61, 8, 3000.0)
    };
    let window = RunWindow {
        t_min,
        t_cap: 10.0 * t_min,
    };
    let masses: Vec<f64> = (0..n_mass)
        .map(|i| 12.0 * i as f64 / (n_mass - 1) as f64)
        .collect();

    // 1. Direct simulation.
    let jobs: Vec<(usize, usize)> = (0..n_mass)
        .flat_map(|m| (0..starts).map(move |o| (m, o)))
        .collect();
    let runs = super::all_runs!(
        opts.ensemble("sphere-bifurcation", jobs.len(), "runs", |j| {
            let (m, o) = jobs[j];
            let ramp = Ramp::new(alpha, masses[m])?;
            Ok(direct_run(
                &body,
                &ramp,
                random_orientation(&body, opts.seed, o),
                window,
            )?)
        })
    );
    let grid = DirectRuns::new(&masses, starts, &runs)?;
    // 2. Period-1 orbits at the lowest inertial mass, continued in m, and their flips.
    let seeds = period_one_seeds(&grid).map_err(|e| match e {
        OrbitDiagramError::NoPeriodOneOrbit {
            starts,
            mass_ratio,
            rested,
        } => {
            // Say why: below α* a start can come to rest (no crossings late in the run).
            let below = if alpha < alpha_star {
                format!(", below this body's α* = {alpha_star:.4}, where some orientations halt")
            } else {
                String::new()
            };
            anyhow!(
                "sphere-bifurcation: none of the {starts} runs at m/m0 = {mass_ratio} (α = {alpha}{below}) \
                 settled on a period-1 orbit ({rested} came to rest), so there is no orbit to continue \
                 in m/m0; give a larger --alpha"
            )
        }
        e => e.into(),
    })?;
    let bar = progress(seeds.len(), "orbits");
    let orbits = par_map(seeds.len(), &bar, |j| {
        continue_orbit(&body, alpha, &masses[1..], j, seeds[j])
    });
    let brackets = flip_brackets(&orbits);
    let bar = progress(brackets.len(), "flips");
    let flips = par_map(brackets.len(), &bar, |i| {
        locate_flip_in(&body, alpha, &brackets[i])
    });
    // 3. The diagram, and the windows of period 2 cross-checked against the flips.
    let diagram = orbit_diagram(&grid, &orbits)?;
    let windows = doubling_windows(&masses, &orbits, &flips, &diagram);
    let rows: Vec<Vec<f64>> = diagram
        .points
        .iter()
        .map(|p| {
            vec![
                p.mass_ratio,
                p.start as f64,
                p.t,
                p.polar,
                p.azimuth,
                p.return_time,
                p.period.map_or(f64::NAN, |k| k as f64),
            ]
        })
        .collect();

    let csv_header = "mass_ratio,start,t,crossing_polar,crossing_azimuth,return_time,period";
    let summary = Summary {
        body: fig.label,
        alpha_star,
        alpha,
        starts,
        t_min,
        t_cap: window.t_cap,
        undecided_runs: grid.undecided(window.t_cap),
        longest_run: grid.longest(),
        masses: diagram.masses,
        orbits,
        flips,
        period_doubling: windows,
    };
    Ok(Computed::Figure(FigureData {
        panels: panels(&summary, &rows),
        columns: 3,
        size: (1950, 650),
        header: csv_header,
        rows,
        summary,
    }))
}

fn panels(s: &Summary, rows: &[Vec<f64>]) -> Vec<Panel> {
    let color_of_k = |k: f64| match k as i64 {
        1 => (0, 0, 0),
        2 => PALETTE[1],
        _ => (150, 150, 150),
    };
    let mut diagram = Vec::new();
    let mut times = Vec::new();
    for k in [1.0, 2.0, f64::NAN] {
        let pick = |r: &&Vec<f64>| {
            if k.is_nan() {
                !(r[6] == 1.0 || r[6] == 2.0)
            } else {
                r[6] == k
            }
        };
        let label = if k.is_nan() {
            "period > 2 or undecided".to_string()
        } else {
            format!("period {k}")
        };
        diagram.push(Series {
            label: label.clone(),
            points: rows.iter().filter(pick).map(|r| (r[0], r[3])).collect(),
            color: color_of_k(k),
            style: Style::Markers,
        });
        times.push(Series {
            label,
            points: rows
                .iter()
                .filter(pick)
                .filter(|r| r[5].is_finite())
                .map(|r| (r[0], r[5]))
                .collect(),
            color: color_of_k(k),
            style: Style::Markers,
        });
    }
    let mut multipliers = vec![Series {
        label: "μ = −1".into(),
        points: vec![(0.0, -1.0), (12.0, -1.0)],
        color: (150, 150, 150),
        style: Style::Line,
    }];
    for b in &s.orbits {
        multipliers.push(Series {
            label: format!("orbit {}: most negative real μ", b.orbit),
            points: b
                .solutions
                .iter()
                .filter_map(|o| Some((o.mass_ratio, o.most_negative_real?)))
                .collect(),
            color: PALETTE[(2 * b.orbit) % PALETTE.len()],
            style: Style::LineMarkers,
        });
        multipliers.push(Series {
            label: format!("orbit {}: max |μ|", b.orbit),
            points: b
                .solutions
                .iter()
                .map(|o| (o.mass_ratio, o.max_modulus))
                .collect(),
            color: PALETTE[(2 * b.orbit + 1) % PALETTE.len()],
            style: Style::Line,
        });
    }
    let windows: Vec<String> = s
        .period_doubling
        .iter()
        .map(|w| {
            format!(
                "orbit {}: {}–{}",
                w.orbit,
                w.onset_mass,
                w.end_mass.map_or("12".into(), |e| e.to_string())
            )
        })
        .collect();
    vec![
        Panel {
            title: format!(
                "(a) late ∂Ω crossings; period 2: {}",
                if windows.is_empty() {
                    "none".into()
                } else {
                    windows.join(", ")
                }
            ),
            x_label: "m/m0".into(),
            y_label: "crossing point polar angle (rad)".into(),
            log_x: false,
            log_y: false,
            series: diagram,
            legend: SeriesLabelPosition::UpperRight,
            equal_aspect: false,
        },
        Panel {
            title: format!("(b) time between crossings (α = {})", s.alpha),
            x_label: "m/m0".into(),
            y_label: "return time".into(),
            log_x: false,
            log_y: false,
            series: times,
            legend: SeriesLabelPosition::LowerRight,
            equal_aspect: false,
        },
        Panel {
            title: if s.flips.is_empty() {
                "(c) multipliers; no flip (no μ passes −1)".into()
            } else {
                format!(
                    "(c) multipliers; flips at m/m0 = {}",
                    s.flips
                        .iter()
                        .map(|f| format!("{:.2}", f.mass_ratio))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            },
            x_label: "m/m0".into(),
            y_label: "multiplier".into(),
            log_x: false,
            log_y: false,
            series: multipliers,
            legend: SeriesLabelPosition::UpperLeft,
            equal_aspect: false,
        },
    ]
}
