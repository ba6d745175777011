//! The orbit diagram of 3D inertial rolling in m/m0 (beyond paper Fig. 4e): direct runs per grid
//! mass, the period-1 orbits continued in m with their Floquet multipliers, the flips where a
//! multiplier passes −1, and the windows of period 2 the runs show, cross-checked against them.
//!
//! The steps, each callable on its own so that a batch job can shard the first (the bulk of the
//! work) and a progress bar can follow the others:
//! 1. [`direct_run`] per (mass, start): a run released from rest, long enough to read the period k
//!    of its attractor off its late crossings of ∂Ω ([`settled_cycle`], antipodes identified).
//! 2. [`period_one_seeds`] picks one run per period-1 orbit at the lowest inertial mass;
//!    [`continue_orbit`] follows each up the mass grid by Newton's method on the return map
//!    ([`crate::analysis::orbits::sphere_return_map::periodic_orbit`]).
//! 3. [`flip_brackets`] and [`locate_flip_in`]: where the most negative real multiplier passes
//!    −1 between grid masses, refined by bisection.
//! 4. [`orbit_diagram`] gathers the late crossings per mass and assigns each period-2 run to the
//!    nearest orbit; [`doubling_windows`] reads the windows of period 2 off it.
//!
//! [`mass_bifurcation`] runs all four in parallel (rayon) for a caller that needs neither.

use std::sync::atomic::{AtomicBool, Ordering};

use glam::{DQuat, DVec3};
use rayon::prelude::*;
use serde::Serialize;

use crate::analysis::fit;
use crate::analysis::orbits::return_map::locate_flip;
use crate::analysis::orbits::sphere_orbits::{
    Crossing, Decide, SETTLED_ON_SAME_ORBIT, boundary_distance, cluster_antipodal, decided_run,
    settled_cycle,
};
use crate::analysis::orbits::sphere_return_map::{
    OrbitSolve, PeriodicOrbit, SectionState, inertial_crossings_until, periodic_orbit,
};
use crate::analysis::studies::sphere::random_orientation;
use crate::dynamics::ModelKind;
use crate::dynamics::{ModelError, Ramp};
use crate::geometry::Sphere;
use crate::integrate::{IntegrateError, MAX_SPAN};

/// Two crossing points closer than this (antipodes identified) are the same point when the
/// period is read off the late crossings.
pub const PERIOD_TOL: f64 = 1e-4;
/// DOP853 tolerance of the direct runs. 1e-9 rather than 1e-10 saves a fifth of the
/// figure's time, and was measured to change nothing the figure states (paper body, α = 0.15,
/// full size): every one of the 488 runs has the same period k, the doubling windows and flips
/// are the same, the alternation amplitudes agree to 2.4e-6 relative and the fitted onset
/// masses to 2e-8.
pub const DIRECT_RTOL: f64 = 1e-9;
/// Longest cycle looked for.
pub const MAX_K: usize = 4;

/// How long a direct run goes on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunWindow {
    /// Every run goes on at least this long…
    pub t_min: f64,
    /// …then until its late crossings close a cycle of k ≤ [`MAX_K`] or it comes to rest, at
    /// most this long.
    pub t_cap: f64,
}

/// One direct run's late crossings: the attractor's points.
#[derive(Debug, Clone, PartialEq)]
pub struct LateRun {
    /// The crossings of ∂Ω in the run's last `t_min`/2 (and after `t_min`/2).
    pub crossings: Vec<Crossing>,
    /// ω at each of them (zero in the viscous model, where ω follows from the orientation).
    pub omegas: Vec<DVec3>,
    /// The attractor's period in crossings, if its crossings closed a cycle of k ≤ [`MAX_K`].
    pub period: Option<usize>,
    /// When the run ended: its fate decided, or the cap.
    pub t_end: f64,
}

