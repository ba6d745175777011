//! Bodies designed for a property: the harmonic coefficients up to degree L searched for a body
//! that meets chosen targets (a critical angle, a window of hysteresis, period doubling, a
//! drift, a number of orbits) under the constraints of a
//! printer (convex, a smallest radius of curvature in mm, an amplitude bound), then checked at
//! the precise setting over the band a bench brings before anything is reported.
//!
//! | file | what it owns |
//! |---|---|
//! | [`space`] | the vector of coefficients ↔ the body, and what makes a body printable |
//! | [`targets`] | each target, measured on a body by the analysis that answers it, and how far it is |
//! | [`mod@check`] | the independent check over α ± δα, m/m0 ± 20 % and print errors of ± ε mm, with margins |
//! | [`at_scale`] | what the design does on each target's ramp, in mm and s at the printed scale |
//! | `start` | where a search starts: the given body, the seed's first convex body, or (doubling) the best of 24 screened |
//! | `why_not` | why a design does not hold ([`Design::why_not`]), for the command line and Python |
//!
//! The optimiser is CMA-ES from the `cmaes` crate rather than one of our own: the objective is
//! non-smooth (α* is a maximum over the surface, a cylinder rolls or stops), has 8 to 77
//! variables, and needs no gradient; CMA-ES is the standard tool for that, and the crate is
//! seeded and evaluates a generation in parallel with the results kept in order, so a design is
//! the same for a seed whatever the thread count. The objective ranks bodies in tiers: not star-
//! shaped, then not convex, then too sharp for the printer, then how far the targets are
//! (ln(1 + Σ violation²), below every tier); it is met when every target is within half its
//! tolerance. A wall-clock budget is the caller's: a stop flag ends the search between
//! generations with the best body so far, which is then checked like any other.

pub mod at_scale;
mod budget;
pub mod check;
pub mod space;
mod start;
pub mod targets;
mod why_not;

use std::sync::atomic::{AtomicBool, Ordering};

use cmaes::{CMAESOptions, DVector, TerminationReason};
use rayon::prelude::*;
use serde::Serialize;

pub use at_scale::{OrbitAtScale, RampPrediction};
pub use budget::{MAX_BUDGET_S, check_budget, with_budget};
pub use check::{Band, Check, DEFAULT_BAND, TargetCheck, check, failure_bound};
pub use space::{DesignSpace, MAX_DESIGN_MODES, Printability};
pub use start::{DOUBLING_SCREEN_SEEDS, DOUBLING_SCREEN_SIGMAS};
pub use targets::{Setting, Target, TargetError};

use at_scale::{predict_at_scale, ramps};

use crate::analysis::rest::critical_angle::critical_angle;
use crate::dynamics::models::asks_for_inertia;
use crate::geometry::Body;

/// The objective at which every target is within half its tolerance (ln(1 + 0.5²)).
const MET_OBJECTIVE: f64 = 0.223_143_551_314_209_7;
/// Most generations a design may ask for.
pub const MAX_GENERATIONS: usize = 100_000;
/// Most stable orbits an orbits target may ask for.
pub const MAX_ORBITS: usize = 16;
/// Most print errors a check may draw.
pub const MAX_DRAWS: usize = 10_000;

/// Millimetres per ⟨r⟩ when neither the caller nor the start body's file names a scale: the
/// authors' prints.
pub const DEFAULT_SCALE_MM: f64 = 10.0;

/// The smallest radius of curvature a printer makes by default, in mm (a 0.4 mm nozzle).
pub const DEFAULT_MIN_RADIUS_MM: f64 = 0.4;
/// The largest |a_l| (2D) or |A_lm| (3D) allowed by default.
pub const DEFAULT_MAX_AMPLITUDE: f64 = 1.0;
/// The most generations a search runs by default.
pub const DEFAULT_GENERATIONS: usize = 400;
/// The highest degree L of the modes a search uses by default (the authors' printed sphere's).
pub const DEFAULT_MODES: u32 = 4;
/// The seed of a search's start and of its steps by default.
pub const DEFAULT_SEED: u64 = 1;

/// What to design.
#[derive(Debug, Clone)]
pub struct DesignOptions {
    /// Which bodies are searched.
    pub space: DesignSpace,
    /// What the body must do (at least one).
    pub targets: Vec<Target>,
    /// Millimetres per ⟨r⟩ of the printed body.
    pub scale_mm: f64,
    /// The smallest radius of curvature the printer can make (mm).
    pub min_radius_mm: f64,
    /// The largest |a_l| (2D) or |A_lm| (3D) allowed.
    pub max_amplitude: f64,
    /// Where to start: a given body (`--from`), or `None` for the first convex random body from
    /// `seed` (σ = 0.08 in 2D, 0.1 in 3D).
    pub start: Option<Body>,
    /// The seed of the start and of the optimiser.
    pub seed: u64,
    /// Most generations of the optimiser.
    pub max_generations: usize,
    /// The band of the final check.
    pub band: Band,
}

