//! What a body does on a ramp, in the lab's terms: the stable periodic motions it settles into
//! from many starts (the fraction of starts that reach each), each with its period, how far its
//! centre moves down and across the ramp per period (per repeat for a doubled orbit), its Floquet
//! multipliers, and the centre's path over a few periods (drawn from above by `predict`).
//!
//! 3D: runs from rest at random orientations ([`crate::analysis::studies::sphere::random_orientation`]) go on
//! until their ∂Ω crossings close a cycle of one or two crossings ([`settled_cycle`]) or they
//! come to rest; period-1 cycles are refined as fixed points of the return map by Newton's method
//! (period and multipliers to the solver's tolerance), doubled ones are measured on the run's
//! last cycle. The advance is the centre's displacement over one period from a crossing, by
//! DOP853 at rtol 1e-10: the orientation repeats, the position moves on. 2D: the disk's fate
//! from rest at equally spaced contact angles; a rolling disk advances its perimeter per turn
//! (exactly, without slip), and its centre's path is a function of the contact angle alone.

use std::sync::atomic::AtomicBool;

use glam::{DQuat, DVec3};
use rayon::prelude::*;
use serde::Serialize;

use crate::analysis::orbits::disk_period::{
    inertial_disk_period_until, inertial_on_hull, viscous_disk_period,
};
use crate::analysis::orbits::return_map::ReturnMapError;
use crate::analysis::orbits::sphere_orbits::{
    Decide, SAME_ORBIT, SETTLED_ON_SAME_ORBIT, boundary_distance, cluster_antipodal, decided_run,
    settled_cycle,
};
use crate::analysis::orbits::sphere_return_map::{
    InertialEnd, OrbitSolve, SectionState, inertial_run, periodic_orbit, viscous_periodic_orbit,
};
use crate::analysis::rest::critical_angle::critical_angle;
use crate::analysis::studies::sphere::{StudyError, random_orientation};
use crate::analysis::verdict::{Fate, FateCounts, Stability, Undecided, steady_drift};
use crate::dynamics::ModelKind;
use crate::dynamics::sphere3d::{SphereInertial, SphereViscous};
use crate::dynamics::validity::{ContactLimits, ContactReport, ContactWatch, Violation};
use crate::dynamics::{DragLaw, Ramp, RollingModel, disk2d};
use crate::geometry::{Body, Disk, Sphere};
use crate::integrate::run::{Flow, Run, Samples};
use crate::integrate::{self, Method};

/// How a prediction is made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PredictOptions {
    /// Starts: random orientations (3D) or equally spaced contact angles (2D), from rest.
    pub starts: usize,
    /// Seed of the random orientations.
    pub seed: u64,
    /// When a 3D run's fate counts as decided (its `max_k` is 2: period 1 or 2).
    pub decide: Decide,
    /// Periods of each orbit's path kept for drawing.
    pub periods_drawn: usize,
    /// Samples of the path per period.
    pub samples_per_period: usize,
    /// The drag law every run uses (linear by default).
    pub drag_law: DragLaw,
}

impl Default for PredictOptions {
    fn default() -> Self {
        PredictOptions {
            starts: 32,
            seed: 1,
            decide: Decide {
                t_min: 600.0,
                t_cap: 20_000.0,
                max_k: 2,
                tol: 1e-5,
            },
            periods_drawn: 3,
            samples_per_period: 200,
            drag_law: DragLaw::LINEAR,
        }
    }
}

