//! The paper's 3D studies callable with plain parameters and returning data: the Poincaré map
//! on ∂Ω over any starts, the cruising fraction over random orientations, and how the runs from
//! random orientations end at one m/m0 (the period-doubling statistics). Each runs its
//! starts in parallel (rayon) and gives the same numbers for any thread count; the figures
//! `sphere-poincare` and `sphere-cruising` compute the same things run by run (so a library or
//! Python caller gets the figures' numbers without the figure).

use std::sync::atomic::{AtomicBool, Ordering};

use glam::{DQuat, DVec3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;
use thiserror::Error;

use crate::analysis::orbits::poincare_field::poincare_step;
use crate::analysis::orbits::return_map::ReturnMapError;
use crate::analysis::orbits::sphere_orbits::{
    Crossing, Decide, DecidedRun, SAME_ORBIT, SETTLED_ON_SAME_ORBIT, Settle, Settlement,
    boundary_distance, cluster_antipodal, decided_run, settle, settled_cycle,
};
use crate::analysis::orbits::sphere_return_map::{
    OrbitSolve, PeriodicOrbit, SectionState, inertial_crossings_until, periodic_orbit,
    viscous_periodic_orbit,
};
use crate::analysis::verdict::Fate;
use crate::dynamics::ModelKind;
use crate::dynamics::sphere3d::orientation_touching;
use crate::dynamics::{ModelError, Ramp};
use crate::geometry::{Body, Sphere};
use crate::integrate::IntegrateError;

/// Why a study could not run.
#[derive(Debug, Error)]
pub enum StudyError {
    /// The study is of orientations in SO(3): it needs a sphere.
    #[error("{0} needs a 3D body (a sphere); this one is a 2D disk")]
    NotASphere(&'static str),
    /// A bad α.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// An integration failed.
    #[error(transparent)]
    Integrate(#[from] IntegrateError),
    /// A start that is not a point of ∂Ω.
    #[error(
        "start {index} = {value:?} is not a finite, non-zero vector (a point of ∂Ω, normalised here)"
    )]
    BadStart {
        /// Which start.
        index: usize,
        /// Its value.
        value: [f64; 3],
    },
    /// A count or limit out of range.
    #[error("{0}")]
    BadArgument(String),
    /// A run closed a period-1 cycle that Newton's method could not refine as a fixed point of
    /// the return map (an orbit too weakly attracting, near a bifurcation).
    #[error(
        "a period-1 cycle seen near {near:?} is not a fixed point Newton's method can refine: \
         {source}; the orbit may be too weakly attracting at this α and m/m0"
    )]
    NoFixedPoint {
        /// The cycle's crossing point.
        near: [f64; 3],
        /// Why Newton failed.
        source: ReturnMapError,
    },
    /// Stopped on request (the `_until` variants).
    #[error("the study was stopped before its end")]
    Stopped,
    /// The bodies of a cross-body statistic could not be found.
    #[error(transparent)]
    Shape(#[from] crate::geometry::ShapeError),
    /// A run's cycle is not 1 to 4 crossings long.
    #[error("run {run}: a cycle of {k} crossings (1 to 4 are counted)")]
    BadCycle {
        /// Which run, in the order given.
        run: usize,
        /// Its cycle length.
        k: usize,
    },
}

fn stopped(stop: &AtomicBool) -> Result<(), StudyError> {
    if stop.load(Ordering::Relaxed) {
        Err(StudyError::Stopped)
    } else {
        Ok(())
    }
}

fn sphere_of<'a>(body: &'a Body, what: &'static str) -> Result<&'a Sphere, StudyError> {
    match body {
        Body::Sphere(s) => Ok(s),
        Body::Disk(_) => Err(StudyError::NotASphere(what)),
    }
}

/// Random orientation `i` of a seed: a uniformly random contact point, then a random spin
/// about the ramp's normal (the starts of `sphere-cruising`, `sphere-orbits` and the others).
///
/// ```
/// use rollphase_core::analysis::studies::sphere::random_orientation;
/// use rollphase_core::geometry::Body;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let rollphase_core::geometry::Body::Sphere(s) = &body else { unreachable!() };
/// let q = random_orientation(s, 1, 0);
/// assert!((q.length() - 1.0).abs() < 1e-12);
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn random_orientation(body: &Sphere, seed: u64, i: usize) -> DQuat {
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(1_000_003).wrapping_add(i as u64));
    let z: f64 = rng.random_range(-1.0..1.0);
    let phi: f64 = rng.random_range(0.0..std::f64::consts::TAU);
    let s = (1.0 - z * z).sqrt();
    let spin: f64 = rng.random_range(0.0..std::f64::consts::TAU);
    orientation_touching(body, DVec3::new(s * phi.cos(), s * phi.sin(), z), spin)
}

