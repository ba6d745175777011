//! `sphere-doubling` — paper Fig. 4e: the orbits of 3D rolling with inertia. On the paper's own
//! body (numpy seed 219, σ = 0.25, l ≤ 5; `--seed` or `--shape` for another) at the paper's
//! α = 0.15, from 100 random orientations released from rest, the body rolls with m/m0 = 0, 6
//! and 10; the contact path [θ(t), φ(t)] over 600 < t < 700 is drawn as in the paper, and each
//! run's period multiplicity is measured from its crossings of ∂Ω: the smallest k for which the
//! crossing points repeat to 1e-5 (k = 1 a period-1 orbit, k = 2 a doubled one; antipodes
//! identified, since q and −q are the same orientation), with the cycle's duration in units of
//! the viscous period and of the perfect sphere's 2π/sin α. A run goes on at least to the
//! paper's t = 2000, then until its fate is decided (a cycle closes, checked at every crossing,
//! or it comes to rest), at most to t = 20 000; the summary counts the runs still undecided
//! there (`undecided`, per mass) and says how long the longest run went.
//!
//! **Finding: the paper's period doubling holds on its body.** Period 1 at m/m0 = 0, period 2 at
//! m/m0 = 6, period 1 again at m/m0 = 10 (see docs/guide/figures.md and `sphere-bifurcation` for the window and
//! the Floquet multipliers). An earlier version of this figure used a body of our own (seed 3)
//! and found period 1 at m/m0 = 6: the doubling is not generic. The cross-body statistic
//! answers how common it is: over the first `CROSS_BODIES` paper-generator bodies (numpy seeds
//! 0, 1, …; σ = 0.25, l ≤ 5) that are convex with α* < 0.13, the fraction with a period-2
//! attractor at m/m0 = 6, α = 0.15.
//!
//! `--shard I/N` splits this body's runs and the other bodies' runs (one list; every shard
//! repeats the cheap search for the other bodies); `merge` counts and draws.

use anyhow::{Result, anyhow};
use serde::Serialize;

use super::shard::{Fields, Record};
use super::{Computed, FigureData, FigureOptions, PAPER_ALPHA, sphere_alpha_star};
use crate::analysis::orbits::sphere_orbits::{Decide, decided_run};
use crate::analysis::rest::critical_angle::paper_spheres_with_alpha_star;
use crate::analysis::studies::sphere::random_orientation;
use crate::analysis::studies::sphere::{
    DoublingAcrossBodies, PeriodCounts, RunOutcome, decided_from_rest, median_cycle_duration,
};
use crate::analysis::verdict::Fate;
use crate::chart::{Panel, Series, SeriesLabelPosition, Style};
use crate::dynamics::Ramp;
use crate::geometry::Sphere;
use crate::geometry::sphere::angles;
use glam::DVec3;

const MASSES: [f64; 3] = [0.0, 6.0, 10.0];
/// Bodies in the cross-body statistic (full size).
pub const CROSS_BODIES: usize = 50;
/// The mass of the cross-body statistic.
const CROSS_MASS: f64 = 6.0;

/// Per-mass result.
#[derive(Debug, Clone, Serialize)]
pub struct MassResult {
    /// m/m0.
    pub mass_ratio: f64,
    /// Runs whose crossing sequence closed with k = 1, 2, 3, 4, or not at all.
    pub cycle_counts: [usize; 5],
    /// Of the runs that did not close: those that came to rest.
    pub at_rest: usize,
    /// Of the runs that did not close: those still undecided at the cap (`t_cap`).
    pub undecided: usize,
    /// Runs whose body left the ramp (counted with those that did not close).
    pub left_model: usize,
    /// The longest a run of this mass went on before its fate was decided (or the cap).
    pub longest_run: f64,
    /// Median cycle duration in units of the viscous orbit period (closed runs).
    pub median_period_ratio: f64,
    /// The same in units of the perfect sphere's period 2π/sin α.
    pub median_period_over_perfect: f64,
}

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// The body: the paper's by default, or `--seed`, or `--shape`.
    pub body: String,
    /// Seed of the body used. (null for a `--shape` file).
    pub seed: Option<u64>,
    /// Its α*.
    pub alpha_star: f64,
    /// α.
    pub alpha: f64,
    /// Orientations.
    pub orientations: usize,
    /// Median viscous orbit period.
    pub viscous_period: f64,
    /// Every run goes on at least this long (the paper's t = 2000)…
    pub t_min: f64,
    /// …then until its crossings close a cycle of k ≤ 4 (to 1e-5) or it comes to rest, and at
    /// most this long; runs still open here are counted as undecided.
    pub t_cap: f64,
    /// Per mass.
    pub masses: Vec<MassResult>,
    /// The same question on other bodies: α* < 0.13 (α/α* > 1.15).
    pub cross_body: DoublingAcrossBodies,
    /// The same for bodies as close to rolling as the paper's (0.13 ≤ α* < 0.15, α/α* < 1.15;
    /// the paper's body has α* = 0.139).
    pub cross_body_near_critical: DoublingAcrossBodies,
}