/// One stable periodic motion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PredictedOrbit {
    /// Time for the motion to repeat (t0 = γ/(F⟨r⟩)): one period, or two crossings of ∂Ω for a
    /// doubled orbit.
    pub period: f64,
    /// 1 for a period-1 orbit, 2 for a doubled one (its `period` and advances are per repeat).
    pub repeat: usize,
    /// The centre's advance down the ramp per repeat (⟨r⟩).
    pub advance_down: f64,
    /// The centre's advance across the ramp per repeat (⟨r⟩; + is the lab's y).
    pub advance_across: f64,
    /// Mean speed down the ramp (⟨r⟩/t0).
    pub speed: f64,
    /// Whether it attracts and the body stays on the ramp along it: [`Self::stability`] is
    /// stable and the normal force stays positive ([`Self::contact`]).
    pub stable: bool,
    /// Stable, neutral or unstable ([`Stability::of`] over the runs' `t_cap`): every Floquet
    /// multiplier inside the unit circle (period 1), or seen to attract runs (a doubled orbit,
    /// whose multipliers are not computed: stable).
    pub stability: Stability,
    /// Distinct orbits this entry stands for: 1, or more for a neutral family (a round body
    /// rolls on a different great circle from each start, all one motion).
    pub members: usize,
    /// The Floquet multipliers (re, im), largest modulus first: two (3D viscous), five (3D
    /// inertial); empty for a disk (its rolling cycle has none in the viscous model) or a
    /// doubled orbit.
    pub multipliers: Vec<[f64; 2]>,
    /// The largest |multiplier| (`null` where none is computed).
    pub max_modulus: Option<f64>,
    /// Fraction of the starts that settle on it.
    pub fraction: f64,
    /// Starts that settle on it.
    pub starts: usize,
    /// 3D: where the orbit crosses ∂Ω (sign arbitrary), with ω there, to start a run on it.
    pub crossing: Option<[f64; 3]>,
    /// 3D: ω at that crossing (zero in the viscous model).
    pub omega: Option<[f64; 3]>,
    /// With inertia, the contact force along the drawn periods of the orbit; `None` in the
    /// viscous model (N = cos α, friction needed tan α throughout).
    pub contact: Option<OrbitContact>,
    /// The centre's path from a point of the orbit over [`PredictOptions::periods_drawn`]
    /// repeats: (down, across) in ⟨r⟩ for a sphere, (down, height) for a disk.
    #[serde(skip)]
    pub path: Vec<[f64; 2]>,
}

/// The ramp's force along an orbit (units of the weight F), from the model's own motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OrbitContact {
    /// The smallest normal force N/F.
    pub min_normal_force: f64,
    /// The largest friction coefficient rolling needs, |f_t|/N (infinite once N ≤ 0).
    pub max_friction_needed: f64,
    /// Time from the orbit's crossing at which N first reaches 0: the body leaves the ramp
    /// there, and the rolling model no longer holds.
    pub lift_off_t: Option<f64>,
}

impl From<ContactReport> for OrbitContact {
    fn from(c: ContactReport) -> Self {
        OrbitContact {
            min_normal_force: c.min_normal_force,
            max_friction_needed: c.max_friction_needed,
            lift_off_t: c.lift_off_t,
        }
    }
}

/// What a body does at one α and m/m0.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Prediction {
    /// The model that ran (its registry name: "sphere-inertial", …).
    pub model: ModelKind,
    /// 2 or 3.
    pub dimension: u32,
    /// The drag law: one field per registered parameter, named by its key.
    #[serde(flatten)]
    pub drag_law: DragLaw,
    /// α (rad).
    pub alpha: f64,
    /// m/m0 (0: viscous).
    pub mass_ratio: f64,
    /// The body's α* (rad).
    pub alpha_star: f64,
    /// Starts tried.
    pub starts: usize,
    /// Fraction of the starts that come to rest.
    pub halts: f64,
    /// Fraction still undecided at the time cap (neither periodic nor at rest).
    pub undecided: f64,
    /// How the starts ended ([`FateCounts`]): periodic, neutral, halted, left the model,
    /// undecided (with why).
    pub fates: FateCounts,
    /// The periodic motions the starts reach, most visited first: stable ones, neutral
    /// families, and any that leave the ramp (not stable, with where).
    pub orbits: Vec<PredictedOrbit>,
}

/// Most starts a prediction runs.
pub const MAX_PREDICT_STARTS: usize = 100_000;

/// The stable periodic motions of `body` at ramp angle `alpha` and `mass_ratio` (0: viscous).
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::prediction::{PredictOptions, predict};
/// use rollphase_core::geometry::Body;
/// // The paper's sphere at α = 0.15: two stable orbits (Fig. 3d), each rolling downhill.
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let options = PredictOptions { starts: 8, ..PredictOptions::default() };
/// let p = predict(&body, 0.15, 0.0, &options)?;
/// assert_eq!(p.orbits.len(), 2);
/// assert!(p.orbits.iter().all(|o| o.stable && o.advance_down > 0.0 && o.repeat == 1));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn predict(
    body: &Body,
    alpha: f64,
    mass_ratio: f64,
    options: &PredictOptions,
) -> Result<Prediction, StudyError> {
    predict_until(body, alpha, mass_ratio, options, &AtomicBool::new(false))
}

