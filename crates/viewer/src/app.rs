//! The desktop window: winit's event loop, the wgpu surface and egui-winit's input glue around
//! the windowless app core ([`Workbench`]). The only module that knows winit.
//!
//! With no display (no `DISPLAY` or `WAYLAND_DISPLAY`, or one that cannot be opened) it fails
//! with one line suggesting `--headless`; it never falls back silently.
//!
//! The 3D scene uses 4× MSAA on a hardware GPU and none on a CPU renderer such as llvmpipe,
//! where multisampling costs about 20 ms a frame (`rollphase bench render`).
//!
//! `--screenshot-after SECONDS FILE` saves the window (controls included) once that much wall
//! time has passed and `--exit-after SECONDS` closes it, printing a frame-time summary: the CI
//! smoke test runs the real window under Xvfb this way.
//!
//! Ctrl-C or a termination signal closes the window from its own event loop
//! ([`request_close`]): exiting from the signal handler's thread while the main thread was inside
//! the GPU driver crashed 3 of ~70 kills (a segfault, a heap-corruption abort, an EGL panic).

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow, bail};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Fullscreen, Window, WindowId};

use crate::render::GpuContext;
use crate::scene::SceneSetup;
use crate::ui::UiAction;
use crate::ui::render_scale::{RenderScale, RenderScaleMode};
use crate::ui::workbench::Workbench;

/// What the window opens with.
pub struct AppOptions {
    /// The scene.
    pub setup: SceneSetup,
    /// The scene file's folder (for saving next to it); `None` for presets.
    pub base: Option<PathBuf>,
    /// Save a screenshot after this many seconds.
    pub screenshot_after: Option<(f64, PathBuf)>,
    /// Close after this many seconds.
    pub exit_after: Option<f64>,
    /// Open in presentation mode.
    pub present: bool,
    /// Open in class mode.
    pub class: bool,
    /// Start the measuring sweep.
    pub sweep: Option<crate::ui::measuring_sweep::MeasuringSweep>,
    /// Start at this playback speed (t per s).
    pub speed: Option<f64>,
    /// Open a lesson at this step (1-based, checked against the timeline).
    pub step: Option<usize>,
    /// Write the plots' data into this folder when the window closes (checked before).
    pub plot_data: Option<PathBuf>,
    /// How finely the 3D view is drawn (`--render-scale`).
    pub render_scale: RenderScaleMode,
}

/// A window's event loop is running (it will see [`CLOSE_REQUESTED`]).
static WINDOW_RUNNING: AtomicBool = AtomicBool::new(false);
/// A signal asked the window to close.
static CLOSE_REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks a running window to close from its event loop (within 0.1 s: the loop wakes at least
/// that often), for the Ctrl-C handler; returns false when no window runs, or when a close was
/// already asked for (a second Ctrl-C, for a window that does not respond), so the caller
/// exits as it does for every other command.
pub fn request_close() -> bool {
    WINDOW_RUNNING.load(Ordering::SeqCst) && !CLOSE_REQUESTED.swap(true, Ordering::SeqCst)
}

/// Whether the window closed because a signal asked it to (the process then exits with 130).
pub fn closed_by_signal() -> bool {
    CLOSE_REQUESTED.load(Ordering::SeqCst)
}

/// Opens the window and runs until it is closed.
pub fn run(options: AppOptions) -> Result<()> {
    if cfg!(all(unix, not(target_os = "macos")))
        && std::env::var_os("DISPLAY").is_none()
        && std::env::var_os("WAYLAND_DISPLAY").is_none()
    {
        bail!(no_display("DISPLAY and WAYLAND_DISPLAY are not set"));
    }
    // From here a signal closes the window from its loop; whatever way `run` ends, the flag
    // goes with it, so a later signal exits at once.
    struct Running;
    impl Drop for Running {
        fn drop(&mut self) {
            WINDOW_RUNNING.store(false, Ordering::SeqCst);
        }
    }
    WINDOW_RUNNING.store(true, Ordering::SeqCst);
    let _running = Running;
    let event_loop = EventLoop::new().map_err(|e| anyhow!(no_display(&e.to_string())))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        options: Some(options),
        window: None,
        error: None,
        started: Instant::now(),
        frame_ms: Vec::new(),
        screenshot_done: false,
    };
    let ran = event_loop.run_app(&mut app);
    // --plot-data: the plots as the window closed.
    let plot_data = app.options.as_ref().and_then(|o| o.plot_data.clone());
    if let (Some(dir), Some(w)) = (plot_data, app.window.as_mut()) {
        let status = w.bench.sim.status();
        w.bench.ui.set_plot_data_dir(&dir);
        w.bench.ui.export_plot_data(&status);
        match w.bench.ui.notice() {
            Some((text, false)) => eprintln!("rollphase: {text}"),
            Some((text, true)) => {
                app.error
                    .get_or_insert_with(|| anyhow!("--plot-data: {text}"));
            }
            None => {}
        }
    }
    // The window, its surface and the GPU go before anything else can end the process.
    drop(app.window.take());
    ran.map_err(|e| anyhow!("the window's event loop failed: {e}"))?;
    if let Some(e) = app.error {
        return Err(e);
    }
    Ok(())
}