/// Why there is no design.
#[derive(Debug, thiserror::Error)]
pub enum DesignError {
    /// A value outside what `design` accepts.
    #[error("{name} = {value} is not allowed (needs {allowed})")]
    BadInput {
        /// Which value.
        name: &'static str,
        /// As given.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    /// Targets asked for in a way that names none, or half of one.
    #[error("{0}")]
    Request(String),
    /// A target could not be measured on the final body.
    #[error(transparent)]
    Target(#[from] TargetError),
    /// The optimiser refused its options.
    #[error("the optimiser refused its options: {0}")]
    Optimiser(String),
    /// No convex start could be drawn.
    #[error(transparent)]
    Shape(#[from] crate::geometry::ShapeError),
}

fn bad(name: &'static str, value: impl ToString, allowed: impl ToString) -> DesignError {
    DesignError::BadInput {
        name,
        value: value.to_string(),
        allowed: allowed.to_string(),
    }
}

impl DesignOptions {
    /// Refuses what cannot be designed, naming the value, before any work.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::design::*;
    /// let band = Band { delta_alpha: 0.005, mass_fraction: 0.2, surface_mm: 0.1, draws: 8, seed: 1 };
    /// let mut o = DesignOptions {
    ///     space: DesignSpace { dimension: 3, modes: 4 },
    ///     targets: vec![Target::Hysteresis { mass: 10.0, fraction: 0.8 }],
    ///     scale_mm: 10.0, min_radius_mm: 0.4, max_amplitude: 1.0, start: None, seed: 1,
    ///     max_generations: 100, band,
    /// };
    /// let e = o.validate().unwrap_err().to_string();
    /// assert!(e.contains("cylinder"), "{e}");
    /// o.targets = vec![Target::AlphaStar { alpha: f64::NAN }];
    /// assert!(o.validate().unwrap_err().to_string().contains("alpha-star"));
    /// ```
    pub fn validate(&self) -> Result<(), DesignError> {
        let s = &self.space;
        if !(2..=3).contains(&s.dimension) {
            return Err(bad("dim", s.dimension, "2 or 3"));
        }
        if !(2..=MAX_DESIGN_MODES).contains(&s.modes) {
            return Err(bad("modes", s.modes, format!("2 ≤ L ≤ {MAX_DESIGN_MODES}")));
        }
        self.validate_targets_and_band()?;
        if let Some(body) = &self.start
            && s.vector(body).is_none()
        {
            return Err(bad(
                "from",
                format!(
                    "a {}D body of degree {}",
                    body.dimension(),
                    body_degree(body)
                ),
                format!("a {}D body of degree ≤ --modes {}", s.dimension, s.modes),
            ));
        }
        Ok(())
    }

    /// The options [`evaluate`] checks the start body with: these, in the body's own space
    /// ([`DesignSpace::of`]), validated as [`Self::validate`] does except for the search's limit
    /// on the degree (a check searches nothing: a fitted print of degree 24 is checked as it is).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::design::*;
    /// use rollphase_core::geometry::Body;
    /// let band = Band { delta_alpha: 0.005, mass_fraction: 0.2, surface_mm: 0.01, draws: 2, seed: 1 };
    /// let o = DesignOptions {
    ///     space: DesignSpace { dimension: 2, modes: 4 },
    ///     targets: vec![Target::AlphaStar { alpha: 0.1 }],
    ///     scale_mm: 10.0, min_radius_mm: 0.4, max_amplitude: 1.0,
    ///     start: Some(Body::paper_disk(3, 0.08, 10)?), seed: 1, max_generations: 1, band,
    /// };
    /// assert!(o.validate().is_err()); // degree 10 is past the search's 8
    /// assert_eq!(o.for_check()?.space, DesignSpace { dimension: 2, modes: 10 });
    /// // A cylinder is not checked as a sphere.
    /// let sphere = DesignOptions { space: DesignSpace { dimension: 3, modes: 4 }, ..o };
    /// let e = sphere.for_check().unwrap_err().to_string();
    /// assert!(e.contains("from = a 2D body is not allowed (needs a 3D body (--dim 3))"), "{e}");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn for_check(&self) -> Result<DesignOptions, DesignError> {
        let body = self
            .start
            .as_ref()
            .ok_or_else(|| bad("from", "none", "a body to check"))?;
        if body.dimension() != self.space.dimension {
            return Err(bad(
                "from",
                format!("a {}D body", body.dimension()),
                format!("a {0}D body (--dim {0})", self.space.dimension),
            ));
        }
        // The targets are measured by runs of the model, which rolls strictly convex bodies:
        // a dented one's α* and orbits would come back NaN, and its report say so only there.
        if !body.is_convex() {
            return Err(bad(
                "from",
                "a body that is not strictly convex",
                "a strictly convex body (the model rolls no other)",
            ));
        }
        let checked = DesignOptions {
            space: DesignSpace::of(body),
            ..self.clone()
        };
        checked.validate_targets_and_band()?;
        Ok(checked)
    }

    /// The targets, the scale, the printability bounds and the band, as [`Self::validate`]
    /// and [`Self::for_check`] both refuse them.
    fn validate_targets_and_band(&self) -> Result<(), DesignError> {
        let s = &self.space;
        if self.targets.is_empty() {
            return Err(bad("targets", "none", "at least one target"));
        }
        let mut alpha_stars = 0;
        for t in &self.targets {
            if let Some(d) = t.dimension()
                && d != s.dimension
            {
                return Err(bad(
                    "dim",
                    s.dimension,
                    format!(
                        "{d} for the target \"{}\" ({})",
                        t.describe(),
                        if d == 2 { "a cylinder" } else { "a sphere" }
                    ),
                ));
            }
            if matches!(t, Target::AlphaStar { .. }) {
                alpha_stars += 1;
            }
            target_values(t)?;
        }
        if alpha_stars > 1 {
            return Err(bad("alpha-star", "given twice", "one α* target"));
        }
        let positive = |name, v: f64, max: f64| {
            if v.is_finite() && v > 0.0 && v <= max {
                Ok(())
            } else {
                Err(bad(name, v, format!("0 < {name} ≤ {max}")))
            }
        };
        positive("scale-mm", self.scale_mm, 10_000.0)?;
        positive("max-amplitude", self.max_amplitude, 1000.0)?;
        if !(self.min_radius_mm.is_finite() && self.min_radius_mm >= 0.0) {
            return Err(bad(
                "min-radius-mm",
                self.min_radius_mm,
                "a finite length ≥ 0 mm",
            ));
        }
        if !(1..=MAX_GENERATIONS).contains(&self.max_generations) {
            return Err(bad(
                "generations",
                self.max_generations,
                format!("1 ≤ generations ≤ {MAX_GENERATIONS}"),
            ));
        }
        let b = &self.band;
        if !(b.delta_alpha.is_finite() && (0.0..0.5).contains(&b.delta_alpha)) {
            return Err(bad("alpha-band", b.delta_alpha, "0 ≤ δα < 0.5 rad"));
        }
        if !(b.mass_fraction.is_finite() && (0.0..1.0).contains(&b.mass_fraction)) {
            return Err(bad("mass-band", b.mass_fraction, "0 ≤ fraction < 1"));
        }
        if !(b.surface_mm.is_finite() && b.surface_mm >= 0.0 && b.surface_mm < 0.5 * self.scale_mm)
        {
            return Err(bad(
                "surface-mm",
                b.surface_mm,
                "0 ≤ ε < half of --scale-mm",
            ));
        }
        if b.draws > MAX_DRAWS {
            return Err(bad("draws", b.draws, format!("at most {MAX_DRAWS}")));
        }
        Ok(())
    }
}

/// Refuses a target's values outside what it can be designed for, naming the value.
fn target_values(t: &Target) -> Result<(), DesignError> {
    // A ramp the model takes (0 < α < 1.5 rad), and an m/m0 that is finite, 0 (viscous) or more.
    let ramp = |name, alpha: f64| {
        if alpha.is_finite() && alpha > 0.0 && alpha < 1.5 {
            Ok(())
        } else {
            Err(bad(name, alpha, "0 < α < 1.5 rad"))
        }
    };
    let any_mass = |name, mass: f64| {
        if mass.is_finite() && (0.0..=1e4).contains(&mass) {
            Ok(())
        } else {
            Err(bad(name, mass, "0 ≤ m/m0 ≤ 1e4 (0: viscous)"))
        }
    };
    // Positive and finite, and so inertial by the one rule.
    let inertial = |name, mass: f64, most: f64, why| {
        if mass.is_finite() && mass.is_sign_positive() && asks_for_inertia(mass) && mass <= most {
            Ok(())
        } else {
            Err(bad(
                name,
                mass,
                format!("0 < m/m0 ≤ {most:e} ({why} needs inertia)"),
            ))
        }
    };
    match *t {
        Target::AlphaStar { alpha } => {
            if !(alpha.is_finite() && alpha > 0.0 && alpha < 1.5) {
                return Err(bad("alpha-star", alpha, "0 < α* < 1.5 rad"));
            }
        }
        Target::Doubling { mass, alpha } => {
            inertial("doubling m/m0", mass, 1e4, "doubling")?;
            ramp("doubling α", alpha)?;
        }
        Target::Drift { drift, alpha, mass } => {
            if !(drift.is_finite() && drift.abs() <= 10.0) {
                return Err(bad("drift", drift, "a finite |D| ≤ 10 across per down"));
            }
            ramp("drift α", alpha)?;
            any_mass("drift m/m0", mass)?;
        }
        Target::Orbits {
            count,
            alpha,
            mass,
            share,
        } => {
            if !(1..=MAX_ORBITS).contains(&count) {
                return Err(bad("orbits", count, format!("1 ≤ K ≤ {MAX_ORBITS}")));
            }
            if !(share.is_finite() && share > 0.0 && share * count as f64 <= 1.0) {
                let most = 1.0 / count as f64;
                return Err(bad(
                    "share",
                    share,
                    format!("0 < share ≤ 1/K = {most:.4} (each of K orbits)"),
                ));
            }
            ramp("orbits α", alpha)?;
            any_mass("orbits m/m0", mass)?;
        }
        Target::Hysteresis { mass, fraction } => {
            inertial("hysteresis m/m0", mass, 1e6, "hysteresis")?;
            if !(fraction.is_finite() && fraction > 0.0 && fraction < 1.0) {
                return Err(bad("hysteresis fraction", fraction, "0 < F < 1 (of α*)"));
            }
        }
    }
    Ok(())
}

/// The targets as a caller asks for them, one optional value per target, as the command line's
/// flags and Python's keywords carry them: one place turns them into [`Target`]s, so every surface
/// asks the same way and is told the same thing.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TargetRequest {
    /// α* (rad).
    pub alpha_star: Option<f64>,
    /// (m/m0, F) of a hysteresis target.
    pub hysteresis: Option<(f64, f64)>,
    /// m/m0 of a doubling target.
    pub doubling: Option<f64>,
    /// Across per down of a drift target.
    pub drift: Option<f64>,
    /// How many stable orbits an orbits target asks for.
    pub orbits: Option<usize>,
    /// The least share of the starts each of them is reached from (default 1/(2K)).
    pub share: Option<f64>,
    /// m/m0 of a drift or orbits target (default 0: viscous).
    pub mass: Option<f64>,
    /// The ramp angle of a doubling, drift or orbits target (rad).
    pub alpha: Option<f64>,
}

/// How a surface spells the request's values in its messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Spelling {
    /// The ramp angle ("--alpha").
    pub alpha: &'static str,
    /// The m/m0 of a drift or orbits target ("--mass").
    pub mass: &'static str,
    /// The orbits target's share ("--share").
    pub share: &'static str,
    /// Every target, for "give at least one".
    pub targets: &'static str,
}

