//! The measuring sweep of α or m/m0, as an orbit diagram is drawn: hold each value until the
//! run there is measured (its period settled, the body halted, or its cycle of ∂Ω crossings
//! found), so the 1/T plot (α) or the crossing plot (m/m0) gets its point, then step. A sweep
//! that moved the parameter a little every frame restarted the period's detection every frame
//! and never drew a point. Plain data: [`SweepHold::observe`] and [`MeasuringSweep::next`] are the
//! whole rule.

use super::{ALPHA_MAX, ALPHA_MIN, MASS_RANGE};

/// What a sweep moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SweepTarget {
    /// α, by a fixed amount (rad) per point.
    Alpha,
    /// m/m0, by a fixed ratio per point (the step is ln of it).
    MassRatio,
}

impl SweepTarget {
    /// Both.
    pub const ALL: [SweepTarget; 2] = [SweepTarget::Alpha, SweepTarget::MassRatio];

    /// As the menu names it.
    pub fn name(self) -> &'static str {
        match self {
            SweepTarget::Alpha => "α",
            SweepTarget::MassRatio => "m/m0",
        }
    }

    /// What the step means.
    pub fn step_hint(self) -> &'static str {
        match self {
            SweepTarget::Alpha => "radians added to α after each point (negative: down)",
            SweepTarget::MassRatio => {
                "the factor m/m0 is multiplied by after each point (×1.051: 5 % more; below \
                 ×1: down)"
            }
        }
    }

    /// The values it may take (the slider's range).
    pub fn range(self) -> (f64, f64) {
        match self {
            SweepTarget::Alpha => (ALPHA_MIN, ALPHA_MAX),
            SweepTarget::MassRatio => MASS_RANGE,
        }
    }

    /// The step as the sweep's field and the status bar both show it: α's in radians
    /// ("+0.00200 rad"), m/m0's as the factor per point ("×1.051"; the step is its ln). The
    /// field once showed m/m0's ln ("0.0500") beside the status bar's factor.
    pub fn shown_step(self, step: f64) -> String {
        // Enough digits that a small step never reads as none ("+0.00000 rad", "×1.000").
        match self {
            SweepTarget::Alpha if step != 0.0 && step.abs() < 1e-4 => format!("{step:+.2e} rad"),
            SweepTarget::Alpha => format!("{step:+.5} rad"),
            SweepTarget::MassRatio if step != 0.0 && step.abs() < 5e-4 => {
                format!("×{:.7}", step.exp())
            }
            SweepTarget::MassRatio => format!("×{:.3}", step.exp()),
        }
    }

    /// A typed step read back as [`Self::shown_step`] writes it (the unit and the × may be left
    /// out); `None` for text that is no step: not a number, or a factor that is not > 0.
    pub fn parse_step(self, text: &str) -> Option<f64> {
        let t = text.trim();
        match self {
            SweepTarget::Alpha => t.trim_end_matches("rad").trim().parse::<f64>().ok(),
            SweepTarget::MassRatio => t
                .trim_start_matches(['×', 'x', '*'])
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|f| *f > 0.0 && f.is_finite())
                .map(f64::ln),
        }
        .filter(|s| s.is_finite())
    }

    /// A step fine enough to follow a branch: about 1 % of the paper's α*, 5 % in m/m0.
    pub fn default_step(self) -> f64 {
        match self {
            SweepTarget::Alpha => 0.002,
            SweepTarget::MassRatio => 0.05,
        }
    }
}

/// A sweep: which parameter, and by how much per point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuringSweep {
    /// What moves.
    pub target: SweepTarget,
    /// The step after each point ([`SweepTarget::step_hint`]).
    pub step: f64,
    /// Where the sweep ends: no value beyond this one (in the step's direction) is taken;
    /// `None` sweeps to the end of the slider's range.
    pub end: Option<f64>,
}

impl Default for MeasuringSweep {
    fn default() -> Self {
        Self {
            target: SweepTarget::MassRatio,
            step: SweepTarget::MassRatio.default_step(),
            end: None,
        }
    }
}

