//! `bench accuracy`: every model × integrator setting against a converged reference at t = 100,
//! as accuracy.csv (deterministic), timing.csv (wall clock) and work–precision plots; then the
//! same settings measured on the *answers* (fate, multiplicity, period, orbits found) over many
//! starts of the paper's body, raw and as `sweep` checks them, as answers.csv.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;

use super::{bundled, fmt_num, write};
use crate::analysis::accuracy::trajectories::{self, AccuracyRow, Case, REFERENCE};
use crate::assets::{
    DISK as BUNDLED_DISK, DISK_INERTIAL as BUNDLED_DISK_INERTIAL, SPHERE as BUNDLED_SPHERE,
};
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style, render_png};
use crate::dynamics::ModelKind;
use crate::figures::csv_text;
use crate::geometry::Body;
use crate::integrate::Method;

/// Options of `bench accuracy`.
///
/// For each model (2D/3D, viscous/inertial, on the bundled bodies) and each setting (RK4 and
/// CF4 at several steps, DOP853 at several tolerances): state error and orbit-period error at
/// t = 100 against DOP853 at rtol 1e-13, right-hand-side evaluations, wall time and simulated
/// time per wall second. Writes OUT/accuracy.csv (deterministic), OUT/timing.csv (wall
/// clock), OUT/work_precision.png and OUT/period_precision.png.
///
/// Then the answers: on the paper's sphere (seed 219) viscous at α = 0.15 and 0.2 and at
/// m/m0 = 6, α = 0.2, from --starts random orientations, each setting's fate, period
/// multiplicity and period against DOP853 at rtol 1e-12, and the distinct orbits it finds;
/// raw (the setting alone) and checked (as `rollphase sweep` reports them, re-decided by the
/// reference where the setting is coarser). Writes OUT/answers.csv.
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct AccuracyArgs {
    /// Output folder.
    #[arg(long, default_value = "bench-accuracy")]
    pub out: PathBuf,
    /// Runs per setting for the wall time (the minimum is reported).
    #[arg(long, default_value_t = 3)]
    pub repeats: u32,
    /// Reduced run for tests: t = 20, and two tolerances for DOP853; 2 starts per answer case.
    #[arg(long)]
    pub quick: bool,
    /// Random starts per answer case [default: 16, or 2 with --quick].
    #[arg(long)]
    pub starts: Option<usize>,
}

/// Most starts per answer case: each is up to 1500 time units per setting, twice.
const MAX_STARTS: usize = 1000;

/// Most repeats of a timed run.
const MAX_REPEATS: u32 = 100;

fn time_run(
    case: &Case,
    method: Method,
    repeats: u32,
) -> (
    Result<trajectories::Outcome, crate::integrate::IntegrateError>,
    f64,
) {
    let mut best = f64::INFINITY;
    let mut result = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let r = trajectories::run_case(case, method);
        best = best.min(start.elapsed().as_secs_f64());
        result = Some(r);
    }
    (result.expect("at least one repeat"), best)
}

/// The cheapest (fewest RHS evaluations) setting of a model whose period error is < `limit`.
pub fn cheapest_below(rows: &[AccuracyRow], model: ModelKind, limit: f64) -> Option<&AccuracyRow> {
    rows.iter()
        .filter(|r| {
            r.model == model
                && r.failure.is_none()
                && r.period_error < limit
                && r.state_error.is_finite()
        })
        .min_by_key(|r| r.rhs_evals)
}

