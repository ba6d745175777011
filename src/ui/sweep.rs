//! The slow automatic sweep of α or m/m0: while the simulation plays, the UI moves the parameter
//! a little for every unit of simulated time, so the 1/T plot (α) or the crossing plot (m/m0)
//! draws its bifurcation diagram live. Plain data: [`AutoSweep::step`] is the whole rule.

use super::{ALPHA_MAX, ALPHA_MIN, MASS_RANGE};

/// What a sweep moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SweepTarget {
    /// α, by a fixed amount (rad) per 100 time units.
    Alpha,
    /// m/m0, by a fixed ratio per 100 time units (the rate is ln of it).
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

    /// What the rate means.
    pub fn rate_hint(self) -> &'static str {
        match self {
            SweepTarget::Alpha => "radians added to α per 100 time units (negative: down)",
            SweepTarget::MassRatio => {
                "ln of the factor m/m0 is multiplied by per 100 time units (0.05: 5 % more; \
                 negative: down)"
            }
        }
    }

    /// A rate slow enough for the orbit to settle between changes.
    pub fn default_rate(self) -> f64 {
        match self {
            SweepTarget::Alpha => 0.001,
            SweepTarget::MassRatio => 0.05,
        }
    }
}

/// A sweep: which parameter, and how fast.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AutoSweep {
    /// What moves.
    pub target: SweepTarget,
    /// How fast, per 100 time units ([`SweepTarget::rate_hint`]).
    pub rate: f64,
}

impl Default for AutoSweep {
    fn default() -> Self {
        Self {
            target: SweepTarget::MassRatio,
            rate: SweepTarget::MassRatio.default_rate(),
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

impl AutoSweep {
    /// The step after `dt` time units from α = `alpha`, m/m0 = `mass_ratio` (a viscous run's 0
    /// starts a mass sweep from `mass_start`, the slider's value).
    pub fn step(&self, alpha: f64, mass_ratio: f64, mass_start: f64, dt: f64) -> SweepStep {
        let dt = if dt.is_finite() { dt.max(0.0) } else { 0.0 };
        let rate = if self.rate.is_finite() {
            self.rate
        } else {
            0.0
        };
        match self.target {
            SweepTarget::Alpha => {
                let next = alpha + rate * dt / 100.0;
                if !(ALPHA_MIN..=ALPHA_MAX).contains(&next) {
                    SweepStep::Done
                } else {
                    SweepStep::Alpha(next)
                }
            }
            SweepTarget::MassRatio => {
                let from = if mass_ratio > 0.0 {
                    mass_ratio
                } else {
                    mass_start
                };
                let next = from * (rate * dt / 100.0).exp();
                if !(MASS_RANGE.0..=MASS_RANGE.1).contains(&next) {
                    SweepStep::Done
                } else {
                    SweepStep::MassRatio(next)
                }
            }
        }
    }

    /// One line for the status bar.
    pub fn describe(&self) -> String {
        match self.target {
            SweepTarget::Alpha => format!("sweeping α by {:+} rad per 100 t", self.rate),
            SweepTarget::MassRatio => format!("sweeping m/m0 by ×{:.3} per 100 t", self.rate.exp()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sweep_moves_its_parameter_at_its_rate_and_stops_at_the_end() {
        let up = AutoSweep {
            target: SweepTarget::Alpha,
            rate: 0.002,
        };
        assert_eq!(up.step(0.1, 0.0, 1.0, 50.0), SweepStep::Alpha(0.1 + 0.001));
        assert_eq!(up.step(ALPHA_MAX - 1e-6, 0.0, 1.0, 100.0), SweepStep::Done);
        let heavier = AutoSweep::default();
        let SweepStep::MassRatio(m) = heavier.step(0.15, 2.0, 1.0, 100.0) else {
            panic!("a mass step")
        };
        assert!((m - 2.0 * 0.05f64.exp()).abs() < 1e-12);
        // From the viscous model a mass sweep starts at the slider's m/m0.
        assert_eq!(heavier.step(0.15, 0.0, 3.0, 0.0), SweepStep::MassRatio(3.0));
        let lighter = AutoSweep {
            target: SweepTarget::MassRatio,
            rate: -1.0,
        };
        assert_eq!(lighter.step(0.15, 1.1e-3, 1.0, 100.0), SweepStep::Done);
        // Bad times or rates move nothing.
        assert_eq!(up.step(0.1, 0.0, 1.0, f64::NAN), SweepStep::Alpha(0.1));
        let broken = AutoSweep {
            target: SweepTarget::Alpha,
            rate: f64::INFINITY,
        };
        assert_eq!(broken.step(0.1, 0.0, 1.0, 1.0), SweepStep::Alpha(0.1));
    }
}