/// What one sweep step asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SweepStep {
    /// Set α to this.
    Alpha(f64),
    /// Set m/m0 to this.
    MassRatio(f64),
    /// The parameter reached the end of its range: the sweep stops.
    Done,
}

impl MeasuringSweep {
    /// The step after a point measured at α = `alpha`, m/m0 = `mass_ratio` (a viscous run's 0
    /// starts a mass sweep at `mass_start`, the slider's value, to be measured first).
    pub fn next(&self, alpha: f64, mass_ratio: f64, mass_start: f64) -> SweepStep {
        let step = if self.step.is_finite() {
            self.step
        } else {
            0.0
        };
        match self.target {
            SweepTarget::Alpha => {
                let next = alpha + step;
                if !(ALPHA_MIN..=ALPHA_MAX).contains(&next) || self.past_end(next) {
                    SweepStep::Done
                } else {
                    SweepStep::Alpha(next)
                }
            }
            SweepTarget::MassRatio if mass_ratio <= 0.0 => SweepStep::MassRatio(mass_start),
            SweepTarget::MassRatio => {
                let next = mass_ratio * step.exp();
                if !(MASS_RANGE.0..=MASS_RANGE.1).contains(&next) || self.past_end(next) {
                    SweepStep::Done
                } else {
                    SweepStep::MassRatio(next)
                }
            }
        }
    }

    /// Whether `value` lies beyond [`Self::end`] in the step's direction (a value within
    /// rounding of the end is taken).
    fn past_end(&self, value: f64) -> bool {
        self.end.is_some_and(|end| {
            let slack = 1e-9 * end.abs().max(1e-12);
            if self.step > 0.0 {
                value > end + slack
            } else {
                value < end - slack
            }
        })
    }

    /// The swept parameter's value.
    pub fn value(&self, alpha: f64, mass_ratio: f64) -> f64 {
        match self.target {
            SweepTarget::Alpha => alpha,
            SweepTarget::MassRatio => mass_ratio,
        }
    }

    /// One line for the status bar: what moves, and where the hold is.
    pub fn describe(&self, hold: &SweepHold) -> String {
        let step = self.target.shown_step(self.step);
        let at = hold.value.map_or(String::new(), |v| {
            format!(" at {} = {v:.5}", self.target.name())
        });
        format!(
            "sweeping {} by {step} per point: measuring{at} ({} crossing(s) so far)",
            self.target.name(),
            hold.crossings
        )
    }
}

/// Longest a sweep holds one value (simulation time) when its run neither settles nor halts;
/// it then steps on without a point and says so.
pub const HOLD_CAP: f64 = 3000.0;

/// Crossings of the section at one value before its period counts: the first starts the
/// clock, one period is the transient, and the last two periods must agree.
pub const CROSSINGS_TO_MEASURE: usize = 4;

/// How closely the last two periods must agree for the run to count as settled.
pub const SETTLED_PERIODS: f64 = 1e-3;

/// How long a body must stay at rest for a halt to count: a run started from rest is at rest
/// for its first instant.
pub const HALT_CONFIRM: f64 = 5.0;

/// Observations at another value than the one sent before the hold takes the run's value
/// instead: the simulation applies a command within a frame or two, so a longer mismatch means
/// the parameter was moved by hand (the slider, a typed value) during the sweep.
const MOVED_BY_HAND: usize = 10;

/// What the run showed at the value a sweep holds, as the snapshot reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HoldObservation {
    /// Simulation time.
    pub t: f64,
    /// The swept parameter's value in the run.
    pub value: f64,
    /// When the run last crossed its section (a full turn in 2D, ∂Ω in 3D).
    pub last_crossing_t: Option<f64>,
    /// The time between the last two crossings.
    pub period: Option<f64>,
    /// The cycle of ∂Ω crossings found (3D), k = 1, 2, …
    pub multiplicity: Option<usize>,
    /// Whether the model reports cycles (3D): its run counts as settled only once a cycle is
    /// found, since a doubled orbit's return times can agree while its crossing points alternate.
    pub reports_cycles: bool,
    /// Whether the body has stopped.
    pub halted: bool,
}