/// The viscous Poincaré map P on ∂Ω, the boundary of the SO(3) ball, at ramp angle `alpha`:
/// for each start p (a unit vector, normalised here; the orientation q = (0, p)), the next
/// crossing P(p), with the sign nearest p since q and −q are one orientation, and the time to
/// it; `None` where the body comes to rest first or `t_max` passes. DOP853 at `rtol`.
///
/// ```
/// use rollphase_core::analysis::studies::sphere::poincare_map;
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DVec3;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let images = poincare_map(&body, 0.15, &[DVec3::X, DVec3::Z], 200.0, 1e-8)?;
/// assert_eq!(images.len(), 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn poincare_map(
    body: &Body,
    alpha: f64,
    starts: &[DVec3],
    t_max: f64,
    rtol: f64,
) -> Result<Vec<Option<(DVec3, f64)>>, StudyError> {
    poincare_map_until(body, alpha, starts, t_max, rtol, &AtomicBool::new(false))
}

/// [`poincare_map`] that stops with [`StudyError::Stopped`] once `stop` is set (each start
/// already under way finishes first).
///
/// ```
/// use std::sync::atomic::AtomicBool;
/// use rollphase_core::analysis::studies::sphere::{StudyError, poincare_map_until};
/// use rollphase_core::geometry::Body;
/// use rollphase_core::glam::DVec3;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// // A flag set before the call (from a Ctrl-C handler, say) stops it at once.
/// let stop = AtomicBool::new(true);
/// let r = poincare_map_until(&body, 0.15, &[DVec3::X; 64], 200.0, 1e-8, &stop);
/// assert!(matches!(r, Err(StudyError::Stopped)));
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn poincare_map_until(
    body: &Body,
    alpha: f64,
    starts: &[DVec3],
    t_max: f64,
    rtol: f64,
    stop: &AtomicBool,
) -> Result<Vec<Option<(DVec3, f64)>>, StudyError> {
    let sphere = sphere_of(body, "the Poincaré map on ∂Ω")?;
    let ramp = Ramp::new(alpha, 0.0)?;
    if !(t_max.is_finite() && t_max > 0.0) {
        return Err(StudyError::BadArgument(format!(
            "t_max = {t_max} is not allowed (needs a finite time > 0)"
        )));
    }
    for (index, p) in starts.iter().enumerate() {
        if !(p.is_finite() && p.length() > 1e-12) {
            return Err(StudyError::BadStart {
                index,
                value: p.to_array(),
            });
        }
    }
    starts
        .par_iter()
        .map(|p| {
            stopped(stop)?;
            // A unit vector is used as given (as the Poincaré field does), any other normalised.
            let unit = (p.length_squared() - 1.0).abs() <= 4.0 * f64::EPSILON;
            Ok(poincare_step(
                sphere,
                &ramp,
                if unit { *p } else { p.normalize() },
                t_max,
                rtol,
            )?)
        })
        .collect::<Result<_, StudyError>>()
}

/// How the starts of [`cruising_fraction`] ended.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Cruising {
    /// Starts that cruise: seen to close an orbit.
    pub cruising: usize,
    /// Starts that came to rest.
    pub halted: usize,
    /// Starts neither periodic nor at rest by the end (the verdict's undecided: counted in
    /// neither `cruising` nor `halted`, so `fraction` is the share seen to cruise).
    pub undecided: usize,
    /// cruising / starts.
    pub fraction: f64,
}

/// Whether a run's fate counts as cruising: it closed an orbit. An undecided run is not
/// counted, however fast it still turns (it was counted from |ω| ≥ 1e-3 on, a second rest rule
/// beside the verdict's): a study reports its undecided starts beside the fraction.
///
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::Settlement;
/// use rollphase_core::analysis::studies::sphere::cruises;
/// assert!(!cruises(&Settlement::Halts { t: 3.0 }));
/// assert!(cruises(&Settlement::Periodic { period: 40.0, k: 1, point: [1.0, 0.0, 0.0], t: 400.0 }));
/// assert!(!cruises(&Settlement::Undecided { omega_end: 0.2 }));
/// ```
pub fn cruises(f: &Settlement) -> bool {
    matches!(f, Settlement::Periodic { .. })
}

