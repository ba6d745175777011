//! `rollphase predict`: the stable periodic motions a body settles into, in the lab's terms.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use serde::Serialize;

use crate::analysis::experiment::prediction::{
    MAX_PREDICT_STARTS, PredictOptions, PredictedOrbit, Prediction, predict,
};
use crate::analysis::orbits::sphere_orbits::Decide;
use crate::analysis::verdict::{FateCounts, Stability};
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::dynamics::ModelKind;
use crate::geometry::{Body, ShapeFile};
use crate::output::{self, Inputs};

/// What a body does on a ramp: the periodic motions it settles into from many starts.
///
/// Runs from rest at --starts random orientations (3D) or equally spaced contact angles (2D) go
/// on until they settle on a periodic motion or come to rest. Each motion found is listed with
/// the fraction of starts that reach it, its period (t0 = γ/(F⟨r⟩)), how far the centre moves
/// down and across the ramp per period (⟨r⟩, and mm when the shape file has "scale_mm", as a
/// body fitted by `shape --from-mesh` does), its mean speed, and its Floquet multipliers (3D
/// period-1 orbits; stable when every |μ| < 1). With inertia (--mass > 0) a 3D orbit may be
/// doubled (period 2): its period and advances are then per repeat, two crossings of ∂Ω.
///
/// Every start gets one fate, printed with its share: periodic (settled on an orbit that
/// attracts), neutral (|μ| = 1 within the multipliers' accuracy or too close to act within
/// --t-cap: a round ball rolls straight on whatever great circle it starts on, listed as one
/// family), halted (still, and the weight's torque zero), left the model (with inertia the
/// contact force is followed: a body that would leave the ramp stops there, and an orbit that
/// does is never stable), or undecided, saying why and what would decide it.
///
/// Seconds need the time unit t0, which depends on the surface's drag: `rollphase track` fits
/// it from a filmed run. For example, the paper authors' printed sphere at sin α = 0.2:
///   rollphase shape --from-mesh printed-sphere.stl -o printed-sphere.json
///   rollphase predict printed-sphere.json --alpha 0.2014 --figure paths.png
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct PredictArgs {
    /// Shape file (JSON), of a disk or a sphere.
    pub file: PathBuf,
    /// Ramp angle α in radians, 1e-9 ≤ α < π/2 (sin α = 0.2 is α = 0.2014).
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: f64,
    /// Mass ratio m/m0 ≥ 0 (0: the viscous model).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub mass: f64,
    /// The drag law's parameters (one flag per registered law).
    #[command(flatten)]
    pub drag_law: super::drag_law::DragLawArgs,
    /// Starts from rest: random orientations (3D) or contact angles (2D), 1 to 100000.
    #[arg(long, default_value_t = 32)]
    pub starts: usize,
    /// Seed of the random orientations.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Longest run (t0): a start neither periodic nor at rest by then is counted as undecided.
    #[arg(long, default_value_t = 20_000.0)]
    pub t_cap: f64,
    /// Print JSON (keys orbits [period, advance_down, advance_across, stable, fraction, …],
    /// halts, undecided, alpha_star, scale_mm).
    #[arg(long)]
    pub json: bool,
    /// Also draw each orbit's centre path over three periods as a PNG (from above for a
    /// sphere: down the ramp against across it; from the side for a disk).
    #[arg(long, value_name = "FILE.png")]
    pub figure: Option<PathBuf>,
}

/// One orbit as `predict --json` prints it.
#[derive(Debug, Serialize)]
pub struct OrbitReport {
    /// The orbit in the model's units.
    #[serde(flatten)]
    pub orbit: PredictedOrbit,
    /// Advance down the ramp per repeat in mm (`null` without a scale).
    pub advance_down_mm: Option<f64>,
    /// Advance across the ramp per repeat in mm.
    pub advance_across_mm: Option<f64>,
}