/// The verdict on the value held.
#[derive(Debug, Clone, PartialEq)]
pub enum HoldVerdict {
    /// Keep holding: the run is not measured yet.
    Waiting,
    /// Measured (the plots have their point): step on. Says what was found.
    Measured(String),
    /// [`HOLD_CAP`] passed without a settled period or a halt: step on without a point.
    GaveUp,
}

/// One value of a sweep, held until it is measured.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SweepHold {
    /// The value held; `None`: whatever the run has when the sweep starts.
    value: Option<f64>,
    since: Option<f64>,
    last_crossing_t: Option<f64>,
    crossings: usize,
    periods: [Option<f64>; 2],
    mismatched: usize,
    halted_since: Option<f64>,
    /// Crossings counted when the cycle was first found, and its period k.
    cycle_found: Option<(usize, usize)>,
}

impl SweepHold {
    /// A hold of `value`, just sent to the simulation: observations at another value (the
    /// simulation has not applied it yet) are not counted.
    pub fn at(value: f64) -> Self {
        Self {
            value: Some(value),
            ..Self::default()
        }
    }

    /// Takes in one observation and says whether the value is measured.
    pub fn observe(&mut self, o: &HoldObservation) -> HoldVerdict {
        match self.value {
            Some(v) if v != o.value => {
                self.mismatched += 1;
                if self.mismatched <= MOVED_BY_HAND {
                    return HoldVerdict::Waiting;
                }
                // Moved by hand: measure where it is now.
                *self = Self::default();
                self.value = Some(o.value);
            }
            Some(_) => self.mismatched = 0,
            None => self.value = Some(o.value),
        }
        if o.halted {
            let since = *self.halted_since.get_or_insert(o.t);
            if o.t - since >= HALT_CONFIRM {
                return HoldVerdict::Measured("halted".into());
            }
        } else {
            self.halted_since = None;
        }
        let Some(since) = self.since else {
            // The first look: crossings from before it belong to the last value.
            self.since = Some(o.t);
            self.last_crossing_t = o.last_crossing_t;
            return HoldVerdict::Waiting;
        };
        if o.last_crossing_t.is_some() && o.last_crossing_t != self.last_crossing_t {
            self.last_crossing_t = o.last_crossing_t;
            self.crossings += 1;
            self.periods = [self.periods[1], o.period];
        }
        // A cycle found is measured over two more turns of it, so that the crossing plot gets
        // every point of the cycle twice (both branches of a doubled orbit).
        match (o.multiplicity, self.cycle_found) {
            (Some(k), Some((_, seen))) if k == seen => {}
            (Some(k), _) => self.cycle_found = Some((self.crossings, k)),
            (None, _) => self.cycle_found = None,
        }
        if self.crossings >= CROSSINGS_TO_MEASURE {
            if let Some((found, k)) = self.cycle_found
                && self.crossings >= found + 2 * k
            {
                return HoldVerdict::Measured(format!("a cycle of period {k}"));
            }
            if let [Some(a), Some(b)] = self.periods
                && !o.reports_cycles
                && (a - b).abs() <= SETTLED_PERIODS * b.abs()
            {
                return HoldVerdict::Measured(format!("T = {b:.4}"));
            }
        }
        if o.t - since > HOLD_CAP {
            return HoldVerdict::GaveUp;
        }
        HoldVerdict::Waiting
    }