/// The window's first size: 1600×900, or 16:9 within 90 % of a smaller screen (on a 1280×720
/// projector the window opened larger than the screen).
fn initial_size(monitor: Option<PhysicalSize<u32>>) -> PhysicalSize<u32> {
    const PREFERRED: (f64, f64) = (1600.0, 900.0);
    let scale = match monitor {
        Some(m) if m.width > 0 && m.height > 0 => (0.9 * f64::from(m.width) / PREFERRED.0)
            .min(0.9 * f64::from(m.height) / PREFERRED.1)
            .min(1.0),
        _ => 1.0,
    };
    PhysicalSize::new(
        (PREFERRED.0 * scale).round() as u32,
        (PREFERRED.1 * scale).round() as u32,
    )
}

fn no_display(why: &str) -> String {
    format!(
        "cannot open a window: no display ({why}); render PNG frames instead with \
         `rollphase --headless --frames N` (add --preset NAME or --scene FILE)"
    )
}

struct WindowState {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: GpuContext,
    egui_winit: egui_winit::State,
    bench: Workbench,
    fullscreen: bool,
    /// The window is hidden (minimised, or fully covered where the platform says so): no
    /// frames are drawn, and the loop sleeps.
    hidden: bool,
}

struct App {
    options: Option<AppOptions>,
    window: Option<WindowState>,
    error: Option<anyhow::Error>,
    started: Instant,
    frame_ms: Vec<f64>,
    screenshot_done: bool,
}

