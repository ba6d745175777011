//! `bench app`: the app's frame time (UI, 3D view, plots) painted offscreen while the simulation
//! thread runs, and the playback speed the simulation delivers.

use std::time::Instant;

use anyhow::{Result, bail};

use super::AppBenchArgs;

/// Runs `bench app`.
pub fn run(a: AppBenchArgs) -> Result<()> {
    use crate::integrate::Preset;
    use crate::live::SimCommand;
    use crate::render::gpu::{APP_FORMAT, OffscreenTarget};
    use crate::ui::render_scale::{RenderScale, RenderScaleMode};
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
            crate::cli::short(speed)
        );
    }
    let settings: Vec<RenderScaleMode> = match &a.render_scale {
        Some(text) => {
            vec![RenderScaleMode::parse(text).map_err(|e| anyhow::anyhow!("--render-scale: {e}"))?]
        }
        None => vec![RenderScaleMode::Fixed(1.0), RenderScaleMode::Auto],
    };
    let setup = crate::cli::pick_scene(None, Some(&a.preset))?;
    let gpu = crate::render::GpuContext::headless()?;
    let cpu = gpu.is_cpu();
    let target = OffscreenTarget::with_format(&gpu.device, a.size, APP_FORMAT);
    let mut bench = Workbench::new(&gpu.device, &gpu.queue, APP_FORMAT, a.msaa, setup, None)?;
    bench.ui.show_plots = !a.no_plots;
    bench
        .sim
        .send(SimCommand::SetMethod(Preset::Precise.method()));
    if let Some(speed) = a.speed {
        bench.sim.send(SimCommand::SetSpeed(speed));
    }
    // Each setting keeps its own scale across its blocks, as a window would.
    let mut scales: Vec<RenderScale> = settings
        .iter()
        .map(|&mode| RenderScale::new(mode, cpu))
        .collect();
    let mut timings: Vec<Timings> = settings.iter().map(|_| Timings::default()).collect();
    let start = Instant::now();
    let frame = |bench: &mut Workbench, scale: &mut RenderScale, timed: Option<&mut Timings>| {
        bench.set_render_scale(scale.clone());
        let elapsed = start.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let frame = bench.run_ui(offscreen_input(a.size, elapsed, Vec::new()), a.size);
        let t1 = Instant::now();
        bench.paint(&gpu.device, &gpu.queue, &target.view, &frame);
        let waited = target.wait(&gpu.device);
        let t2 = Instant::now();
        scale.record((t2 - t0).as_secs_f64());
        if let Some(t) = timed {
            t.ui_ms.push((t1 - t0).as_secs_f64() * 1e3);
            t.paint_ms.push((t2 - t1).as_secs_f64() * 1e3);
            t.total_ms.push((t2 - t0).as_secs_f64() * 1e3);
            t.lagging += usize::from(frame.status.lagging);
            t.last_scale = scale.scale();
        }
        waited
    };
    // Warm-up: 1 s, then each automatic scale probes and settles for 12 s (15 windows of 15
    // frames: the start, each of 5 coarser steps twice, and the confirmation).
    let warm = |bench: &mut Workbench, scale: &mut RenderScale, seconds: f64| -> Result<()> {
        let until = Instant::now() + std::time::Duration::from_secs_f64(seconds);
        while Instant::now() < until {
            frame(bench, scale, None)?;
        }
        Ok(())
    };
    warm(&mut bench, &mut scales[0], 1.0)?;
    for scale in &mut scales {
        if scale.mode() == RenderScaleMode::Auto && cpu {
            warm(&mut bench, scale, 12.0)?;
        }
    }
    // Alternate blocks: full, auto, full, auto: a slow spell of the machine falls on both.
    let blocks = if settings.len() > 1 { 2 } else { 1 };
    let block_s = a.seconds / blocks as f64;
    for _ in 0..blocks {
        for (scale, timed) in scales.iter_mut().zip(timings.iter_mut()) {
            let until = Instant::now() + std::time::Duration::from_secs_f64(block_s);
            while Instant::now() < until {
                frame(&mut bench, scale, Some(timed))?;
            }
        }
    }
    let status = bench.sim.status();
    if timings.iter().any(|t| t.total_ms.is_empty()) {
        bail!("no frame finished within the timed {} s", a.seconds);
    }
    outln!(
        "{} at {}x{}, {}× MSAA, integrator {}, plots {}, on {}; {} s timed per setting in {} \
         alternate block(s)\n",
        a.preset,
        a.size.0,
        a.size.1,
        a.msaa,
        status.method,
        if a.no_plots { "hidden" } else { "shown" },
        gpu.describe(),
        a.seconds,
        blocks
    )?;
    outln!(
        "| 3D view drawn at | frames | UI mean ms | paint mean ms (p95) | frame mean ms (p50, \
         p95) | frames/s |"
    )?;
    outln!("|---|---|---|---|---|---|")?;
    for (mode, t) in settings.iter().zip(&timings) {
        let (ui, _, _) = stats(&t.ui_ms);
        let (paint, _, paint95) = stats(&t.paint_ms);
        let (mean, p50, p95) = stats(&t.total_ms);
        let setting = match mode {
            RenderScaleMode::Fixed(s) if *s >= 1.0 => "full resolution".to_string(),
            RenderScaleMode::Fixed(s) => format!("{:.0} % (fixed)", s * 100.0),
            RenderScaleMode::Auto if cpu => {
                format!("auto: {:.0} % at the end", t.last_scale * 100.0)
            }
            RenderScaleMode::Auto => "auto: full (a GPU)".to_string(),
        };
        outln!(
            "| {setting} | {} | {ui:.1} | {paint:.1} ({paint95:.1}) | {mean:.1} ({p50:.1}, \
             {p95:.1}) | {:.1} |",
            t.total_ms.len(),
            1e3 / mean
        )?;
    }
    let lagging: usize = timings.iter().map(|t| t.lagging).sum();
    let frames: usize = timings.iter().map(|t| t.total_ms.len()).sum();
    outln!(
        "\nsimulation delivers {} of the requested {:.2} time units per second{}",
        status
            .delivered_speed
            .map_or("(not measured)".into(), |d| format!("{d:.2}")),
        status.speed,
        if lagging > 0 {
            format!("; the UI showed \"cannot keep up\" in {lagging} of {frames} frames")
        } else {
            String::new()
        }
    )?;
    if let Some(m) = &status.message {
        outln!("message: {m}")?;
    }
    Ok(())
}

/// One setting's frame times.
#[derive(Default)]
struct Timings {
    ui_ms: Vec<f64>,
    paint_ms: Vec<f64>,
    total_ms: Vec<f64>,
    lagging: usize,
    last_scale: f32,
}

/// Mean, median and 95th percentile.
fn stats(v: &[f64]) -> (f64, f64, f64) {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let mean = s.iter().sum::<f64>() / s.len().max(1) as f64;
    let at = |q: f64| s[((s.len().max(1) - 1) as f64 * q).round() as usize];
    (mean, at(0.5), at(0.95))
}