/// Why a step of the orbit diagram failed.
#[derive(Debug, thiserror::Error)]
pub enum OrbitDiagramError {
    /// A bad α or m/m0.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// An integration failed.
    #[error(transparent)]
    Integrate(#[from] IntegrateError),
    /// No run at the lowest inertial mass settled on a period-1 orbit.
    #[error(
        "none of the {starts} runs at m/m0 = {mass_ratio} settled on a period-1 orbit \
         ({rested} came to rest), so there is no orbit to continue in m/m0"
    )]
    NoPeriodOneOrbit {
        /// Runs at that mass.
        starts: usize,
        /// The lowest inertial mass.
        mass_ratio: f64,
        /// How many of them came to rest.
        rested: usize,
    },
    /// The runs do not fill the grid: `masses.len() × starts` are needed, in that order.
    #[error("{runs} runs for {masses} masses × {starts} starts")]
    GridMismatch {
        /// Runs given.
        runs: usize,
        /// Grid masses.
        masses: usize,
        /// Starts per mass.
        starts: usize,
    },
    /// The grid needs a viscous mass first, at least one inertial mass after it, and a start.
    #[error(
        "the grid needs at least two masses (m/m0 = 0, then inertial ones) and one start per \
         mass; it has {masses} masses and {starts} starts"
    )]
    EmptyGrid {
        /// Grid masses.
        masses: usize,
        /// Starts per mass.
        starts: usize,
    },
    /// A bad argument of [`mass_bifurcation`]: which, and what is allowed.
    #[error("{0}")]
    BadArgument(String),
    /// Stopped on request ([`mass_bifurcation_until`]).
    #[error("the orbit diagram was stopped before its end")]
    Stopped,
    /// A run claims a period outside 1..=[`MAX_K`].
    #[error("run {start} at m/m0 = {mass_ratio}: a cycle of {period} crossings")]
    BadPeriod {
        /// Which start.
        start: usize,
        /// Its mass.
        mass_ratio: f64,
        /// The period claimed.
        period: usize,
    },
}

/// One direct run from rest at `q0`: at least `window.t_min`, then until its late crossings
/// close a cycle of k ≤ [`MAX_K`] (or it comes to rest), at most `window.t_cap` (DOP853 at
/// [`DIRECT_RTOL`]).
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::orbit_diagram::{RunWindow, direct_run};
/// use rollphase_core::analysis::studies::sphere::random_orientation;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// let Body::Sphere(body) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let ramp = Ramp::new(0.15, 1.0)?;
/// let window = RunWindow { t_min: 400.0, t_cap: 4000.0 };
/// let run = direct_run(&body, &ramp, random_orientation(&body, 1, 0), window)?;
/// // At m/m0 = 1 the paper's body cruises on a period-1 orbit.
/// assert_eq!(run.period, Some(1));
/// assert!(run.crossings.iter().all(|c| c.t >= 200.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn direct_run(
    body: &Sphere,
    ramp: &Ramp,
    q0: DQuat,
    window: RunWindow,
) -> Result<LateRun, IntegrateError> {
    let RunWindow { t_min, t_cap } = window;
    let (crossings, omegas, t_end) = match ModelKind::for_dimension(3, ramp) {
        ModelKind::SphereViscous => {
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
                DIRECT_RTOL,
            )?;
            let n = r.crossings.len();
            (r.crossings, vec![DVec3::ZERO; n], r.t_end)
        }
        ModelKind::SphereInertial => {
            let to_crossing = |c: &SectionState| Crossing {
                t: c.t,
                point: c.point,
            };
            let (s, t_end) = inertial_crossings_until(
                body,
                ramp,
                q0,
                DVec3::ZERO,
                (t_min, t_cap),
                DIRECT_RTOL,
                |s| {
                    let late: Vec<Crossing> = s.iter().map(to_crossing).collect();
                    settled_cycle(&late, MAX_K, PERIOD_TOL).is_some()
                },
            )?;
            (
                s.iter().map(to_crossing).collect(),
                s.iter().map(|c| DVec3::from_array(c.omega)).collect(),
                t_end,
            )
        }
        other @ (ModelKind::DiskViscous | ModelKind::DiskInertial) => other.wrong_dimension(3),
    };
    // The cycle from the whole sequence (its steadiness looks 10k crossings back), the points
    // from the late window.
    let period = settled_cycle(&crossings, MAX_K, PERIOD_TOL).map(|c| c.0);
    let from = crossings.partition_point(|c| c.t < (t_end - 0.5 * t_min).max(0.5 * t_min));
    Ok(LateRun {
        crossings: crossings[from..].to_vec(),
        omegas: omegas[from..].to_vec(),
        period,
        t_end,
    })
}