impl App {
    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<WindowState> {
        let options = self
            .options
            .as_ref()
            .ok_or_else(|| anyhow!("the window was already opened"))?;
        let attributes = Window::default_attributes()
            .with_title(format!("rollphase: {}", options.setup.scene.name))
            .with_inner_size(initial_size(event_loop.primary_monitor().map(|m| m.size())));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| anyhow!(no_display(&e.to_string())))?,
        );
        let mut desc = wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(
            event_loop.owned_display_handle(),
        ));
        if std::env::var_os("WGPU_BACKEND").is_none() {
            desc.backends = crate::render::gpu::default_backends();
        }
        let backends = desc.backends;
        let instance = wgpu::Instance::new(desc);
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| anyhow!("cannot draw into the window: {e}"))?;
        let drawable: Vec<wgpu::Adapter> =
            pollster::block_on(instance.enumerate_adapters(backends))
                .into_iter()
                .filter(|a| a.is_surface_supported(&surface))
                .collect();
        let adapter = crate::render::gpu::pick(drawable).ok_or_else(|| {
            anyhow!(
                "no GPU adapter can draw into this window: install Mesa's drivers \
                 (Debian/Ubuntu: apt-get install libegl1 libgl1-mesa-dri), or use --headless"
            )
        })?;
        let gpu = GpuContext::from_adapter(instance, adapter)?;
        let caps = surface.get_capabilities(&gpu.adapter);
        let format = surface_format(&caps.formats)
            .ok_or_else(|| anyhow!("the window's surface offers no pixel format"))?;
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            color_space: wgpu::SurfaceColorSpace::default(),
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: vec![],
        };
        surface.configure(&gpu.device, &config);
        let cpu = gpu.is_cpu();
        let samples = if cpu { 1 } else { 4 };
        let options = self
            .options
            .take()
            .ok_or_else(|| anyhow!("the window was already opened"))?;
        let mut bench = Workbench::new(
            &gpu.device,
            &gpu.queue,
            format,
            samples,
            options.setup.clone(),
            options.base.clone(),
        )
        .context("cannot start the simulation thread")?;
        bench.set_render_scale(RenderScale::new(options.render_scale, cpu));
        if options.present {
            bench.ui.present_on_start();
        }
        if options.class {
            bench.ui.class_on_start();
        }
        if let Some(speed) = options.speed {
            let command = bench.ui.set_speed(speed);
            bench.sim.send(command);
        }
        if let Some(sweep) = options.sweep {
            bench.ui.set_measuring_sweep(Some(sweep));
        }
        // A lesson opens at its step 1; step k is where N, pressed k − 1 times, goes.
        for _ in 1..options.step.unwrap_or(1) {
            bench.sim.send(crate::live::SimCommand::NextStep);
        }
        let egui_winit = egui_winit::State::new(
            bench.ctx.clone(),
            egui::ViewportId::ROOT,
            event_loop,
            Some(window.scale_factor() as f32),
            None,
            Some(gpu.device.limits().max_texture_dimension_2d as usize),
        );
        eprintln!(
            "rollphase: window on {} ({format:?}, {samples}× MSAA)",
            gpu.describe()
        );
        self.options = Some(options);
        Ok(WindowState {
            window,
            surface,
            config,
            gpu,
            egui_winit,
            bench,
            fullscreen: false,
            hidden: false,
        })
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let Some(w) = self.window.as_mut() else {
            return;
        };
        let t0 = Instant::now();
        let input = w.egui_winit.take_egui_input(&w.window);
        let size = (w.config.width, w.config.height);
        let frame = w.bench.run_ui(input, size);
        w.egui_winit
            .handle_platform_output(&w.window, frame.platform_output.clone());
        for action in &frame.window_actions {
            if let UiAction::Fullscreen(on) = action
                && *on != w.fullscreen
            {
                w.fullscreen = *on;
                w.window
                    .set_fullscreen(on.then_some(Fullscreen::Borderless(None)));
                // Without a window manager (a bare X server, a kiosk) the fullscreen request
                // does nothing: ask for the monitor's size as well.
                if *on && let Some(monitor) = w.window.current_monitor() {
                    let _ = w.window.request_inner_size(monitor.size());
                }
            }
        }
        let texture = match w.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                w.surface.configure(&w.gpu.device, &w.config);
                return;
            }
            _ => return,
        };
        let view = texture.texture.create_view(&Default::default());
        w.bench.paint(&w.gpu.device, &w.gpu.queue, &view, &frame);
        w.window.pre_present_notify();
        w.gpu.queue.present(texture);
        let frame_s = t0.elapsed().as_secs_f64();
        w.bench.frame_done(frame_s);
        self.frame_ms.push(frame_s * 1e3);

        let elapsed = self.started.elapsed().as_secs_f64();
        if let Some((after, path)) = self
            .options
            .as_ref()
            .and_then(|o| o.screenshot_after.clone())
            && !self.screenshot_done
            && elapsed >= after
        {
            self.screenshot_done = true;
            match w.bench.capture(&w.gpu.device, &w.gpu.queue, &frame) {
                Ok(image) => match crate::png::write_png(&path, &image, &Default::default()) {
                    Ok(()) => eprintln!("rollphase: screenshot saved to {}", path.display()),
                    Err(e) => {
                        self.error = Some(anyhow!("screenshot: {e}"));
                        event_loop.exit();
                    }
                },
                Err(e) => {
                    self.error = Some(e.context("taking the screenshot"));
                    event_loop.exit();
                }
            }
        }
        if let Some(limit) = self.options.as_ref().and_then(|o| o.exit_after)
            && elapsed >= limit
        {
            let status = w.bench.sim.status();
            eprintln!(
                "{}",
                frame_summary(&self.frame_ms, status.delivered_speed, status.speed)
            );
            event_loop.exit();
        }
    }
}

