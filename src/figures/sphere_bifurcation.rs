//! `sphere-bifurcation` — beyond paper Fig. 4e: the orbit diagram of 3D inertial rolling in
//! m/m0, the Floquet multipliers of its period-1 orbits, and the masses where they flip.
//!
//! On the paper's body at α = 0.15 (by default), for each m/m0 on a grid:
//! 1. **Direct simulation.** From several orientations released from rest, the body rolls at
//!    least to `t_min`, then on until its late crossings close a cycle (or it rests), at most to
//!    `t_cap` = 10 `t_min`; the crossings of ∂Ω in the run's last `t_min`/2 are the attractor's
//!    points. The attractor's period k is the smallest k with p_n ≈ p_{n−k} ≈ p_{n−2k}
//!    ([`settled_cycle`], antipodes identified; a cycle of k ≥ 2 must also be steady). The
//!    diagram plots each late crossing against m: one branch per period-1 orbit, two where it
//!    has doubled. Runs within ~0.01 of a flip can stay undecided to the cap (the summary's
//!    `undecided_runs`): there the multiplier is so near −1 that the orbit attracts too slowly.
//! 2. **Floquet multipliers.** Each period-1 orbit found at the lowest inertial mass is
//!    continued in m as a fixed point of the return map on ∂Ω (5 dimensions: the boundary point
//!    and ω), by Newton's method with a central-difference Jacobian
//!    ([`crate::analysis::sphere_return_map`]); its multipliers are that Jacobian's eigenvalues
//!    (nalgebra). Where the most negative real multiplier passes −1 the orbit flips; the flip
//!    mass m_c is located by bisection.
//! 3. **Cross-check.** Each doubling window seen in the simulations (`onset_mass`, the first grid
//!    mass with a period-2 attractor near that orbit, and `end_mass`, the first after it without
//!    one) is compared with the flips, and near onset the squared alternation amplitude
//!    |p_n − p_{n−1}|² is fitted against m: it grows linearly from its own m_c at a
//!    supercritical flip.
//!
//! `--shard I/N` splits the direct simulations (step 1, the bulk of the work); `merge` runs
//! steps 2 and 3.

use anyhow::{Result, anyhow};
use glam::{DQuat, DVec3};
use serde::Serialize;

use super::shard::{Fields, Record};
use super::sphere_orbits::random_orientation;
use super::{
    Computed, FigureData, FigureOptions, PAPER_ALPHA, par_map, progress, sphere_alpha_star,
};
use crate::analysis::fit;
use crate::analysis::return_map::locate_flip;
use crate::analysis::sphere_orbits::{
    Crossing, Decide, boundary_distance, cluster_antipodal, decided_run, settled_cycle,
};
use crate::analysis::sphere_return_map::{
    OrbitSolve, PeriodicOrbit, SectionState, inertial_crossings_until, periodic_orbit,
};
use crate::dynamics::Ramp;
use crate::geometry::Sphere;
use crate::plot::{PALETTE, Panel, Series, SeriesLabelPosition, Style};

/// Two crossing points closer than this (antipodes identified) are the same point when the
/// period is read off the late crossings.
pub const PERIOD_TOL: f64 = 1e-4;
/// DOP853 tolerance of the direct simulations. 1e-9 rather than 1e-10 saves a fifth of the
/// figure's time, and was measured to change nothing the figure states (paper body, α = 0.15,
/// full size): every one of the 488 runs has the same period k, the doubling windows and flips
/// are the same, the alternation amplitudes agree to 2.4e-6 relative and the fitted onset
/// masses to 2e-8.
const RTOL: f64 = 1e-9;
/// Longest cycle looked for.
const MAX_K: usize = 4;

/// One grid mass of the orbit diagram.
#[derive(Debug, Clone, Serialize)]
pub struct MassRow {
    /// m/m0.
    pub mass_ratio: f64,
    /// Runs whose late crossings close with k = 1, 2, 3, 4, or not at all (last entry).
    pub period_counts: [usize; 5],
    /// Median |p_n − p_{n−1}| over the period-2 runs near each orbit (0 if none), by orbit.
    pub alternation_amplitude: Vec<f64>,
}

/// One orbit continued in m/m0.
#[derive(Debug, Clone, Serialize)]
pub struct OrbitBranch {
    /// Index (0, 1, …) in the order found at the lowest inertial mass.
    pub orbit: usize,
    /// The solved fixed point and multipliers per grid mass (from the lowest inertial mass on,
    /// while Newton converges).
    pub solutions: Vec<PeriodicOrbit>,
}

