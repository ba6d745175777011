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
    let setup = crate::cli::pick_scene(None, Some(&a.preset))?;
    let gpu = crate::render::GpuContext::headless()?;
    let target = OffscreenTarget::with_format(&gpu.device, a.size, APP_FORMAT);
    let mut bench = Workbench::new(&gpu.device, &gpu.queue, APP_FORMAT, a.msaa, setup, None)?;
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
        status.method,
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
