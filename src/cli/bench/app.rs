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

    let settings = check_args(&a)?;
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
    let paint = |bench: &mut Workbench, events| {
        let frame = bench.run_ui(
            offscreen_input(a.size, start.elapsed().as_secs_f64(), events),
            a.size,
        );
        bench.paint(&gpu.device, &gpu.queue, &target.view, &frame);
        target.wait(&gpu.device)?;
        Ok(frame.status.scene_id)
    };
    stroke_timing(&mut bench, a.strokes, paint)
}

/// `bench app --strokes N` (nothing for 0): N clicks on the body facing the camera (a dent, then a bump, in
/// turn), each timed from the click to the first frame of the restarted run, and the steps
/// between it timed alone on the same bodies.
fn stroke_timing(
    bench: &mut crate::ui::workbench::Workbench,
    strokes: usize,
    mut paint: impl FnMut(
        &mut crate::ui::workbench::Workbench,
        crate::ui::workbench::UiEvents,
    ) -> Result<u64>,
) -> Result<()> {
    use crate::geometry::sculpt::{Stroke, sculpt};
    use crate::scene::sculpt::{SculptReadout, sculpted_scene};
    use crate::view::pick::body_point_at;

    if strokes == 0 {
        return Ok(());
    }
    bench.ui.sculpt.on = true;
    bench.ui.sculpt.depth = 0.005;
    let ms = |t: Instant| t.elapsed().as_secs_f64() * 1e3;
    let mut rows: [Vec<f64>; 7] = Default::default();
    for i in 0..strokes {
        paint(bench, crate::ui::workbench::UiEvents::new())?;
        let status = bench.sim.status();
        let body = status.setup.body.clone();
        let view = bench
            .ui
            .sculpt
            .pick_view
            .ok_or_else(|| anyhow::anyhow!("the body was not drawn"))?;
        let (p, pos) = front_of_body(bench, &body, &view)?;
        let [press, release] = crate::ui::workbench::click_events(pos, i % 2 == 1);
        paint(bench, press)?;
        // From the release (a click is a press and its release) to the new run on the screen.
        let clicked = Instant::now();
        // Until a frame draws the new run (its meshes built): the click's own frame, where the
        // simulation takes the load in time.
        let mut drawn = paint(bench, release)?;
        while drawn == status.scene_id {
            if let Some((why, true)) = bench.ui.notice() {
                bail!("stroke {i} was refused: {why}");
            }
            if clicked.elapsed().as_secs() > 30 {
                bail!(
                    "stroke {i}: no restarted run within 30 s ({:?})",
                    bench.ui.notice()
                );
            }
            drawn = paint(bench, crate::ui::workbench::UiEvents::new())?;
        }
        rows[5].push(ms(clicked));
        // The panels' readout follows the frame after.
        paint(bench, crate::ui::workbench::UiEvents::new())?;
        // The steps alone, on the same body and point.
        let (x, y, _) = view.project(p).unwrap_or_default();
        let t = Instant::now();
        let at = body_point_at(&view, &body, x, y)
            .ok_or_else(|| anyhow::anyhow!("no body under its own front point"))?;
        rows[0].push(ms(t));
        let stroke = Stroke {
            at,
            width: bench.ui.sculpt.width,
            height: -0.005,
        };
        let t = Instant::now();
        let sculpted = sculpt(&body, &stroke)?;
        rows[1].push(ms(t));
        let t = Instant::now();
        SculptReadout::of(&sculpted, 20.0);
        rows[2].push(ms(t));
        let t = Instant::now();
        let (_, setup) = sculpted_scene(
            &status.setup.scene,
            &sculpted,
            crate::scene::InitialSpec::default(),
            (None, Some(20.0)),
        )?;
        rows[3].push(ms(t));
        let t = Instant::now();
        crate::live::LiveRun::new(setup).snapshot();
        rows[4].push(ms(t));
    }
    // The click table is printed even if the drag fails.
    let drag = drag_timing(bench, strokes.min(MAX_DRAG_MOVES), &mut paint);
    if let Ok(times) = &drag {
        rows[6].clone_from(times);
    }
    outln!(
        "\nsculpting: {strokes} strokes (width {} rad, depth 0.005) on the body point facing \
         the camera, a dent then a bump in turn, then one drag up from it in up to {} moves of \
         {DRAG_MOVE_POINTS} points ({:.4} mean r each; {} timed, to the edge of convexity at \
         most); the drift is measured on a worker thread beside them\n",
        bench.ui.sculpt.width,
        strokes.min(MAX_DRAG_MOVES),
        f64::from(DRAG_MOVE_POINTS) * crate::ui::DRAG_HEIGHT_PER_POINT,
        rows[6].len()
    )?;
    outln!("| step | mean ms | p50 ms | p95 ms |")?;
    outln!("|---|---|---|---|")?;
    let names = [
        "pick the body point under the pointer",
        "the stroke (least-squares map, convexity check)",
        "the readout (α*, curvature at the print scale)",
        "the scene's setup (checks, α*)",
        "the new run and its first snapshot",
        "release to the first frame that draws the restarted run (frames included)",
        "a drag's move to the first frame that draws its run (live stroke, frames included)",
    ];
    for (name, v) in names.iter().zip(&rows).filter(|(_, v)| !v.is_empty()) {
        let (mean, p50, p95) = stats(v);
        outln!("| {name} | {mean:.1} | {p50:.1} | {p95:.1} |")?;
    }
    drag.map(|_| ())
}

