//! `rollphase period`: the period of a rolling disk and its order parameter 2π/T.

use std::path::PathBuf;

use anyhow::{Result, anyhow, bail};
use clap::Args;
use serde::Serialize;

use crate::analysis::verdict::{Fate, Undecided};
use crate::dynamics::{ModelKind, Ramp};
use crate::geometry::Body;
use crate::simulate::InitialState;
use crate::simulate::period::{PeriodError, PeriodPlan};
use crate::simulate::start::StartRequest;

/// Period T of a rolling disk and its mean angular speed 2π/T, or that it halts.
///
/// Viscous (--mass 0, the default): T = ∫ dθ/θ̇ by adaptive quadrature; the disk halts iff
/// α ≤ α*. Inertial (--mass > 0): simulated from (--theta0, --thetadot0) until successive periods
/// agree to 1e-8, at most --t-max time units; with inertia a disk can keep rolling below α*
/// (hysteresis) and its fate depends on where it starts.
///
/// Within about 1e-8 of α* a viscous T is given with how well it is known (α* is found to a few
/// ulps, and T grows as (α − α*)^−½), and within a few ulps of α* none is: undecided. The fate's
/// words are every command's: periodic, halted, or undecided with what would decide it.
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct PeriodArgs {
    /// Shape file of a disk (JSON, "kind": "disk").
    pub file: PathBuf,
    /// Ramp angle α in radians, 1e-9 ≤ α < π/2.
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: f64,
    /// Mass ratio m/m0 ≥ 0 (0: viscous model).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub mass: f64,
    /// The drag law's parameters (one flag per registered law).
    #[command(flatten)]
    pub drag_law: super::drag_law::DragLawArgs,
    /// Inertial: initial contact angle θ₀.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub theta0: f64,
    /// Inertial: initial θ̇₀.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub thetadot0: f64,
    /// Inertial: longest simulated time.
    #[arg(long, default_value_t = 5000.0)]
    pub t_max: f64,
    /// Inertial: DOP853 relative tolerance.
    #[arg(long, default_value = "1e-10")]
    pub rtol: f64,
    /// Print JSON (keys period, mean_angular_speed (null when undecided), halts, converged,
    /// note, fate, …).
    #[arg(long)]
    pub json: bool,
}

/// What `period --json` prints.
#[derive(Debug, Serialize)]
pub struct PeriodReport {
    /// Time for θ to advance 2π; null when the disk halts.
    pub period: Option<f64>,
    /// 2π/T; 0 when it halts; null when undecided (neither is known).
    pub mean_angular_speed: Option<f64>,
    /// Whether it comes to rest: `fate` is "halted".
    pub halts: bool,
    /// Whether the number is converged (quadrature error ≤ 1e-9, or periodic to 1e-8).
    pub converged: bool,
    /// disk-viscous or disk-inertial.
    pub model: ModelKind,
    /// Why no period is given when the disk neither rolls periodically nor halts (what would
    /// decide it); otherwise a note on the model chosen, or null.
    pub note: Option<String>,
    /// The run's fate in the words every command uses: `fate` ("periodic", with
    /// `multiplicity`; "halted"; "undecided", with `why`).
    #[serde(flatten)]
    pub fate: crate::analysis::verdict::Fate,
    /// α (rad).
    pub alpha: f64,
    /// α* of the disk (rad).
    pub alpha_star: f64,
    /// m/m0.
    pub mass_ratio: f64,
    /// The drag law: one field per registered parameter, named by its key.
    #[serde(flatten)]
    pub drag_law: crate::dynamics::DragLaw,
}

