//! `rollphase bench`: measured speed/accuracy trade-offs, printed as tables and written as CSV
//! and PNG. `accuracy`: every model × integrator setting against a converged reference.
//! `stiff`: the inertial model as m/m0 → 0, its cost and its distance from the viscous model.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use serde::Serialize;

use crate::analysis::accuracy::{self, AccuracyRow, Case, REFERENCE};
use crate::dynamics::Ramp;
use crate::geometry::{Body, ShapeFile};
use crate::integrate::Method;
use crate::plot::{PALETTE, Panel, Series, SeriesLabelPosition, Style, render_png};

/// The bundled bodies, so the benchmarks run from any directory.
pub const BUNDLED_SPHERE: &str = include_str!("../../assets/shapes/sphere.json");
/// The bundled 2D body for viscous runs (σ = 0.08, M = 10).
pub const BUNDLED_DISK: &str = include_str!("../../assets/shapes/disk.json");
/// The bundled 2D body for inertial runs (σ = 0.12, M = 5).
pub const BUNDLED_DISK_INERTIAL: &str = include_str!("../../assets/shapes/disk-inertial.json");

/// Measure the speed/accuracy trade of the integrators.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Which benchmark.
    #[command(subcommand)]
    pub which: BenchKind,
}

/// The benchmarks.
#[derive(Debug, Subcommand)]
pub enum BenchKind {
    /// Every model × integrator setting against a converged reference at t = 100.
    Accuracy(AccuracyArgs),
    /// The inertial models as m/m0 → 0: cost (stiffness) and distance from the viscous model.
    Stiff(StiffArgs),
    /// Wall time of the full-size ensemble figures against their targets (sphere-poincare ≤ 30 s,
    /// sphere-cruising ≤ 60 s, sphere-doubling ≤ 60 s, sphere-bifurcation ≤ 120 s on 2 cores).
    Figures(FiguresBenchArgs),
    /// Frames per second of the headless renderer (rendering alone, with readback, with PNG
    /// writing on worker threads) at 1280×720 on whatever adapter is found (llvmpipe here).
    Render(RenderBenchArgs),
    /// Frame time of the app (UI, 3D view, plots) painted offscreen while the simulation thread
    /// runs at the "precise" setting, and the playback speed the simulation delivers.
    App(AppBenchArgs),
}

/// Options of `bench app`.
#[derive(Debug, Args)]
pub struct AppBenchArgs {
    /// Preset to run.
    #[arg(long, default_value = "sphere-two-orbits")]
    pub preset: String,
    /// Window size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1600x900", value_parser = super::render::parse_size)]
    pub size: (u32, u32),
    /// Wall seconds timed (after 1 s of warm-up).
    #[arg(long, default_value_t = 8.0)]
    pub seconds: f64,
    /// Requested playback speed, simulation time per second [default: the preset's].
    #[arg(long)]
    pub speed: Option<f64>,
    /// MSAA samples of the 3D view (the window uses 4 on a GPU, 1 on a CPU renderer).
    #[arg(long, default_value_t = 1, value_parser = super::render::parse_msaa)]
    pub msaa: u32,
    /// Hide the plots panel (to see what the plots cost).
    #[arg(long)]
    pub no_plots: bool,
}

/// Options of `bench render`.
#[derive(Debug, Args)]
pub struct RenderBenchArgs {
    /// Preset to render.
    #[arg(long, default_value = "sphere-cruising")]
    pub preset: String,
    /// Frame size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = super::render::parse_size)]
    pub size: (u32, u32),
    /// Frames timed per row (after 5 warm-up frames).
    #[arg(long, default_value_t = 60)]
    pub frames: u64,
}

/// Options of `bench figures`.
#[derive(Debug, Args)]
pub struct FiguresBenchArgs {
    /// Output folder for the figures produced while timing.
    #[arg(long, default_value = "bench-figures")]
    pub out: PathBuf,
}