    /// Crossings counted at this value.
    pub fn crossings(&self) -> usize {
        self.crossings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_field_and_the_status_bar_show_the_step_alike() {
        let sweep = MeasuringSweep::default();
        let field = sweep.target.shown_step(sweep.step);
        assert_eq!(field, "×1.051");
        assert!(
            sweep.describe(&SweepHold::default()).contains(&field),
            "{}",
            sweep.describe(&SweepHold::default())
        );
        // What the field shows reads back (to its digits), with or without the ×.
        let back = sweep.target.parse_step(&field).unwrap();
        assert!((back.exp() - 1.051).abs() < 1e-12);
        assert_eq!(sweep.target.parse_step("0.95"), Some(0.95f64.ln()));
        let alpha = SweepTarget::Alpha;
        assert_eq!(alpha.shown_step(-0.002), "-0.00200 rad");
        assert_eq!(alpha.parse_step("-0.00200 rad"), Some(-0.002));
        // No step: a factor ≤ 0, NaN or text.
        for bad in ["×0", "-1.2", "NaN", "inf", "fast", ""] {
            assert_eq!(sweep.target.parse_step(bad), None, "{bad}");
        }
        assert_eq!(alpha.parse_step("nan rad"), None);
        // A small step still reads as one, and back.
        assert_eq!(alpha.shown_step(1e-6), "+1.00e-6 rad");
        assert_eq!(alpha.parse_step("+1.00e-6 rad"), Some(1e-6));
        let small = sweep.target.shown_step(0.0004);
        assert_eq!(small, "×1.0004001");
        assert!((sweep.target.parse_step(&small).unwrap() - 0.0004).abs() < 1e-7);
    }

    #[test]
    fn a_sweep_steps_by_its_step_and_stops_at_the_end() {
        let up = MeasuringSweep {
            target: SweepTarget::Alpha,
            step: 0.002,
            end: None,
        };
        assert_eq!(up.next(0.1, 0.0, 1.0), SweepStep::Alpha(0.1 + 0.002));
        // An end stops it there: 0.104 is taken, 0.106 is past 0.105.
        let to = MeasuringSweep {
            end: Some(0.105),
            ..up
        };
        assert_eq!(to.next(0.102, 0.0, 1.0), SweepStep::Alpha(0.102 + 0.002));
        assert_eq!(to.next(0.104, 0.0, 1.0), SweepStep::Done);
        let down_to = MeasuringSweep {
            step: -0.002,
            end: Some(0.1),
            ..up
        };
        assert_eq!(down_to.next(0.101, 0.0, 1.0), SweepStep::Done);
        assert_eq!(up.next(ALPHA_MAX - 1e-6, 0.0, 1.0), SweepStep::Done);
        let heavier = MeasuringSweep::default();
        let SweepStep::MassRatio(m) = heavier.next(0.15, 2.0, 1.0) else {
            panic!("a mass step")
        };
        assert!((m - 2.0 * 0.05f64.exp()).abs() < 1e-12);
        // From the viscous model a mass sweep starts at the slider's m/m0.
        assert_eq!(heavier.next(0.15, 0.0, 3.0), SweepStep::MassRatio(3.0));
        let lighter = MeasuringSweep {
            target: SweepTarget::MassRatio,
            step: -1.0,
            end: None,
        };
        assert_eq!(lighter.next(0.15, 1.1e-3, 1.0), SweepStep::Done);
        // A broken step moves nothing (and the hold then measures the same value again).
        let broken = MeasuringSweep {
            target: SweepTarget::Alpha,
            step: f64::INFINITY,
            end: None,
        };
        assert_eq!(broken.next(0.1, 0.0, 1.0), SweepStep::Alpha(0.1));
    }

    fn seen(t: f64, value: f64, crossing: Option<f64>, period: Option<f64>) -> HoldObservation {
        HoldObservation {
            t,
            value,
            last_crossing_t: crossing,
            period,
            multiplicity: None,
            reports_cycles: false,
            halted: false,
        }
    }

    #[test]
    fn a_value_is_held_until_its_period_settles() {
        let mut hold = SweepHold::at(0.2);
        // The simulation has not applied the new value yet: nothing counts.
        assert_eq!(
            hold.observe(&seen(0.0, 0.19, Some(0.0), Some(9.0))),
            HoldVerdict::Waiting
        );
        // The first look takes the crossing it sees as the old value's.
        assert_eq!(
            hold.observe(&seen(1.0, 0.2, Some(0.0), None)),
            HoldVerdict::Waiting
        );
        // Periods 12, 10.5, 10.01, 10.005: settled at the fourth crossing, when the last two
        // agree to 1e-3.
        let periods = [12.0, 10.5, 10.01, 10.005];
        let mut t = 0.0;
        let mut verdicts = Vec::new();
        for p in periods {
            t += p;
            // A few frames between crossings repeat the same crossing: counted once.
            for frame in 0..3 {
                verdicts.push(hold.observe(&seen(t + frame as f64, 0.2, Some(t), Some(p))));
            }
        }
        assert!(
            verdicts[..9].iter().all(|v| *v == HoldVerdict::Waiting),
            "{verdicts:?}"
        );
        assert_eq!(verdicts[9], HoldVerdict::Measured("T = 10.0050".into()));
        assert_eq!(hold.crossings(), 4);
    }

    #[test]
    fn a_halt_a_cycle_or_the_cap_ends_the_hold() {
        // At rest for a moment (a start from rest) is not a halt; at rest for HALT_CONFIRM is.
        let mut hold = SweepHold::at(0.1);
        let at_rest = |t: f64| HoldObservation {
            halted: true,
            ..seen(t, 0.1, None, None)
        };
        assert_eq!(hold.observe(&at_rest(0.0)), HoldVerdict::Waiting);
        assert_eq!(
            hold.observe(&seen(1.0, 0.1, None, None)),
            HoldVerdict::Waiting
        );
        assert_eq!(hold.observe(&at_rest(2.0)), HoldVerdict::Waiting);
        assert_eq!(
            hold.observe(&at_rest(2.0 + HALT_CONFIRM / 2.0)),
            HoldVerdict::Waiting
        );
        assert_eq!(
            hold.observe(&at_rest(2.0 + HALT_CONFIRM)),
            HoldVerdict::Measured("halted".into())
        );

        // A period-2 cycle: the periods alternate and never agree, the cycle is found.
        let mut hold = SweepHold::default();
        hold.observe(&seen(0.0, 6.0, None, None));
        let mut t = 0.0;
        let mut verdict = HoldVerdict::Waiting;
        let mut first_measured = None;
        for i in 0..9 {
            let p = if i % 2 == 0 { 40.0 } else { 49.0 };
            t += p;
            // Return times that agree do not settle a 3D run: its crossing points may alternate.
            let p = if i < 3 { p } else { 44.0 };
            let mut o = seen(t, 6.0, Some(t), Some(p));
            o.reports_cycles = true;
            o.multiplicity = (i >= 3).then_some(2);
            verdict = hold.observe(&o);
            if verdict != HoldVerdict::Waiting && first_measured.is_none() {
                first_measured = Some(i);
            }
        }
        assert_eq!(verdict, HoldVerdict::Measured("a cycle of period 2".into()));
        // Found at the fourth crossing (i = 3), then held for two turns of the cycle.
        assert_eq!(first_measured, Some(3 + 4));

        // Moved by hand during the sweep: after a few looks the hold measures the new value.
        let mut hold = SweepHold::at(0.2);
        for i in 0..=MOVED_BY_HAND {
            assert_eq!(
                hold.observe(&seen(i as f64, 0.25, None, None)),
                HoldVerdict::Waiting
            );
        }
        hold.observe(&seen(20.0, 0.25, None, None));
        assert_eq!(hold.value, Some(0.25));

        // No crossing for longer than the cap: give up.
        let mut hold = SweepHold::at(0.3);
        assert_eq!(
            hold.observe(&seen(10.0, 0.3, None, None)),
            HoldVerdict::Waiting
        );
        assert_eq!(
            hold.observe(&seen(10.0 + HOLD_CAP, 0.3, None, None)),
            HoldVerdict::Waiting
        );
        assert_eq!(
            hold.observe(&seen(11.0 + HOLD_CAP, 0.3, None, None)),
            HoldVerdict::GaveUp
        );
    }
}