/// How far the pointer goes in one move of the timed drag (screen points): past egui's
/// click distance (6), so the first move starts the drag.
const DRAG_MOVE_POINTS: f32 = 8.0;

/// The most moves the timed drag makes: 160 points, a height of 0.08 mean r.
const MAX_DRAG_MOVES: usize = 20;

/// The body point facing the camera (body frame) and where it is drawn (screen points).
fn front_of_body(
    bench: &crate::ui::workbench::Workbench,
    body: &crate::geometry::Body,
    view: &crate::view::pick::PickView,
) -> Result<(crate::glam::DVec3, crate::ui::workbench::Pos2)> {
    let eye = crate::view::pick::eye_in_body(view);
    let p = match body {
        crate::geometry::Body::Sphere(s) => s.radius(eye.normalize()) * eye.normalize(),
        crate::geometry::Body::Disk(d) => {
            let theta = eye.z.atan2(eye.x);
            let r = d.jet(theta).r;
            crate::glam::DVec3::new(r * theta.cos(), 0.0, r * theta.sin())
        }
    };
    let pos = bench
        .ui
        .body_point_position(p)
        .ok_or_else(|| anyhow::anyhow!("the body's front is off the view"))?;
    Ok((p, pos))
}

/// One drag from the body's front straight up, in `moves` moves of [`DRAG_MOVE_POINTS`]: each
/// timed from its frame to the first frame that draws the run on the body it made.
fn drag_timing(
    bench: &mut crate::ui::workbench::Workbench,
    moves: usize,
    paint: &mut impl FnMut(
        &mut crate::ui::workbench::Workbench,
        crate::ui::workbench::UiEvents,
    ) -> Result<u64>,
) -> Result<Vec<f64>> {
    use crate::ui::workbench::{UiEvents, drag_events};
    paint(bench, UiEvents::new())?;
    let status = bench.sim.status();
    let view = bench
        .ui
        .sculpt
        .pick_view
        .ok_or_else(|| anyhow::anyhow!("the body was not drawn"))?;
    let (_, pos) = front_of_body(bench, &status.setup.body, &view)?;
    paint(bench, drag_events(pos, Some(true)))?;
    let mut times = Vec::with_capacity(moves);
    let mut to = pos;
    for i in 0..moves {
        let id = bench.sim.status().scene_id;
        to.y -= DRAG_MOVE_POINTS;
        let moved = Instant::now();
        let mut drawn = paint(bench, drag_events(to, None))?;
        while drawn == id {
            match bench.ui.notice() {
                // Held at the edge of convexity: nothing more to restart.
                Some((why, true)) if why.contains("the edge of convexity") => {
                    paint(bench, drag_events(to, Some(false)))?;
                    return Ok(times);
                }
                Some((why, true)) => bail!("drag move {i} was refused: {why}"),
                _ => {}
            }
            if moved.elapsed().as_secs() > 30 {
                bail!(
                    "drag move {i}: no restarted run within 30 s ({:?})",
                    bench.ui.notice()
                );
            }
            drawn = paint(bench, UiEvents::new())?;
        }
        times.push(moved.elapsed().as_secs_f64() * 1e3);
    }
    paint(bench, drag_events(to, Some(false)))?;
    Ok(times)
}

/// The options checked before any work: the settings the frames are timed at.
fn check_args(a: &AppBenchArgs) -> Result<Vec<crate::ui::render_scale::RenderScaleMode>> {
    use crate::ui::render_scale::RenderScaleMode;
    if a.strokes > 1000 {
        bail!(
            "--strokes {} is not allowed (needs 0 ≤ strokes ≤ 1000)",
            a.strokes
        );
    }
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
    Ok(match &a.render_scale {
        Some(text) => {
            vec![RenderScaleMode::parse(text).map_err(|e| anyhow::anyhow!("--render-scale: {e}"))?]
        }
        None => vec![RenderScaleMode::Fixed(1.0), RenderScaleMode::Auto],
    })
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