/// Runs `period`.
pub fn run(a: PeriodArgs) -> Result<()> {
    let body = super::load_body(&a.file)?;
    if !matches!(body, Body::Disk(_)) {
        bail!(
            "{} is a 3D sphere; `period` is for disks. A sphere's orbits are found by simulation: \
             use `rollphase simulate`",
            a.file.display()
        );
    }
    // A dented body or a print's outline rolls on its hull: the viscous period is exact there.
    body.check_rollable()?;
    let ramp = Ramp::new(a.alpha, a.mass)?.with_drag_law(a.drag_law.law()?);
    if !(a.t_max.is_finite() && a.t_max > 0.0 && a.t_max <= crate::integrate::MAX_SPAN) {
        bail!(
            "--t-max {} is not allowed (needs 0 < t_max ≤ {}: past that the integrator's \
             smallest step, 16 ε × t_max, exceeds the steps an orbit needs)",
            super::short(a.t_max),
            super::short(crate::integrate::MAX_SPAN)
        );
    }
    // The start checked as `simulate` checks it: --thetadot0 with --mass 0 is an error, not
    // ignored (the viscous period does not depend on where the disk starts).
    let request = StartRequest {
        theta0: Some(a.theta0),
        theta_dot0: Some(a.thetadot0).filter(|v| *v != 0.0),
        ..StartRequest::default()
    };
    let InitialState::Disk { theta0, theta_dot0 } =
        super::simulate::checked_start(&body, &a.file, a.mass, &request)?
    else {
        bail!("{} is not a disk", a.file.display());
    };
    // The model as `simulate` chooses it (the viscous limit at m/m0 ≤ rtol, said in the
    // note); above it a warning when the inertial run would take minutes.
    let plan = PeriodPlan::new(&body, ramp, a.rtol).map_err(|e| match e {
        PeriodError::OnHull(why) => anyhow!("{}: {why}", a.file.display()),
        e => e.into(),
    })?;
    let (ramp, model, alpha_star) = (plan.ramp, plan.model, plan.alpha_star);
    if model.is_inertial() {
        super::warn_if_stiff(&body, &ramp, a.t_max, "--t-max");
    }
    let never = std::sync::atomic::AtomicBool::new(false);
    let p = plan
        .run(theta0, theta_dot0, a.t_max, &never)?
        .ok_or_else(|| anyhow!("the period run was stopped"))?;
    let (fate, period) = (p.fate, p.period);
    let note = match fate {
        Fate::Undecided { why } => Some(match why {
            Undecided::AtThreshold { .. } => why.what_would_decide(),
            _ => format!(
                "T is not measurable within --t-max {}: {}{}",
                super::short(a.t_max),
                why.what_would_decide(),
                crate::analysis::orbits::disk_period::coarse_rtol_hint(&why, a.rtol, "--rtol")
            ),
        }),
        // A period known to less than 1e-9 says how well beside the number.
        _ => match (p.caveat.clone(), plan.note.clone()) {
            (Some(caveat), Some(note)) => Some(format!("{caveat}; {note}")),
            (caveat, note) => caveat.or(note),
        },
    };
    let report = PeriodReport {
        note: note.clone(),
        fate,
        period,
        mean_angular_speed: p.mean_angular_speed,
        // The fate's word, as a flag (kept for scripts that read it).
        halts: matches!(fate, Fate::Halted { .. }),
        converged: p.converged,
        model,
        alpha: a.alpha,
        alpha_star,
        mass_ratio: a.mass,
        drag_law: ramp.drag_law,
    };
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&report)?)?;
    } else {
        outln!(
            "{model}, α = {} rad (α* = {:.10}){}",
            a.alpha,
            alpha_star,
            super::drag_law::describe(&ramp.drag_law)
        )?;
        match (fate, period, &p.caveat) {
            (Fate::Periodic { .. }, Some(t), None) => outln!(
                "  periodic: T = {t:.12}, 2π/T = {:.12}",
                p.mean_angular_speed.unwrap_or(f64::NAN)
            )?,
            // Only the digits that are known.
            (Fate::Periodic { .. }, Some(t), Some(caveat)) => {
                let digits = (-p.relative_error.log10()).floor().clamp(1.0, 14.0) as usize;
                outln!(
                    "  periodic: T = {t:.digits$e}, 2π/T = {:.digits$e}  ({caveat})",
                    p.mean_angular_speed.unwrap_or(f64::NAN)
                )?
            }
            (Fate::Halted { .. }, _, _) => outln!("  halted: 2π/T = 0")?,
            _ => outln!("  undecided: {}", note.clone().unwrap_or_default())?,
        }
        if let Some(n) = &plan.note
            && !matches!(fate, Fate::Undecided { .. })
        {
            outln!("  note: {n}")?;
        }
    }
    Ok(())
}
