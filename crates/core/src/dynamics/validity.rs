//! Where a run leaves the model's assumptions: every model assumes the body stays on the ramp
//! (normal force N > 0) and rolls without slipping (the friction it needs, |f_t|/N, within what
//! the surface gives). [`ContactWatch`] follows the exact contact force
//! ([`crate::dynamics::ContactForce`]) along a run and reports its extremes and the first time
//! either assumption fails ([`ContactReport`]); the caller's [`ContactLimits`] say whether a
//! failure stops the run ([`OnViolation::Stop`]) or is reported as a warning.
//!
//! The force is evaluated once a step, at its end. Between two step ends a quantity can dip
//! below both by at most |q''| h²/8 (h the step, q'' its second derivative, estimated from the
//! last three ends); only a step where that could beat the run's extreme so far (with a
//! safety factor of 4) is searched, by golden section on the step's dense output, and a sign
//! change of N or of μ_req − μ is located by Brent's method. So the extremes and the first
//! times do not depend on where the integrator stepped, and a run pays one force evaluation a
//! step plus a search or two per period of its motion (measured in the issue 34 note).

use serde::Serialize;

use super::ContactForce;
use crate::integrate::Stepper;
use crate::numeric::optimize::golden_max;
use crate::numeric::roots::brent;

/// What a run does when the motion stops being rollable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum OnViolation {
    /// Go on, and say so in the summary and on standard error.
    #[default]
    Warn,
    /// Stop there with an error naming the time and the force.
    Stop,
}

/// The surface a run is checked against.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactLimits {
    /// The coefficient of static friction μ of the surface; `None`: slip is not checked (the
    /// friction needed is still reported).
    pub friction: Option<f64>,
    /// What a violation does.
    pub on_violation: OnViolation,
}

impl ContactLimits {
    /// Checks μ: finite and ≥ 0.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::simulate::ContactLimits;
    /// let ok = ContactLimits { friction: Some(0.5), ..ContactLimits::default() };
    /// assert!(ok.validate().is_ok());
    /// let bad = ContactLimits { friction: Some(f64::NAN), ..ContactLimits::default() };
    /// assert!(bad.validate().unwrap_err().contains("friction"));
    /// ```
    pub fn validate(&self) -> Result<(), String> {
        match self.friction {
            Some(mu) if !(mu.is_finite() && mu >= 0.0) => Err(format!(
                "friction mu = {} is not allowed (needs a finite coefficient of static friction \
                 mu ≥ 0; rubber on wood is about 0.5 to 1)",
                crate::integrate::readable(mu)
            )),
            _ => Ok(()),
        }
    }
}

/// The first time a run stopped being rollable.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Violation {
    /// N fell to 0: the body leaves the ramp.
    LiftOff {
        /// When.
        t: f64,
    },
    /// The friction needed exceeded the surface's μ: the body slips.
    Slip {
        /// When.
        t: f64,
        /// The surface's μ.
        friction: f64,
        /// The largest friction the run needs (over the whole run when it went on, so far when
        /// it stopped).
        needed: f64,
    },
}

impl Violation {
    /// When it happened.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::simulate::Violation;
    /// assert_eq!(Violation::LiftOff { t: 20.2 }.t(), 20.2);
    /// ```
    pub fn t(&self) -> f64 {
        match self {
            Violation::LiftOff { t } | Violation::Slip { t, .. } => *t,
        }
    }

    /// One sentence for the warnings and errors: [`Self::headline`] and what it means for the
    /// numbers after it.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::validity::Violation;
    /// let v = Violation::Slip { t: 3.0, friction: 0.5, needed: 1.374 };
    /// assert!(v.describe().contains("needs μ ≥ 1.374"));
    /// assert!(v.describe().ends_with("the rolling model does not hold after it"));
    /// ```
    pub fn describe(&self) -> String {
        format!(
            "{}; the rolling model does not hold after it",
            self.headline()
        )
    }