/// A real multiplier passing −1.
#[derive(Debug, Clone, Serialize)]
pub struct Flip {
    /// Which orbit.
    pub orbit: usize,
    /// m_c by bisection.
    pub mass_ratio: f64,
    /// True where the orbit loses stability with increasing m (a 2-cycle is born), false where
    /// it regains it.
    pub loses_stability: bool,
}

/// A window of period 2.
#[derive(Debug, Clone, Serialize)]
pub struct DoublingWindow {
    /// Which period-1 orbit doubled.
    pub orbit: usize,
    /// First grid m/m0 with a period-2 attractor near this orbit.
    pub onset_mass: f64,
    /// First grid m/m0 after the onset with no such attractor (`null`: still there at the end).
    pub end_mass: Option<f64>,
    /// The flip where the orbit loses stability, nearest the onset (Floquet).
    pub flip_onset_mass: Option<f64>,
    /// The flip where it regains stability, nearest the end.
    pub flip_end_mass: Option<f64>,
    /// m_c from a straight-line fit of the squared alternation amplitude against m over the
    /// first grid masses of the window (at least 3), if it has that many.
    pub amplitude_fit_onset_mass: Option<f64>,
    /// The multipliers of the orbit at the grid masses bracketing the onset flip, (re, im).
    pub multipliers_at_onset: Vec<Vec<[f64; 2]>>,
    /// The same at the end flip.
    pub multipliers_at_end: Vec<Vec<[f64; 2]>>,
}

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

/// One direct run's late crossings.
pub(crate) struct LateRun {
    crossings: Vec<Crossing>,
    omegas: Vec<DVec3>,
    k: Option<usize>,
    /// When the run ended: its fate decided, or the cap.
    t_end: f64,
}

impl Record for LateRun {
    fn encode(&self, out: &mut Vec<f64>) {
        self.crossings.encode(out);
        self.omegas.encode(out);
        self.k.encode(out);
        self.t_end.encode(out);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let run = LateRun {
            crossings: Record::decode(f)?,
            omegas: Record::decode(f)?,
            k: Record::decode(f)?,
            t_end: Record::decode(f)?,
        };
        if !(run.t_end.is_finite() && run.t_end >= 0.0) {
            return Err(anyhow!("the run's end time {} is not a time", run.t_end));
        }
        // What the reduction relies on: a cycle of 1..=MAX_K crossings, finite ω.
        if let Some(k) = run.k
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

/// One direct run from rest at `q0`: at least `t_min`, then until its late crossings close a
/// cycle of k ≤ `MAX_K` (or it comes to rest), at most `t_cap`. The attractor's points are the
/// crossings of the run's last `t_min`/2 (and after `t_min`/2).
fn direct_run(
    body: &Sphere,
    ramp: &Ramp,
    q0: DQuat,
    (t_min, t_cap): (f64, f64),
) -> Result<LateRun> {
    let (crossings, omegas, t_end) = if ramp.is_viscous() {
        let r = decided_run(
            body,
            ramp,
            q0,
            &Decide {
                t_min,
                t_cap,
                max_k: MAX_K,
                tol: PERIOD_TOL,
            },
            (0.0, 0.0, 0),
            RTOL,
        )?;
        let n = r.crossings.len();
        (r.crossings, vec![DVec3::ZERO; n], r.t_end)
    } else {
        let to_crossing = |c: &SectionState| Crossing {
            t: c.t,
            point: c.point,
        };
        let (s, t_end) =
            inertial_crossings_until(body, ramp, q0, DVec3::ZERO, (t_min, t_cap), RTOL, |s| {
                let late: Vec<Crossing> = s.iter().map(to_crossing).collect();
                settled_cycle(&late, MAX_K, PERIOD_TOL).is_some()
            })?;
        (
            s.iter().map(to_crossing).collect(),
            s.iter().map(|c| DVec3::from_array(c.omega)).collect(),
            t_end,
        )
    };
    // The cycle from the whole sequence (its steadiness looks 10k crossings back), the points
    // from the late window.
    let k = settled_cycle(&crossings, MAX_K, PERIOD_TOL).map(|c| c.0);
    let from = crossings.partition_point(|c| c.t < (t_end - 0.5 * t_min).max(0.5 * t_min));
    let crossings = crossings[from..].to_vec();
    let omegas = omegas[from..].to_vec();
    Ok(LateRun {
        crossings,
        omegas,
        k,
        t_end,
    })
}

/// What the stages after the direct runs read: the body, the mass grid and the runs.
struct Stage<'a> {
    body: &'a Sphere,
    alpha: f64,
    alpha_star: f64,
    masses: &'a [f64],
    starts: usize,
    runs: &'a [LateRun],
}

/// The orbit diagram's rows and per-mass statistics, and where each orbit doubled.
struct Diagram {
    rows: Vec<Vec<f64>>,
    mass_rows: Vec<MassRow>,
    /// `doubled[orbit][m]`: a period-2 attractor near this orbit at grid mass m.
    doubled: Vec<Vec<bool>>,
    /// `amplitude[orbit][m]`: the median alternation |p_n − p_{n−1}| there (0 if none).
    amplitude: Vec<Vec<f64>>,
}

impl Stage<'_> {
    fn run_at(&self, m: usize, o: usize) -> &LateRun {
        &self.runs[m * self.starts + o]
    }