/// The direct runs of a mass grid: `runs[m * starts + o]` is start `o` (orientation
/// [`random_orientation`]`(body, seed, o)`) at `masses[m]`.
#[derive(Debug, Clone, Copy)]
pub struct DirectRuns<'a> {
    /// m/m0 per grid point, ascending; the first is 0 (viscous).
    pub masses: &'a [f64],
    /// Starts per mass.
    pub starts: usize,
    /// The runs, mass-major.
    pub runs: &'a [LateRun],
}

impl<'a> DirectRuns<'a> {
    /// Checks that `runs` fills the grid and that it has an inertial mass after the viscous one.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::orbits::orbit_diagram::DirectRuns;
    /// assert!(DirectRuns::new(&[0.0, 1.0], 2, &[]).is_err());
    /// ```
    pub fn new(
        masses: &'a [f64],
        starts: usize,
        runs: &'a [LateRun],
    ) -> Result<Self, OrbitDiagramError> {
        if runs.len() != masses.len() * starts {
            return Err(OrbitDiagramError::GridMismatch {
                runs: runs.len(),
                masses: masses.len(),
                starts,
            });
        }
        if masses.len() < 2 || starts == 0 {
            return Err(OrbitDiagramError::EmptyGrid {
                masses: masses.len(),
                starts,
            });
        }
        Ok(DirectRuns {
            masses,
            starts,
            runs,
        })
    }

    /// Start `o` at grid mass `m`.
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::analysis::orbits::orbit_diagram::{DirectRuns, LateRun};
    /// let run = LateRun { crossings: vec![], omegas: vec![], period: None, t_end: 5.0 };
    /// let runs = vec![run.clone(), run];
    /// let grid = DirectRuns::new(&[0.0, 1.0], 1, &runs)?;
    /// assert_eq!(grid.run_at(1, 0).t_end, 5.0);
    /// # Ok::<(), rollphase_core::analysis::orbits::orbit_diagram::OrbitDiagramError>(())
    /// ```
    pub fn run_at(&self, m: usize, o: usize) -> &LateRun {
        &self.runs[m * self.starts + o]
    }

    /// Runs still without a cycle at `t_cap` (not at rest).
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::analysis::orbits::orbit_diagram::{DirectRuns, LateRun};
    /// let capped = LateRun { crossings: vec![], omegas: vec![], period: None, t_end: 10.0 };
    /// let settled = LateRun { period: Some(1), ..capped.clone() };
    /// let runs = vec![capped, settled];
    /// assert_eq!(DirectRuns::new(&[0.0, 1.0], 1, &runs)?.undecided(10.0), 1);
    /// # Ok::<(), rollphase_core::analysis::orbits::orbit_diagram::OrbitDiagramError>(())
    /// ```
    pub fn undecided(&self, t_cap: f64) -> usize {
        self.runs
            .iter()
            .filter(|r| r.period.is_none() && r.t_end >= t_cap)
            .count()
    }