/// The settling criteria of the cruising study (as `sphere-cruising`): at most t = 2000, a
/// cycle's points and duration repeating to 1e-5.
///
/// # Example
/// ```
/// use rollphase_core::analysis::studies::sphere::cruising_settle;
/// let s = cruising_settle();
/// assert_eq!((s.t_max, s.point_tol), (2000.0, 1e-5));
/// ```
pub fn cruising_settle() -> Settle {
    Settle {
        t_max: 2000.0,
        point_tol: 1e-5,
        period_rtol: 1e-5,
        ..Settle::default()
    }
}

/// Most starts of one study.
pub const MAX_STARTS: usize = 10_000_000;

/// The fraction of `orientations` random starts ([`random_orientation`] with `seed`, i = 0,
/// 1, …), released from rest on a ramp at `alpha` with the viscous model, that cruise rather
/// than halt (paper Fig. 3b; `sphere-cruising` gives the same numbers).
///
/// ```
/// use rollphase_core::analysis::studies::sphere::cruising_fraction;
/// use rollphase_core::geometry::Body;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let c = cruising_fraction(&body, 0.15, 8, 1)?; // above α* = 0.1394: all cruise
/// assert_eq!(c.cruising, 8);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn cruising_fraction(
    body: &Body,
    alpha: f64,
    orientations: usize,
    seed: u64,
) -> Result<Cruising, StudyError> {
    cruising_fraction_until(body, alpha, orientations, seed, &AtomicBool::new(false))
}

/// [`cruising_fraction`] that stops with [`StudyError::Stopped`] once `stop` is set (each run
/// already under way finishes first).
///
/// # Example
/// ```
/// use rollphase_core::analysis::studies::sphere::{StudyError, cruising_fraction_until};
/// use rollphase_core::geometry::Body;
/// use std::sync::atomic::AtomicBool;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// // Stopped before it starts: an error saying so, not a partial answer.
/// let stop = AtomicBool::new(true);
/// assert!(matches!(cruising_fraction_until(&body, 0.12, 8, 1, &stop), Err(StudyError::Stopped)));
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn cruising_fraction_until(
    body: &Body,
    alpha: f64,
    orientations: usize,
    seed: u64,
    stop: &AtomicBool,
) -> Result<Cruising, StudyError> {
    let sphere = sphere_of(body, "the cruising fraction over orientations")?;
    let ramp = Ramp::new(alpha, 0.0)?;
    if !(1..=MAX_STARTS).contains(&orientations) {
        return Err(StudyError::BadArgument(format!(
            "orientations = {orientations} is not allowed (needs 1 ≤ orientations ≤ {MAX_STARTS})"
        )));
    }
    let opts = cruising_settle();
    let fates: Vec<Settlement> = (0..orientations)
        .into_par_iter()
        .map(|o| {
            stopped(stop)?;
            Ok(settle(sphere, &ramp, random_orientation(sphere, seed, o), &opts)?.0)
        })
        .collect::<Result<_, StudyError>>()?;
    let cruising = fates.iter().filter(|f| cruises(f)).count();
    Ok(Cruising {
        cruising,
        halted: fates
            .iter()
            .filter(|f| matches!(f, Settlement::Halts { .. }))
            .count(),
        undecided: fates
            .iter()
            .filter(|f| matches!(f, Settlement::Undecided { .. }))
            .count(),
        fraction: cruising as f64 / orientations as f64,
    })
}

/// Run `o` of [`period_counts`]: released from rest at [`random_orientation`] `o` of `seed`,
/// going on until `decide` says its fate is decided (DOP853 at rtol 1e-9). `sphere-doubling`'s
/// runs on other bodies are these.
///
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::Decide;
/// use rollphase_core::analysis::verdict::Fate;
/// use rollphase_core::analysis::studies::sphere::decided_from_rest;
/// use rollphase_core::dynamics::Ramp;
/// use rollphase_core::geometry::Body;
/// let Body::Sphere(sphere) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// // A short window: decided by t = 400 at the latest.
/// let decide = Decide { t_min: 100.0, t_cap: 400.0, max_k: 4, tol: 1e-5 };
/// let run = decided_from_rest(&sphere, &Ramp::new(0.15, 1.0)?, 1, 0, &decide)?;
/// // This start settles on a period-1 orbit: one crossing of ∂Ω per period.
/// assert_eq!(run.fate, Fate::Periodic { multiplicity: 1 });
/// let (k, period) = run.cycle.unwrap();
/// assert_eq!(k, 1);
/// assert!(period > 0.0 && run.crossings.len() >= 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn decided_from_rest(
    sphere: &Sphere,
    ramp: &Ramp,
    seed: u64,
    o: usize,
    decide: &Decide,
) -> Result<DecidedRun, IntegrateError> {
    decided_run(
        sphere,
        ramp,
        random_orientation(sphere, seed, o),
        decide,
        (0.0, 0.0, 0),
        1e-9,
    )
}