    fn solve_at(&self, mass: f64, guess: (DVec3, DVec3)) -> Option<PeriodicOrbit> {
        let ramp = Ramp::new(self.alpha, mass).ok()?;
        periodic_orbit(self.body, &ramp, guess.0, guess.1, &OrbitSolve::default()).ok()
    }

    /// The period-1 orbits found at the lowest inertial mass, each continued up the mass grid
    /// by Newton's method while it converges.
    fn continue_orbits(&self) -> Result<Vec<OrbitBranch>> {
        let (masses, starts, alpha, alpha_star) =
            (self.masses, self.starts, self.alpha, self.alpha_star);
        let run_at = |m: usize, o: usize| self.run_at(m, o);
        let first = 1;
        let seeds: Vec<(DVec3, DVec3)> = {
            let finals: Vec<DVec3> = (0..starts)
                .filter_map(|o| {
                    let r = run_at(first, o);
                    let last = r.crossings.last()?;
                    (r.k == Some(1)).then(|| DVec3::from_array(last.point))
                })
                .collect();
            cluster_antipodal(&finals, 1e-3)
                .into_iter()
                .filter_map(|(p, _)| {
                    (0..starts).find_map(|o| {
                        let r = run_at(first, o);
                        let last = r.crossings.last()?;
                        let omega = *r.omegas.last()?;
                        (r.k == Some(1)
                            && boundary_distance(DVec3::from_array(last.point), p) < 1e-3)
                            .then(|| (DVec3::from_array(last.point), omega))
                    })
                })
                .collect()
        };
        if seeds.is_empty() {
            // Say why: below α* a start can come to rest (no crossings late in the run).
            let rested = (0..starts)
                .filter(|&o| run_at(first, o).crossings.is_empty())
                .count();
            let below = if alpha < alpha_star {
                format!(", below this body's α* = {alpha_star:.4}, where some orientations halt")
            } else {
                String::new()
            };
            return Err(anyhow!(
                "sphere-bifurcation: none of the {starts} runs at m/m0 = {} (α = {alpha}{below}) \
                 settled on a period-1 orbit ({rested} came to rest), so there is no orbit to continue \
                 in m/m0; give a larger --alpha",
                masses[first]
            ));
        }
        let solve_at = |mass: f64, guess: (DVec3, DVec3)| self.solve_at(mass, guess);
        let bar = progress(seeds.len(), "orbits");
        let orbits: Vec<OrbitBranch> = par_map(seeds.len(), &bar, |j| {
            let mut guess = seeds[j];
            let mut solutions = Vec::new();
            for &mass in &masses[first..] {
                match solve_at(mass, guess) {
                    Some(o) => {
                        guess = (DVec3::from_array(o.point), DVec3::from_array(o.omega));
                        solutions.push(o);
                    }
                    None => break,
                }
            }
            OrbitBranch {
                orbit: j,
                solutions,
            }
        });
        Ok(orbits)
    }

