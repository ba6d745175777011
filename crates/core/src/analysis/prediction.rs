//! What a body does on a ramp, in the lab's terms: the stable periodic motions it settles into
//! from many starts (the fraction of starts that reach each), each with its period, how far its
//! centre moves down and across the ramp per period (per repeat for a doubled orbit), its Floquet
//! multipliers, and the centre's path over a few periods (drawn from above by `predict`).
//!
//! 3D: runs from rest at random orientations ([`super::studies::random_orientation`]) go on
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

use super::critical_angle::critical_angle;
use super::period::{inertial_disk_period_until, viscous_disk_period};
use super::sphere_orbits::{
    Decide, RunEnd, boundary_distance, cluster_antipodal, decided_run, settled_cycle,
};
use super::sphere_return_map::{
    OrbitSolve, SectionState, inertial_crossings_until, periodic_orbit, viscous_periodic_orbit,
};
use super::studies::{StudyError, random_orientation};
use crate::dynamics::sphere3d::{SphereInertial, SphereViscous};
use crate::dynamics::{Ramp, disk2d};
use crate::geometry::{Body, Disk, Sphere};
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
    /// Whether it attracts: every Floquet multiplier inside the unit circle (period 1), or seen
    /// to attract runs (a doubled orbit, whose multipliers are not computed).
    pub stable: bool,
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
    /// The centre's path from a point of the orbit over [`PredictOptions::periods_drawn`]
    /// repeats: (down, across) in ⟨r⟩ for a sphere, (down, height) for a disk.
    #[serde(skip)]
    pub path: Vec<[f64; 2]>,
}

/// What a body does at one α and m/m0.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Prediction {
    /// 2 or 3.
    pub dimension: u32,
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
    /// The stable periodic motions, most visited first.
    pub orbits: Vec<PredictedOrbit>,
}

/// Most starts a prediction runs.
pub const MAX_PREDICT_STARTS: usize = 100_000;