/// How the runs from random orientations ended at one m/m0 ([`period_counts`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PeriodCounts {
    /// Runs whose crossings of ∂Ω closed a cycle of k = 1, 2, 3, 4, …, `max_k` (index k − 1);
    /// the last entry counts the runs that closed none.
    pub cycle_counts: [usize; 5],
    /// Of the runs that closed no cycle: those that came to rest.
    pub at_rest: usize,
    /// Of the runs that closed no cycle: those still undecided at the cap.
    pub undecided: usize,
    /// Runs whose body left the ramp: no cycle or rest is claimed for them (they count in the
    /// last entry of `cycle_counts`, not in `at_rest` or `undecided`).
    pub left_model: usize,
    /// The longest any run went on before its fate was decided (or the cap).
    pub longest_run: f64,
}

/// How one run from rest ended, as the period statistics read it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunOutcome {
    /// The cycle its crossings of ∂Ω closed: (k, its duration).
    pub cycle: Option<(usize, f64)>,
    /// It came to rest (else, without a cycle, it was still undecided at the cap).
    pub at_rest: bool,
    /// When its fate was decided, or the cap.
    pub t_end: f64,
    /// The body left the ramp during the run ([`DecidedRun::left_model`]).
    pub left_model: bool,
}

impl From<&DecidedRun> for RunOutcome {
    fn from(r: &DecidedRun) -> Self {
        RunOutcome {
            cycle: r.cycle,
            at_rest: matches!(r.fate, Fate::Halted { .. }),
            t_end: r.t_end,
            left_model: r.left_model(),
        }
    }
}

impl PeriodCounts {
    /// Counts the runs by cycle length, at rest and undecided, and their longest duration.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::studies::sphere::{PeriodCounts, RunOutcome};
    /// let runs = [
    ///     RunOutcome { cycle: Some((2, 87.0)), at_rest: false, t_end: 2000.0, left_model: false },
    ///     RunOutcome { cycle: None, at_rest: true, t_end: 150.0, left_model: false },
    ///     RunOutcome { cycle: None, at_rest: false, t_end: 20_000.0, left_model: false },
    ///     // Left the ramp: its cycle is not counted as one.
    ///     RunOutcome { cycle: Some((1, 40.0)), at_rest: false, t_end: 900.0, left_model: true },
    /// ];
    /// let c = PeriodCounts::of(&runs)?;
    /// assert_eq!(c.cycle_counts, [0, 1, 0, 0, 3]);
    /// assert_eq!((c.at_rest, c.undecided, c.left_model, c.longest_run), (1, 1, 1, 20_000.0));
    /// // A cycle of 5 crossings is not one the statistics count.
    /// let five = [RunOutcome { cycle: Some((5, 1.0)), ..runs[0] }];
    /// assert!(PeriodCounts::of(&five).is_err());
    /// # Ok::<(), rollphase_core::analysis::studies::sphere::StudyError>(())
    /// ```
    pub fn of(runs: &[RunOutcome]) -> Result<Self, StudyError> {
        let mut c = PeriodCounts {
            cycle_counts: [0; 5],
            at_rest: 0,
            undecided: 0,
            left_model: 0,
            longest_run: 0.0,
        };
        for (run, r) in runs.iter().enumerate() {
            c.longest_run = c.longest_run.max(r.t_end);
            if r.left_model {
                c.left_model += 1;
                c.cycle_counts[4] += 1;
                continue;
            }
            match r.cycle {
                Some((k, _)) => {
                    *c.cycle_counts
                        .get_mut(k.wrapping_sub(1))
                        .filter(|_| k <= 4)
                        .ok_or(StudyError::BadCycle { run, k })? += 1
                }
                None => {
                    c.cycle_counts[4] += 1;
                    if r.at_rest {
                        c.at_rest += 1;
                    } else {
                        c.undecided += 1;
                    }
                }
            }
            c.longest_run = c.longest_run.max(r.t_end);
        }
        Ok(c)
    }
}

