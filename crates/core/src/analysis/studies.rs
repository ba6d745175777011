//! The paper's 3D studies callable with plain parameters and returning data: the Poincaré map
//! on ∂Ω over any starts, the cruising fraction over random orientations, and how the runs from
//! random orientations end at one m/m0 (the period-doubling statistics). Each runs its
//! starts in parallel (rayon) and gives the same numbers for any thread count; the figures
//! `sphere-poincare` and `sphere-cruising` compute the same things run by run (so a library or
//! Python caller gets the figures' numbers without the figure).

use glam::{DQuat, DVec3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;
use thiserror::Error;

use super::sphere_orbits::{
    Decide, DecidedRun, Fate, RunEnd, Settle, decided_run, poincare_step, settle,
};
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
/// use rollphase_core::analysis::studies::random_orientation;
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
/// use rollphase_core::analysis::studies::poincare_map;
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
    Ok(starts
        .par_iter()
        .map(|p| {
            // A unit vector is used as given (as the Poincaré field does), any other normalised.
            let unit = (p.length_squared() - 1.0).abs() <= 4.0 * f64::EPSILON;
            poincare_step(
                sphere,
                &ramp,
                if unit { *p } else { p.normalize() },
                t_max,
                rtol,
            )
        })
        .collect::<Result<_, _>>()?)
}

/// How the starts of [`cruising_fraction`] ended.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Cruising {
    /// Starts that cruise: a closed orbit, or still rolling (|ω| ≥ 1e-3) when undecided.
    pub cruising: usize,
    /// Starts that came to rest.
    pub halted: usize,
    /// Starts neither periodic nor at rest by the end (counted as cruising when |ω| ≥ 1e-3).
    pub undecided: usize,
    /// cruising / starts.
    pub fraction: f64,
}

/// Whether a run's fate counts as cruising: a closed orbit, or an undecided run still turning
/// (|ω| ≥ 1e-3 at the end).
pub fn cruises(f: &Fate) -> bool {
    match f {
        Fate::Halts { .. } => false,
        Fate::Periodic { .. } => true,
        Fate::Undecided { omega_end } => *omega_end >= 1e-3,
    }
}

/// The settling criteria of the cruising study (as `sphere-cruising`): at most t = 2000, a
/// cycle's points and duration repeating to 1e-5.
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
/// use rollphase_core::analysis::studies::cruising_fraction;
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
    let sphere = sphere_of(body, "the cruising fraction over orientations")?;
    let ramp = Ramp::new(alpha, 0.0)?;
    if !(1..=MAX_STARTS).contains(&orientations) {
        return Err(StudyError::BadArgument(format!(
            "orientations = {orientations} is not allowed (needs 1 ≤ orientations ≤ {MAX_STARTS})"
        )));
    }
    let opts = cruising_settle();
    let fates: Vec<Fate> = (0..orientations)
        .into_par_iter()
        .map(|o| settle(sphere, &ramp, random_orientation(sphere, seed, o), &opts).map(|r| r.0))
        .collect::<Result<_, _>>()?;
    let cruising = fates.iter().filter(|f| cruises(f)).count();
    Ok(Cruising {
        cruising,
        halted: fates
            .iter()
            .filter(|f| matches!(f, Fate::Halts { .. }))
            .count(),
        undecided: fates
            .iter()
            .filter(|f| matches!(f, Fate::Undecided { .. }))
            .count(),
        fraction: cruising as f64 / orientations as f64,
    })
}

/// Run `o` of [`period_counts`]: released from rest at [`random_orientation`] `o` of `seed`,
/// going on until `decide` says its fate is decided (DOP853 at rtol 1e-9). `sphere-doubling`'s
/// runs on other bodies are these.
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
    /// The longest any run went on before its fate was decided (or the cap).
    pub longest_run: f64,
}

/// The period multiplicities of `orientations` runs released from rest at random orientations
/// ([`random_orientation`] with `seed`) at ramp angle `alpha` and `mass_ratio` (0: viscous),
/// each going on until `decide` says its fate is decided (paper Fig. 4e; `sphere-doubling`
/// counts the same). `decide.max_k` is at most 4.
///
/// ```
/// use rollphase_core::analysis::sphere_orbits::Decide;
/// use rollphase_core::analysis::studies::period_counts;
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
    let sphere = sphere_of(body, "the period statistics over orientations")?;
    let ramp = Ramp::new(alpha, mass_ratio)?;
    if !(1..=MAX_STARTS).contains(&orientations) {
        return Err(StudyError::BadArgument(format!(
            "orientations = {orientations} is not allowed (needs 1 ≤ orientations ≤ {MAX_STARTS})"
        )));
    }
    let valid = (1..=4).contains(&decide.max_k)
        && decide.t_min.is_finite()
        && decide.t_min > 0.0
        && decide.t_cap >= decide.t_min
        && decide.tol.is_finite()
        && decide.tol > 0.0;
    if !valid {
        return Err(StudyError::BadArgument(format!(
            "{decide:?} is not allowed (needs 1 ≤ max_k ≤ 4, 0 < t_min ≤ t_cap, tol > 0)"
        )));
    }
    let runs: Vec<_> = (0..orientations)
        .into_par_iter()
        .map(|o| decided_from_rest(sphere, &ramp, seed, o, decide))
        .collect::<Result<_, _>>()?;
    let mut c = PeriodCounts {
        cycle_counts: [0; 5],
        at_rest: 0,
        undecided: 0,
        longest_run: 0.0,
    };
    for r in &runs {
        match r.cycle {
            Some((k, _)) => c.cycle_counts[k - 1] += 1,
            None => {
                c.cycle_counts[4] += 1;
                if r.end == RunEnd::Rest {
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