/// How long a run goes at least, and at most, and when it is decided.
fn decide(quick: bool) -> Decide {
    Decide {
        t_min: if quick { 1200.0 } else { 2000.0 },
        t_cap: if quick { 6000.0 } else { T_CAP },
        max_k: MAX_MULTIPLICITY,
        tol: CYCLE_TOL,
    }
}

/// The longest a run goes on (10 × the paper's t = 2000).
const T_CAP: f64 = 20_000.0;
/// Crossing points that repeat to this close a cycle.
const CYCLE_TOL: f64 = 1e-5;

/// How a run from rest at orientation `o` ends ([`DecidedRun::multiplicity`]).
///
/// [`DecidedRun::multiplicity`]: crate::analysis::orbits::sphere_orbits::DecidedRun::multiplicity
fn run_period(
    body: &Sphere,
    alpha: f64,
    mass: f64,
    seed: u64,
    o: usize,
    decide: &Decide,
) -> Result<Option<usize>> {
    Ok(decided_from_rest(body, &Ramp::new(alpha, mass)?, seed, o, decide)?.multiplicity())
}

/// The bodies of one α* band of the cross-body statistic and the starts each one gets.
struct CrossBand {
    band: (f64, f64),
    orientations: usize,
    bodies: Vec<(u32, Sphere)>,
}

impl CrossBand {
    fn find(n: usize, band: (f64, f64), orientations: usize) -> Result<Self> {
        Ok(CrossBand {
            band,
            orientations,
            bodies: paper_spheres_with_alpha_star(n, band.0, band.1)?,
        })
    }

    fn runs(&self) -> usize {
        self.bodies.len() * self.orientations
    }

    fn statistic(&self, periods: &[Option<usize>]) -> DoublingAcrossBodies {
        let seeds = self.bodies.iter().map(|b| b.0).collect();
        DoublingAcrossBodies::from_periods(self.band, seeds, self.orientations, periods)
    }
}

/// The longest cycle (in crossings of ∂Ω) the figure looks for.
const MAX_MULTIPLICITY: usize = 4;

/// One run of the ensemble: this body's (its cycle and sampled contact path), or another
/// body's period multiplicity.
pub(crate) enum Run {
    Main {
        cycle: Option<(usize, f64)>,
        path: Vec<DVec3>,
        /// Came to rest (else, without a cycle, undecided at the cap).
        rest: bool,
        /// When it was decided, or the cap.
        t_end: f64,
        /// The body left the ramp (no cycle or rest is claimed for it).
        left_model: bool,
    },
    /// k, 0 at rest, `None` undecided.
    Cross(Option<usize>),
}