/// The median duration of the closed cycles among `runs` (of `k` crossings only, if given):
/// the middle one, the upper of the two for an even count; `None` if none closed.
///
/// # Example
/// ```
/// use rollphase_core::analysis::studies::sphere::{RunOutcome, median_cycle_duration};
/// let run = |cycle| RunOutcome { cycle, at_rest: false, t_end: 2000.0, left_model: false };
/// let runs = [run(Some((1, 43.0))), run(Some((2, 87.0))), run(Some((1, 44.0))), run(None)];
/// assert_eq!(median_cycle_duration(&runs, None), Some(44.0));
/// assert_eq!(median_cycle_duration(&runs, Some(1)), Some(44.0));
/// assert_eq!(median_cycle_duration(&runs, Some(3)), None);
/// ```
pub fn median_cycle_duration(runs: &[RunOutcome], k: Option<usize>) -> Option<f64> {
    let mut durations: Vec<f64> = runs
        .iter()
        .filter(|r| !r.left_model)
        .filter_map(|r| r.cycle)
        .filter(|c| k.is_none_or(|k| c.0 == k))
        .map(|c| c.1)
        .collect();
    durations.sort_by(f64::total_cmp);
    durations.get(durations.len() / 2).copied()
}

/// Is period doubling generic? The period multiplicities of paper-generator bodies in a band of
/// α*, at one m/m0 (paper Fig. 4e asks it of one body).
#[derive(Debug, Clone, Serialize)]
pub struct DoublingAcrossBodies {
    /// The band: lowest α* included.
    pub alpha_star_from: f64,
    /// The band: α* below this.
    pub alpha_star_below: f64,
    /// Bodies examined (the first convex ones in the band among numpy seeds 0, 1, …).
    pub bodies: usize,
    /// Their numpy seeds.
    pub seeds: Vec<u32>,
    /// Orientations per body.
    pub orientations: usize,
    /// Bodies with at least one period-2 attractor.
    pub with_period_2: usize,
    /// with_period_2 / bodies.
    pub fraction_with_period_2: f64,
    /// Bodies whose every run was period 2.
    pub all_period_2: usize,
    /// Bodies with a run that neither closed (k ≤ 4) nor came to rest by the cap.
    pub with_undecided: usize,
}

impl DoublingAcrossBodies {
    /// The statistic from each body's run multiplicities ([`DecidedRun::multiplicity`]:
    /// k, 0 at rest, `None` undecided), body-major, `orientations` runs per body in the order
    /// of `seeds`; `band` is (lowest α* included, α* below).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::studies::sphere::DoublingAcrossBodies;
    /// // Two bodies, two runs each: the first doubles once, the second rests and stays open.
    /// let periods = [Some(2), Some(1), Some(0), None];
    /// let d = DoublingAcrossBodies::from_periods((0.0, 0.13), vec![4, 9], 2, &periods);
    /// assert_eq!((d.with_period_2, d.all_period_2, d.with_undecided), (1, 0, 1));
    /// assert_eq!(d.fraction_with_period_2, 0.5);
    /// ```
    pub fn from_periods(
        band: (f64, f64),
        seeds: Vec<u32>,
        orientations: usize,
        periods: &[Option<usize>],
    ) -> Self {
        let per_body: Vec<&[Option<usize>]> = periods.chunks(orientations.max(1)).collect();
        let with_period_2 = per_body.iter().filter(|r| r.contains(&Some(2))).count();
        DoublingAcrossBodies {
            alpha_star_from: band.0,
            alpha_star_below: band.1,
            bodies: seeds.len(),
            with_period_2,
            fraction_with_period_2: with_period_2 as f64 / seeds.len() as f64,
            seeds,
            orientations,
            all_period_2: per_body
                .iter()
                .filter(|r| r.iter().all(|k| *k == Some(2)))
                .count(),
            with_undecided: per_body.iter().filter(|r| r.contains(&None)).count(),
        }
    }
}