/// The stable periodic motions of `body` at ramp angle `alpha` and `mass_ratio` (0: viscous).
///
/// # Example
/// ```
/// use rollphase_core::analysis::prediction::{PredictOptions, predict};
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
/// use rollphase_core::analysis::prediction::{PredictOptions, predict_until};
/// use rollphase_core::analysis::studies::StudyError;
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
    let ramp = Ramp::new(alpha, mass_ratio)?;
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
    let (orbits, halts, undecided) = match body {
        Body::Disk(disk) => predict_disk(disk, &ramp, options, stop)?,
        Body::Sphere(sphere) => predict_sphere(sphere, &ramp, options, stop)?,
    };
    let n = options.starts as f64;
    Ok(Prediction {
        dimension: body.dimension(),
        alpha,
        mass_ratio,
        alpha_star,
        starts: options.starts,
        halts: halts as f64 / n,
        undecided: undecided as f64 / n,
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
}

/// How one start ended.
#[derive(Debug, Clone)]
enum StartEnd {
    Rest,
    Undecided,
    /// A cycle of `k` crossings lasting `duration`; the last crossings (point, ω), newest last.
    Cycle {
        k: usize,
        duration: f64,
        last: Vec<(DVec3, DVec3)>,
    },
}

#[expect(
    clippy::too_many_lines,
    reason = "the runs from every start, the grouping of their cycles into orbits (period 1 \
              refined by Newton, period 2 as seen) and each orbit's advance are one computation \
              that shares the ramp, the model and the options"
)]
fn predict_sphere(
    sphere: &Sphere,
    ramp: &Ramp,
    options: &PredictOptions,
    stop: &AtomicBool,
) -> Result<(Vec<PredictedOrbit>, usize, usize), StudyError> {
    const RTOL: f64 = 1e-9;
    let decide = Decide {
        max_k: 2,
        ..options.decide
    };
    let ends: Vec<StartEnd> = (0..options.starts)
        .into_par_iter()
        .map(|o| {
            stopped(stop)?;
            let q0 = random_orientation(sphere, options.seed, o);
            if ramp.is_viscous() {
                let r = decided_run(sphere, ramp, q0, &decide, (0.0, 0.0, 0), RTOL)?;
                Ok(match (r.end, r.cycle) {
                    (RunEnd::Periodic, Some((k, duration))) => StartEnd::Cycle {
                        k,
                        duration,
                        last: r.crossings[r.crossings.len() - k..]
                            .iter()
                            .map(|c| (DVec3::from_array(c.point), DVec3::ZERO))
                            .collect(),
                    },
                    (RunEnd::Rest, _) => StartEnd::Rest,
                    _ => StartEnd::Undecided,
                })
            } else {
                let to_crossing = |c: &SectionState| super::sphere_orbits::Crossing {
                    t: c.t,
                    point: c.point,
                };
                let (s, t_end) = inertial_crossings_until(
                    sphere,
                    ramp,
                    q0,
                    DVec3::ZERO,
                    (decide.t_min, decide.t_cap),
                    RTOL,
                    |s| {
                        let c: Vec<_> = s.iter().map(to_crossing).collect();
                        settled_cycle(&c, decide.max_k, decide.tol).is_some()
                    },
                )?;
                let c: Vec<_> = s.iter().map(to_crossing).collect();
                Ok(match settled_cycle(&c, decide.max_k, decide.tol) {
                    Some((k, duration)) => StartEnd::Cycle {
                        k,
                        duration,
                        last: s[s.len() - k..]
                            .iter()
                            .map(|c| (DVec3::from_array(c.point), DVec3::from_array(c.omega)))
                            .collect(),
                    },
                    None if t_end < decide.t_cap => StartEnd::Rest,
                    None => StartEnd::Undecided,
                })
            }
        })
        .collect::<Result<_, StudyError>>()?;
    let halts = ends.iter().filter(|e| matches!(e, StartEnd::Rest)).count();
    let undecided = ends
        .iter()
        .filter(|e| matches!(e, StartEnd::Undecided))
        .count();
    // Period 1: clusters of last crossings, each refined by Newton.
    let singles: Vec<(DVec3, DVec3)> = ends
        .iter()
        .filter_map(|e| match e {
            StartEnd::Cycle { k: 1, last, .. } => Some(last[0]),
            _ => None,
        })
        .collect();
    let points: Vec<DVec3> = singles.iter().map(|s| s.0).collect();
    let clusters = cluster_antipodal(&points, 1e-3);
    let solve = OrbitSolve::default();
    let refined: Vec<(super::sphere_return_map::PeriodicOrbit, usize)> = clusters
        .par_iter()
        .map(|&(centre, count)| {
            stopped(stop)?;
            let &(p, omega) = singles
                .iter()
                .find(|s| boundary_distance(s.0, centre) < 1e-3)
                .unwrap_or(&(centre, DVec3::ZERO));
            let orbit = if ramp.is_viscous() {
                viscous_periodic_orbit(sphere, ramp, p, &solve)
            } else {
                periodic_orbit(sphere, ramp, p, omega, &solve)
            };
            orbit
                .map(|o| (o, count))
                .map_err(|source| StudyError::NoFixedPoint {
                    near: p.to_array(),
                    source,
                })
        })
        .collect::<Result<_, StudyError>>()?;
    let mut found: Vec<Seen> = Vec::new();
    for (orbit, count) in refined {
        let p = DVec3::from_array(orbit.point);
        match found
            .iter_mut()
            .find(|f| f.repeat == 1 && boundary_distance(f.point, p) < 1e-6)
        {
            Some(same) => same.starts += count,
            None => found.push(Seen {
                point: p,
                omega: DVec3::from_array(orbit.omega),
                period: orbit.period,
                starts: count,
                repeat: 1,
                multipliers: orbit.multipliers.clone(),
                max_modulus: orbit.max_modulus,
            }),
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
                    .any(|(p, _)| boundary_distance(f.point, *p) < 1e-3)
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
            }),
        }
    }
    let mut orbits: Vec<PredictedOrbit> = found
        .into_par_iter()
        .map(
            |Seen {
                 point: p,
                 omega,
                 period,
                 starts: count,
                 repeat,
                 multipliers,
                 max_modulus,
             }| {
                stopped(stop)?;
                let path = sphere_path(sphere, ramp, p, omega, period, options)?;
                let per = options.samples_per_period;
                let (down, across) = (path[per][0] - path[0][0], path[per][1] - path[0][1]);
                let modulus = (repeat == 1).then_some(max_modulus);
                Ok(PredictedOrbit {
                    period,
                    repeat,
                    advance_down: down,
                    advance_across: across,
                    speed: down / period,
                    stable: modulus.is_none_or(|m| m < 1.0),
                    multipliers,
                    max_modulus: modulus,
                    fraction: count as f64 / options.starts as f64,
                    starts: count,
                    crossing: Some(p.to_array()),
                    omega: Some(omega.to_array()),
                    path,
                })
            },
        )
        .collect::<Result<_, StudyError>>()?;
    orbits.sort_by(|a, b| b.starts.cmp(&a.starts).then(a.period.total_cmp(&b.period)));
    Ok((orbits, halts, undecided))
}