/// [`predict`] that stops with [`StudyError::Stopped`] once `stop` is set.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::prediction::{PredictOptions, predict_until};
/// use rollphase_core::analysis::studies::sphere::StudyError;
/// use rollphase_core::geometry::Body;
/// use std::sync::atomic::AtomicBool;
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let stop = AtomicBool::new(true);
/// let e = predict_until(&body, 0.15, 0.0, &PredictOptions::default(), &stop);
/// assert!(matches!(e, Err(StudyError::Stopped)));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn predict_until(
    body: &Body,
    alpha: f64,
    mass_ratio: f64,
    options: &PredictOptions,
    stop: &AtomicBool,
) -> Result<Prediction, StudyError> {
    let ramp = Ramp::new(alpha, mass_ratio)?.with_drag_law(options.drag_law);
    if !(1..=MAX_PREDICT_STARTS).contains(&options.starts) {
        return Err(StudyError::BadArgument(format!(
            "starts = {} is not allowed (needs 1 ≤ starts ≤ {MAX_PREDICT_STARTS})",
            options.starts
        )));
    }
    if !(1..=100).contains(&options.periods_drawn)
        || !(2..=10_000).contains(&options.samples_per_period)
    {
        return Err(StudyError::BadArgument(format!(
            "periods drawn = {}, samples per period = {} is not allowed (needs 1 to 100 and 2 to \
             10000)",
            options.periods_drawn, options.samples_per_period
        )));
    }
    let d = options.decide;
    let valid = d.t_min.is_finite()
        && d.t_min > 0.0
        && d.t_cap.is_finite()
        && d.t_cap >= d.t_min
        && d.tol.is_finite()
        && d.tol > 0.0;
    if !valid {
        return Err(StudyError::BadArgument(format!(
            "t_min = {}, t_cap = {}, tol = {} is not allowed (needs 0 < t_min ≤ t_cap < ∞, tol > 0)",
            d.t_min, d.t_cap, d.tol
        )));
    }
    let alpha_star = critical_angle(body).alpha_star;
    let (orbits, fates) = match body {
        Body::Disk(disk) => predict_disk(disk, &ramp, options, stop)?,
        Body::Sphere(sphere) => predict_sphere(sphere, &ramp, options, stop)?,
    };
    let fates = FateCounts::of(&fates);
    Ok(Prediction {
        model: ModelKind::of(body, &ramp),
        dimension: body.dimension(),
        drag_law: ramp.drag_law,
        alpha,
        mass_ratio,
        alpha_star,
        starts: options.starts,
        halts: fates.halted,
        undecided: fates.undecided,
        fates,
        orbits,
    })
}

fn stopped(stop: &AtomicBool) -> Result<(), StudyError> {
    if stop.load(std::sync::atomic::Ordering::Relaxed) {
        Err(StudyError::Stopped)
    } else {
        Ok(())
    }
}

/// An orbit as the runs found it, before its advance is measured.
struct Seen {
    point: DVec3,
    omega: DVec3,
    period: f64,
    starts: usize,
    repeat: usize,
    multipliers: Vec<[f64; 2]>,
    max_modulus: f64,
    stability: Stability,
    members: usize,
}

/// How one start ended, with what the orbit search needs.
#[derive(Debug, Clone)]
enum StartEnd {
    Rest(f64),
    LeftModel(Violation),
    /// No cycle; the last crossing (point, ω) if it made three or more (a neutral orbit may be
    /// near), and, if its crossings drift steadily ([`steady_drift`]), the last interval
    /// between them.
    Undecided(Undecided, Option<(DVec3, DVec3)>, Option<f64>),
    /// A cycle of `k` crossings lasting `duration`; the last crossings (point, ω), newest last.
    Cycle {
        k: usize,
        duration: f64,
        last: Vec<(DVec3, DVec3)>,
    },
}