/// What `predict --json` prints.
#[derive(Debug, Serialize)]
pub struct PredictReport {
    /// The shape file.
    pub body: String,
    /// The model's registry name ("sphere-viscous", "disk-inertial", …).
    pub model: ModelKind,
    /// Millimetres per ⟨r⟩ (from the shape file), `null` if it has none.
    pub scale_mm: Option<f64>,
    /// α, α*, the fractions and counts.
    #[serde(flatten)]
    pub prediction: PredictionHead,
    /// The stable periodic motions, most visited first.
    pub orbits: Vec<OrbitReport>,
}

/// The prediction without its orbits.
#[derive(Debug, Serialize)]
pub struct PredictionHead {
    /// 2 or 3.
    pub dimension: u32,
    /// α (rad).
    pub alpha: f64,
    /// m/m0.
    pub mass_ratio: f64,
    /// The drag law: one field per registered parameter, named by its key.
    #[serde(flatten)]
    pub drag_law: crate::dynamics::DragLaw,
    /// α* (rad).
    pub alpha_star: f64,
    /// Starts tried.
    pub starts: usize,
    /// Fraction of starts that come to rest.
    pub halts: f64,
    /// Fraction undecided at --t-cap.
    pub undecided: f64,
    /// Every start's fate: fractions periodic, neutral, halted, left_model, undecided, with
    /// `undecided_reasons` and `first_violation`.
    pub fates: FateCounts,
}

/// Runs `predict`.
pub fn run(a: PredictArgs) -> Result<()> {
    let (body, scale) = ShapeFile::load_scaled(&a.file)?;
    // A dented cylinder or a print's outline rolls on its hull; a sphere must be convex.
    body.check_rollable()?;
    crate::dynamics::Ramp::new(a.alpha, a.mass)?;
    let drag_law = a.drag_law.law()?;
    if !(1..=MAX_PREDICT_STARTS).contains(&a.starts) {
        bail!(
            "--starts {} is not allowed (needs 1 ≤ starts ≤ {MAX_PREDICT_STARTS})",
            a.starts
        );
    }
    if !(a.t_cap.is_finite() && a.t_cap >= 10.0 && a.t_cap <= crate::integrate::MAX_SPAN) {
        bail!(
            "--t-cap {} is not allowed (needs 10 ≤ t_cap ≤ {}: a run must have time to settle)",
            super::short(a.t_cap),
            super::short(crate::integrate::MAX_SPAN)
        );
    }
    let inputs = Inputs::of([&a.file]);
    if let Some(f) = &a.figure {
        output::check_file(f, &inputs)?;
    }
    let ramp = crate::dynamics::Ramp::new(a.alpha, a.mass)?.with_drag_law(drag_law);
    if ModelKind::of(&body, &ramp).is_inertial() {
        super::warn_if_stiff(&body, &ramp, a.t_cap, "--t-cap");
    }
    let options = PredictOptions {
        starts: a.starts,
        seed: a.seed,
        decide: Decide {
            t_min: 600f64.min(a.t_cap),
            t_cap: a.t_cap,
            max_k: 2,
            tol: 1e-5,
        },
        drag_law,
        ..PredictOptions::default()
    };
    let spinner = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        indicatif::ProgressBar::new_spinner()
    } else {
        indicatif::ProgressBar::hidden()
    };
    spinner.set_message(format!("{} runs from rest…", a.starts));
    spinner.enable_steady_tick(std::time::Duration::from_millis(200));
    let p = predict(&body, a.alpha, a.mass, &options)?;
    spinner.finish_and_clear();
    let mut outputs = output::OutputSet::new();
    if let Some(f) = &a.figure {
        let true_scale = path_panel(&p, &body, scale);
        let mut magnified = true_scale.clone();
        magnified.equal_aspect = false;
        magnified.title = "the same paths, the vertical axis magnified".into();
        let png = crate::chart::png_bytes(&[true_scale, magnified], 1, (1100, 1100))?;
        outputs.write(f, &png, &inputs)?;
    }
    let report = report_of(&a, p, scale);
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&report)?)?;
    } else {
        print_table(&report)?;
    }
    outputs.commit()?;
    Ok(())
}