impl TargetRequest {
    /// The targets asked for, refusing a request that names none, gives a ramp angle or m/m0
    /// to no target that takes one, or a share to no orbits target (values are checked by
    /// [`DesignOptions::validate`]).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::design::{Spelling, Target, TargetRequest};
    /// let spell = Spelling { alpha: "alpha", mass: "mass", share: "share", targets: "alpha_star, …" };
    /// let r = TargetRequest { orbits: Some(2), alpha: Some(0.15), ..Default::default() };
    /// assert_eq!(
    ///     r.targets(&spell)?,
    ///     vec![Target::Orbits { count: 2, alpha: 0.15, mass: 0.0, share: 0.25 }]
    /// );
    /// let r = TargetRequest { drift: Some(0.1), ..Default::default() };
    /// assert!(r.targets(&spell).unwrap_err().to_string().contains("alpha"));
    /// # Ok::<(), rollphase_core::analysis::design::DesignError>(())
    /// ```
    pub fn targets(&self, spell: &Spelling) -> Result<Vec<Target>, DesignError> {
        let refuse = |why: String| Err(DesignError::Request(why));
        let ramp = self.doubling.is_some() || self.drift.is_some() || self.orbits.is_some();
        let alpha = match (self.alpha, ramp) {
            (Some(a), true) => a,
            (None, true) => {
                return refuse(format!(
                    "the doubling, drift and orbits targets need {}, the ramp angle (rad)",
                    spell.alpha
                ));
            }
            (Some(_), false) => {
                return refuse(format!(
                    "{} is the ramp angle of a 3D target (doubling, drift or orbits); give one, \
                     or leave it out",
                    spell.alpha
                ));
            }
            (None, false) => 0.0,
        };
        let on_ramp = self.drift.is_some() || self.orbits.is_some();
        if let Some(m) = self.mass
            && !on_ramp
        {
            return refuse(format!(
                "{} = {m} is the m/m0 of a drift or orbits target; give one, or leave it out \
                 (doubling and hysteresis carry their own)",
                spell.mass
            ));
        }
        if self.share.is_some() && self.orbits.is_none() {
            return refuse(format!(
                "{} is the share of starts of an orbits target; give one, or leave it out",
                spell.share
            ));
        }
        let mass = self.mass.unwrap_or(0.0);
        let mut targets = Vec::new();
        if let Some(alpha) = self.alpha_star {
            targets.push(Target::AlphaStar { alpha });
        }
        if let Some((mass, fraction)) = self.hysteresis {
            targets.push(Target::Hysteresis { mass, fraction });
        }
        if let Some(mass) = self.doubling {
            targets.push(Target::Doubling { mass, alpha });
        }
        if let Some(drift) = self.drift {
            targets.push(Target::Drift { drift, alpha, mass });
        }
        if let Some(count) = self.orbits {
            targets.push(Target::Orbits {
                count,
                alpha,
                mass,
                share: self.share.unwrap_or(0.5 / count.max(1) as f64),
            });
        }
        if targets.is_empty() {
            return refuse(format!("give at least one target: {}", spell.targets));
        }
        Ok(targets)
    }
}