impl Record for Run {
    fn encode(&self, out: &mut Vec<f64>) {
        match self {
            Run::Main {
                cycle,
                path,
                rest,
                t_end,
                left_model,
            } => {
                out.push(0.0);
                cycle.encode(out);
                path.encode(out);
                rest.encode(out);
                t_end.encode(out);
                left_model.encode(out);
            }
            Run::Cross(k) => {
                out.push(1.0);
                k.encode(out);
            }
        }
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let run = match f.count()? {
            0 => Run::Main {
                cycle: Record::decode(f)?,
                path: Record::decode(f)?,
                rest: Record::decode(f)?,
                t_end: Record::decode(f)?,
                left_model: Record::decode(f)?,
            },
            1 => Run::Cross(Record::decode(f)?),
            v => return Err(anyhow!("{v} is not a run kind")),
        };
        // What the reduction relies on: a cycle of 1..=4 crossings with a finite positive
        // duration, and a finite path.
        let multiplicity_ok = |k: usize| (1..=MAX_MULTIPLICITY).contains(&k);
        match &run {
            Run::Main {
                cycle, path, t_end, ..
            } => {
                if !(t_end.is_finite() && *t_end >= 0.0) {
                    return Err(anyhow!("the run's end time {t_end} is not a time"));
                }
                if let Some((k, d)) = cycle
                    && !(multiplicity_ok(*k) && d.is_finite() && *d > 0.0)
                {
                    return Err(anyhow!(
                        "cycle ({k} crossings, duration {d}) is not a cycle of 1 to \
                         {MAX_MULTIPLICITY} crossings with a positive duration"
                    ));
                }
                if !path.iter().all(|u| u.is_finite()) {
                    return Err(anyhow!("the contact path holds a non-finite point"));
                }
            }
            Run::Cross(Some(k)) if *k != 0 && !multiplicity_ok(*k) => {
                return Err(anyhow!(
                    "period multiplicity {k} is not 0 (at rest) or 1 to {MAX_MULTIPLICITY}"
                ));
            }
            Run::Cross(_) => {}
        }
        Ok(run)
    }
}

/// One mass's runs (in orientation order): the counts of each period and the median cycle
/// (from the core), its panel of contact paths, and its rows (appended to `rows`); `t1` is the
/// viscous period.
fn mass_result(
    m: f64,
    outcomes: &[RunOutcome],
    paths: &[&Vec<DVec3>],
    (t1, alpha): (f64, f64),
    rows: &mut Vec<Vec<f64>>,
) -> Result<(MassResult, Panel)> {
    let n = outcomes.len();
    let counts = PeriodCounts::of(outcomes)?;
    let mut series = Vec::new();
    for (o, path) in paths.iter().enumerate() {
        // The contact path in (φ, θ), broken where φ wraps.
        let mut piece: Vec<(f64, f64)> = Vec::new();
        for u in path.iter() {
            let (th, ph) = angles(*u);
            if piece
                .last()
                .is_some_and(|l| (ph - l.0).abs() > std::f64::consts::PI)
            {
                series.push(Series {
                    label: String::new(),
                    points: std::mem::take(&mut piece),
                    color: (0, 0, 0),
                    style: Style::Line,
                });
            }
            piece.push((ph, th));
            rows.push(vec![m, o as f64, ph, th]);
        }
        series.push(Series {
            label: String::new(),
            points: piece,
            color: (0, 0, 0),
            style: Style::Line,
        });
    }
    let median = median_cycle_duration(outcomes, None).map_or(f64::NAN, |d| d / t1);
    let perfect = std::f64::consts::TAU / alpha.sin();
    let cycle_counts = counts.cycle_counts;
    let majority = (0..4).max_by_key(|&i| cycle_counts[i]).unwrap_or(0) + 1;
    let panel = Panel {
        title: format!(
            "m/m0 = {m}: period {majority} in {} of {n} runs{}",
            cycle_counts[majority - 1],
            match counts.undecided {
                0 => String::new(),
                u => format!(", {u} undecided"),
            }
        ),
        x_label: "contact azimuth φ (rad), 600 < t < 700".into(),
        y_label: "contact polar angle θ (rad)".into(),
        log_x: false,
        log_y: false,
        series,
        legend: SeriesLabelPosition::UpperRight,
        equal_aspect: false,
    };
    let result = MassResult {
        mass_ratio: m,
        cycle_counts,
        at_rest: counts.at_rest,
        undecided: counts.undecided,
        left_model: counts.left_model,
        longest_run: counts.longest_run,
        median_period_ratio: median,
        median_period_over_perfect: median * t1 / perfect,
    };
    Ok((result, panel))
}