fn figures_bench(a: FiguresBenchArgs) -> Result<()> {
    let opts = crate::figures::FigureOptions {
        out: a.out.clone(),
        seed: 1,
        quick: false,
        ..crate::figures::FigureOptions::default()
    };
    let threads = rayon::current_num_threads();
    outln!(
        "{:<18} {:>10} {:>10}   ({threads} threads)",
        "figure",
        "wall s",
        "target s"
    )?;
    let timed = |name: &str, target: f64, f: &dyn Fn() -> Result<()>| -> Result<()> {
        let start = Instant::now();
        f()?;
        let wall = start.elapsed().as_secs_f64();
        outln!(
            "{name:<18} {wall:>10.1} {target:>10.0}{}",
            if wall <= target { "" } else { "   OVER TARGET" }
        )?;
        Ok(())
    };
    timed("sphere-poincare", 30.0, &|| {
        crate::figures::sphere_poincare::run(&opts).map(|_| ())
    })?;
    timed("sphere-cruising", 60.0, &|| {
        crate::figures::sphere_cruising::run(&opts).map(|_| ())
    })?;
    timed("sphere-doubling", 60.0, &|| {
        crate::figures::sphere_doubling::run(&opts).map(|_| ())
    })?;
    timed("sphere-bifurcation", 120.0, &|| {
        crate::figures::sphere_bifurcation::run(&opts).map(|_| ())
    })?;
    Ok(())
}

/// Options of `bench accuracy`.
///
/// For each model (2D/3D, viscous/inertial, on the bundled bodies) and each setting (RK4 and
/// CF4 at several steps, DOP853 at several tolerances): state error and orbit-period error at
/// t = 100 against DOP853 at rtol 1e-13, right-hand-side evaluations, wall time and simulated
/// time per wall second. Writes OUT/accuracy.csv (deterministic), OUT/timing.csv (wall
/// clock), OUT/work_precision.png and OUT/period_precision.png.
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct AccuracyArgs {
    /// Output folder.
    #[arg(long, default_value = "bench-accuracy")]
    pub out: PathBuf,
    /// Runs per setting for the wall time (the minimum is reported).
    #[arg(long, default_value_t = 3)]
    pub repeats: u32,
    /// Reduced run for tests: t = 20, and two tolerances for DOP853.
    #[arg(long)]
    pub quick: bool,
}

/// Options of `bench stiff`.
///
/// For m/m0 from 1e-4 to 1: DOP853 (rtol 1e-8) work for t = 0..100 and the inertial model's
/// distance from the viscous one (state at t = 100, and relative period difference).
/// Writes OUT/stiff.csv and OUT/stiff.png.
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct StiffArgs {
    /// Output folder.
    #[arg(long, default_value = "bench-stiff")]
    pub out: PathBuf,
    /// Reduced run for tests.
    #[arg(long)]
    pub quick: bool,
}

/// Runs `bench`.
pub fn run(a: BenchArgs) -> Result<()> {
    match a.which {
        BenchKind::Accuracy(a) => accuracy_bench(a),
        BenchKind::Stiff(a) => stiff_bench(a),
        BenchKind::Figures(a) => figures_bench(a),
        BenchKind::Render(a) => render_bench(a),
        BenchKind::App(a) => app_bench(a),
    }
}

fn bundled(text: &str) -> Result<Body> {
    let file = ShapeFile::from_json(text).context("bundled shape file")?;
    Ok(Body::from_file(&file)?)
}

fn fmt_num(v: f64) -> String {
    if v.is_finite() {
        format!("{v:e}")
    } else {
        String::new()
    }
}

fn time_run(
    case: &Case,
    method: Method,
    repeats: u32,
) -> (
    Result<accuracy::Outcome, crate::integrate::IntegrateError>,
    f64,
) {
    let mut best = f64::INFINITY;
    let mut result = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let r = accuracy::run_case(case, method);
        best = best.min(start.elapsed().as_secs_f64());
        result = Some(r);
    }
    (result.expect("at least one repeat"), best)
}

/// The cheapest (fewest RHS evaluations) setting of a model whose period error is < `limit`.
pub fn cheapest_below<'a>(
    rows: &'a [AccuracyRow],
    model: &str,
    limit: f64,
) -> Option<&'a AccuracyRow> {
    rows.iter()
        .filter(|r| {
            r.model == model
                && r.failure.is_none()
                && r.period_error < limit
                && r.state_error.is_finite()
        })
        .min_by_key(|r| r.rhs_evals)
}