    /// The longest any run went on.
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::analysis::orbits::orbit_diagram::{DirectRuns, LateRun};
    /// let a = LateRun { crossings: vec![], omegas: vec![], period: None, t_end: 10.0 };
    /// let b = LateRun { t_end: 30.0, ..a.clone() };
    /// let runs = vec![a, b];
    /// assert_eq!(DirectRuns::new(&[0.0, 1.0], 1, &runs)?.longest(), 30.0);
    /// # Ok::<(), rollphase_core::analysis::orbits::orbit_diagram::OrbitDiagramError>(())
    /// ```
    pub fn longest(&self) -> f64 {
        self.runs.iter().map(|r| r.t_end).fold(0.0, f64::max)
    }
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

/// Where to look for a flip: two neighbouring solutions of one orbit with μ_min + 1 of
/// opposite signs.
#[derive(Debug, Clone)]
pub struct FlipBracket {
    /// Which orbit.
    pub orbit: usize,
    /// The solution at the lower mass.
    pub below: PeriodicOrbit,
    /// The solution at the higher mass.
    pub above: PeriodicOrbit,
    /// True where μ_min + 1 goes from positive to negative (stability lost).
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

/// One late crossing of one run: a point of the diagram.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiagramPoint {
    /// m/m0.
    pub mass_ratio: f64,
    /// Which start.
    pub start: usize,
    /// Time of the crossing.
    pub t: f64,
    /// Polar angle of the crossing point, sign chosen with p_z ≥ 0 (antipodes identified).
    pub polar: f64,
    /// Its azimuth.
    pub azimuth: f64,
    /// Time since the previous late crossing (NaN for the first).
    pub return_time: f64,
    /// The run's period, if it closed a cycle.
    pub period: Option<usize>,
}

/// The orbit diagram: every run's last 8 crossings, per-mass statistics, and where each orbit
/// doubled.
#[derive(Debug, Clone)]
pub struct OrbitDiagram {
    /// The points, mass by mass, start by start.
    pub points: Vec<DiagramPoint>,
    /// Per grid mass.
    pub masses: Vec<MassRow>,
    /// `doubled[orbit][m]`: a period-2 attractor near this orbit at grid mass m.
    pub doubled: Vec<Vec<bool>>,
    /// `amplitude[orbit][m]`: the median alternation |p_n − p_{n−1}| there (0 if none).
    pub amplitude: Vec<Vec<f64>>,
}

/// Everything [`mass_bifurcation`] finds.
#[derive(Debug, Clone)]
pub struct MassBifurcation {
    /// The direct runs, mass-major (see [`DirectRuns`]).
    pub runs: Vec<LateRun>,
    /// The period-1 orbits continued in m.
    pub orbits: Vec<OrbitBranch>,
    /// Every flip found.
    pub flips: Vec<Flip>,
    /// The diagram.
    pub diagram: OrbitDiagram,
    /// The windows of period 2 with the flips bracketing them.
    pub windows: Vec<DoublingWindow>,
}

/// One run per period-1 orbit at the lowest inertial mass (grid index 1): its last crossing
/// point and ω, the guess [`continue_orbit`] starts from. Orbits are told apart by their
/// boundary points (within 1e-3, antipodes identified), in the order their clusters were first
/// met.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::orbit_diagram::{DirectRuns, OrbitDiagramError, LateRun, period_one_seeds};
/// // Every run came to rest: no orbit to continue.
/// let rested = LateRun { crossings: vec![], omegas: vec![], period: None, t_end: 50.0 };
/// let runs = vec![rested.clone(), rested];
/// let grid = DirectRuns::new(&[0.0, 1.0], 1, &runs)?;
/// assert!(matches!(
///     period_one_seeds(&grid),
///     Err(OrbitDiagramError::NoPeriodOneOrbit { rested: 1, .. })
/// ));
/// # Ok::<(), OrbitDiagramError>(())
/// ```
pub fn period_one_seeds(grid: &DirectRuns) -> Result<Vec<(DVec3, DVec3)>, OrbitDiagramError> {
    let first = 1;
    let starts = grid.starts;
    let last_of = |o: usize| {
        let r = grid.run_at(first, o);
        let last = r.crossings.last()?;
        (r.period == Some(1)).then(|| DVec3::from_array(last.point))
    };
    let finals: Vec<DVec3> = (0..starts).filter_map(last_of).collect();
    let seeds: Vec<(DVec3, DVec3)> = cluster_antipodal(&finals, SETTLED_ON_SAME_ORBIT)
        .into_iter()
        .filter_map(|(p, _)| {
            (0..starts).find_map(|o| {
                let point = last_of(o)?;
                let omega = *grid.run_at(first, o).omegas.last()?;
                (boundary_distance(point, p) < SETTLED_ON_SAME_ORBIT).then_some((point, omega))
            })
        })
        .collect();
    if seeds.is_empty() {
        return Err(OrbitDiagramError::NoPeriodOneOrbit {
            starts,
            mass_ratio: grid.masses[first],
            rested: (0..starts)
                .filter(|&o| grid.run_at(first, o).crossings.is_empty())
                .count(),
        });
    }
    Ok(seeds)
}

/// The period-1 orbit near `guess` (boundary point, ω) at α and m/m0, or `None` where the ramp
/// is invalid or Newton does not converge.
fn solve_at(body: &Sphere, alpha: f64, mass: f64, guess: (DVec3, DVec3)) -> Option<PeriodicOrbit> {
    let ramp = Ramp::new(alpha, mass).ok()?;
    periodic_orbit(body, &ramp, guess.0, guess.1, &OrbitSolve::default()).ok()
}

/// Orbit `orbit`, found near `seed` at `masses[0]`, continued up `masses` by Newton's method:
/// each solution is the next mass's guess; the branch ends where Newton stops converging.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::orbit_diagram::{RunWindow, continue_orbit, direct_run};
/// use rollphase_core::analysis::studies::sphere::random_orientation;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DVec3;
/// let Body::Sphere(body) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// // A run at m/m0 = 1 ends on a period-1 orbit: its last crossing is the guess.
/// let window = RunWindow { t_min: 400.0, t_cap: 4000.0 };
/// let run = direct_run(&body, &Ramp::new(0.15, 1.0)?, random_orientation(&body, 1, 0), window)?;
/// let point = DVec3::from_array(run.crossings.last().unwrap().point);
/// let branch = continue_orbit(&body, 0.15, &[1.0, 1.2], 0, (point, *run.omegas.last().unwrap()));
/// assert_eq!(branch.solutions.len(), 2);
/// assert!(branch.solutions[0].max_modulus < 1.0, "stable at m/m0 = 1");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn continue_orbit(
    body: &Sphere,
    alpha: f64,
    masses: &[f64],
    orbit: usize,
    seed: (DVec3, DVec3),
) -> OrbitBranch {
    let mut guess = seed;
    let mut solutions = Vec::new();
    for &mass in masses {
        match solve_at(body, alpha, mass, guess) {
            Some(o) => {
                guess = (DVec3::from_array(o.point), DVec3::from_array(o.omega));
                solutions.push(o);
            }
            None => break,
        }
    }
    OrbitBranch { orbit, solutions }
}

