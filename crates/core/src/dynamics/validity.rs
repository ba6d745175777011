//! Where a run leaves the model's assumptions: every model assumes the body stays on the ramp
//! (normal force N > 0) and rolls without slipping (the friction it needs, |f_t|/N, within what
//! the surface gives). [`ContactWatch`] follows the exact contact force
//! ([`crate::dynamics::ContactForce`]) along a run and reports its extremes and the first time
//! either assumption fails ([`ContactReport`]); the caller's [`ContactLimits`] say whether a
//! failure stops the run ([`OnViolation::Stop`]) or is reported as a warning.
//!
//! The force is evaluated at each accepted step's end and at three interior points of its
//! dense output; an extreme that may beat the run's so far is refined by golden-section search
//! on the dense output, and a sign change of N or of μ_req − μ by Brent's method, so the
//! extremes and the first times do not depend on where the integrator happened to step.

use serde::Serialize;

use super::ContactForce;
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
#[derive(Debug, Clone, Copy, PartialEq)]
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

    /// One sentence, as the app's overlay and the warnings say it.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::simulate::Violation;
    /// let v = Violation::Slip { t: 3.0, friction: 0.5, needed: 1.374 };
    /// assert!(v.describe().contains("needs mu ≥ 1.374"));
    /// ```
    pub fn describe(&self) -> String {
        match self {
            Violation::LiftOff { t } => format!(
                "leaves the ramp at t = {}: the normal force falls to 0 there, so the ramp would \
                 have to pull the body down; the rolling model does not hold after it",
                short(*t)
            ),
            Violation::Slip {
                t,
                friction,
                needed,
            } if needed.is_finite() => format!(
                "slips at t = {}: it needs mu ≥ {} to roll without slipping, more than the \
                 surface's mu = {}; the rolling model does not hold after it",
                short(*t),
                short(*needed),
                short(*friction)
            ),
            Violation::Slip { t, friction, .. } => format!(
                "slips at t = {}: it needs more friction than the surface's mu = {} to roll \
                 without slipping (and later no friction at all would do: it leaves the ramp); \
                 the rolling model does not hold after it",
                short(*t),
                short(*friction)
            ),
        }
    }
}