fn accuracy_bench(a: AccuracyArgs) -> Result<()> {
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let mut cases = accuracy::default_cases(
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
    let mut timing =
        String::from("model,integrator,parameter,wall_seconds,sim_time_per_wall_second\n");
    let mut csv = String::from(
        "model,integrator,parameter,state_error,period_error,rhs_evals,steps,failure\n",
    );
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
        let reference = accuracy::run_case(case, REFERENCE)
            .with_context(|| format!("reference run of {}", case.name))?;
        for method in settings(case, a.quick) {
            let (run, wall) = time_run(case, method, a.repeats);
            let row = accuracy::row(case, method, &run, &reference);
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
            let _ = writeln!(
                csv,
                "{},{},{:e},{},{},{},{},{}",
                row.model,
                row.integrator,
                row.parameter,
                fmt_num(row.state_error),
                fmt_num(row.period_error),
                row.rhs_evals,
                row.steps,
                row.failure.as_deref().unwrap_or("").replace(',', ";")
            );
            let _ = writeln!(
                timing,
                "{},{},{:e},{:e},{}",
                row.model,
                row.integrator,
                row.parameter,
                wall,
                fmt_num(sim_rate)
            );
            rows.push(row);
        }
    }
    bar.finish_and_clear();
    write(&a.out.join("accuracy.csv"), &csv)?;
    write(&a.out.join("timing.csv"), &timing)?;
    let names: Vec<&'static str> = cases.iter().map(|c| c.name).collect();
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
        match cheapest_below(&rows, name, 1e-3) {
            Some(r) => outln!(
                "{name}: cheapest setting with period error < 1e-3: {} {:e} ({} RHS evaluations, period error {:.1e})",
                r.integrator,
                r.parameter,
                r.rhs_evals,
                r.period_error
            )?,
            None => outln!("{name}: no setting reached period error < 1e-3")?,
        }
    }
    outln!("wrote {}", a.out.display())?;
    Ok(())
}

fn settings(case: &Case, quick: bool) -> Vec<Method> {
    let all = accuracy::default_settings(case);
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

fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

fn plot_work_precision(
    rows: &[AccuracyRow],
    models: &[&'static str],
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
            }
        })
        .collect();
    render_png(&panels, 2, (1400, 1000), path)
}

/// One row of the stiffness table.
#[derive(Debug, Serialize)]
struct StiffRow {
    model: &'static str,
    mass_ratio: f64,
    rhs_evals: u64,
    steps: u64,
    distance_from_viscous: f64,
    period_difference: f64,
}

fn stiff_bench(a: StiffArgs) -> Result<()> {
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let masses: Vec<f64> = if a.quick {
        vec![1e-3, 1e-2, 1e-1, 1.0]
    } else {
        vec![1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1, 3e-1, 1.0]
    };
    let t_end = if a.quick { 30.0 } else { 100.0 };
    let bodies = [
        ("disk", bundled(BUNDLED_DISK)?, 0.25, [0.0; 3]),
        ("sphere", bundled(BUNDLED_SPHERE)?, 0.3, [1.0, 2.0, 0.5]),
    ];
    let method = Method::dop853(1e-8);
    let mut rows = Vec::new();
    outln!(
        "{:<8} {:>8} {:>11} {:>9} {:>18} {:>14}",
        "body",
        "m/m0",
        "RHS evals",
        "steps",
        "|state − viscous|",
        "ΔT/T viscous"
    )?;
    for (name, body, alpha, start) in &bodies {
        let viscous = Case {
            name: "viscous",
            body: body.clone(),
            ramp: Ramp::new(*alpha, 0.0)?,
            start: *start,
            t_end,
        };
        let v = accuracy::run_case(&viscous, REFERENCE)?;
        let tv = accuracy::period_estimate(&v.crossings, t_end);
        for &m in &masses {
            let case = Case {
                name: "inertial",
                body: body.clone(),
                ramp: Ramp::new(*alpha, m)?,
                start: *start,
                t_end,
            };
            let o = accuracy::run_case(&case, method)
                .with_context(|| format!("{name} at m/m0 = {m}"))?;
            let period_difference = match (accuracy::period_estimate(&o.crossings, t_end), tv) {
                (Some(p), Some(r)) => ((p - r) / r).abs(),
                _ => f64::NAN,
            };
            let row = StiffRow {
                model: name,
                mass_ratio: m,
                rhs_evals: o.stats.rhs_evals,
                steps: o.stats.steps,
                distance_from_viscous: accuracy::state_error(&o, &v),
                period_difference,
            };
            outln!(
                "{:<8} {:>8.0e} {:>11} {:>9} {:>18.3e} {:>14.3e}",
                row.model,
                row.mass_ratio,
                row.rhs_evals,
                row.steps,
                row.distance_from_viscous,
                row.period_difference
            )?;
            rows.push(row);
        }
    }
    let mut csv =
        String::from("body,mass_ratio,rhs_evals,steps,distance_from_viscous,period_difference\n");
    for r in &rows {
        let _ = writeln!(
            csv,
            "{},{:e},{},{},{},{}",
            r.model,
            r.mass_ratio,
            r.rhs_evals,
            r.steps,
            fmt_num(r.distance_from_viscous),
            fmt_num(r.period_difference)
        );
    }
    write(&a.out.join("stiff.csv"), &csv)?;
    let series = |f: &dyn Fn(&StiffRow) -> f64| -> Vec<Series> {
        ["disk", "sphere"]
            .iter()
            .enumerate()
            .map(|(i, b)| Series {
                label: format!("{b} (DOP853, rtol 1e-8)"),
                points: rows
                    .iter()
                    .filter(|r| r.model == *b)
                    .map(|r| (r.mass_ratio, f(r)))
                    .collect(),
                color: PALETTE[i],
                style: Style::LineMarkers,
            })
            .collect()
    };
    let panels = vec![
        Panel {
            title: "cost of the inertial model, t = 0..100".into(),
            x_label: "mass ratio m/m0".into(),
            y_label: "right-hand-side evaluations".into(),
            log_x: true,
            log_y: true,
            series: series(&|r| r.rhs_evals as f64),
            legend: SeriesLabelPosition::UpperRight,
        },
        Panel {
            title: "inertial minus viscous".into(),
            x_label: "mass ratio m/m0".into(),
            y_label: "relative period difference".into(),
            log_x: true,
            log_y: true,
            series: series(&|r| r.period_difference),
            legend: SeriesLabelPosition::UpperLeft,
        },
    ];
    render_png(&panels, 2, (1400, 560), &a.out.join("stiff.png"))?;
    outln!("wrote {}", a.out.display())?;
    Ok(())
}