/// The centre's (down, across) from the crossing (p, ω) over `periods_drawn` repeats of
/// `period`, relative to its start.
fn sphere_path(
    sphere: &Sphere,
    ramp: &Ramp,
    p: DVec3,
    omega: DVec3,
    period: f64,
    options: &PredictOptions,
) -> Result<Vec<[f64; 2]>, StudyError> {
    // On ∂Ω the rotation is by π about p: q = (0, p).
    let q0 = DQuat::from_xyzw(p.x, p.y, p.z, 0.0).normalize();
    let n = options.periods_drawn * options.samples_per_period;
    let times: Vec<f64> = (0..=n)
        .map(|i| period * i as f64 / options.samples_per_period as f64)
        .collect();
    let method = Method::dop853(1e-10);
    let path = if ramp.is_viscous() {
        let m = SphereViscous::new(sphere, ramp);
        let mut st = integrate::stepper(&m, 0.0, SphereViscous::initial_state(q0), method)?;
        sample(st.as_mut(), &times, |y| [y[4], y[5]])?
    } else {
        let m = SphereInertial::new(sphere, ramp);
        let mut st = integrate::stepper(&m, 0.0, SphereInertial::initial_state(q0, omega), method)?;
        sample(st.as_mut(), &times, |y| [y[7], y[8]])?
    };
    let start = path[0];
    Ok(path
        .into_iter()
        .map(|c| [c[0] - start[0], c[1] - start[1]])
        .collect())
}

/// `pick` of the state at each of `times` (increasing, from the stepper's start), from the
/// dense output.
fn sample<const N: usize>(
    st: &mut dyn integrate::Stepper<N>,
    times: &[f64],
    pick: impl Fn(&[f64; N]) -> [f64; 2],
) -> Result<Vec<[f64; 2]>, StudyError> {
    let mut out = Vec::with_capacity(times.len());
    let end = times.last().copied().unwrap_or(0.0);
    let mut next = 0;
    while next < times.len() {
        while next < times.len() && times[next] <= st.t() {
            let y = if times[next] == st.t() {
                *st.y()
            } else {
                st.dense(times[next])
            };
            out.push(pick(&y));
            next += 1;
        }
        if next < times.len() {
            st.step(end)?;
        }
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
) -> Result<(Vec<PredictedOrbit>, usize, usize), StudyError> {
    const RTOL: f64 = 1e-10;
    // Each start's period (None: it halts; Err: undecided at the cap).
    let periods: Vec<Option<Option<f64>>> = if ramp.is_viscous() {
        // The viscous disk's fate does not depend on where it starts.
        let p = viscous_disk_period(disk, ramp);
        vec![
            if p.halts {
                Some(None)
            } else {
                p.period.map(Some)
            };
            options.starts
        ]
    } else {
        (0..options.starts)
            .into_par_iter()
            .map(|i| {
                let theta0 = std::f64::consts::TAU * i as f64 / options.starts as f64;
                let p = inertial_disk_period_until(
                    disk,
                    ramp,
                    theta0,
                    0.0,
                    RTOL,
                    options.decide.t_cap,
                    stop,
                )?
                .ok_or(StudyError::Stopped)?;
                Ok(if p.halts {
                    Some(None)
                } else if p.converged {
                    p.period.map(Some)
                } else {
                    None
                })
            })
            .collect::<Result<_, StudyError>>()?
    };
    let halts = periods.iter().filter(|p| matches!(p, Some(None))).count();
    let undecided = periods.iter().filter(|p| p.is_none()).count();
    let rolling: Vec<f64> = periods.iter().filter_map(|p| p.flatten()).collect();
    if rolling.is_empty() {
        return Ok((Vec::new(), halts, undecided));
    }
    // Every rolling start is on the same cycle (the disk's phase space is a cylinder with one
    // rolling orbit at most at this α; shown by the periods agreeing).
    let period = if ramp.is_viscous() {
        rolling[0]
    } else {
        rolling.iter().sum::<f64>() / rolling.len() as f64
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
        multipliers: Vec::new(),
        max_modulus: None,
        fraction: rolling.len() as f64 / options.starts as f64,
        starts: rolling.len(),
        crossing: None,
        omega: None,
        path,
    };
    Ok((vec![orbit], halts, undecided))
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
/// advances per turn rolling without slip.
///
/// # Example
/// ```
/// use rollphase_core::analysis::prediction::disk_perimeter;
/// use rollphase_core::geometry::Disk;
/// assert!((disk_perimeter(&Disk::perfect()) - std::f64::consts::TAU).abs() < 1e-14);
/// ```
pub fn disk_perimeter(disk: &Disk) -> f64 {
    // The trapezoidal rule on equally spaced angles is spectrally accurate for a periodic
    // integrand.
    let n = 4096;
    let h = std::f64::consts::TAU / n as f64;
    (0..n)
        .map(|i| disk.jet(i as f64 * h).arc_rate())
        .sum::<f64>()
        * h
}