/// μ_min + 1 of a solved orbit (1 where no real multiplier is negative).
fn flip_value(o: &PeriodicOrbit) -> f64 {
    o.most_negative_real.map_or(1.0, |mu| mu + 1.0)
}

/// Every pair of neighbouring solutions where μ_min + 1 changes sign, orbit by orbit.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::orbit_diagram::{OrbitBranch, flip_brackets};
/// assert!(flip_brackets(&[OrbitBranch { orbit: 0, solutions: vec![] }]).is_empty());
/// ```
pub fn flip_brackets(orbits: &[OrbitBranch]) -> Vec<FlipBracket> {
    let mut brackets = Vec::new();
    for b in orbits {
        for w in b.solutions.windows(2) {
            let (f0, f1) = (flip_value(&w[0]), flip_value(&w[1]));
            if f0.signum() != f1.signum() {
                brackets.push(FlipBracket {
                    orbit: b.orbit,
                    below: w[0].clone(),
                    above: w[1].clone(),
                    loses_stability: f0 > 0.0,
                });
            }
        }
    }
    brackets
}

/// The flip mass m_c inside a bracket, by bisection to 1e-3 (each end's solution guessing for
/// its half); the bracket's midpoint where the bisection loses the orbit.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::orbit_diagram::*;
/// use rollphase_core::analysis::studies::sphere::random_orientation;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DVec3;
/// let Body::Sphere(body) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let window = RunWindow { t_min: 400.0, t_cap: 4000.0 };
/// let run = direct_run(&body, &Ramp::new(0.15, 1.0)?, random_orientation(&body, 1, 1), window)?;
/// let seed = (DVec3::from_array(run.crossings.last().unwrap().point), *run.omegas.last().unwrap());
/// let branch = continue_orbit(&body, 0.15, &[1.0, 2.0, 3.0, 3.4], 0, seed);
/// // This orbit's multiplier passes −1 between m/m0 = 3 and 3.4: it loses stability there.
/// let brackets = flip_brackets(&[branch]);
/// assert_eq!(brackets.len(), 1);
/// let flip = locate_flip_in(&body, 0.15, &brackets[0]);
/// assert!(flip.loses_stability && (3.1..3.2).contains(&flip.mass_ratio), "{flip:?}");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn locate_flip_in(body: &Sphere, alpha: f64, bracket: &FlipBracket) -> Flip {
    let (lo, hi) = (&bracket.below, &bracket.above);
    let guess_of = |o: &PeriodicOrbit| (DVec3::from_array(o.point), DVec3::from_array(o.omega));
    let mid = 0.5 * (lo.mass_ratio + hi.mass_ratio);
    let m_c = locate_flip(lo.mass_ratio, hi.mass_ratio, 1e-3, |m| {
        let guess = if m <= mid { guess_of(lo) } else { guess_of(hi) };
        solve_at(body, alpha, m, guess).map(|o| flip_value(&o))
    })
    .unwrap_or(mid);
    Flip {
        orbit: bracket.orbit,
        mass_ratio: m_c,
        loses_stability: bracket.loses_stability,
    }
}