fn render_bench(a: RenderBenchArgs) -> Result<()> {
    use crate::headless::{HeadlessRenderer, PngWriter, frame_name};
    if a.frames == 0 {
        anyhow::bail!("--frames 0 times nothing (needs at least 1)");
    }
    let setup = super::render::pick_scene(None, Some(&a.preset))?;
    let out = std::env::temp_dir().join(format!("rollphase-bench-render-{}", std::process::id()));
    std::fs::create_dir_all(&out)?;
    let mut table = String::new();
    let (w, h) = a.size;
    let mut adapter = String::new();
    writeln!(table, "| MSAA | what is timed | frames/s | ms/frame |")?;
    writeln!(table, "|---|---|---|---|")?;
    for samples in [4, 1] {
        let mut r = HeadlessRenderer::new(setup.clone(), a.size, samples)?;
        adapter = r.adapter();
        let mut k = 0u64;
        for _ in 0..5 {
            r.frame(k)?;
            k += 1;
        }
        let mut row = |what: &str,
                       f: &mut dyn FnMut(&mut HeadlessRenderer, u64) -> Result<()>|
         -> Result<()> {
            let start = Instant::now();
            for _ in 0..a.frames {
                f(&mut r, k)?;
                k += 1;
            }
            rate_row(
                &mut table,
                samples,
                what,
                a.frames,
                start.elapsed().as_secs_f64(),
            )
        };
        row(
            "rendering alone (simulate, build, draw, wait for the GPU)",
            &mut |r, k| {
                r.draw(k)?;
                r.finish()
            },
        )?;
        row(
            "rendering alone, pipelined (wait for the GPU every 4th frame)",
            &mut |r, k| {
                r.draw(k)?;
                if k % 4 == 3 { r.finish() } else { Ok(()) }
            },
        )?;
        row("+ readback to memory", &mut |r, k| r.frame(k).map(|_| ()))?;
        let writer = PngWriter::new(2);
        let start = Instant::now();
        for _ in 0..a.frames {
            let img = r.frame(k)?;
            writer.write(out.join(frame_name(k)), img)?;
            k += 1;
        }
        writer.close()?;
        let seconds = start.elapsed().as_secs_f64();
        rate_row(
            &mut table,
            samples,
            "+ PNG writing on 2 threads",
            a.frames,
            seconds,
        )?;
    }
    let _ = std::fs::remove_dir_all(&out);
    outln!(
        "{} at {w}x{h}, {} frames a row, on {adapter}\n",
        a.preset,
        a.frames
    )?;
    super::output::write_text(None, &table, &[], "stdout")?;
    Ok(())
}

/// One row of the render table: frames per second and milliseconds per frame.
fn rate_row(table: &mut String, samples: u32, what: &str, frames: u64, seconds: f64) -> Result<()> {
    writeln!(
        table,
        "| {samples}× | {what} | {:.1} | {:.1} |",
        frames as f64 / seconds,
        1000.0 * seconds / frames as f64
    )?;
    Ok(())
}