    /// One short line, as the app's overlay says it: "leaves the ramp at t = 20.2 (N falls to
    /// 0)" or "slips at t = 3.1: needs μ ≥ 1.37 to roll without slipping (surface μ = 0.5)".
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::validity::Violation;
    /// let v = Violation::LiftOff { t: 20.207 };
    /// assert_eq!(
    ///     v.headline(),
    ///     "leaves the ramp at t = 20.207 (the normal force falls to 0: the ramp would have to pull)"
    /// );
    /// ```
    pub fn headline(&self) -> String {
        match self {
            Violation::LiftOff { t } => format!(
                "leaves the ramp at t = {} (the normal force falls to 0: the ramp would have to \
                 pull)",
                short(*t)
            ),
            Violation::Slip {
                t,
                friction,
                needed,
            } if needed.is_finite() => format!(
                "slips at t = {}: needs μ ≥ {} to roll without slipping (surface μ = {})",
                short(*t),
                short(*needed),
                short(*friction)
            ),
            // Once the body has gone on to leave the ramp, the friction needed grew without bound.
            Violation::Slip { t, friction, .. } => format!(
                "slips at t = {}: needs more than the surface's μ = {} (and later leaves the ramp)",
                short(*t),
                short(*friction)
            ),
        }
    }
}

fn short(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

/// The contact force over a run, in units of the weight F.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactReport {
    /// min N/F.
    pub min_normal_force: f64,
    /// max N/F.
    pub max_normal_force: f64,
    /// max |f_t|/N over the times N > 0 (infinite once N ≤ 0).
    pub max_friction_needed: f64,
    /// The first time N ≤ 0, if any.
    pub lift_off_t: Option<f64>,
    /// The first time the friction needed exceeded `friction`, if it did.
    pub slip_t: Option<f64>,
    /// The surface's μ checked against, if one was given.
    pub friction: Option<f64>,
}

impl ContactReport {
    /// This report followed by `later`'s (a run continued from where this one ended): the
    /// extremes of both, and the first times from this one where it has them.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::validity::ContactReport;
    /// let early = ContactReport {
    ///     min_normal_force: 0.9, max_normal_force: 1.1, max_friction_needed: 0.2,
    ///     lift_off_t: None, slip_t: None, friction: None,
    /// };
    /// let late = ContactReport { min_normal_force: -0.1, lift_off_t: Some(80.0), ..early };
    /// let both = early.merged(&late);
    /// assert_eq!((both.min_normal_force, both.lift_off_t), (-0.1, Some(80.0)));
    /// ```
    pub fn merged(&self, later: &ContactReport) -> ContactReport {
        ContactReport {
            min_normal_force: self.min_normal_force.min(later.min_normal_force),
            max_normal_force: self.max_normal_force.max(later.max_normal_force),
            max_friction_needed: self.max_friction_needed.max(later.max_friction_needed),
            lift_off_t: self.lift_off_t.or(later.lift_off_t),
            slip_t: self.slip_t.or(later.slip_t),
            friction: self.friction,
        }
    }

    /// The violations, first first: lift-off and slip (each if it happened).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::validity::{ContactReport, Violation};
    /// let r = ContactReport {
    ///     min_normal_force: -0.1, max_normal_force: 2.0, max_friction_needed: f64::INFINITY,
    ///     lift_off_t: Some(20.2), slip_t: Some(3.0), friction: Some(1.0),
    /// };
    /// let v = r.violations();
    /// assert!(matches!(v[0], Violation::Slip { t, .. } if t == 3.0));
    /// assert_eq!(v[1], Violation::LiftOff { t: 20.2 });
    /// ```
    pub fn violations(&self) -> Vec<Violation> {
        let mut v = Vec::new();
        if let Some(t) = self.lift_off_t {
            v.push(Violation::LiftOff { t });
        }
        if let (Some(t), Some(friction)) = (self.slip_t, self.friction) {
            v.push(Violation::Slip {
                t,
                friction,
                needed: self.max_friction_needed,
            });
        }
        v.sort_by(|a, b| a.t().total_cmp(&b.t()));
        v
    }
}