/// "frames: N, frame time mean … p50 … p95 … max … ms (… frames/s); simulation … of … t/s".
pub fn frame_summary(frame_ms: &[f64], delivered: Option<f64>, speed: f64) -> String {
    // The first frames include shader compilation and the window's mapping.
    let steady: Vec<f64> = frame_ms.iter().copied().skip(5).collect();
    if steady.is_empty() {
        return format!("rollphase: {} frame(s) drawn", frame_ms.len());
    }
    let mut sorted = steady.clone();
    sorted.sort_by(f64::total_cmp);
    let pick = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
    let mean = steady.iter().sum::<f64>() / steady.len() as f64;
    format!(
        "rollphase: {} frames; frame time mean {mean:.1} ms, p50 {:.1}, p95 {:.1}, max {:.1} \
         ({:.0} frames/s); simulation delivers {} of {speed:.2} t per s",
        frame_ms.len(),
        pick(0.5),
        pick(0.95),
        pick(1.0),
        1e3 / mean,
        delivered.map_or("(not measured)".to_string(), |d| format!("{d:.2}")),
    )
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(w) => self.window = Some(w),
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(w) = self.window.as_mut() else {
            return;
        };
        let response = w.egui_winit.on_window_event(&w.window, &event);
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                w.config.width = size.width.max(1);
                w.config.height = size.height.max(1);
                w.surface.configure(&w.gpu.device, &w.config);
                w.window.request_redraw();
            }
            WindowEvent::Occluded(hidden) => w.hidden = hidden,
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            _ => {
                if response.repaint {
                    w.window.request_redraw();
                }
            }
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if CLOSE_REQUESTED.load(Ordering::SeqCst) {
            event_loop.exit();
            return;
        }
        // The simulation moves on by itself, so the window redraws continuously (vsync paces
        // it); a short sleep keeps a window without vsync from spinning a core. A minimised or
        // covered window draws nothing and wakes ten times a second only to notice it is back
        // (the simulation thread keeps time on its own).
        let hidden = self.window.as_ref().is_some_and(|w| {
            w.hidden
                || w.window.is_minimized() == Some(true)
                || !w.window.is_visible().unwrap_or(true)
        });
        if let Some(w) = &self.window
            && !hidden
        {
            w.window.request_redraw();
        }
        let nap = if hidden { 100 } else { 1 };
        event_loop.set_control_flow(ControlFlow::WaitUntil(
            Instant::now() + Duration::from_millis(nap),
        ));
    }
}

/// The window's pixel format among those its surface offers: a non-sRGB one where there is one
/// (as eframe chooses). egui then blends in gamma space and its shader skips two sRGB
/// conversions per pixel (11 of a 1920×1080 frame's 70 ms on llvmpipe); the 3D shaders encode
/// sRGB themselves, so the view shows the headless PNGs' colours either way
/// (`render::gpu::APP_FORMAT`). Only sRGB on offer: the first, and both still draw right.
fn surface_format(offered: &[wgpu::TextureFormat]) -> Option<wgpu::TextureFormat> {
    offered
        .iter()
        .copied()
        .find(|f| !f.is_srgb())
        .or_else(|| offered.first().copied())
}

#[cfg(test)]
mod tests {
    use super::{initial_size, surface_format};
    use wgpu::TextureFormat as F;

    #[test]
    fn the_window_takes_a_non_srgb_format_where_one_is_offered() {
        let offered = [F::Bgra8UnormSrgb, F::Bgra8Unorm, F::Rgba8Unorm];
        assert_eq!(surface_format(&offered), Some(F::Bgra8Unorm));
        assert_eq!(
            surface_format(&[F::Rgba8UnormSrgb]),
            Some(F::Rgba8UnormSrgb)
        );
        assert_eq!(surface_format(&[]), None);
    }
    use winit::dpi::PhysicalSize;

    #[test]
    fn the_window_fits_the_screen_it_opens_on() {
        let size = |w, h| initial_size(Some(PhysicalSize::new(w, h)));
        assert_eq!(size(1920, 1080), PhysicalSize::new(1600, 900));
        assert_eq!(size(3840, 2160), PhysicalSize::new(1600, 900));
        assert_eq!(size(1280, 720), PhysicalSize::new(1152, 648));
        // A tall or narrow screen: the smaller ratio decides, 16:9 kept.
        assert_eq!(size(1024, 1280), PhysicalSize::new(922, 518));
        assert_eq!(initial_size(None), PhysicalSize::new(1600, 900));
        assert_eq!(size(0, 0), PhysicalSize::new(1600, 900));
    }
}