fn body_degree(body: &Body) -> u32 {
    match body {
        Body::Disk(d) => d.modes().iter().map(|m| m.l).max().unwrap_or(0),
        Body::Sphere(s) => s.max_degree(),
    }
}

/// A constraint at the designed body.
#[derive(Debug, Clone, Serialize)]
pub struct Constraint {
    /// Which.
    pub name: &'static str,
    /// Its value at the body.
    pub value: f64,
    /// Its bound.
    pub bound: f64,
    /// (value − bound) relative to the bound's scale: < 0 violated.
    pub slack: f64,
    /// Within 5 % of its bound: it limits the design.
    pub binding: bool,
}

/// One target as the design achieved it.
#[derive(Debug, Clone, Serialize)]
pub struct Achieved {
    /// The target.
    #[serde(flatten)]
    pub target: Target,
    /// Measured at the optimiser's (fast) setting.
    pub fast: f64,
    /// Measured at the precise setting.
    pub precise: f64,
    /// The precise value meets the target.
    pub met: bool,
}

/// Why the search ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Ended {
    /// Every target within half its tolerance on a printable body.
    Met,
    /// The optimiser stopped improving (its step or the objective's spread fell below its tolerance).
    Converged,
    /// The generations ran out.
    Generations,
    /// The caller's stop flag (a time budget, Ctrl-C).
    Stopped,
    /// No search: a given body checked ([`evaluate`]).
    CheckedOnly,
}