/// One start from rest at orientation `q0`, followed until its fate is decided: the viscous
/// model by [`decided_run`], the inertial one by [`inertial_run`] with the contact force
/// watched (a start that would leave the ramp ends there).
fn sphere_start(
    sphere: &Sphere,
    ramp: &Ramp,
    q0: DQuat,
    decide: &Decide,
    rtol: f64,
) -> Result<StartEnd, StudyError> {
    let last_of = |points: &[(DVec3, DVec3)]| (points.len() >= 3).then(|| points[points.len() - 1]);
    // A steady slow drift, with the last interval between crossings (its period).
    let drifts = |points: &[(DVec3, DVec3)], times: &[f64]| {
        let n = times.len();
        steady_drift(&points.iter().map(|p| p.0).collect::<Vec<_>>())
            .and_then(|_| (n >= 2).then(|| times[n - 1] - times[n - 2]))
    };
    match ModelKind::for_dimension(3, ramp) {
        ModelKind::SphereViscous => {
            let r = decided_run(sphere, ramp, q0, decide, (0.0, 0.0, 0), rtol)?;
            let points: Vec<(DVec3, DVec3)> = r
                .crossings
                .iter()
                .map(|c| (DVec3::from_array(c.point), DVec3::ZERO))
                .collect();
            return Ok(match (r.fate, r.cycle) {
                (Fate::Periodic { .. }, Some((k, duration))) => StartEnd::Cycle {
                    k,
                    duration,
                    last: points[points.len() - k..].to_vec(),
                },
                (Fate::Halted { .. }, _) => StartEnd::Rest(r.t_end),
                (Fate::LeftModel { violation }, _) => StartEnd::LeftModel(violation),
                (Fate::Undecided { why }, _) => StartEnd::Undecided(
                    why,
                    last_of(&points),
                    drifts(
                        &points,
                        &r.crossings.iter().map(|c| c.t).collect::<Vec<_>>(),
                    ),
                ),
                (fate, cycle) => unreachable!("a decided run's fate {fate:?} with cycle {cycle:?}"),
            });
        }
        ModelKind::SphereInertial => {}
        other @ (ModelKind::DiskViscous | ModelKind::DiskInertial) => other.wrong_dimension(3),
    }
    let to_crossing = |c: &SectionState| crate::analysis::orbits::sphere_orbits::Crossing {
        t: c.t,
        point: c.point,
    };
    let run = inertial_run(
        sphere,
        ramp,
        q0,
        DVec3::ZERO,
        (decide.t_min, decide.t_cap),
        rtol,
        true,
        |s| {
            let c: Vec<_> = s.iter().map(to_crossing).collect();
            settled_cycle(&c, decide.max_k, decide.tol).is_some()
        },
    )?;
    let points: Vec<(DVec3, DVec3)> = run
        .crossings
        .iter()
        .map(|c| (DVec3::from_array(c.point), DVec3::from_array(c.omega)))
        .collect();
    Ok(match run.end {
        InertialEnd::LiftOff => StartEnd::LeftModel(Violation::LiftOff { t: run.t_end }),
        InertialEnd::Rest => StartEnd::Rest(run.t_end),
        InertialEnd::Decided | InertialEnd::Cap => {
            let c: Vec<_> = run.crossings.iter().map(to_crossing).collect();
            match settled_cycle(&c, decide.max_k, decide.tol) {
                Some((k, duration)) => StartEnd::Cycle {
                    k,
                    duration,
                    last: points[points.len() - k..].to_vec(),
                },
                None => StartEnd::Undecided(
                    decide.undecided(points.len(), run.angular_speed),
                    last_of(&points),
                    drifts(
                        &points,
                        &run.crossings.iter().map(|c| c.t).collect::<Vec<_>>(),
                    ),
                ),
            }
        }
    })
}

/// The period-1 orbit through the section state (p, ω), by Newton on the return map.
fn refine(
    sphere: &Sphere,
    ramp: &Ramp,
    (p, omega): (DVec3, DVec3),
) -> Result<crate::analysis::orbits::sphere_return_map::PeriodicOrbit, ReturnMapError> {
    let solve = OrbitSolve::default();
    match ModelKind::for_dimension(3, ramp) {
        ModelKind::SphereViscous => viscous_periodic_orbit(sphere, ramp, p, &solve),
        ModelKind::SphereInertial => periodic_orbit(sphere, ramp, p, omega, &solve),
        other @ (ModelKind::DiskViscous | ModelKind::DiskInertial) => other.wrong_dimension(3),
    }
}