fn app_bench(a: AppBenchArgs) -> Result<()> {
    use crate::integrate::Preset;
    use crate::render::gpu::{OFFSCREEN_FORMAT, OffscreenTarget};
    use crate::sim::SimCommand;
    use crate::ui::workbench::{Workbench, offscreen_input};

    if !(a.seconds.is_finite() && a.seconds > 0.0) {
        bail!(
            "--seconds {} is not allowed (needs a number > 0)",
            a.seconds
        );
    }
    // Checked here as well as in the simulation thread, so a refused speed stops the bench
    // instead of timing the preset's speed under a wrong label.
    if let Some(speed) = a.speed
        && !(speed.is_finite() && speed > 0.0 && speed <= 10_000.0)
    {
        bail!(
            "--speed {} is not allowed (needs 0 < speed ≤ 10000 time units per second)",
            super::short(speed)
        );
    }
    let setup = super::render::pick_scene(None, Some(&a.preset))?;
    let gpu = crate::render::GpuContext::headless()?;
    let target = OffscreenTarget::new(&gpu.device, a.size);
    let mut bench = Workbench::new(
        &gpu.device,
        &gpu.queue,
        OFFSCREEN_FORMAT,
        a.msaa,
        setup,
        None,
    );
    bench.ui.show_plots = !a.no_plots;
    bench
        .sim
        .send(SimCommand::SetMethod(Preset::Precise.method()));
    if let Some(speed) = a.speed {
        bench.sim.send(SimCommand::SetSpeed(speed));
    }
    let start = Instant::now();
    let mut ui_ms = Vec::new();
    let mut paint_ms = Vec::new();
    let mut total_ms = Vec::new();
    let mut lagging_frames = 0usize;
    loop {
        let elapsed = start.elapsed().as_secs_f64();
        if elapsed > 1.0 + a.seconds {
            break;
        }
        let t0 = Instant::now();
        let frame = bench.run_ui(offscreen_input(a.size, elapsed, Vec::new()), a.size);
        let t1 = Instant::now();
        bench.paint(&gpu.device, &gpu.queue, &target.view, &frame);
        target.wait(&gpu.device)?;
        let t2 = Instant::now();
        if elapsed >= 1.0 {
            ui_ms.push((t1 - t0).as_secs_f64() * 1e3);
            paint_ms.push((t2 - t1).as_secs_f64() * 1e3);
            total_ms.push((t2 - t0).as_secs_f64() * 1e3);
            lagging_frames += usize::from(frame.status.lagging);
        }
    }
    let status = bench.sim.status();
    let stats = |v: &[f64]| -> (f64, f64, f64) {
        let mut s = v.to_vec();
        s.sort_by(f64::total_cmp);
        let mean = s.iter().sum::<f64>() / s.len().max(1) as f64;
        let at = |q: f64| s[((s.len().max(1) - 1) as f64 * q).round() as usize];
        (mean, at(0.5), at(0.95))
    };
    if total_ms.is_empty() {
        bail!("no frame finished within the timed {} s", a.seconds);
    }
    outln!(
        "{} at {}x{}, {}× MSAA, integrator {}, on {}; {} frames in {} s\n",
        a.preset,
        a.size.0,
        a.size.1,
        a.msaa,
        crate::ui::describe_method(&status.method),
        gpu.describe(),
        total_ms.len(),
        a.seconds
    )?;
    outln!("| part of the frame | mean ms | p50 ms | p95 ms |")?;
    outln!("|---|---|---|---|")?;
    for (what, v) in [
        ("UI (egui layout, plots, tessellation)", &ui_ms),
        ("paint (3D view + panels, GPU finished)", &paint_ms),
        ("whole frame", &total_ms),
    ] {
        let (mean, p50, p95) = stats(v);
        outln!("| {what} | {mean:.1} | {p50:.1} | {p95:.1} |")?;
    }
    let (mean, _, _) = stats(&total_ms);
    outln!(
        "\n{:.1} frames/s; simulation delivers {} of the requested {:.2} time units per second{}",
        1e3 / mean,
        status
            .delivered_speed
            .map_or("(not measured)".into(), |d| format!("{d:.2}")),
        status.speed,
        if lagging_frames > 0 {
            format!(
                "; the UI showed \"cannot keep up\" in {lagging_frames} of {} frames",
                total_ms.len()
            )
        } else {
            String::new()
        }
    )?;
    if let Some(m) = &status.message {
        outln!("message: {m}")?;
    }
    Ok(())
}