/// A designed body and everything known about it.
#[derive(Debug, Clone, Serialize)]
pub struct Design {
    /// The body.
    #[serde(skip)]
    pub body: Body,
    /// Its coefficients in the space's order.
    pub vector: Vec<f64>,
    /// Its α* (rad).
    pub alpha_star: f64,
    /// A cylinder's α* turned end for end (its section mirrored), which the targets hold for
    /// too; `None` for a sphere.
    pub alpha_star_turned: Option<f64>,
    /// Each target.
    pub achieved: Vec<Achieved>,
    /// What a printer sees.
    pub printability: Printability,
    /// The constraints and which bind.
    pub constraints: Vec<Constraint>,
    /// The check over the band.
    pub check: Check,
    /// What the body does on each target's ramp at the printed scale, at the precise setting
    /// (none for a body that is not convex).
    pub predicted: Vec<RampPrediction>,
    /// The objective at the body.
    pub objective: f64,
    /// Generations run.
    pub generations: usize,
    /// Bodies evaluated.
    pub evaluations: usize,
    /// Why the search ended.
    pub ended: Ended,
    /// Where the search started, in words: the given body, the first convex generator body
    /// of the seed, or (a doubling target) the best of the generator bodies screened.
    pub start: String,
}

impl Design {
    /// Every target met at the precise setting, every constraint kept, and the check holds.
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::analysis::design::*;
    /// # fn f(d: &Design) -> bool {
    /// d.holds()
    /// # }
    /// ```
    pub fn holds(&self) -> bool {
        self.achieved.iter().all(|a| a.met)
            && self.constraints.iter().all(|c| c.slack >= 0.0)
            && self.check.holds()
    }
}

/// Progress after each generation.
#[derive(Debug, Clone)]
pub struct DesignProgress {
    /// Generations run.
    pub generation: usize,
    /// Of at most this many.
    pub max_generations: usize,
    /// The best objective so far.
    pub best: f64,
    /// The best body so far, as a vector of the design space ([`DesignSpace::body`] makes it
    /// a body): the app rolls it on the ramp while the search goes on.
    pub best_vector: Vec<f64>,
}