/// Adds a period-1 orbit that `count` starts settled on (or roll near, for a neutral one) to
/// `found`: the same orbit (its crossing within [`SAME_ORBIT`]) counts them once more; a neutral orbit
/// joins a neutral family of the same period and speed (within 1 %): a round body has one
/// motion, rolling straight, whatever great circle it rolls on.
fn add_orbit(
    found: &mut Vec<Seen>,
    orbit: &crate::analysis::orbits::sphere_return_map::PeriodicOrbit,
    count: usize,
    stability: Stability,
) {
    let p = DVec3::from_array(orbit.point);
    let same = found.iter_mut().find(|f| {
        f.repeat == 1
            && (boundary_distance(f.point, p) < SAME_ORBIT
                || (stability == Stability::Neutral
                    && f.stability == Stability::Neutral
                    && (f.period - orbit.period).abs() < 0.01 * orbit.period))
    });
    match same {
        Some(f) => {
            if boundary_distance(f.point, p) >= SAME_ORBIT {
                f.members += 1;
                f.max_modulus = f.max_modulus.max(orbit.max_modulus);
            }
            f.starts += count;
        }
        None => found.push(Seen {
            point: p,
            omega: DVec3::from_array(orbit.omega),
            period: orbit.period,
            starts: count,
            repeat: 1,
            multipliers: orbit.multipliers.clone(),
            max_modulus: orbit.max_modulus,
            stability,
            members: 1,
        }),
    }
}