/// The cross-body statistic of period doubling: the first `bodies` convex paper-generator bodies
/// with α* in `band` ([`crate::analysis::rest::critical_angle::paper_spheres_with_alpha_star`]), each
/// released from rest at `orientations` random orientations ([`random_orientation`] with
/// `seed`) at ramp angle `alpha` and `mass_ratio`, every run going on as `decide` says; in
/// parallel, one task per run.
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::Decide;
/// use rollphase_core::analysis::studies::sphere::doubling_across_bodies;
/// let decide = Decide { t_min: 1200.0, t_cap: 6000.0, max_k: 4, tol: 1e-5 };
/// let d = doubling_across_bodies(2, (0.13, 0.15), 1, 0.15, 6.0, 1, &decide)?;
/// assert_eq!((d.bodies, d.seeds.len()), (2, 2));
/// assert!(d.with_period_2 <= d.bodies);
/// # Ok::<(), rollphase_core::analysis::studies::sphere::StudyError>(())
/// ```
pub fn doubling_across_bodies(
    bodies: usize,
    band: (f64, f64),
    orientations: usize,
    alpha: f64,
    mass_ratio: f64,
    seed: u64,
    decide: &Decide,
) -> Result<DoublingAcrossBodies, StudyError> {
    check_counts(orientations, decide)?;
    if !(1..=1000).contains(&bodies) {
        return Err(StudyError::BadArgument(format!(
            "bodies = {bodies} is not allowed (needs 1 ≤ bodies ≤ 1000)"
        )));
    }
    let ramp = Ramp::new(alpha, mass_ratio)?;
    let found = crate::analysis::rest::critical_angle::paper_spheres_with_alpha_star(
        bodies, band.0, band.1,
    )?;
    let periods: Vec<Option<usize>> = (0..found.len() * orientations)
        .into_par_iter()
        .with_max_len(1)
        .map(|j| {
            let (body, o) = (&found[j / orientations].1, j % orientations);
            Ok(decided_from_rest(body, &ramp, seed, o, decide)?.multiplicity())
        })
        .collect::<Result<_, StudyError>>()?;
    let seeds = found.iter().map(|b| b.0).collect();
    Ok(DoublingAcrossBodies::from_periods(
        band,
        seeds,
        orientations,
        &periods,
    ))
}

/// The period multiplicities of `orientations` runs released from rest at random orientations
/// ([`random_orientation`] with `seed`) at ramp angle `alpha` and `mass_ratio` (0: viscous),
/// each going on until `decide` says its fate is decided (paper Fig. 4e; `sphere-doubling`
/// counts the same). `decide.max_k` is at most 4.
///
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::Decide;
/// use rollphase_core::analysis::studies::sphere::period_counts;
/// use rollphase_core::geometry::Body;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let decide = Decide { t_min: 1200.0, t_cap: 6000.0, max_k: 4, tol: 1e-5 };
/// let c = period_counts(&body, 0.15, 6.0, 2, 1, &decide)?;
/// assert_eq!(c.cycle_counts[1], 2); // period 2 at m/m0 = 6 on the paper's body
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn period_counts(
    body: &Body,
    alpha: f64,
    mass_ratio: f64,
    orientations: usize,
    seed: u64,
    decide: &Decide,
) -> Result<PeriodCounts, StudyError> {
    period_counts_until(
        body,
        alpha,
        mass_ratio,
        orientations,
        seed,
        decide,
        &AtomicBool::new(false),
    )
}

/// [`period_counts`] that stops with [`StudyError::Stopped`] once `stop` is set (each run
/// already under way finishes first).
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::Decide;
/// use rollphase_core::analysis::studies::sphere::{StudyError, period_counts_until};
/// use rollphase_core::geometry::Body;
/// use std::sync::atomic::AtomicBool;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let decide = Decide { t_min: 1200.0, t_cap: 6000.0, max_k: 4, tol: 1e-5 };
/// let c = period_counts_until(&body, 0.15, 0.0, 2, 1, &decide, &AtomicBool::new(false))?;
/// assert_eq!(c.cycle_counts[0], 2);
/// let stop = AtomicBool::new(true);
/// assert!(matches!(period_counts_until(&body, 0.15, 0.0, 2, 1, &decide, &stop), Err(StudyError::Stopped)));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn period_counts_until(
    body: &Body,
    alpha: f64,
    mass_ratio: f64,
    orientations: usize,
    seed: u64,
    decide: &Decide,
    stop: &AtomicBool,
) -> Result<PeriodCounts, StudyError> {
    let sphere = sphere_of(body, "the period statistics over orientations")?;
    let ramp = Ramp::new(alpha, mass_ratio)?;
    check_counts(orientations, decide)?;
    let runs: Vec<_> = (0..orientations)
        .into_par_iter()
        .map(|o| {
            stopped(stop)?;
            Ok(decided_from_rest(sphere, &ramp, seed, o, decide)?)
        })
        .collect::<Result<_, StudyError>>()?;
    let outcomes: Vec<RunOutcome> = runs.iter().map(RunOutcome::from).collect();
    PeriodCounts::of(&outcomes)
}