/// The safety factor on the curvature bound of what a step's interior can hide.
const HIDDEN_FACTOR: f64 = 4.0;
/// Time tolerance of the crossing times (lift-off, slip).
const TIME_TOL: f64 = 1e-9;
/// Tolerance of an extreme's search, relative to the step: an extreme's value is flat to second
/// order, so a time within 1e-4 of the step gives the value to ~1e-8 of its variation.
const SEARCH_TOL: f64 = 1e-4;

/// Follows the contact force along a run.
#[derive(Debug, Clone)]
pub struct ContactWatch {
    limits: ContactLimits,
    report: ContactReport,
    last: (f64, ContactForce),
    /// The step end before `last`, for the curvature estimate.
    before: Option<(f64, ContactForce)>,
    /// Whether the extremes are refined inside the steps ([`Self::new`]) or only a lift-off
    /// is ([`Self::lift_off_only`]).
    refine_extremes: bool,
}

/// How far a quantity `q` could reach beyond its values at the step's ends t0, t1 inside the
/// step: |q''| h²/8 with q'' the second divided difference through (tm, t0, t1), times
/// [`HIDDEN_FACTOR`]; infinite without an earlier end (the first step is always searched).
fn hidden(before: Option<(f64, f64)>, (t0, q0): (f64, f64), (t1, q1): (f64, f64)) -> f64 {
    let Some((tm, qm)) = before else {
        return f64::INFINITY;
    };
    let h = t1 - t0;
    if !(h > 0.0 && t0 > tm) {
        return f64::INFINITY;
    }
    let second = 2.0 * ((q1 - q0) / h - (q0 - qm) / (t0 - tm)) / (t1 - tm);
    let bound = HIDDEN_FACTOR * second.abs() * h * h / 8.0;
    if bound.is_finite() {
        bound
    } else {
        f64::INFINITY
    }
}

impl ContactWatch {
    /// Starts watching at time `t0` with force `f0`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ContactForce;
    /// use rollphase_core::dynamics::validity::{ContactLimits, ContactWatch};
    /// let limits = ContactLimits { friction: Some(0.2), ..ContactLimits::default() };
    /// let watch = ContactWatch::new(limits, 0.0, ContactForce::viscous(0.3));
    /// // tan 0.3 = 0.31 > 0.2: a viscous body on this ramp slips from the start.
    /// assert_eq!(watch.report().slip_t, Some(0.0));
    /// ```
    pub fn new(limits: ContactLimits, t0: f64, f0: ContactForce) -> Self {
        let mu0 = f0.friction_needed();
        let report = ContactReport {
            min_normal_force: f0.normal,
            max_normal_force: f0.normal,
            max_friction_needed: mu0,
            lift_off_t: (f0.normal <= 0.0).then_some(t0),
            slip_t: limits.friction.filter(|mu| mu0 > *mu).map(|_| t0),
            friction: limits.friction,
        };
        Self {
            limits,
            report,
            last: (t0, f0),
            before: None,
            refine_extremes: true,
        }
    }

    /// A watch for a run that needs only to know whether and when the body leaves the ramp
    /// (a study's many runs): N is searched inside a step only where the step could hide
    /// N ≤ 0, so the lift-off time is as exact as [`Self::new`]'s, at a fraction of the force
    /// evaluations. Its report's extremes are those at the steps' ends, not refined, and it
    /// watches no friction.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ContactForce;
    /// use rollphase_core::dynamics::validity::{ContactLimits, ContactWatch};
    /// // N dips to −0.25 at t = 1.5 inside one long step: both watches time the lift-off at t = 1.
    /// let force = |t: f64| ContactForce { normal: (t - 1.5).powi(2) - 0.25, friction: [0.1, 0.0] };
    /// let mut cheap = ContactWatch::lift_off_only(0.0, force(0.0));
    /// let mut full = ContactWatch::new(ContactLimits::default(), 0.0, force(0.0));
    /// cheap.step(3.0, force);
    /// full.step(3.0, force);
    /// assert_eq!(cheap.report().lift_off_t, full.report().lift_off_t);
    /// assert!((cheap.report().lift_off_t.unwrap() - 1.0).abs() < 1e-8);
    /// ```
    pub fn lift_off_only(t0: f64, f0: ContactForce) -> Self {
        Self {
            refine_extremes: false,
            ..Self::new(ContactLimits::default(), t0, f0)
        }
    }