/// The objective of vector `x` (lower is better; see the module doc).
fn objective(opts: &DesignOptions, x: &[f64], extra_room: f64) -> f64 {
    let over = opts.space.largest_amplitude(x) / opts.max_amplitude - 1.0;
    if over > 0.0 {
        return 1e8 * (1.0 + over);
    }
    let body = opts.space.body(x);
    let p = Printability::of(&body, opts.scale_mm);
    if p.smallest_r <= 0.0 {
        return 1e6 * (1.0 - p.smallest_r);
    }
    if !p.convex {
        return 1e4 * (1.0 - p.convexity_min.min(0.0));
    }
    if p.smallest_radius_mm < opts.min_radius_mm {
        return 1e2 * (2.0 - p.smallest_radius_mm / opts.min_radius_mm);
    }
    // Each target is aimed at where the band is hardest for it (the lightest m/m0, the ramp δα
    // lower), so that the check has room to pass.
    let alpha_star = critical_angle(&body).alpha_star;
    let alpha_room = opts.band.delta_alpha / alpha_star.max(1e-9);
    let mut sum = 0.0;
    let mut printed_alpha_star = None;
    // The random starts a target runs from (drift, orbits) are seeded by the body itself: a
    // sample fixed for every body would let the search find bodies whose few starts happen to
    // miss an orbit, where a fresh sample for each body leaves it only noise.
    let setting = Setting {
        seed: seed_of(x),
        ..Setting::FAST
    };
    for t in &opts.targets {
        let factors = t.optimiser_factors(opts.band.mass_fraction);
        match t.measure_at(&body, &factors, 0.0, &setting) {
            // The worst of the factors: the largest value for each target but α*'s, whose
            // value is the same at every m/m0.
            Ok(v) => {
                let worst = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let room = match t {
                    Target::Hysteresis { .. } => alpha_room + extra_room,
                    _ => extra_room,
                };
                sum += t.violation(worst, room).powi(2);
                // A sphere designed to roll must roll from every start across the band: α* a
                // little below the lowest ramp, in units of 1e-3 rad, printed as well as drawn.
                if let Target::Doubling { alpha, .. }
                | Target::Drift { alpha, .. }
                | Target::Orbits { alpha, .. } = t
                {
                    let highest = alpha - opts.band.delta_alpha - 0.002;
                    let top = *printed_alpha_star
                        .get_or_insert_with(|| highest_printed_alpha_star(opts, x, alpha_star));
                    let over = (top - highest).max(0.0) / 1e-3;
                    sum += over * over;
                }
            }
            // A body a target cannot be measured on ranks just below the printable ones.
            Err(_) => return 99.0,
        }
    }
    (1.0 + sum).ln().min(98.0)
}