/// A period-1 orbit found by [`periodic_orbits`]: the fixed point of the return map on ∂Ω
/// with its Floquet multipliers, and how many of the starts settled on it.
#[derive(Debug, Clone, Serialize)]
pub struct FoundOrbit {
    /// The orbit: its crossing point on ∂Ω, ω there, period and multipliers.
    pub orbit: PeriodicOrbit,
    /// Starts whose runs closed a period-1 cycle on this orbit.
    pub starts: usize,
}

/// The period-1 orbits that `orientations` runs from rest at random orientations
/// ([`random_orientation`] with `seed`) settle on at ramp angle `alpha` and `mass_ratio`
/// (0: viscous), each refined as a fixed point of the return map on ∂Ω by Newton's method, with
/// its Floquet multipliers (two for the viscous map, five for the inertial one: see
/// [`crate::analysis::orbits::sphere_return_map`]). Each run goes on as `decide` says (DOP853 at rtol
/// 1e-9); a run that closes a period-1 cycle seeds an orbit, and seeds within 1e-3 of each
/// other (antipodes identified) are solved once. Orbits are listed most-visited first. Runs
/// that halt, double or stay undecided seed nothing.
///
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::Decide;
/// use rollphase_core::analysis::studies::sphere::periodic_orbits;
/// use rollphase_core::geometry::Body;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let decide = Decide { t_min: 600.0, t_cap: 6000.0, max_k: 1, tol: 1e-5 };
/// let orbits = periodic_orbits(&body, 0.15, 0.0, 8, 1, &decide)?;
/// assert_eq!(orbits.len(), 2, "the paper's two stable orbits (Fig. 3d)");
/// assert!(orbits.iter().all(|o| o.orbit.max_modulus < 1.0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn periodic_orbits(
    body: &Body,
    alpha: f64,
    mass_ratio: f64,
    orientations: usize,
    seed: u64,
    decide: &Decide,
) -> Result<Vec<FoundOrbit>, StudyError> {
    periodic_orbits_until(
        body,
        alpha,
        mass_ratio,
        orientations,
        seed,
        decide,
        &AtomicBool::new(false),
    )
}

