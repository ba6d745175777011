//! The price of accuracy measured on the *answers*: for each integrator setting, over many
//! starts of the paper's 3D body, whether its fate (halt, cycle, undecided), period multiplicity
//! and period agree with the reference's, and how many distinct orbits (attractors) it finds.
//! A trajectory error says little about these: RK4 at a step of 0.8 keeps the state error small
//! and still gets every fate at m/m0 = 6 wrong.
//!
//! Each setting is measured twice: *raw* ([`settle_with`], the setting's own answer) and
//! *checked* ([`settle_checked`], the answer `rollphase sweep` reports, re-decided by the
//! reference where the setting is coarser). `rollphase bench accuracy` prints the table.

use rayon::prelude::*;
use serde::Serialize;

use crate::analysis::orbits::sphere_orbits::{
    Settle, Settlement, same_answer, settle_checked, settle_with,
};
use crate::analysis::studies::sphere::random_orientation;
use crate::dynamics::{ModelError, Ramp};
use crate::geometry::Sphere;
use crate::integrate::{IntegrateError, Method};

/// One question asked of every setting: a body on a ramp, released from rest at
/// `orientations` random orientations ([`random_orientation`] with seed 1), settled by `settle`.
#[derive(Debug, Clone)]
pub struct AnswerCase {
    /// A short name ("viscous α = 0.15").
    pub name: String,
    /// The body.
    pub body: Sphere,
    /// Tilt and mass.
    pub ramp: Ramp,
    /// Starts.
    pub orientations: usize,
    /// When a fate is decided.
    pub settle: Settle,
}

/// The reference integrator of the answer table: DOP853 at rtol 1e-12 (the `precise` preset).
pub const ANSWER_REFERENCE: Method = Method::Dop853 {
    rtol: 1e-12,
    atol: 1e-12,
};

/// The paper's questions (SI §2F–2G), on `body` (the paper's sphere, seed 219): the viscous
/// model at α = 0.15 (Fig. 4e, two stable orbits) and 0.2, and the inertial one at α = 0.2,
/// m/m0 = 6 (near the period doubling), each decided as `rollphase sweep` decides (t_max 1500,
/// cycles up to 4 crossings, points and periods to 1e-5).
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::answers::paper_answer_cases;
/// use rollphase_core::geometry::Body;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let cases = paper_answer_cases(&s, 4)?;
/// assert_eq!(cases.len(), 3);
/// assert_eq!(cases[2].ramp.mass_ratio, 6.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn paper_answer_cases(
    body: &Sphere,
    orientations: usize,
) -> Result<Vec<AnswerCase>, ModelError> {
    let settle = Settle {
        t_max: 1500.0,
        point_tol: 1e-5,
        period_rtol: 1e-5,
        max_k: 4,
        ..Settle::default()
    };
    let case = |name: &str, alpha, mass| -> Result<AnswerCase, ModelError> {
        Ok(AnswerCase {
            name: name.into(),
            body: body.clone(),
            ramp: Ramp::new(alpha, mass)?,
            orientations,
            settle,
        })
    };
    Ok(vec![
        case("viscous α = 0.15", 0.15, 0.0)?,
        case("viscous α = 0.2", 0.2, 0.0)?,
        case("m/m0 = 6, α = 0.2", 0.2, 6.0)?,
    ])
}

/// The settings the answer table tries on the 3D models: fixed steps from 0.8 (the coarsest
/// the step's own check lets through on the paper's body) down, and DOP853 tolerances.
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::answers::answer_settings;
/// use rollphase_core::integrate::Method;
/// assert!(answer_settings().contains(&Method::Rk4 { dt: 0.5 }));
/// ```
pub fn answer_settings() -> Vec<Method> {
    let mut v = Vec::new();
    for dt in [0.8, 0.5, 0.4, 0.2, 0.1] {
        v.push(Method::Rk4 { dt });
    }
    for dt in [0.8, 0.5, 0.4, 0.2] {
        v.push(Method::Cf4 { dt });
    }
    for rtol in [1e-4, 1e-6, 1e-8, 1e-10] {
        v.push(Method::dop853(rtol));
    }
    v
}

/// One setting's answers on one case, against the reference's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnswerRow {
    /// The case's name.
    pub case: String,
    /// The setting, as the sweep spec names it (`rk4:0.5`, `dop853:1e-8`).
    pub setting: String,
    /// Starts.
    pub runs: usize,
    /// Raw: runs whose fate kind (halt, cycle, undecided) is the reference's.
    pub raw_fate: usize,
    /// Raw: runs whose whole answer (kind, multiplicity, period to the settle tolerance) is
    /// the reference's.
    pub raw_answer: usize,
    /// Raw: distinct orbits found (cycles told apart by multiplicity and period).
    pub raw_orbits: usize,
    /// Raw: right-hand-side evaluations, all runs.
    pub raw_rhs_evals: u64,
    /// Checked: runs whose whole answer is the reference's.
    pub checked_answer: usize,
    /// Checked: distinct orbits found.
    pub checked_orbits: usize,
    /// Checked: right-hand-side evaluations, all runs (re-decisions included).
    pub checked_rhs_evals: u64,
    /// The reference's distinct orbits.
    pub reference_orbits: usize,
}