#[expect(
    clippy::too_many_lines,
    reason = "the runs from every start, the grouping of their cycles into orbits (period 1 \
              refined by Newton and judged stable, neutral or unstable, period 2 as seen) and \
              each orbit's advance and contact force are one computation that shares the ramp, \
              the model and the options"
)]
fn predict_sphere(
    sphere: &Sphere,
    ramp: &Ramp,
    options: &PredictOptions,
    stop: &AtomicBool,
) -> Result<(Vec<PredictedOrbit>, Vec<Fate>), StudyError> {
    const RTOL: f64 = 1e-9;
    let decide = Decide {
        max_k: 2,
        ..options.decide
    };
    let ends: Vec<StartEnd> = (0..options.starts)
        .into_par_iter()
        .map(|o| {
            stopped(stop)?;
            sphere_start(
                sphere,
                ramp,
                random_orientation(sphere, options.seed, o),
                &decide,
                RTOL,
            )
        })
        .collect::<Result<_, StudyError>>()?;
    // Period 1: clusters of last crossings, each refined by Newton.
    let singles: Vec<(DVec3, DVec3)> = ends
        .iter()
        .filter_map(|e| match e {
            StartEnd::Cycle { k: 1, last, .. } => Some(last[0]),
            _ => None,
        })
        .collect();
    let points: Vec<DVec3> = singles.iter().map(|s| s.0).collect();
    let clusters = cluster_antipodal(&points, SETTLED_ON_SAME_ORBIT);
    let refined: Vec<(
        crate::analysis::orbits::sphere_return_map::PeriodicOrbit,
        usize,
    )> = clusters
        .par_iter()
        .map(|&(centre, count)| {
            stopped(stop)?;
            let &(p, omega) = singles
                .iter()
                .find(|s| boundary_distance(s.0, centre) < SETTLED_ON_SAME_ORBIT)
                .unwrap_or(&(centre, DVec3::ZERO));
            refine(sphere, ramp, (p, omega))
                .map(|o| (o, count))
                .map_err(|source| StudyError::NoFixedPoint {
                    near: p.to_array(),
                    source,
                })
        })
        .collect::<Result<_, StudyError>>()?;
    // An undecided start that rolls near a neutral orbit, or whose crossings drift steadily
    // and slowly, is on a neutral motion: it attracts too slowly (or not at all) for its
    // crossings to repeat within the tolerance.
    let near_neutral: Vec<(
        bool,
        Option<crate::analysis::orbits::sphere_return_map::PeriodicOrbit>,
    )> = ends
        .par_iter()
        .map(|e| match e {
            StartEnd::Undecided(Undecided::NoRepeat { .. }, Some(last), drifting) => {
                stopped(stop)?;
                let orbit = refine(sphere, ramp, *last).ok().filter(|o| {
                    Stability::of(o.max_modulus, o.period, decide.t_cap) == Stability::Neutral
                });
                Ok((orbit.is_some() || drifting.is_some(), orbit))
            }
            _ => Ok((false, None)),
        })
        .collect::<Result<_, StudyError>>()?;
    let mut found: Vec<Seen> = Vec::new();
    for (orbit, count) in &refined {
        let stability = Stability::of(orbit.max_modulus, orbit.period, decide.t_cap);
        add_orbit(&mut found, orbit, *count, stability);
    }
    for orbit in near_neutral.iter().filter_map(|n| n.1.as_ref()) {
        add_orbit(&mut found, orbit, 1, Stability::Neutral);
    }
    // A drifting start without an orbit of its own joins the neutral family of its period.
    for (e, n) in ends.iter().zip(&near_neutral) {
        if let (StartEnd::Undecided(_, _, Some(period)), (true, None)) = (e, n)
            && let Some(f) = found.iter_mut().find(|f| {
                f.stability == Stability::Neutral && (f.period - period).abs() < 0.01 * period
            })
        {
            f.starts += 1;
        }
    }
    // Period 2: runs on the same 2-cycle share one of its two crossing points.
    for e in &ends {
        let StartEnd::Cycle {
            k: 2,
            duration,
            last,
        } = e
        else {
            continue;
        };
        let same = found.iter_mut().find(|f| {
            f.repeat == 2
                && last
                    .iter()
                    .any(|(p, _)| boundary_distance(f.point, *p) < SETTLED_ON_SAME_ORBIT)
        });
        match same {
            Some(f) => f.starts += 1,
            None => found.push(Seen {
                point: last[1].0,
                omega: last[1].1,
                period: *duration,
                starts: 1,
                repeat: 2,
                multipliers: Vec::new(),
                max_modulus: f64::NAN,
                stability: Stability::Stable,
                members: 1,
            }),
        }
    }
    // Each start's fate; a period-1 start takes its orbit's stability.
    let fates: Vec<Fate> = ends
        .iter()
        .zip(&near_neutral)
        .map(|(e, neutral)| match e {
            StartEnd::Rest(t) => Fate::Halted { t: Some(*t) },
            StartEnd::LeftModel(violation) => Fate::LeftModel {
                violation: *violation,
            },
            StartEnd::Undecided(why, ..) => {
                if neutral.0 {
                    Fate::Neutral
                } else {
                    Fate::Undecided { why: *why }
                }
            }
            StartEnd::Cycle { k: 1, last, .. } => {
                // Its cluster's refined orbit (the same test that grouped it).
                let orbit = clusters.iter().zip(&refined).find(|((centre, _), _)| {
                    boundary_distance(*centre, last[0].0) < SETTLED_ON_SAME_ORBIT
                });
                match orbit.map(|(_, (o, _))| Stability::of(o.max_modulus, o.period, decide.t_cap))
                {
                    Some(Stability::Neutral) => Fate::Neutral,
                    _ => Fate::Periodic { multiplicity: 1 },
                }
            }
            StartEnd::Cycle { k, .. } => Fate::Periodic { multiplicity: *k },
        })
        .collect();
    let mut orbits: Vec<PredictedOrbit> = found
        .into_par_iter()
        .map(|seen| {
            stopped(stop)?;
            let (path, contact) =
                sphere_path(sphere, ramp, seen.point, seen.omega, seen.period, options)?;
            let per = options.samples_per_period;
            let (down, across) = (path[per][0] - path[0][0], path[per][1] - path[0][1]);
            let modulus = (seen.repeat == 1).then_some(seen.max_modulus);
            let leaves = contact.as_ref().and_then(|c| c.lift_off_t);
            Ok(PredictedOrbit {
                period: seen.period,
                repeat: seen.repeat,
                advance_down: down,
                advance_across: across,
                speed: down / seen.period,
                stable: seen.stability == Stability::Stable && leaves.is_none(),
                stability: seen.stability,
                members: seen.members,
                multipliers: seen.multipliers,
                max_modulus: modulus,
                fraction: seen.starts as f64 / options.starts as f64,
                starts: seen.starts,
                crossing: Some(seen.point.to_array()),
                omega: Some(seen.omega.to_array()),
                contact: contact.map(OrbitContact::from),
                path,
            })
        })
        .collect::<Result<_, StudyError>>()?;
    orbits.sort_by(|a, b| b.starts.cmp(&a.starts).then(a.period.total_cmp(&b.period)));
    Ok((orbits, fates))
}