fn report_of(a: &PredictArgs, p: Prediction, scale: Option<f64>) -> PredictReport {
    let orbits = p
        .orbits
        .into_iter()
        .map(|orbit| OrbitReport {
            advance_down_mm: scale.map(|s| s * orbit.advance_down),
            advance_across_mm: scale.map(|s| s * orbit.advance_across),
            orbit,
        })
        .collect();
    PredictReport {
        body: a.file.display().to_string(),
        model: p.model,
        scale_mm: scale,
        prediction: PredictionHead {
            dimension: p.dimension,
            alpha: p.alpha,
            mass_ratio: p.mass_ratio,
            drag_law: p.drag_law,
            alpha_star: p.alpha_star,
            starts: p.starts,
            halts: p.halts,
            undecided: p.undecided,
            fates: p.fates,
        },
        orbits,
    }
}

fn print_table(r: &PredictReport) -> Result<()> {
    let h = &r.prediction;
    outln!(
        "{}: {}D, {} model, α = {} rad (sin α = {:.4}; α* = {:.4}){}{}",
        r.body,
        h.dimension,
        r.model,
        h.alpha,
        h.alpha.sin(),
        h.alpha_star,
        if r.model.is_inertial() {
            format!(", m/m0 = {}", h.mass_ratio)
        } else {
            String::new()
        },
        super::drag_law::describe(&h.drag_law)
    )?;
    print_fates(h)?;
    if r.orbits.is_empty() {
        return Ok(());
    }
    let unit = if r.scale_mm.is_some() {
        "mm"
    } else {
        "⟨r⟩"
    };
    outln!(
        "  {:<6} {:>9} {:>9} {:>12} {:>12} {:>12} {:>10} {:>8}",
        "orbit",
        "fraction",
        "repeat",
        "period (t0)",
        format!("down ({unit})"),
        format!("across ({unit})"),
        "speed",
        "|μ| max"
    )?;
    for (i, o) in r.orbits.iter().enumerate() {
        let k = &o.orbit;
        let (down, across) = match (o.advance_down_mm, o.advance_across_mm) {
            (Some(d), Some(c)) => (d, c),
            _ => (k.advance_down, k.advance_across),
        };
        outln!(
            "  {:<6} {:>8.1}% {:>9} {:>12.4} {:>12.4} {:>12.4} {:>10.5} {:>8}",
            i + 1,
            100.0 * k.fraction,
            if k.repeat == 2 { "2 doubled" } else { "1" },
            k.period,
            down,
            across,
            k.speed,
            k.max_modulus
                .map_or_else(|| "–".to_string(), |m| format!("{m:.4}"))
        )?;
    }
    let all_stable = r.orbits.iter().all(|o| o.orbit.stable);
    outln!(
        "  per repeat; speed in ⟨r⟩/t0{}",
        if all_stable {
            "; every motion listed is stable"
        } else {
            ""
        }
    )?;
    for (i, o) in r.orbits.iter().enumerate() {
        let k = &o.orbit;
        if let Some(t) = k.contact.and_then(|c| c.lift_off_t) {
            outln!(
                "  orbit {}: leaves the ramp {t:.2} t0 after its ∂Ω crossing (the normal force \
                 falls to 0, min N/F = {:.3}): not a motion the body can make; the rolling model \
                 does not hold on it",
                i + 1,
                k.contact.map_or(f64::NAN, |c| c.min_normal_force)
            )?;
        }
        match k.stability {
            Stability::Neutral => outln!(
                "  orbit {}: neutral (|μ| max {}): {}; none attracts, each start rolls on its \
                 own",
                i + 1,
                k.max_modulus
                    .map_or_else(|| "–".to_string(), |m| format!("{m:.6}")),
                if k.members > 1 {
                    format!(
                        "a family of {} orbits with the same period and speed",
                        k.members
                    )
                } else {
                    "one of a family of motions".to_string()
                }
            )?,
            Stability::Unstable => outln!("  orbit {}: unstable (|μ| max ≥ 1)", i + 1)?,
            Stability::Stable => {}
        }
    }
    if let Some(c) = r.orbits.iter().find_map(|o| o.orbit.contact) {
        let worst = r
            .orbits
            .iter()
            .filter_map(|o| o.orbit.contact)
            .fold(c, |a, b| {
                if b.min_normal_force < a.min_normal_force {
                    b
                } else {
                    a
                }
            });
        outln!(
            "  contact along the orbits: N/F ≥ {:.3}, friction needed μ ≤ {:.3}",
            worst.min_normal_force,
            r.orbits
                .iter()
                .filter_map(|o| o.orbit.contact)
                .map(|c| c.max_friction_needed)
                .fold(0.0, f64::max)
        )?;
    }
    Ok(())
}