impl Violation {
    /// One short line for the app's overlay: "leaves the ramp at t = 20.2" or "slips at
    /// t = 3.1: needs μ ≥ 1.37 to roll without slipping (surface μ = 0.5)".
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::validity::Violation;
    /// let v = Violation::LiftOff { t: 20.207 };
    /// assert_eq!(v.headline(), "leaves the ramp at t = 20.207: the rolling model stops holding");
    /// ```
    pub fn headline(&self) -> String {
        match self {
            Violation::LiftOff { t } => format!(
                "leaves the ramp at t = {}: the rolling model stops holding",
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
            Violation::Slip { t, friction, .. } => format!(
                "slips at t = {}: needs more than the surface's μ = {}",
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

/// How far (in units of F for N, relative for μ) a sampled value may lie from the run's extreme
/// and still be refined: between samples a quarter-step apart the force moves by far less.
const REFINE_MARGIN: f64 = 0.05;
/// Time tolerance of the refinements.
const TIME_TOL: f64 = 1e-9;

/// Follows the contact force along a run.
#[derive(Debug, Clone)]
pub struct ContactWatch {
    limits: ContactLimits,
    report: ContactReport,
    last: (f64, ContactForce),
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
        }
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
    /// assert!((watch.report().min_normal_force + 0.25).abs() < 1e-12);
    /// ```
    pub fn step(
        &mut self,
        t1: f64,
        mut force: impl FnMut(f64) -> ContactForce,
    ) -> Option<Violation> {
        let before = self.report.violations().len();
        let t0 = self.last.0;
        let mut pts = [self.last; 5];
        for (k, p) in pts.iter_mut().enumerate().skip(1) {
            let t = if k == 4 {
                t1
            } else {
                t0 + (t1 - t0) * k as f64 / 4.0
            };
            *p = (t, force(t));
        }
        self.last = pts[4];
        let normal = |p: &(f64, ContactForce)| p.1.normal;
        let needed = |p: &(f64, ContactForce)| p.1.friction_needed();
        let bracket = |k: usize| (pts[k.saturating_sub(1)].0, pts[(k + 1).min(4)].0);

        // N's minimum (refined when it may be the run's), then the first time N ≤ 0.
        let k_min = argmin(&pts, normal);
        if normal(&pts[k_min]) < self.report.min_normal_force + REFINE_MARGIN {
            let (a, b) = bracket(k_min);
            let t = golden_max(|t| -force(t).normal, a, b, TIME_TOL);
            let v = force(t).normal.min(normal(&pts[k_min]));
            self.report.min_normal_force = self.report.min_normal_force.min(v);
            if self.report.lift_off_t.is_none() && v <= 0.0 {
                // The first sign change up to the minimum.
                let (ta, na) = pts
                    .iter()
                    .take_while(|p| p.0 < t)
                    .take_while(|p| p.1.normal > 0.0)
                    .last()
                    .map_or((t0, normal(&pts[0])), |p| (p.0, p.1.normal));
                let tb = pts
                    .iter()
                    .find(|p| p.0 > ta && p.1.normal <= 0.0)
                    .map_or(t, |p| p.0.min(t));
                let nb = force(tb).normal;
                self.report.lift_off_t = Some(if na > 0.0 && nb <= 0.0 {
                    brent(|t| force(t).normal, ta, tb, na, nb, TIME_TOL)
                } else {
                    ta
                });
            }
        }
        let k_max = argmin(&pts, |p| -normal(p));
        if normal(&pts[k_max]) > self.report.max_normal_force - REFINE_MARGIN {
            let (a, b) = bracket(k_max);
            let t = golden_max(|t| force(t).normal, a, b, TIME_TOL);
            let v = force(t).normal.max(normal(&pts[k_max]));
            self.report.max_normal_force = self.report.max_normal_force.max(v);
        }

        // The friction needed, while the body is pressed on the ramp.
        let k_mu = argmin(&pts, |p| -needed(p));
        let mu_max = needed(&pts[k_mu]);
        let mut t_mu = pts[k_mu].0;
        if mu_max.is_finite() && mu_max > self.report.max_friction_needed * (1.0 - REFINE_MARGIN) {
            let (a, b) = bracket(k_mu);
            let t = golden_max(|t| force(t).friction_needed(), a, b, TIME_TOL);
            let at_t = force(t).friction_needed();
            if at_t > mu_max {
                t_mu = t;
            }
            let v = at_t.max(mu_max);
            self.report.max_friction_needed = self.report.max_friction_needed.max(v);
        } else if !mu_max.is_finite() {
            self.report.max_friction_needed = f64::INFINITY;
        }
        if let (Some(mu), None) = (self.limits.friction, self.report.slip_t)
            && self.report.max_friction_needed > mu
        {
            let excess = |f: ContactForce| f.friction_needed().min(1e300) - mu;
            let (ta, ea) = pts
                .iter()
                .take_while(|p| excess(p.1) <= 0.0)
                .last()
                .map_or((t0, excess(pts[0].1)), |p| (p.0, excess(p.1)));
            let tb = pts
                .iter()
                .find(|p| p.0 > ta && excess(p.1) > 0.0)
                .map_or(t_mu, |p| p.0);
            let tb = if tb > ta { tb } else { t1 };
            let eb = excess(force(tb));
            self.report.slip_t = Some(if ea <= 0.0 && eb > 0.0 {
                brent(|t| excess(force(t)), ta, tb, ea, eb, TIME_TOL)
            } else {
                ta
            });
        }

        if self.limits.on_violation == OnViolation::Stop && before == 0 {
            self.report.violations().first().copied()
        } else {
            None
        }
    }
}

fn argmin(pts: &[(f64, ContactForce); 5], key: impl Fn(&(f64, ContactForce)) -> f64) -> usize {
    (0..pts.len())
        .min_by(|&a, &b| key(&pts[a]).total_cmp(&key(&pts[b])))
        .unwrap_or(0)
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
            assert!((r.min_normal_force - 0.2).abs() < 1e-10, "{steps}: {r:?}");
            assert!((r.max_normal_force - 1.8).abs() < 1e-10, "{steps}: {r:?}");
            assert!((r.max_friction_needed - 1.5).abs() < 1e-9, "{steps}: {r:?}");
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