/// The centre's (down, across) from the crossing (p, ω) over `periods_drawn` repeats of
/// `period`, relative to its start; with inertia, the contact force along it (watched on each
/// step's dense output).
fn sphere_path(
    sphere: &Sphere,
    ramp: &Ramp,
    p: DVec3,
    omega: DVec3,
    period: f64,
    options: &PredictOptions,
) -> Result<(Vec<[f64; 2]>, Option<ContactReport>), StudyError> {
    // On ∂Ω the rotation is by π about p: q = (0, p).
    let q0 = DQuat::from_xyzw(p.x, p.y, p.z, 0.0).normalize();
    let n = options.periods_drawn * options.samples_per_period;
    let times: Vec<f64> = (0..=n)
        .map(|i| period * i as f64 / options.samples_per_period as f64)
        .collect();
    let method = Method::dop853(1e-10);
    let (path, contact) = match ModelKind::for_dimension(3, ramp) {
        ModelKind::SphereViscous => {
            let m = SphereViscous::new(sphere, ramp);
            let run = Run::new(&m, 0.0, SphereViscous::initial_state(q0), method)?;
            (sample(run, &times, |y| [y[4], y[5]], |_| {})?, None)
        }
        ModelKind::SphereInertial => {
            let m = SphereInertial::new(sphere, ramp);
            let y0 = SphereInertial::initial_state(q0, omega);
            let mut watch = ContactWatch::new(ContactLimits::default(), 0.0, m.contact_force(&y0));
            let run = Run::new(&m, 0.0, y0, method)?;
            let path = sample(
                run,
                &times,
                |y| [y[7], y[8]],
                |st| {
                    let at = (st.t(), *st.y());
                    watch.step_along(st, at, |y| m.contact_force(y));
                },
            )?;
            (path, Some(watch.report()))
        }
        other @ (ModelKind::DiskViscous | ModelKind::DiskInertial) => other.wrong_dimension(3),
    };
    let start = path[0];
    Ok((
        path.into_iter()
            .map(|c| [c[0] - start[0], c[1] - start[1]])
            .collect(),
        contact,
    ))
}

/// `pick` of the state at each of `times` (increasing, from the run's start), from the dense
/// output; `on_step` sees each step (an observer: it must not move the stepper).
fn sample<const N: usize>(
    mut run: Run<'_, N>,
    times: &[f64],
    pick: impl Fn(&[f64; N]) -> [f64; 2],
    mut on_step: impl FnMut(&mut dyn integrate::Stepper<N>),
) -> Result<Vec<[f64; 2]>, StudyError> {
    let mut out = Vec::with_capacity(times.len());
    let mut samples = Samples::new(times);
    samples.take_at_start(&run, |_, y| out.push(pick(y)));
    if !samples.done() {
        let end = times.last().copied().unwrap_or(0.0);
        run.until::<StudyError>(end, u64::MAX, |st| {
            on_step(st);
            samples.take(st, |_, y| out.push(pick(y)));
            Ok(if samples.done() {
                Flow::Stop
            } else {
                Flow::Continue
            })
        })?;
    }
    Ok(out)
}