/// Runs `bench accuracy`.
pub fn run(a: AccuracyArgs) -> Result<()> {
    if !(1..=MAX_REPEATS).contains(&a.repeats) {
        anyhow::bail!(
            "--repeats {} is not allowed (needs 1 ≤ repeats ≤ {MAX_REPEATS}: the minimum wall \
             time of a few runs is already stable)",
            a.repeats
        );
    }
    let starts = a.starts.unwrap_or(if a.quick { 2 } else { 16 });
    if !(1..=MAX_STARTS).contains(&starts) {
        anyhow::bail!("--starts {starts} is not allowed (needs 1 ≤ starts ≤ {MAX_STARTS})");
    }
    crate::output::check_folder(
        &a.out,
        &[
            "accuracy.csv",
            "timing.csv",
            "answers.csv",
            "work_precision.png",
            "period_precision.png",
        ],
        &crate::output::Inputs::none(),
    )?;
    crate::output::create_folder(&a.out)?;
    let mut cases = trajectories::default_cases(
        &bundled(BUNDLED_DISK)?,
        &bundled(BUNDLED_DISK_INERTIAL)?,
        &bundled(BUNDLED_SPHERE)?,
    );
    if a.quick {
        for c in &mut cases {
            c.t_end = 20.0;
        }
    }
    let mut rows: Vec<AccuracyRow> = Vec::new();
    let mut timing = Vec::new();
    let mut csv = Vec::new();
    let total: usize = cases.iter().map(|c| settings(c, a.quick).len()).sum();
    let bar = indicatif::ProgressBar::new(total as u64);
    outln!(
        "{:<16} {:<7} {:>9} {:>11} {:>11} {:>10} {:>10} {:>12}",
        "model",
        "method",
        "dt/rtol",
        "state err",
        "period err",
        "RHS evals",
        "wall ms",
        "sim t/wall s"
    )?;
    for case in &cases {
        let reference = trajectories::run_case(case, REFERENCE)
            .with_context(|| format!("reference run of {}", case.model()))?;
        for method in settings(case, a.quick) {
            let (run, wall) = time_run(case, method, a.repeats);
            let row = trajectories::row(case, method, &run, &reference);
            bar.inc(1);
            let sim_rate = if row.failure.is_none() {
                case.t_end / wall
            } else {
                f64::NAN
            };
            bar.suspend(|| {
                outln!(
                    "{:<16} {:<7} {:>9.0e} {:>11.2e} {:>11.2e} {:>10} {:>10.3} {:>12.3e}{}",
                    row.model,
                    row.integrator,
                    row.parameter,
                    row.state_error,
                    row.period_error,
                    row.rhs_evals,
                    wall * 1e3,
                    sim_rate,
                    row.failure
                        .as_deref()
                        .map(|f| format!("  FAILED: {f}"))
                        .unwrap_or_default()
                )
            })?;
            csv.push(vec![
                row.model.to_string(),
                row.integrator.to_string(),
                format!("{:e}", row.parameter),
                fmt_num(row.state_error),
                fmt_num(row.period_error),
                row.rhs_evals.to_string(),
                row.steps.to_string(),
                row.failure.clone().unwrap_or_default(),
            ]);
            timing.push(vec![
                row.model.to_string(),
                row.integrator.to_string(),
                format!("{:e}", row.parameter),
                format!("{wall:e}"),
                fmt_num(sim_rate),
            ]);
            rows.push(row);
        }
    }
    bar.finish_and_clear();
    let csv = csv_text(
        "model,integrator,parameter,state_error,period_error,rhs_evals,steps,failure",
        csv,
    )?;
    let timing = csv_text(
        "model,integrator,parameter,wall_seconds,sim_time_per_wall_second",
        timing,
    )?;
    write(&a.out.join("accuracy.csv"), &csv)?;
    write(&a.out.join("timing.csv"), &timing)?;
    let names: Vec<ModelKind> = cases.iter().map(Case::model).collect();
    plot_work_precision(
        &rows,
        &names,
        |r| r.state_error,
        "state error at t_end (rad, length)",
        &a.out.join("work_precision.png"),
    )?;
    plot_work_precision(
        &rows,
        &names,
        |r| r.period_error,
        "relative error of the orbit period",
        &a.out.join("period_precision.png"),
    )?;
    outln!()?;
    for name in &names {
        match cheapest_below(&rows, *name, 1e-3) {
            Some(r) => outln!(
                "{name}: cheapest setting with period error < 1e-3 over one run to t = 100: {} {:e} ({} RHS evaluations, period error {:.1e}); a trajectory measure only, see the answers below",
                r.integrator,
                r.parameter,
                r.rhs_evals,
                r.period_error
            )?,
            None => outln!("{name}: no setting reached period error < 1e-3")?,
        }
    }
    answers(&a.out, starts, a.quick)?;
    outln!("wrote {}", a.out.display())?;
    Ok(())
}