    /// [`Self::step`] over an integrator's last step, up to `(t1, y1)` (the step's end, or a
    /// switch inside it), with `force` the model's force at a state: evaluated at `y1`, and on
    /// the step's dense output only where a search needs it. The one way the runs call it.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::validity::{ContactLimits, ContactWatch};
    /// use rollphase_core::dynamics::{DiskInertial, Ramp, RollingModel};
    /// use rollphase_core::geometry::Disk;
    /// use rollphase_core::integrate::run::{Flow, Run};
    /// use rollphase_core::integrate::{IntegrateError, Method};
    /// let disk = Disk::perfect();
    /// let model = DiskInertial::new(&disk, &Ramp::with_drag(0.3, 2.0, 0.0)?);
    /// let y0 = [0.0, 0.0, 0.0, 0.0];
    /// let mut watch = ContactWatch::new(ContactLimits::default(), 0.0, model.contact_force(&y0));
    /// let mut run = Run::new(&model, 0.0, y0, Method::dop853(1e-10))?;
    /// run.until::<IntegrateError>(5.0, u64::MAX, |st| {
    ///     let end = (st.t(), *st.y());
    ///     watch.step_along(st, end, |y| model.contact_force(y));
    ///     Ok(Flow::Continue)
    /// })?;
    /// // A uniform disk rolling freely is pressed with cos α throughout.
    /// assert!((watch.report().min_normal_force - 0.3f64.cos()).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn step_along<const N: usize>(
        &mut self,
        st: &mut dyn Stepper<N>,
        (t1, y1): (f64, [f64; N]),
        force: impl Fn(&[f64; N]) -> ContactForce,
    ) -> Option<Violation> {
        self.step(t1, |t| {
            if t == t1 {
                force(&y1)
            } else {
                force(&st.dense(t))
            }
        })
    }

    /// Goes on from a state reached by a jump at `t` (a tip across a bridge), with force `f`
    /// there: the force in the jump itself is impulsive and not followed.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ContactForce;
    /// use rollphase_core::dynamics::validity::{ContactLimits, ContactWatch};
    /// let mut w = ContactWatch::new(ContactLimits::default(), 0.0, ContactForce::viscous(0.3));
    /// w.jump(1.0, ContactForce { normal: 0.5, friction: [0.0, 0.0] });
    /// assert_eq!(w.report().min_normal_force, 0.5);
    /// ```
    pub fn jump(&mut self, t: f64, f: ContactForce) {
        let r = &mut self.report;
        r.min_normal_force = r.min_normal_force.min(f.normal);
        r.max_normal_force = r.max_normal_force.max(f.normal);
        r.max_friction_needed = r.max_friction_needed.max(f.friction_needed());
        if f.normal <= 0.0 && r.lift_off_t.is_none() {
            r.lift_off_t = Some(t);
        }
        if let (Some(mu), None) = (self.limits.friction, r.slip_t)
            && f.friction_needed() > mu
        {
            r.slip_t = Some(t);
        }
        self.last = (t, f);
        self.before = None;
    }

    /// What it has seen so far.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ContactForce;
    /// use rollphase_core::dynamics::validity::{ContactLimits, ContactWatch};
    /// let watch = ContactWatch::new(ContactLimits::default(), 0.0, ContactForce::viscous(0.3));
    /// assert_eq!(watch.report().min_normal_force, 0.3f64.cos());
    /// ```
    pub fn report(&self) -> ContactReport {
        self.report
    }

    /// The limits it checks against.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ContactForce;
    /// use rollphase_core::dynamics::validity::{ContactLimits, ContactWatch};
    /// let watch = ContactWatch::new(ContactLimits::default(), 0.0, ContactForce::viscous(0.3));
    /// assert_eq!(watch.limits().friction, None);
    /// ```
    pub fn limits(&self) -> ContactLimits {
        self.limits
    }

    /// Takes in the step that ended at `t1`, with `force(t)` the force on its dense output for
    /// t in [last time, t1]. Returns the first violation that happened in it, if the watch is
    /// set to stop on one (and none was seen before).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::ContactForce;
    /// use rollphase_core::dynamics::validity::{ContactLimits, ContactWatch, OnViolation, Violation};
    /// // A made-up force whose N dips to −0.25 at t = 1.5 inside one long step: the dip is found
    /// // between the samples, and the lift-off time is the root of N.
    /// let force = |t: f64| ContactForce { normal: (t - 1.5).powi(2) - 0.25, friction: [0.1, 0.0] };
    /// let limits = ContactLimits { friction: None, on_violation: OnViolation::Stop };
    /// let mut watch = ContactWatch::new(limits, 0.0, force(0.0));
    /// let v = watch.step(3.0, force);
    /// assert!(matches!(v, Some(Violation::LiftOff { t }) if (t - 1.0).abs() < 1e-8));
    /// assert!((watch.report().min_normal_force + 0.25).abs() < 1e-8);
    /// ```
    pub fn step(
        &mut self,
        t1: f64,
        mut force: impl FnMut(f64) -> ContactForce,
    ) -> Option<Violation> {
        let before = self.report.violations().len();
        let (t0, f0) = self.last;
        let f1 = force(t1);
        let prior = self.before;
        self.before = Some(self.last);
        self.last = (t1, f1);
        let (n0, n1) = (f0.normal, f1.normal);
        let n_hidden = hidden(prior.map(|(t, f)| (t, f.normal)), (t0, n0), (t1, n1));

        // N's minimum, searched where the step may hide one below the run's; then the first
        // time N ≤ 0.
        let lo = n0.min(n1);
        // Without refined extremes, only a step that could hide the first N ≤ 0 is searched.
        let search = if self.refine_extremes {
            lo - n_hidden < self.report.min_normal_force || n1 <= 0.0
        } else {
            self.report.min_normal_force = self.report.min_normal_force.min(lo);
            self.report.lift_off_t.is_none() && (lo - n_hidden <= 0.0 || n1 <= 0.0)
        };
        if search {
            let t = golden_max(|t| -force(t).normal, t0, t1, SEARCH_TOL * (t1 - t0));
            let at_t = force(t).normal;
            let v = at_t.min(lo);
            self.report.min_normal_force = self.report.min_normal_force.min(v);
            if self.report.lift_off_t.is_none() && v <= 0.0 {
                // The first crossing: before the interior minimum if N dips below 0 there,
                // else before the step's end.
                let (tb, nb) = if at_t <= 0.0 { (t, at_t) } else { (t1, n1) };
                self.report.lift_off_t = Some(if n0 > 0.0 && nb <= 0.0 {
                    brent(|t| force(t).normal, t0, tb, n0, nb, TIME_TOL)
                } else {
                    t0
                });
            }
        }
        let hi = n0.max(n1);
        if !self.refine_extremes {
            self.report.max_normal_force = self.report.max_normal_force.max(hi);
            let top = f0.friction_needed().max(f1.friction_needed());
            self.report.max_friction_needed = self.report.max_friction_needed.max(top);
            return None;
        }
        if hi + n_hidden > self.report.max_normal_force {
            let t = golden_max(|t| force(t).normal, t0, t1, SEARCH_TOL * (t1 - t0));
            let v = force(t).normal.max(hi);
            self.report.max_normal_force = self.report.max_normal_force.max(v);
        }

        // The friction needed, while the body is pressed on the ramp.
        let (m0, m1) = (f0.friction_needed(), f1.friction_needed());
        if m0.is_finite() && m1.is_finite() {
            let m_hidden = hidden(
                prior.map(|(t, f)| (t, f.friction_needed())),
                (t0, m0),
                (t1, m1),
            );
            let top = m0.max(m1);
            let mut t_top = if m1 >= m0 { t1 } else { t0 };
            if top + m_hidden > self.report.max_friction_needed {
                let t = golden_max(
                    |t| force(t).friction_needed(),
                    t0,
                    t1,
                    SEARCH_TOL * (t1 - t0),
                );
                let at_t = force(t).friction_needed();
                if at_t > top {
                    t_top = t;
                }
                self.report.max_friction_needed =
                    self.report.max_friction_needed.max(at_t.max(top));
            }
            if let (Some(mu), None) = (self.limits.friction, self.report.slip_t)
                && self.report.max_friction_needed > mu
            {
                let excess = |f: ContactForce| f.friction_needed().min(1e300) - mu;
                let (tb, eb) = if m1 > mu {
                    (t1, m1 - mu)
                } else {
                    (t_top, excess(force(t_top)))
                };
                self.report.slip_t = Some(if m0 <= mu && eb > 0.0 {
                    brent(|t| excess(force(t)), t0, tb, m0 - mu, eb, TIME_TOL)
                } else {
                    t0
                });
            }
        } else {
            self.report.max_friction_needed = f64::INFINITY;
            if let (Some(_), None) = (self.limits.friction, self.report.slip_t) {
                // No friction holds a body the ramp does not press: from where N reached 0.
                self.report.slip_t = self.report.lift_off_t.or(Some(t1));
            }
        }

        if self.limits.on_violation == OnViolation::Stop && before == 0 {
            self.report.violations().first().copied()
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn watch_of(
        f: impl Fn(f64) -> ContactForce,
        friction: Option<f64>,
        steps: usize,
        t_end: f64,
    ) -> ContactReport {
        let limits = ContactLimits {
            friction,
            on_violation: OnViolation::Warn,
        };
        let mut w = ContactWatch::new(limits, 0.0, f(0.0));
        for i in 1..=steps {
            w.step(t_end * i as f64 / steps as f64, &f);
        }
        w.report()
    }

    #[test]
    fn extremes_do_not_depend_on_the_steps() {
        // N = 1 + 0.8 sin(3t), μ_req = 0.3/N: exact extremes 0.2, 1.8 and 1.5.
        let f = |t: f64| ContactForce {
            normal: 1.0 + 0.8 * (3.0 * t).sin(),
            friction: [0.3, 0.0],
        };
        for steps in [7, 13, 50, 400] {
            let r = watch_of(f, Some(1.0), steps, 10.0);
            // To SEARCH_TOL's promise: 1e-8 of the variation (1.6 in N, 1.3 in μ).
            assert!((r.min_normal_force - 0.2).abs() < 2e-8, "{steps}: {r:?}");
            assert!((r.max_normal_force - 1.8).abs() < 2e-8, "{steps}: {r:?}");
            assert!((r.max_friction_needed - 1.5).abs() < 2e-8, "{steps}: {r:?}");
            // μ_req = 1 where N = 0.3: sin 3t = −0.875, first at t = (π + asin 0.875)/3.
            let t_slip = (std::f64::consts::PI + 0.875f64.asin()) / 3.0;
            assert!((r.slip_t.unwrap() - t_slip).abs() < 1e-8, "{steps}: {r:?}");
            assert_eq!(r.lift_off_t, None);
        }
    }

    #[test]
    fn a_lift_off_is_timed_and_makes_the_friction_needed_infinite() {
        let f = |t: f64| ContactForce {
            normal: 1.0 - 0.1 * t,
            friction: [0.1, 0.0],
        };
        let r = watch_of(f, None, 3, 15.0);
        assert!((r.lift_off_t.unwrap() - 10.0).abs() < 1e-8);
        assert!(r.max_friction_needed.is_infinite());
        assert!((r.min_normal_force + 0.5).abs() < 1e-12);
        assert_eq!(r.slip_t, None);
    }

    #[test]
    fn stop_reports_only_the_first_violation() {
        let f = |t: f64| ContactForce {
            normal: 1.0 - 0.1 * t,
            friction: [0.1, 0.0],
        };
        let limits = ContactLimits {
            friction: Some(0.5),
            on_violation: OnViolation::Stop,
        };
        let mut w = ContactWatch::new(limits, 0.0, f(0.0));
        let first = (1..=20).find_map(|i| w.step(i as f64, f));
        // μ_req = 0.1/N reaches 0.5 at N = 0.2 (t = 8), before N reaches 0 (t = 10).
        let Some(Violation::Slip { t, .. }) = first else {
            panic!("{first:?}")
        };
        assert!((t - 8.0).abs() < 1e-8);
    }
}