/// Runs the figure: computes it, then writes OUT/sphere-doubling/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("sphere-doubling")?;
    super::written(compute(opts)?, &dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<Computed<FigureData<Summary>>> {
    let fig = opts.sphere("sphere-doubling")?;
    let (body, seed) = (fig.body.clone(), fig.seed);
    let a_star = sphere_alpha_star(&body);
    let alpha = opts.single_alpha("sphere-doubling", PAPER_ALPHA)?;
    let n = if opts.quick { 8 } else { 100 };
    let (t_from, t_to) = (600.0, 700.0);
    let main_decide = decide(opts.quick);
    // The other bodies' runs start deciding at the paper's t = 2000 even in --quick.
    let cross_decide = Decide {
        t_min: 2000.0,
        ..main_decide
    };
    let jobs: Vec<(usize, usize)> = (0..MASSES.len())
        .flat_map(|m| (0..n).map(move |o| (m, o)))
        .collect();
    // The cross-body statistics' bodies (a cheap search, repeated by every shard).
    let (n_bodies, n_near, n_orient) = if opts.quick {
        (4, 2, 2)
    } else {
        (CROSS_BODIES, 30, 4)
    };
    let bands = [
        CrossBand::find(n_bodies, (0.0, 0.13), n_orient)?,
        CrossBand::find(n_near, (0.13, 0.15), n_orient)?,
    ];
    let cross_jobs: Vec<(usize, usize, usize)> = bands
        .iter()
        .enumerate()
        .flat_map(|(band, c)| {
            (0..c.bodies.len()).flat_map(move |b| (0..c.orientations).map(move |o| (band, b, o)))
        })
        .collect();
    // One ensemble: this body's runs, then the other bodies' runs at m/m0 = 6.
    let all = super::all_runs!(opts.ensemble(
        "sphere-doubling",
        jobs.len() + cross_jobs.len(),
        "runs",
        |k| -> Result<Run> {
            if let Some(&(band, b, o)) = k.checked_sub(jobs.len()).map(|j| &cross_jobs[j]) {
                let body = &bands[band].bodies[b].1;
                return Ok(Run::Cross(run_period(
                    body,
                    alpha,
                    CROSS_MASS,
                    opts.seed,
                    o,
                    &cross_decide,
                )?));
            }
            let (m, o) = jobs[k];
            let ramp = Ramp::new(alpha, MASSES[m])?;
            let r = decided_run(
                &body,
                &ramp,
                random_orientation(&body, opts.seed, o),
                &main_decide,
                (t_from, t_to, 400),
                1e-9,
            )?;
            Ok(Run::Main {
                left_model: r.left_model(),
                cycle: r.cycle,
                path: r.path,
                rest: matches!(r.fate, Fate::Halted { .. }),
                t_end: r.t_end,
            })
        },
    ));
    let (main_runs, cross_runs) = all.split_at(jobs.len());
    let mut outcomes = Vec::with_capacity(jobs.len());
    let mut paths = Vec::with_capacity(jobs.len());
    for r in main_runs {
        let Run::Main {
            cycle,
            path,
            rest,
            t_end,
            left_model,
        } = r
        else {
            return Err(anyhow!(
                "sphere-doubling: the runs came back in the wrong order"
            ));
        };
        outcomes.push(RunOutcome {
            cycle: *cycle,
            at_rest: *rest,
            t_end: *t_end,
            left_model: *left_model,
        });
        paths.push(path);
    }
    let mut periods = Vec::with_capacity(cross_runs.len());
    for r in cross_runs {
        let Run::Cross(k) = r else {
            return Err(anyhow!(
                "sphere-doubling: the runs came back in the wrong order"
            ));
        };
        periods.push(*k);
    }
    let (first_band, near_band) = periods.split_at(bands[0].runs());
    let cross_body = bands[0].statistic(first_band);
    let cross_body_near_critical = bands[1].statistic(near_band);
    // The viscous period: the median period-1 cycle at m/m0 = 0.
    let t1 = median_cycle_duration(&outcomes[..n], Some(1))
        .ok_or_else(|| anyhow!("no viscous run closed an orbit"))?;
    let mut masses = Vec::new();
    let mut rows = Vec::new();
    let mut panels = Vec::new();
    for (mi, &m) in MASSES.iter().enumerate() {
        let (result, panel) = mass_result(
            m,
            &outcomes[mi * n..(mi + 1) * n],
            &paths[mi * n..(mi + 1) * n],
            (t1, alpha),
            &mut rows,
        )?;
        masses.push(result);
        panels.push(panel);
    }
    let csv_header = "mass_ratio,orientation,phi,theta";
    let summary = Summary {
        body: fig.label,
        seed,
        alpha_star: a_star,
        alpha,
        orientations: n,
        viscous_period: t1,
        t_min: main_decide.t_min,
        t_cap: main_decide.t_cap,
        masses,
        cross_body,
        cross_body_near_critical,
    };
    Ok(Computed::Figure(FigureData {
        panels,
        columns: 3,
        size: (1950, 620),
        header: csv_header,
        rows,
        summary,
    }))
}