/// The answer table: each setting's fates on the paper's questions, raw and checked.
fn answers(out: &Path, starts: usize, quick: bool) -> Result<()> {
    use crate::analysis::accuracy::answers::{
        answer_row, answer_settings, paper_answer_cases, reference_fates,
    };
    let Body::Sphere(body) = Body::paper_sphere(219, 0.25, 5)? else {
        anyhow::bail!("internal error: the paper's sphere is not a sphere");
    };
    let cases = paper_answer_cases(&body, starts)?;
    let settings: Vec<Method> = answer_settings()
        .into_iter()
        .filter(|m| {
            !quick || matches!(m, Method::Rk4 { dt } if *dt == 0.5) || *m == Method::dop853(1e-8)
        })
        .collect();
    outln!()?;
    outln!(
        "answers on the paper's sphere (seed 219), {starts} starts per case, against DOP853 rtol 1e-12:"
    )?;
    outln!(
        "{:<18} {:<12} {:>9} {:>9} {:>7} {:>11} {:>9} {:>7} {:>11}  {}",
        "case",
        "setting",
        "raw fate",
        "raw all",
        "orbits",
        "raw RHS",
        "checked",
        "orbits",
        "checked RHS",
        "keeps the answers alone"
    )?;
    let bar = indicatif::ProgressBar::new((cases.len() * settings.len()) as u64);
    let mut csv = Vec::new();
    let mut cheapest: Vec<(String, Option<(String, u64)>)> = Vec::new();
    for case in &cases {
        let mut best: Option<(String, u64)> = None;
        let reference =
            reference_fates(case).with_context(|| format!("reference runs of {}", case.name))?;
        for &method in &settings {
            let row = answer_row(case, method, &reference)
                .with_context(|| format!("{} with {method}", case.name))?;
            bar.inc(1);
            bar.suspend(|| {
                outln!(
                    "{:<18} {:<12} {:>4}/{:<4} {:>4}/{:<4} {:>3}/{:<3} {:>11} {:>4}/{:<4} {:>3}/{:<3} {:>11}  {}",
                    row.case,
                    row.setting,
                    row.raw_fate,
                    row.runs,
                    row.raw_answer,
                    row.runs,
                    row.raw_orbits,
                    row.reference_orbits,
                    row.raw_rhs_evals,
                    row.checked_answer,
                    row.runs,
                    row.checked_orbits,
                    row.reference_orbits,
                    row.checked_rhs_evals,
                    if row.keeps_answers() { "yes" } else { "no" }
                )
            })?;
            csv.push(vec![
                row.case.clone(),
                row.setting.clone(),
                row.runs.to_string(),
                row.raw_fate.to_string(),
                row.raw_answer.to_string(),
                row.raw_orbits.to_string(),
                row.raw_rhs_evals.to_string(),
                row.checked_answer.to_string(),
                row.checked_orbits.to_string(),
                row.checked_rhs_evals.to_string(),
                row.reference_orbits.to_string(),
                row.keeps_answers().to_string(),
            ]);
            if row.keeps_answers() && best.as_ref().is_none_or(|b| row.raw_rhs_evals < b.1) {
                best = Some((row.setting.clone(), row.raw_rhs_evals));
            }
        }
        cheapest.push((case.name.clone(), best));
    }
    bar.finish_and_clear();
    outln!()?;
    for (name, best) in cheapest {
        match best {
            Some((setting, rhs)) => outln!(
                "{name}: cheapest setting that keeps every answer by itself: {setting} ({rhs} RHS evaluations)"
            )?,
            None => outln!("{name}: no setting tried keeps every answer by itself")?,
        }
    }
    let csv = csv_text(
        "case,setting,runs,raw_fate_agree,raw_answer_agree,raw_orbits,raw_rhs_evals,\
         checked_answer_agree,checked_orbits,checked_rhs_evals,reference_orbits,keeps_answers",
        csv,
    )?;
    write(&out.join("answers.csv"), &csv)
}

fn settings(case: &Case, quick: bool) -> Vec<Method> {
    let all = trajectories::default_settings(case);
    if !quick {
        return all;
    }
    all.into_iter()
        .filter(|m| match *m {
            Method::Rk4 { dt } | Method::Cf4 { dt } => dt <= 0.2,
            Method::Dop853 { rtol, .. } => rtol == 1e-6 || rtol == 1e-10,
        })
        .collect()
}

fn plot_work_precision(
    rows: &[AccuracyRow],
    models: &[ModelKind],
    error: impl Fn(&AccuracyRow) -> f64,
    y_label: &str,
    path: &Path,
) -> Result<()> {
    let panels: Vec<Panel> = models
        .iter()
        .map(|m| {
            let series = ["rk4", "cf4", "dop853"]
                .iter()
                .enumerate()
                .filter_map(|(i, integ)| {
                    let points: Vec<(f64, f64)> = rows
                        .iter()
                        .filter(|r| r.model == *m && r.integrator == *integ && r.failure.is_none())
                        .map(|r| (r.rhs_evals as f64, error(r).max(1e-16)))
                        .collect();
                    (!points.is_empty()).then(|| Series {
                        label: match *integ {
                            "rk4" => "RK4 (dt)".to_string(),
                            "cf4" => "CF4 Lie group (dt)".to_string(),
                            _ => "DOP853 (rtol)".to_string(),
                        },
                        points,
                        color: PALETTE[i],
                        style: Style::LineMarkers,
                    })
                })
                .collect();
            Panel {
                title: (*m).to_string(),
                x_label: "right-hand-side evaluations".into(),
                y_label: y_label.into(),
                log_x: true,
                log_y: true,
                series,
                legend: SeriesLabelPosition::UpperRight,
                equal_aspect: false,
            }
        })
        .collect();
    render_png(&panels, 2, (1400, 1000), path)
}