/// [`periodic_orbits`] that stops with [`StudyError::Stopped`] once `stop` is set (each run or
/// Newton solve already under way finishes first).
///
/// # Example
/// ```
/// use rollphase_core::analysis::orbits::sphere_orbits::Decide;
/// use rollphase_core::analysis::studies::sphere::{StudyError, periodic_orbits_until};
/// use rollphase_core::geometry::Body;
/// use std::sync::atomic::AtomicBool;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let decide = Decide { t_min: 600.0, t_cap: 6000.0, max_k: 1, tol: 1e-5 };
/// let stop = AtomicBool::new(true);
/// assert!(matches!(periodic_orbits_until(&body, 0.15, 0.0, 4, 1, &decide, &stop), Err(StudyError::Stopped)));
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn periodic_orbits_until(
    body: &Body,
    alpha: f64,
    mass_ratio: f64,
    orientations: usize,
    seed: u64,
    decide: &Decide,
    stop: &AtomicBool,
) -> Result<Vec<FoundOrbit>, StudyError> {
    let sphere = sphere_of(body, "the periodic orbits over orientations")?;
    let ramp = Ramp::new(alpha, mass_ratio)?;
    check_counts(orientations, decide)?;
    const RTOL: f64 = 1e-9;
    // Each run's last crossing (point, ω) when it closed a period-1 cycle.
    let seeds: Vec<Option<(DVec3, DVec3)>> = (0..orientations)
        .into_par_iter()
        .map(|o| {
            stopped(stop)?;
            let q0 = random_orientation(sphere, seed, o);
            let span = (decide.t_min, decide.t_cap);
            let (max_k, tol) = (decide.max_k, decide.tol);
            match ModelKind::for_dimension(3, &ramp) {
                ModelKind::SphereViscous => {
                    let r = decided_run(sphere, &ramp, q0, decide, (0.0, 0.0, 0), RTOL)?;
                    let last = r.crossings.last().map(|c| DVec3::from_array(c.point));
                    Ok(last
                        .filter(|_| matches!(r.cycle, Some((1, _))))
                        .map(|p| (p, DVec3::ZERO)))
                }
                ModelKind::SphereInertial => {
                    let to_crossing = |c: &SectionState| Crossing {
                        t: c.t,
                        point: c.point,
                    };
                    let (s, _) = inertial_crossings_until(
                        sphere,
                        &ramp,
                        q0,
                        DVec3::ZERO,
                        span,
                        RTOL,
                        |s| {
                            let c: Vec<Crossing> = s.iter().map(to_crossing).collect();
                            settled_cycle(&c, max_k, tol).is_some()
                        },
                    )?;
                    let c: Vec<Crossing> = s.iter().map(to_crossing).collect();
                    let period_one = matches!(settled_cycle(&c, max_k, tol), Some((1, _)));
                    Ok(s.last()
                        .filter(|_| period_one)
                        .map(|c| (DVec3::from_array(c.point), DVec3::from_array(c.omega))))
                }
                other @ (ModelKind::DiskViscous | ModelKind::DiskInertial) => {
                    other.wrong_dimension(3)
                }
            }
        })
        .collect::<Result<_, StudyError>>()?;
    let found: Vec<(DVec3, DVec3)> = seeds.into_iter().flatten().collect();
    let points: Vec<DVec3> = found.iter().map(|s| s.0).collect();
    let clusters = cluster_antipodal(&points, SETTLED_ON_SAME_ORBIT);
    let solve = OrbitSolve::default();
    let solved: Vec<(PeriodicOrbit, usize)> = clusters
        .par_iter()
        .map(|&(centre, count)| {
            stopped(stop)?;
            let &(p, omega) = found
                .iter()
                .find(|s| boundary_distance(s.0, centre) < SETTLED_ON_SAME_ORBIT)
                .unwrap_or(&(centre, DVec3::ZERO));
            let orbit = match ModelKind::for_dimension(3, &ramp) {
                ModelKind::SphereViscous => viscous_periodic_orbit(sphere, &ramp, p, &solve),
                ModelKind::SphereInertial => periodic_orbit(sphere, &ramp, p, omega, &solve),
                other @ (ModelKind::DiskViscous | ModelKind::DiskInertial) => {
                    other.wrong_dimension(3)
                }
            };
            orbit
                .map(|o| (o, count))
                .map_err(|source| StudyError::NoFixedPoint {
                    near: p.to_array(),
                    source,
                })
        })
        .collect::<Result<_, StudyError>>()?;
    let mut orbits: Vec<FoundOrbit> = Vec::new();
    for (orbit, count) in solved {
        let p = DVec3::from_array(orbit.point);
        match orbits
            .iter_mut()
            .find(|o| boundary_distance(DVec3::from_array(o.orbit.point), p) < SAME_ORBIT)
        {
            Some(same) => same.starts += count,
            None => orbits.push(FoundOrbit {
                orbit,
                starts: count,
            }),
        }
    }
    orbits.sort_by(|a, b| {
        b.starts
            .cmp(&a.starts)
            .then(a.orbit.period.total_cmp(&b.orbit.period))
    });
    Ok(orbits)
}

fn check_counts(orientations: usize, decide: &Decide) -> Result<(), StudyError> {
    if !(1..=MAX_STARTS).contains(&orientations) {
        return Err(StudyError::BadArgument(format!(
            "orientations = {orientations} is not allowed (needs 1 ≤ orientations ≤ {MAX_STARTS})"
        )));
    }
    let valid = (1..=4).contains(&decide.max_k)
        && decide.t_min.is_finite()
        && decide.t_min > 0.0
        && decide.t_cap.is_finite()
        && decide.t_cap >= decide.t_min
        && decide.tol.is_finite()
        && decide.tol > 0.0;
    if !valid {
        return Err(StudyError::BadArgument(format!(
            "t_min = {}, t_cap = {}, max_k = {}, tol = {} is not allowed (needs 1 ≤ max_k ≤ 4, \
             0 < t_min ≤ t_cap < ∞, tol > 0)",
            crate::integrate::readable(decide.t_min),
            crate::integrate::readable(decide.t_cap),
            decide.max_k,
            crate::integrate::readable(decide.tol)
        )));
    }
    Ok(())
}