/// A seed drawn from the bits of `x` (SplitMix64's mixer over them): the same vector always
/// gives the same seed, on every machine and build.
fn seed_of(x: &[f64]) -> u64 {
    let mix = |mut z: u64| {
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    x.iter().fold(0x9E37_79B9_7F4A_7C15, |h, v| {
        mix(h ^ v.to_bits()).wrapping_add(0x9E37_79B9_7F4A_7C15)
    })
}

/// Print errors the optimiser draws of its own, to keep a rolling design's α* below the ramp
/// once printed.
const OPTIMISER_DRAWS: usize = 4;

/// The highest of `alpha_star` (the design's, vector `x`) and the α* of [`OPTIMISER_DRAWS`] print
/// errors of the band's size added to it, seeded apart from the check's so that the check stays
/// independent: a print error of ε mm tilts the surface by about ε/λ, and moves α* by as much.
fn highest_printed_alpha_star(opts: &DesignOptions, x: &[f64], alpha_star: f64) -> f64 {
    let band = Band {
        seed: opts.band.seed.wrapping_add(0x005E_ED0F_0971_A115),
        ..opts.band
    };
    (0..OPTIMISER_DRAWS)
        .map(|i| {
            let printed = check::with_print_error(&opts.space, x, &band, opts.scale_mm, i);
            critical_angle(&printed).alpha_star
        })
        .fold(alpha_star, f64::max)
}

/// Designs a body (see the module doc), `stop` ending the search between generations and
/// `progress` told after each.
///
/// # Example
/// ```
/// use std::sync::atomic::AtomicBool;
/// use rollphase_core::analysis::design::*;
/// let band = Band { delta_alpha: 0.005, mass_fraction: 0.2, surface_mm: 0.05, draws: 4, seed: 1 };
/// let opts = DesignOptions {
///     space: DesignSpace { dimension: 2, modes: 4 },
///     targets: vec![Target::AlphaStar { alpha: 0.2 }],
///     scale_mm: 10.0, min_radius_mm: 0.4, max_amplitude: 1.0, start: None, seed: 1,
///     max_generations: 300, band,
/// };
/// let d = design_until(&opts, &AtomicBool::new(false), &|_| {})?;
/// assert_eq!(d.ended, Ended::Met);
/// assert!((d.alpha_star - 0.2).abs() < 1e-4 && d.printability.convex);
/// # Ok::<(), DesignError>(())
/// ```
pub fn design_until(
    opts: &DesignOptions,
    stop: &AtomicBool,
    progress: &dyn Fn(DesignProgress),
) -> Result<Design, DesignError> {
    opts.validate()?;
    let space = &opts.space;
    let (x0, start) = start::search_start(opts, stop)?;
    progress(DesignProgress {
        generation: 0,
        max_generations: opts.max_generations,
        best: objective(opts, &x0, 0.0),
        best_vector: x0.clone(),
    });
    let mut x = x0;
    let (mut generations, mut evaluations, mut extra_room) = (0, 0, 0.0);
    let mut sigma = if space.dimension == 2 { 0.05 } else { 0.08 };
    for round in 0..=MAX_ROUNDS {
        let found = search(opts, x, sigma, extra_room, generations, stop, progress)?;
        (x, generations) = (found.x, found.generations);
        evaluations += found.evaluations;
        let mut design = finish(
            opts,
            x.clone(),
            found.value,
            generations,
            evaluations,
            found.ended,
        )?;
        design.start = start.clone();
        // A target met at its aim but not over the band: aim again, as much lower as it missed
        // by (and 1 % more), from where this round ended.
        let deficit = design
            .check
            .targets
            .iter()
            .filter(|c| c.margin < 0.0 && !matches!(c.target, Target::AlphaStar { .. }))
            .map(|c| match c.target {
                Target::Hysteresis { .. } => -c.margin / design.alpha_star,
                _ => -c.margin,
            })
            .fold(0.0, f64::max);
        if found.ended != Ended::Met
            || deficit == 0.0
            || round == MAX_ROUNDS
            || generations >= opts.max_generations
            // Stopped while this round's body was checked: that body is the answer, not a
            // round that stops at once and checks it again.
            || stop.load(Ordering::Relaxed)
        {
            return Ok(design);
        }
        extra_room += deficit + 0.01;
        sigma *= 0.5;
    }
    unreachable!("the last round returns")
}

/// A given body (`opts.start`, which must be set) measured, constrained and checked against
/// the targets as a design would be, without a search: what `design` would say of a body you
/// have (the authors' printed sphere, last week's print).
///
/// # Example
/// ```
/// use rollphase_core::analysis::design::*;
/// use rollphase_core::geometry::Body;
/// let band = Band { delta_alpha: 0.005, mass_fraction: 0.2, surface_mm: 0.02, draws: 2, seed: 1 };
/// let opts = DesignOptions {
///     space: DesignSpace { dimension: 2, modes: 5 },
///     targets: vec![Target::AlphaStar { alpha: 0.0572 }],
///     scale_mm: 10.0, min_radius_mm: 0.4, max_amplitude: 1.0,
///     start: Some(Body::paper_disk(84, 0.12, 5)?), seed: 1, max_generations: 1, band,
/// };
/// let d = evaluate(&opts)?;
/// assert_eq!((d.ended, d.generations), (Ended::CheckedOnly, 0));
/// // α* = 0.05721 as it lies, but 0.0603 turned end for end: a cylinder's target holds both
/// // ways round, and this one does not.
/// assert!((d.alpha_star - 0.0572).abs() < 1e-4 && d.alpha_star_turned.unwrap() > 0.06);
/// assert!(!d.holds() && !d.achieved[0].met);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn evaluate(opts: &DesignOptions) -> Result<Design, DesignError> {
    let opts = &opts.for_check()?;
    let x = opts
        .start
        .as_ref()
        .and_then(|b| opts.space.vector(b))
        .ok_or_else(|| bad("from", "none", "a body to check"))?;
    let value = objective(opts, &x, 0.0);
    let mut design = finish(opts, x, value, 0, 1, Ended::CheckedOnly)?;
    design.start = "the given body".into();
    Ok(design)
}

/// Rounds of [`design_until`]: a search, then one more for each time the check finds a target
/// met but not over the band.
const MAX_ROUNDS: usize = 3;

/// What one search found.
struct Found {
    x: Vec<f64>,
    value: f64,
    generations: usize,
    evaluations: usize,
    ended: Ended,
}