/// A disk's prediction: the starts' fates, then the one rolling cycle's period, perimeter and
/// path.
fn predict_disk(
    disk: &Disk,
    ramp: &Ramp,
    options: &PredictOptions,
    stop: &AtomicBool,
) -> Result<(Vec<PredictedOrbit>, Vec<Fate>), StudyError> {
    const RTOL: f64 = 1e-10;
    let t_cap = options.decide.t_cap;
    let alpha_star = critical_angle(&Body::Disk(disk.clone())).alpha_star;
    let is_periodic = |f: &Fate| matches!(f, Fate::Periodic { .. });
    // Each start's fate, with its period when it rolls.
    let ends: Vec<(Fate, Option<f64>)> = match ModelKind::for_dimension(2, ramp) {
        ModelKind::DiskViscous => {
            // The viscous disk's fate does not depend on where it starts.
            let p = viscous_disk_period(disk, ramp);
            let fate = p.fate(ramp.alpha_rad - alpha_star, t_cap);
            vec![(fate, p.period.filter(|_| is_periodic(&fate))); options.starts]
        }
        ModelKind::DiskInertial if let Some(why) = inertial_on_hull(disk) => {
            return Err(StudyError::BadArgument(why));
        }
        ModelKind::DiskInertial => (0..options.starts)
            .into_par_iter()
            .map(|i| {
                let theta0 = std::f64::consts::TAU * i as f64 / options.starts as f64;
                let p = inertial_disk_period_until(disk, ramp, theta0, 0.0, RTOL, t_cap, stop)?
                    .ok_or(StudyError::Stopped)?;
                let fate = p.fate(ramp.alpha_rad - alpha_star, t_cap);
                Ok((fate, p.period.filter(|_| is_periodic(&fate))))
            })
            .collect::<Result<_, StudyError>>()?,
        other @ (ModelKind::SphereViscous | ModelKind::SphereInertial) => other.wrong_dimension(2),
    };
    let fates: Vec<Fate> = ends.iter().map(|e| e.0).collect();
    let rolling: Vec<f64> = ends.iter().filter_map(|e| e.1).collect();
    if rolling.is_empty() {
        return Ok((Vec::new(), fates));
    }
    // Every rolling start is on the same cycle (the disk's phase space is a cylinder with one
    // rolling orbit at most at this α; shown by the periods agreeing).
    let period = match ModelKind::for_dimension(2, ramp) {
        ModelKind::DiskViscous => rolling[0],
        ModelKind::DiskInertial => rolling.iter().sum::<f64>() / rolling.len() as f64,
        other @ (ModelKind::SphereViscous | ModelKind::SphereInertial) => other.wrong_dimension(2),
    };
    let perimeter = disk_perimeter(disk);
    let per = options.samples_per_period;
    let n = options.periods_drawn * per;
    // x_c(θ) = ∫ arc rate dθ; rolling downhill θ increases (θ̇ = sin α on the perfect disk).
    let step = std::f64::consts::TAU / per as f64;
    let mut path = Vec::with_capacity(n + 1);
    let mut x_c = 0.0;
    let mut previous = None;
    for i in 0..=n {
        let theta = i as f64 * step;
        if let Some(prev) = previous {
            x_c += simpson_arc(disk, theta, prev);
        }
        previous = Some(theta);
        let pose = disk2d::pose(disk, theta, x_c);
        path.push([pose.x, pose.y]);
    }
    let start = path[0][0];
    for p in &mut path {
        p[0] -= start;
    }
    let orbit = PredictedOrbit {
        period,
        repeat: 1,
        advance_down: perimeter,
        advance_across: 0.0,
        speed: perimeter / period,
        stable: true,
        stability: Stability::Stable,
        members: 1,
        multipliers: Vec::new(),
        max_modulus: None,
        fraction: rolling.len() as f64 / options.starts as f64,
        starts: rolling.len(),
        crossing: None,
        omega: None,
        contact: None,
        path,
    };
    Ok((vec![orbit], fates))
}

/// The arc of the body's boundary between contact angles `a` and `b` (Simpson's rule on 16
/// panels: exact to round-off for the few-mode bodies here).
fn simpson_arc(disk: &Disk, a: f64, b: f64) -> f64 {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    let n = 16;
    let h = (hi - lo) / n as f64;
    let f = |t: f64| disk.jet(t).arc_rate();
    let mut s = f(lo) + f(hi);
    for i in 1..n {
        s += f(lo + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

/// The perimeter of a disk's cross-section, ∫ √(r² + r′²) dθ over a turn: what its centre
/// advances per turn rolling without slip. A body that rolls on its hull advances by the
/// hull's perimeter: its curved parts' arcs and its flats' lengths.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::prediction::disk_perimeter;
/// use rollphase_core::geometry::Disk;
/// use rollphase_core::geometry::facets::PrintedSection;
/// assert!((disk_perimeter(&Disk::perfect()) - std::f64::consts::TAU).abs() < 1e-14);
/// // A square print of side 2: 8, less its corners' rounding ρ (8ρ − 2πρ).
/// let square = PrintedSection { vertices: vec![[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]] };
/// let print = Disk::perfect().with_printed_section(Some(square));
/// let rho = rollphase_core::geometry::outline::CORNER_RADIUS;
/// assert!((disk_perimeter(&print) - (8.0 - 8.0 * rho + std::f64::consts::TAU * rho)).abs() < 1e-10);
/// ```
pub fn disk_perimeter(disk: &Disk) -> f64 {
    if let Some(parts) = crate::analysis::orbits::disk_period::curved_parts(disk) {
        let arc = |t: f64| disk.jet(t).arc_rate();
        let curved: f64 = parts
            .iter()
            .map(|&(a, b)| {
                crate::numeric::quadrature::integrate_adaptive(&arc, a, b, 1e-13, 100_000).value
            })
            .sum();
        return curved + disk.hull().bridges().iter().map(|b| b.length).sum::<f64>();
    }
    // The trapezoidal rule on equally spaced angles is spectrally accurate for a periodic
    // integrand.
    let n = 4096;
    let h = std::f64::consts::TAU / n as f64;
    (0..n)
        .map(|i| disk.jet(i as f64 * h).arc_rate())
        .sum::<f64>()
        * h
}