/// The sign of a boundary point with p_z ≥ 0 (antipodes identified).
fn canonical(p: [f64; 3]) -> DVec3 {
    let p = DVec3::from_array(p);
    if p.z < 0.0 { -p } else { p }
}

/// The diagram's points (the last 8 crossings of every run) and the per-mass statistics, with
/// each period-2 run assigned to the nearest solved orbit at its mass.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::orbit_diagram::{DirectRuns, LateRun, orbit_diagram};
/// use rollphase_core::analysis::orbits::sphere_orbits::Crossing;
/// let run = LateRun {
///     crossings: (0..10).map(|i| Crossing { t: i as f64, point: [0.0, 0.0, -1.0] }).collect(),
///     omegas: vec![Default::default(); 10],
///     period: Some(1),
///     t_end: 10.0,
/// };
/// let runs = vec![run.clone(), run];
/// let d = orbit_diagram(&DirectRuns::new(&[0.0, 1.0], 1, &runs)?, &[])?;
/// assert_eq!(d.points.len(), 16); // the last 8 crossings of each run
/// assert_eq!(d.points[0].polar, 0.0); // antipode folded onto p_z ≥ 0
/// assert_eq!(d.masses[1].period_counts, [1, 0, 0, 0, 0]);
/// # Ok::<(), rollphase_core::analysis::orbits::orbit_diagram::OrbitDiagramError>(())
/// ```
pub fn orbit_diagram(
    grid: &DirectRuns,
    orbits: &[OrbitBranch],
) -> Result<OrbitDiagram, OrbitDiagramError> {
    let (masses, starts) = (grid.masses, grid.starts);
    let n_mass = masses.len();
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
    let mut points = Vec::new();
    let mut mass_rows = Vec::new();
    let mut doubled: Vec<Vec<bool>> = vec![vec![false; n_mass]; orbits.len()];
    let mut amplitude: Vec<Vec<f64>> = vec![vec![0.0; n_mass]; orbits.len()];
    for (m, &mass) in masses.iter().enumerate() {
        let mut counts = [0usize; 5];
        let mut amps: Vec<Vec<f64>> = vec![Vec::new(); orbits.len()];
        for o in 0..starts {
            let r = grid.run_at(m, o);
            let slot = r.period.map_or(4, |k| k.wrapping_sub(1));
            *counts.get_mut(slot).ok_or(OrbitDiagramError::BadPeriod {
                start: o,
                mass_ratio: mass,
                period: slot.wrapping_add(1),
            })? += 1;
            let n = r.crossings.len();
            if r.period == Some(2) && n >= 2 {
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
                points.push(DiagramPoint {
                    mass_ratio: mass,
                    start: o,
                    t: c.t,
                    polar: p.z.clamp(-1.0, 1.0).acos(),
                    azimuth: p.y.atan2(p.x),
                    return_time: if i > 0 {
                        c.t - r.crossings[i - 1].t
                    } else {
                        f64::NAN
                    },
                    period: r.period,
                });
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
    Ok(OrbitDiagram {
        points,
        masses: mass_rows,
        doubled,
        amplitude,
    })
}

/// The windows of period 2 per orbit, with the flips nearest their edges and the onset fitted
/// from the alternation amplitude (a straight line through the squared amplitude over the
/// window's first ≤ 4 grid masses, at least 3).
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::orbit_diagram::{OrbitBranch, OrbitDiagram, doubling_windows};
/// // Orbit 0 shows period 2 at the second and third of four masses.
/// let diagram = OrbitDiagram {
///     points: vec![],
///     masses: vec![],
///     doubled: vec![vec![false, true, true, false]],
///     amplitude: vec![vec![0.0, 0.1, 0.2, 0.0]],
/// };
/// let orbits = [OrbitBranch { orbit: 0, solutions: vec![] }];
/// let w = doubling_windows(&[0.0, 1.0, 2.0, 3.0], &orbits, &[], &diagram);
/// assert_eq!((w[0].onset_mass, w[0].end_mass), (1.0, Some(3.0)));
/// assert_eq!(w[0].amplitude_fit_onset_mass, None); // two points: no fit
/// ```
pub fn doubling_windows(
    masses: &[f64],
    orbits: &[OrbitBranch],
    flips: &[Flip],
    diagram: &OrbitDiagram,
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

/// The whole orbit diagram on `body` at α over `masses` (ascending, the first 0), `starts`
/// orientations per mass ([`random_orientation`] with `seed`), each run over `window`: the
/// direct runs, the orbits continued in m, their flips, the diagram and its windows of period
/// 2. Every step runs in parallel, one task per run (their costs differ by orders of
/// magnitude).
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::orbit_diagram::{RunWindow, mass_bifurcation};
/// use rollphase_core::geometry::Body;
/// let Body::Sphere(body) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let window = RunWindow { t_min: 400.0, t_cap: 4000.0 };
/// let b = mass_bifurcation(&body, 0.15, &[0.0, 1.0, 2.0, 3.0, 3.4], 4, 1, window)?;
/// // The two stable period-1 orbits, found at m/m0 = 1 and continued to 3.4 …
/// assert_eq!(b.orbits.len(), 2);
/// assert!(b.orbits.iter().all(|o| o.solutions.len() == 4));
/// // … where the first flip happens (the other orbit's comes near m/m0 = 4).
/// assert_eq!(b.flips.len(), 1);
/// assert!((3.1..3.2).contains(&b.flips[0].mass_ratio));
/// assert_eq!(b.diagram.masses.len(), 5);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn mass_bifurcation(
    body: &Sphere,
    alpha: f64,
    masses: &[f64],
    starts: usize,
    seed: u64,
    window: RunWindow,
) -> Result<MassBifurcation, OrbitDiagramError> {
    mass_bifurcation_until(
        body,
        alpha,
        masses,
        starts,
        seed,
        window,
        &AtomicBool::new(false),
    )
}

/// Most grid masses, and most starts per mass, of [`mass_bifurcation`].
pub const MAX_GRID: usize = 100_000;

/// Checks [`mass_bifurcation`]'s arguments before any run.
fn check_grid(masses: &[f64], starts: usize, window: RunWindow) -> Result<(), OrbitDiagramError> {
    let bad = |s: String| Err(OrbitDiagramError::BadArgument(s));
    if !(2..=MAX_GRID).contains(&masses.len()) || masses[0] != 0.0 {
        return bad(format!(
            "masses needs 2 to {MAX_GRID} values, the first 0 (viscous) and then the inertial \
             ones ascending; got {} values starting {:?}",
            masses.len(),
            masses.first()
        ));
    }
    if let Some(w) = masses
        .windows(2)
        .find(|w| !(w[1].is_finite() && w[1] > w[0]))
    {
        return bad(format!(
            "masses must ascend through finite values: {} follows {}",
            w[1], w[0]
        ));
    }
    if !(1..=MAX_GRID).contains(&starts) {
        return bad(format!(
            "starts = {starts} is not allowed (needs 1 ≤ starts ≤ {MAX_GRID})"
        ));
    }
    let RunWindow { t_min, t_cap } = window;
    if !(t_min.is_finite()
        && t_min > 0.0
        && t_cap.is_finite()
        && t_cap >= t_min
        && t_cap <= MAX_SPAN)
    {
        return bad(format!(
            "the run window t_min = {t_min}, t_cap = {t_cap} is not allowed (needs 0 < t_min ≤ \
             t_cap ≤ {MAX_SPAN:e})"
        ));
    }
    Ok(())
}

/// [`mass_bifurcation`] that stops with [`OrbitDiagramError::Stopped`] once `stop` is set
/// (each run or orbit already under way finishes first).
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::orbit_diagram::{OrbitDiagramError, RunWindow, mass_bifurcation_until};
/// use rollphase_core::geometry::Body;
/// use std::sync::atomic::AtomicBool;
/// let Body::Sphere(body) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let window = RunWindow { t_min: 400.0, t_cap: 4000.0 };
/// let stop = AtomicBool::new(true);
/// let r = mass_bifurcation_until(&body, 0.15, &[0.0, 1.0], 2, 1, window, &stop);
/// assert!(matches!(r, Err(OrbitDiagramError::Stopped)));
/// // Arguments are checked before any run: the grid starts at the viscous m/m0 = 0.
/// let r = mass_bifurcation_until(&body, 0.15, &[1.0, 2.0], 2, 1, window, &AtomicBool::new(false));
/// assert!(matches!(r, Err(OrbitDiagramError::BadArgument(_))));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn mass_bifurcation_until(
    body: &Sphere,
    alpha: f64,
    masses: &[f64],
    starts: usize,
    seed: u64,
    window: RunWindow,
    stop: &AtomicBool,
) -> Result<MassBifurcation, OrbitDiagramError> {
    check_grid(masses, starts, window)?;
    let ramps: Vec<Ramp> = masses
        .iter()
        .map(|&m| Ramp::new(alpha, m))
        .collect::<Result<_, _>>()?;
    let stopped = || {
        if stop.load(Ordering::Relaxed) {
            Err(OrbitDiagramError::Stopped)
        } else {
            Ok(())
        }
    };
    let runs: Vec<LateRun> = (0..masses.len() * starts)
        .into_par_iter()
        .with_max_len(1)
        .map(|j| {
            stopped()?;
            let (m, o) = (j / starts, j % starts);
            Ok(direct_run(
                body,
                &ramps[m],
                random_orientation(body, seed, o),
                window,
            )?)
        })
        .collect::<Result<_, OrbitDiagramError>>()?;
    let grid = DirectRuns::new(masses, starts, &runs)?;
    let seeds = period_one_seeds(&grid)?;
    let orbits: Vec<OrbitBranch> = (0..seeds.len())
        .into_par_iter()
        .with_max_len(1)
        .map(|j| {
            stopped()?;
            Ok(continue_orbit(body, alpha, &masses[1..], j, seeds[j]))
        })
        .collect::<Result<_, OrbitDiagramError>>()?;
    let flips: Vec<Flip> = flip_brackets(&orbits)
        .par_iter()
        .with_max_len(1)
        .map(|b| {
            stopped()?;
            Ok(locate_flip_in(body, alpha, b))
        })
        .collect::<Result<_, OrbitDiagramError>>()?;
    let diagram = orbit_diagram(&grid, &orbits)?;
    let windows = doubling_windows(masses, &orbits, &flips, &diagram);
    Ok(MassBifurcation {
        runs,
        orbits,
        flips,
        diagram,
        windows,
    })
}