impl AnswerRow {
    /// Whether the setting's own answers are all the reference's (it keeps the paper's
    /// answers without checking).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::accuracy::answers::AnswerRow;
    /// let row = AnswerRow {
    ///     case: "c".into(), setting: "rk4:0.5".into(), runs: 4, raw_fate: 4, raw_answer: 3,
    ///     raw_orbits: 2, raw_rhs_evals: 10, checked_answer: 4, checked_orbits: 1,
    ///     checked_rhs_evals: 20, reference_orbits: 1,
    /// };
    /// assert!(!row.keeps_answers());
    /// ```
    pub fn keeps_answers(&self) -> bool {
        self.raw_answer == self.runs && self.raw_orbits == self.reference_orbits
    }
}

/// The name a sweep spec gives `method`: `rk4:0.5`, `cf4:0.2`, `dop853:1e-8`.
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::answers::spec_name;
/// use rollphase_core::integrate::Method;
/// assert_eq!(spec_name(Method::Rk4 { dt: 0.5 }), "rk4:0.5");
/// assert_eq!(spec_name(Method::dop853(1e-8)), "dop853:1e-8");
/// ```
pub fn spec_name(method: Method) -> String {
    match method {
        Method::Rk4 { dt } => format!("rk4:{dt}"),
        Method::Cf4 { dt } => format!("cf4:{dt}"),
        Method::Dop853 { rtol, .. } => format!("dop853:{rtol:e}"),
    }
}

/// Distinct orbits among fates: cycles whose multiplicity is equal and whose periods agree to
/// `rtol` are one orbit (a halt or an undecided run is none).
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::answers::distinct_orbits;
/// use rollphase_core::analysis::orbits::sphere_orbits::Settlement;
/// let cycle = |period, k| Settlement::Periodic { period, k, point: [1.0, 0.0, 0.0], t: 0.0 };
/// let fates = [cycle(37.98, 1), cycle(37.9800001, 1), cycle(37.11, 1), Settlement::Halts { t: 1.0 }];
/// assert_eq!(distinct_orbits(&fates, 1e-5), 2);
/// ```
pub fn distinct_orbits(fates: &[Settlement], rtol: f64) -> usize {
    let mut orbits: Vec<&Settlement> = Vec::new();
    for f in fates {
        if matches!(f, Settlement::Periodic { .. })
            && !orbits.iter().any(|o| same_answer(o, f, rtol))
        {
            orbits.push(f);
        }
    }
    orbits.len()
}

/// The reference's fates on `case` (one per start, in parallel).
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::answers::{paper_answer_cases, reference_fates};
/// use rollphase_core::analysis::orbits::sphere_orbits::Settlement;
/// use rollphase_core::geometry::Body;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let case = &paper_answer_cases(&s, 1)?[1];
/// let fates = reference_fates(case)?;
/// assert!(matches!(fates[0], Settlement::Periodic { k: 1, .. }));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn reference_fates(case: &AnswerCase) -> Result<Vec<Settlement>, IntegrateError> {
    (0..case.orientations)
        .into_par_iter()
        .map(|o| {
            let q0 = random_orientation(&case.body, 1, o);
            settle_with(&case.body, &case.ramp, q0, &case.settle, ANSWER_REFERENCE).map(|r| r.0)
        })
        .collect()
}

/// One setting's row on `case`, given the reference's fates ([`reference_fates`]).
///
/// # Example
/// ```
/// use rollphase_core::analysis::accuracy::answers::{answer_row, paper_answer_cases, reference_fates};
/// use rollphase_core::geometry::Body;
/// use rollphase_core::integrate::Method;
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let case = &paper_answer_cases(&s, 2)?[2]; // m/m0 = 6, α = 0.2
/// let reference = reference_fates(case)?;
/// let row = answer_row(case, Method::Rk4 { dt: 0.8 }, &reference)?;
/// // The step's own answers are wrong; checked, none is left.
/// assert!(!row.keeps_answers());
/// assert_eq!(row.checked_answer, row.runs);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn answer_row(
    case: &AnswerCase,
    method: Method,
    reference: &[Settlement],
) -> Result<AnswerRow, IntegrateError> {
    let tol = case.settle.period_rtol;
    let runs: Vec<(Settlement, u64, Settlement, u64)> = (0..case.orientations)
        .into_par_iter()
        .map(|o| {
            let q0 = random_orientation(&case.body, 1, o);
            let (raw, _, raw_stats) =
                settle_with(&case.body, &case.ramp, q0, &case.settle, method)?;
            let checked = settle_checked(&case.body, &case.ramp, q0, &case.settle, method)?;
            Ok((
                raw,
                raw_stats.rhs_evals,
                checked.fate,
                checked.stats.rhs_evals,
            ))
        })
        .collect::<Result<_, IntegrateError>>()?;
    let kind = |f: &Settlement| std::mem::discriminant(f);
    let raw: Vec<Settlement> = runs.iter().map(|r| r.0.clone()).collect();
    let checked: Vec<Settlement> = runs.iter().map(|r| r.2.clone()).collect();
    let agree = |fates: &[Settlement]| {
        fates
            .iter()
            .zip(reference)
            .filter(|(f, r)| same_answer(f, r, tol))
            .count()
    };
    Ok(AnswerRow {
        case: case.name.clone(),
        setting: spec_name(method),
        runs: case.orientations,
        raw_fate: raw
            .iter()
            .zip(reference)
            .filter(|(f, r)| kind(f) == kind(r))
            .count(),
        raw_answer: agree(&raw),
        raw_orbits: distinct_orbits(&raw, tol),
        raw_rhs_evals: runs.iter().map(|r| r.1).sum(),
        checked_answer: agree(&checked),
        checked_orbits: distinct_orbits(&checked, tol),
        checked_rhs_evals: runs.iter().map(|r| r.3).sum(),
        reference_orbits: distinct_orbits(reference, tol),
    })
}