    /// The flips: where μ_min + 1 changes sign between grid masses, refined by bisection.
    fn flips(&self, orbits: &[OrbitBranch]) -> Vec<Flip> {
        let flip_value = |o: &PeriodicOrbit| o.most_negative_real.map_or(1.0, |mu| mu + 1.0);
        let mut brackets = Vec::new();
        for b in orbits {
            for w in b.solutions.windows(2) {
                let (f0, f1) = (flip_value(&w[0]), flip_value(&w[1]));
                if f0.signum() != f1.signum() {
                    brackets.push((b.orbit, w[0].clone(), w[1].clone(), f0 > 0.0));
                }
            }
        }
        let bar = progress(brackets.len(), "flips");
        let flips: Vec<Flip> = par_map(brackets.len(), &bar, |i| {
            let (orbit, lo, hi, loses) = &brackets[i];
            let guess_of =
                |o: &PeriodicOrbit| (DVec3::from_array(o.point), DVec3::from_array(o.omega));
            let mid = 0.5 * (lo.mass_ratio + hi.mass_ratio);
            let m_c = locate_flip(lo.mass_ratio, hi.mass_ratio, 1e-3, |m| {
                let guess = if m <= mid { guess_of(lo) } else { guess_of(hi) };
                self.solve_at(m, guess).map(|o| flip_value(&o))
            })
            .unwrap_or(mid);
            Flip {
                orbit: *orbit,
                mass_ratio: m_c,
                loses_stability: *loses,
            }
        });
        flips
    }

    /// The diagram's rows (the last 8 crossings of every run) and the per-mass statistics, with
    /// each period-2 run assigned to the nearest solved orbit.
    fn diagram(&self, orbits: &[OrbitBranch]) -> Result<Diagram> {
        let (masses, starts) = (self.masses, self.starts);
        let n_mass = masses.len();
        let run_at = |m: usize, o: usize| self.run_at(m, o);
        // Which orbit a late crossing belongs to: the nearest solved fixed point at that mass.
        let orbit_of = |m: usize, p: DVec3| -> Option<usize> {
            orbits
                .iter()
                .filter_map(|b| {
                    let s = b.solutions.iter().find(|s| s.mass_ratio == masses[m])?;
                    Some((b.orbit, boundary_distance(DVec3::from_array(s.point), p)))
                })
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|x| x.0)
        };

        // The diagram's rows and the per-mass statistics.
        let mut rows = Vec::new();
        let mut mass_rows = Vec::new();
        let mut doubled: Vec<Vec<bool>> = vec![vec![false; n_mass]; orbits.len()];
        let mut amplitude: Vec<Vec<f64>> = vec![vec![0.0; n_mass]; orbits.len()];
        for (m, &mass) in masses.iter().enumerate() {
            let mut counts = [0usize; 5];
            let mut amps: Vec<Vec<f64>> = vec![Vec::new(); orbits.len()];
            for o in 0..starts {
                let r = run_at(m, o);
                let slot = r.k.map_or(4, |k| k.wrapping_sub(1));
                *counts.get_mut(slot).ok_or_else(|| {
                    anyhow!("run {o} at m/m0 = {mass}: a cycle of {slot} + 1 crossings")
                })? += 1;
                let n = r.crossings.len();
                if r.k == Some(2) && n >= 2 {
                    let (a, b) = (r.crossings[n - 1].point, r.crossings[n - 2].point);
                    if let Some(j) = orbit_of(m, DVec3::from_array(a)) {
                        amps[j].push(boundary_distance(
                            DVec3::from_array(a),
                            DVec3::from_array(b),
                        ));
                        doubled[j][m] = true;
                    }
                }
                for (i, c) in r.crossings.iter().enumerate().skip(n.saturating_sub(8)) {
                    let p = canonical(c.point);
                    let tau = if i > 0 {
                        c.t - r.crossings[i - 1].t
                    } else {
                        f64::NAN
                    };
                    rows.push(vec![
                        mass,
                        o as f64,
                        c.t,
                        p.z.clamp(-1.0, 1.0).acos(),
                        p.y.atan2(p.x),
                        tau,
                        r.k.map_or(f64::NAN, |k| k as f64),
                    ]);
                }
            }
            for (j, a) in amps.iter_mut().enumerate() {
                a.sort_by(f64::total_cmp);
                amplitude[j][m] = a.get(a.len() / 2).copied().unwrap_or(0.0);
            }
            mass_rows.push(MassRow {
                mass_ratio: mass,
                period_counts: counts,
                alternation_amplitude: amplitude.iter().map(|a| a[m]).collect(),
            });
        }
        Ok(Diagram {
            rows,
            mass_rows,
            doubled,
            amplitude,
        })
    }
}

