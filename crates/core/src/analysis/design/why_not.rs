//! Why a design does not hold, in short sentences a person acts on: the targets not met at the
//! precise setting, those the check over the band misses and by how much, the runs that do not
//! repeat as a doubling target asks, print errors that dent the body, and what binds or why the
//! search ended before it got there. The one home of that diagnosis: `rollphase design` prints
//! it and Python's report carries it, each naming its own settings.

use super::{Design, Ended, Target};

impl Design {
    /// Why the design does not hold, one reason each (empty when it holds). `setting` writes a
    /// setting's name as the caller's surface spells it (`budget` → `--budget` on the command
    /// line, `budget=` in Python).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::design::*;
    /// use rollphase_core::geometry::Body;
    /// let band = Band { delta_alpha: 0.005, mass_fraction: 0.2, surface_mm: 0.1, draws: 8, seed: 1 };
    /// let opts = DesignOptions {
    ///     space: DesignSpace { dimension: 2, modes: 5 },
    ///     targets: vec![Target::AlphaStar { alpha: 0.0572 }],
    ///     scale_mm: 10.0, min_radius_mm: 0.4, max_amplitude: 1.0,
    ///     start: Some(Body::paper_disk(84, 0.12, 5)?), seed: 1, max_generations: 1, band,
    /// };
    /// // The paper's disk: α* = 0.0572 as it lies, 0.0603 turned end for end.
    /// let d = evaluate(&opts)?;
    /// let why = d.why_not(&|s| format!("--{s}"));
    /// assert!(why[0].starts_with("α* = 0.0572 rad is not met"), "{why:?}");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn why_not(&self, setting: &dyn Fn(&str) -> String) -> Vec<String> {
        if self.holds() {
            return Vec::new();
        }
        let mut why = Vec::new();
        for t in self.achieved.iter().filter(|t| !t.met) {
            let achieved = match t.target {
                Target::Orbits { .. } => format!("short by {:.4} of the starts", t.precise),
                _ => format!("achieved {:.6}", t.precise),
            };
            why.push(format!("{} is not met ({achieved})", t.target.describe()));
        }
        for c in self.check.targets.iter().filter(|c| !c.holds) {
            if c.margin < 0.0 {
                why.push(format!(
                    "{} misses the band by {:.4} {}",
                    c.target.describe(),
                    -c.margin,
                    c.margin_unit
                ));
            }
            if let Some(e) = &c.evidence
                && e.runs.cycle_counts[1] < e.runs.cycle_counts.iter().sum::<usize>()
            {
                why.push(format!(
                    "of {} runs from rest at the target's m/m0, {} repeat after two crossings",
                    e.runs.cycle_counts.iter().sum::<usize>(),
                    e.runs.cycle_counts[1]
                ));
            }
        }
        if !self.check.prints_checked() {
            // `--draws 0` on the command line, `draws=0` in Python.
            let draws = setting("draws");
            let space = if draws.ends_with('=') { "" } else { " " };
            why.push(format!(
                "no print error was drawn ({draws}{space}0): whether a print within ± {} mm \
                 holds is not checked (draw at least 1, or give a surface error of 0 for an \
                 exact print)",
                self.check.band.surface_mm
            ));
        }
        if self.check.convex_draws < self.check.band.draws {
            why.push(format!(
                "{} of {} print errors dent the body",
                self.check.band.draws - self.check.convex_draws,
                self.check.band.draws
            ));
        }
        let binding: Vec<&str> = self
            .constraints
            .iter()
            .filter(|c| c.binding)
            .map(|c| c.name)
            .collect();
        let tries = format!(
            "{}, {} or another {}",
            setting("generations"),
            setting("modes"),
            setting("seed")
        );
        if binding.is_empty() {
            match self.ended {
                Ended::Met | Ended::CheckedOnly => {}
                Ended::Stopped => why.push(format!(
                    "no constraint binds: the {} ran out before the search got there (try a \
                     larger {}, more {tries})",
                    setting("budget"),
                    setting("budget"),
                )),
                Ended::Generations | Ended::Converged => why.push(format!(
                    "no constraint binds: the search ended before it got there (try more {tries})"
                )),
            }
        } else {
            why.push(format!("binding: {}", binding.join(", ")));
            if matches!(self.ended, Ended::Stopped) {
                why.push(format!(
                    "the {} ran out (a larger {} searches further)",
                    setting("budget"),
                    setting("budget")
                ));
            }
        }
        why
    }
}