/// One CMA-ES search from `x0` with step `sigma`, its generations counted on from `done`.
fn search(
    opts: &DesignOptions,
    x0: Vec<f64>,
    sigma: f64,
    extra_room: f64,
    done: usize,
    stop: &AtomicBool,
    progress: &dyn Fn(DesignProgress),
) -> Result<Found, DesignError> {
    let mut search = CMAESOptions::new(DVector::from_vec(x0.clone()), sigma)
        .seed(opts.seed.wrapping_add(done as u64))
        .max_generations(opts.max_generations - done)
        .fun_target(MET_OBJECTIVE)
        .build(|x: &DVector<f64>| objective(opts, x.as_slice(), extra_room))
        .map_err(|e| DesignError::Optimiser(format!("{e:?}")))?;
    let ended = loop {
        if stop.load(Ordering::Relaxed) {
            break Ended::Stopped;
        }
        let step = search.next_parallel();
        let best = search.overall_best_individual();
        progress(DesignProgress {
            generation: done + search.generation(),
            max_generations: opts.max_generations,
            best: best.map_or(f64::INFINITY, |b| b.value),
            best_vector: best.map_or_else(|| x0.clone(), |b| b.point.as_slice().to_vec()),
        });
        if let Some(data) = step {
            break if data.reasons.contains(&TerminationReason::FunTarget) {
                Ended::Met
            } else if data.reasons.contains(&TerminationReason::MaxGenerations) {
                Ended::Generations
            } else {
                Ended::Converged
            };
        }
    };
    let (x, value) = match search.overall_best_individual() {
        Some(b) => (b.point.as_slice().to_vec(), b.value),
        None => {
            let value = objective(opts, &x0, extra_room);
            (x0, value)
        }
    };
    Ok(Found {
        x,
        value,
        generations: done + search.generation(),
        evaluations: search.function_evals(),
        ended,
    })
}

/// The designed body measured, constrained and checked.
fn finish(
    opts: &DesignOptions,
    x: Vec<f64>,
    value: f64,
    generations: usize,
    evaluations: usize,
    ended: Ended,
) -> Result<Design, DesignError> {
    let body = opts.space.body(&x);
    let printability = Printability::of(&body, opts.scale_mm);
    let amplitude = opts.space.largest_amplitude(&x);
    let mut constraints = vec![
        Constraint {
            name: "amplitude",
            value: amplitude,
            bound: opts.max_amplitude,
            slack: 1.0 - amplitude / opts.max_amplitude,
            binding: false,
        },
        // Curvature in 1/⟨r⟩: a round body has 1, so the slack is the curvature itself.
        Constraint {
            name: "convexity (smallest curvature, 1/⟨r⟩)",
            value: printability.convexity_min,
            bound: 0.0,
            slack: printability.convexity_min,
            binding: false,
        },
        Constraint {
            name: "smallest radius of curvature (mm)",
            value: printability.smallest_radius_mm,
            bound: opts.min_radius_mm,
            slack: if opts.min_radius_mm > 0.0 {
                printability.smallest_radius_mm / opts.min_radius_mm - 1.0
            } else {
                f64::INFINITY
            },
            binding: false,
        },
    ];
    for c in &mut constraints {
        c.binding = c.slack < 0.05;
    }
    let convex = printability.convex;
    let mut achieved = Vec::new();
    for t in &opts.targets {
        let (fast, precise) = if convex {
            (
                t.measure(&body, 1.0, &Setting::FAST)?,
                t.measure(&body, 1.0, &Setting::PRECISE)?,
            )
        } else {
            (f64::NAN, f64::NAN)
        };
        achieved.push(Achieved {
            target: *t,
            fast,
            precise,
            met: convex && t.met_by(precise),
        });
    }
    let check = if convex {
        check(&opts.space, &x, &opts.targets, &opts.band, opts.scale_mm)?
    } else {
        Check {
            band: opts.band,
            targets: Vec::new(),
            convex_draws: 0,
            smallest_radius_mm: printability.smallest_radius_mm,
            print_failure_bound: None,
        }
    };
    let alpha_star = critical_angle(&body).alpha_star;
    let predicted = if convex {
        ramps(&opts.targets, alpha_star, &opts.band)
            .par_iter()
            .map(|(why, alpha, mass)| {
                predict_at_scale(&body, why, *alpha, *mass, opts.scale_mm, &Setting::PRECISE)
            })
            .collect::<Result<_, _>>()?
    } else {
        Vec::new()
    };
    let alpha_star_turned = match &body {
        Body::Disk(d) => Some(critical_angle(&Body::Disk(d.turned())).alpha_star),
        Body::Sphere(_) => None,
    };
    Ok(Design {
        alpha_star,
        alpha_star_turned,
        predicted,
        body,
        vector: x,
        achieved,
        printability,
        constraints,
        check,
        objective: value,
        generations,
        evaluations,
        ended,
        start: String::new(),
    })
}