/// How the starts ended, one line per kind that happened.
fn print_fates(h: &PredictionHead) -> Result<()> {
    let f = &h.fates;
    let pct = |x: f64| format!("{:.1} %", 100.0 * x);
    let mut parts = Vec::new();
    for (share, words) in [
        (f.periodic, "settle on a periodic motion below"),
        (
            f.neutral,
            "roll on a neutral motion (|μ| max within the band around 1: no single orbit \
             attracts within --t-cap)",
        ),
        (f.halted, "come to rest"),
        (f.left_model, "leave the rolling model"),
        (f.undecided, "undecided"),
    ] {
        if share > 0.0 {
            parts.push(format!("{} {words}", pct(share)));
        }
    }
    outln!("  {} starts from rest: {}", h.starts, parts.join(", "))?;
    if let Some(v) = f.first_violation {
        outln!("  left the model: the first {}", v.headline())?;
    }
    for u in &f.undecided_reasons {
        outln!("  undecided ({}): {}", pct(u.fraction), u.what_would_decide)?;
    }
    if f.periodic == 0.0 && f.neutral == 0.0 {
        outln!(
            "  no periodic motion found{}",
            if f.halted == 1.0 {
                ": every start comes to rest"
            } else {
                ""
            }
        )?;
    }
    Ok(())
}

/// Each orbit's centre path, in mm when the body has a scale.
fn path_panel(p: &Prediction, body: &Body, scale: Option<f64>) -> Panel {
    let (k, unit) = scale.map_or((1.0, "⟨r⟩"), |s| (s, "mm"));
    let series = p
        .orbits
        .iter()
        .enumerate()
        .map(|(i, o)| Series {
            label: format!(
                "orbit {}: T = {:.2} t0, {:.1} % of starts{}",
                i + 1,
                o.period,
                100.0 * o.fraction,
                if o.repeat == 2 { ", period 2" } else { "" }
            ),
            points: o.path.iter().map(|c| (k * c[0], k * c[1])).collect(),
            color: PALETTE[i % PALETTE.len()],
            style: Style::Line,
        })
        .collect();
    let sphere = matches!(body, Body::Sphere(_));
    Panel {
        title: format!(
            "centre path over three periods, to scale, α = {:.4} rad{}",
            p.alpha,
            if p.model.is_inertial() {
                format!(", m/m0 = {}", p.mass_ratio)
            } else {
                String::new()
            }
        ),
        x_label: format!("down the ramp ({unit})"),
        y_label: if sphere {
            format!("across the ramp ({unit})")
        } else {
            format!("height of the centre ({unit})")
        },
        log_x: false,
        log_y: false,
        series,
        legend: SeriesLabelPosition::UpperLeft,
        equal_aspect: sphere,
    }
}