/// The windows of period 2 per orbit, with the flips nearest their edges and the onset fitted
/// from the alternation amplitude.
fn doubling_windows(
    masses: &[f64],
    orbits: &[OrbitBranch],
    flips: &[Flip],
    diagram: &Diagram,
) -> Vec<DoublingWindow> {
    let n_mass = masses.len();
    let (doubled, amplitude) = (&diagram.doubled, &diagram.amplitude);
    let mut windows = Vec::new();
    for b in orbits {
        let mut m = 0;
        while m < n_mass {
            if !doubled[b.orbit][m] {
                m += 1;
                continue;
            }
            let start = m;
            while m < n_mass && doubled[b.orbit][m] {
                m += 1;
            }
            let onset_mass = masses[start];
            let end_mass = (m < n_mass).then(|| masses[m]);
            let nearest_flip = |target: f64, loses: bool| {
                flips
                    .iter()
                    .filter(|f| f.orbit == b.orbit && f.loses_stability == loses)
                    .min_by(|x, y| {
                        (x.mass_ratio - target)
                            .abs()
                            .total_cmp(&(y.mass_ratio - target).abs())
                    })
                    .map(|f| f.mass_ratio)
            };
            let flip_onset_mass = nearest_flip(onset_mass, true);
            let flip_end_mass = end_mass.and_then(|e| nearest_flip(e, false));
            let fit_points: Vec<(f64, f64)> = (start..m.min(start + 4))
                .map(|i| (masses[i], amplitude[b.orbit][i].powi(2)))
                .collect();
            let amplitude_fit_onset_mass = (fit_points.len() >= 3)
                .then(|| fit::line(&fit_points))
                .flatten()
                .filter(|f| f.slope > 0.0)
                .map(|f| -f.intercept / f.slope);
            let multipliers_near = |m_c: Option<f64>| -> Vec<Vec<[f64; 2]>> {
                let Some(m_c) = m_c else { return Vec::new() };
                b.solutions
                    .windows(2)
                    .find(|w| w[0].mass_ratio <= m_c && m_c <= w[1].mass_ratio)
                    .map(|w| vec![w[0].multipliers.clone(), w[1].multipliers.clone()])
                    .unwrap_or_default()
            };
            windows.push(DoublingWindow {
                orbit: b.orbit,
                onset_mass,
                end_mass,
                flip_onset_mass,
                flip_end_mass,
                amplitude_fit_onset_mass,
                multipliers_at_onset: multipliers_near(flip_onset_mass),
                multipliers_at_end: multipliers_near(flip_end_mass),
            });
        }
    }
    windows
}

/// The sign of a boundary point with p_z ≥ 0 (antipodes identified), for plotting.
fn canonical(p: [f64; 3]) -> DVec3 {
    let p = DVec3::from_array(p);
    if p.z < 0.0 { -p } else { p }
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
    let t_cap = 10.0 * t_min;
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
            direct_run(
                &body,
                &ramp,
                random_orientation(&body, opts.seed, o),
                (t_min, t_cap),
            )
        })
    );
    let undecided_runs = runs
        .iter()
        .filter(|r| r.k.is_none() && r.t_end >= t_cap)
        .count();
    let longest_run = runs.iter().map(|r| r.t_end).fold(0.0, f64::max);
    let stage = Stage {
        body: &body,
        alpha,
        alpha_star,
        masses: &masses,
        starts,
        runs: &runs,
    };
    // 2. Period-1 orbits at the lowest inertial mass, continued in m, and their flips.
    let orbits = stage.continue_orbits()?;
    let flips = stage.flips(&orbits);
    // 3. The diagram, and the windows of period 2 cross-checked against the flips.
    let diagram = stage.diagram(&orbits)?;
    let windows = doubling_windows(&masses, &orbits, &flips, &diagram);
    let (rows, mass_rows) = (diagram.rows, diagram.mass_rows);

    let csv_header = "mass_ratio,start,t,crossing_polar,crossing_azimuth,return_time,period";
    let summary = Summary {
        body: fig.label,
        alpha_star,
        alpha,
        starts,
        t_min,
        t_cap,
        undecided_runs,
        longest_run,
        masses: mass_rows,
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
            title: format!(
                "(c) multipliers; flips at m/m0 = {}",
                s.flips
                    .iter()
                    .map(|f| format!("{:.2}", f.mass_ratio))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
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
