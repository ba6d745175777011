//! The app minus the window: the simulation thread, the UI state, the egui context and the
//! painter, run one frame at a time against any wgpu target. `app.rs` wraps it in a winit
//! window; the windowless tests and `rollphase bench app` drive it offscreen, so everything
//! but the window itself is exercised where there is no display.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, anyhow};
use image::RgbaImage;

use super::painter::{EguiFrame, Painter, rect_to_pixels};
use super::render_scale::{RenderScale, RenderScaleMode};
use super::{AppUi, RecordProgress, UiAction};
use crate::clip::{ClipKind, ClipWriter};
use crate::live::{SimStatus, SimThread};
use crate::output::{self, Inputs};
use crate::png::{PngWriter, frame_name, write_png};
use crate::render::gpu::OffscreenTarget;
use crate::scene::SceneSetup;

/// One frame's UI result, ready to paint.
pub struct UiFrame {
    /// egui's tessellated output.
    pub egui: EguiFrame,
    /// What egui asks of the platform (cursor, clipboard, links), for the window to apply.
    pub platform_output: egui::PlatformOutput,
    /// The status the frame shows.
    pub status: std::sync::Arc<SimStatus>,
    /// The 3D area, pixels.
    pub scene_rect: [u32; 4],
    /// The target size, pixels.
    pub size: (u32, u32),
    /// Requests only the window can carry out (full screen).
    pub window_actions: Vec<UiAction>,
}

struct Recording {
    /// Made at the first recorded frame (the device is at hand there).
    target: Option<OffscreenTarget>,
    size: (u32, u32),
    sink: RecordSink,
    done: u32,
    total: u32,
}

/// Where recorded frames go: PNG files in a folder, or one clip (a path ending in .gif or .mp4).
enum RecordSink {
    Pngs { writer: PngWriter, dir: PathBuf },
    Clip { writer: ClipWriter, path: PathBuf },
}

impl RecordSink {
    fn write(&mut self, index: u32, image: RgbaImage) -> Result<()> {
        match self {
            RecordSink::Pngs { writer, dir } => {
                Ok(writer.write(dir.join(frame_name(index as u64)), image)?)
            }
            RecordSink::Clip { writer, .. } => Ok(writer.push(image)?),
        }
    }

    /// Finishes the files; returns where they went.
    fn close(self) -> Result<PathBuf> {
        match self {
            RecordSink::Pngs { writer, dir } => {
                writer.close()?;
                Ok(dir)
            }
            RecordSink::Clip { writer, path } => {
                writer.finish()?;
                Ok(path)
            }
        }
    }
}

/// The app's state and machinery for one target format.
pub struct Workbench {
    /// The egui context.
    pub ctx: egui::Context,
    /// The UI state.
    pub ui: AppUi,
    /// The simulation thread.
    pub sim: SimThread,
    painter: Painter,
    format: wgpu::TextureFormat,
    recording: Option<Recording>,
    pending_screenshots: Vec<PathBuf>,
    /// egui's texture changes not yet uploaded (a frame the window skips keeps them here).
    textures: egui::TexturesDelta,
    frame_times: std::collections::VecDeque<Instant>,
    render_scale: RenderScale,
    /// The texts the last frame cut at the side of the area they are drawn in.
    cut_texts: Vec<String>,
    upright_bars: Vec<egui::Rect>,
}

impl Workbench {
    /// Starts the simulation of `setup` and builds the renderers for `format`; fails only when
    /// the simulation's thread cannot be started.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        format: wgpu::TextureFormat,
        sample_count: u32,
        setup: SceneSetup,
        base: Option<PathBuf>,
    ) -> std::io::Result<Self> {
        let ui = AppUi::new(&setup, base);
        let ctx = egui::Context::default();
        ctx.set_fonts(super::fonts::definitions());
        Ok(Self {
            ctx,
            ui,
            sim: SimThread::spawn(setup)?,
            painter: Painter::new(device, queue, format, sample_count),
            format,
            recording: None,
            pending_screenshots: Vec::new(),
            textures: egui::TexturesDelta::default(),
            frame_times: Default::default(),
            cut_texts: Vec::new(),
            upright_bars: Vec::new(),
            render_scale: RenderScale::new(RenderScaleMode::Auto, false),
        })
    }

    /// Sets how finely the 3D view is drawn (`--render-scale`, and whether the adapter is a CPU
    /// renderer); until called, at full resolution.
    pub fn set_render_scale(&mut self, scale: RenderScale) {
        self.render_scale = scale;
    }

    /// Counts one frame's wall time (the UI and the paint) towards the automatic render scale.
    pub fn frame_done(&mut self, seconds: f64) {
        self.render_scale.record(seconds);
    }

    /// The scale the live frames' 3D view is drawn at: the View menu's "3D at full resolution"
    /// overrides the automatic choice.
    pub fn render_scale(&self) -> f32 {
        if self.ui.full_resolution {
            1.0
        } else {
            self.render_scale.scale()
        }
    }

    /// Runs the UI on `input` for a `size`-pixel target: reads the latest status (never
    /// waiting for the simulation, but for a load this frame asked for: up to
    /// [`RESTART_WAIT`], so that the frame draws it), sends the commands the user gave, and
    /// tessellates.
    pub fn run_ui(&mut self, input: egui::RawInput, size: (u32, u32)) -> UiFrame {
        let now = Instant::now();
        self.frame_times.push_back(now);
        while self
            .frame_times
            .front()
            .is_some_and(|t| (now - *t).as_secs_f64() > 1.0)
        {
            self.frame_times.pop_front();
        }
        if self.frame_times.len() > 2 {
            self.ui.fps = Some((self.frame_times.len() - 1) as f64);
        }
        self.ui.render_scale_note = if self.ui.full_resolution {
            None
        } else {
            self.render_scale.shown()
        };
        let status = self.sim.status();
        let (scale, note) = self.painter.sync(&status, &self.ui.views);
        self.ui.field_note = note;
        let samples = self.sim.take_plot_samples();
        self.ui.follow_status(&status, scale, samples);
        // Under a lesson's caption, while its step's evidence is measured: say so (the plot
        // under the claim would otherwise look empty or partial without a word).
        let status = match self.ui.evidence_note(&status) {
            Some(note) => {
                let mut shown = (*status).clone();
                let caption = shown.snapshot.caption.take().unwrap_or_default();
                shown.snapshot.caption = Some(format!("{caption} ({note})"));
                std::sync::Arc::new(shown)
            }
            None => status,
        };
        self.ui.recording = self.recording.as_ref().map(|r| RecordProgress {
            done: r.done,
            total: r.total,
        });
        let mut actions = Vec::new();
        let output = self.ctx.run_ui(input, |ui| {
            actions = self.ui.show(ui, &status);
        });
        let mut window_actions = Vec::new();
        let mut loads = false;
        for action in actions {
            match action {
                UiAction::Sim(c) => {
                    loads |= matches!(c, crate::live::SimCommand::Load(_));
                    self.sim.send(c);
                }
                UiAction::Screenshot(path) => self.pending_screenshots.push(path),
                UiAction::Record { dir, frames } => self.start_recording(dir, frames, size),
                UiAction::Fullscreen(_) => window_actions.push(action),
            }
        }
        let status = if loads {
            self.restarted(status)
        } else {
            status
        };
        self.textures.append(output.textures_delta);
        self.cut_texts = texts_cut_at_the_side(&output.shapes);
        self.upright_bars = upright_bars(&output.shapes);
        let pixels_per_point = output.pixels_per_point;
        let primitives = self.ctx.tessellate(output.shapes, pixels_per_point);
        let scene_rect = self
            .ui
            .scene_rect
            .map(|r| rect_to_pixels(r, pixels_per_point, size))
            .unwrap_or([0, 0, size.0, size.1]);
        UiFrame {
            egui: EguiFrame {
                primitives,
                pixels_per_point,
            },
            platform_output: output.platform_output,
            status,
            scene_rect,
            size,
            window_actions,
        }
    }

    /// The status of the run a load this frame asked for, waited for at most
    /// [`RESTART_WAIT`] (the simulation takes a load within a tick, 8 ms): the 3D view then
    /// draws a sculpting stroke's new body in the frame of the click, not the frame after, which
    /// on a CPU renderer is 55–100 ms later. The only wait for the simulation: every other
    /// frame reads the latest status as it is. `status` if the load has not arrived by then.
    fn restarted(&mut self, status: std::sync::Arc<SimStatus>) -> std::sync::Arc<SimStatus> {
        let asked = Instant::now();
        while asked.elapsed() < RESTART_WAIT {
            let now = self.sim.status();
            if now.scene_id != status.scene_id {
                // The new body's meshes for this frame; the panels follow it next frame.
                let (_, note) = self.painter.sync(&now, &self.ui.views);
                self.ui.field_note = note;
                return now;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        status
    }

    /// Records the 3D view of the next `frames` painted frames (at its size now, in a `size`
    /// target) as PNGs in `dir`: what the UI's Record button does.
    pub fn start_recording(&mut self, dir: PathBuf, frames: u32, size: (u32, u32)) {
        let rect = self
            .ui
            .scene_rect
            .map(|r| rect_to_pixels(r, self.ctx.pixels_per_point(), size))
            .unwrap_or([0, 0, size.0, size.1]);
        // Even sizes keep video encoders happy.
        let frame_size = ((rect[2].max(16)) & !1, (rect[3].max(16)) & !1);
        let kind = match dir.extension().and_then(|e| e.to_str()) {
            Some("gif") => Some(ClipKind::Gif),
            Some("mp4") => Some(ClipKind::Mp4),
            _ => None,
        };
        let sink = match kind {
            Some(kind) => {
                let fps = self.sim.status().setup.scene.playback.fps;
                match ClipWriter::new(kind, &dir, frame_size, fps, &Inputs::none()) {
                    Ok(writer) => RecordSink::Clip { writer, path: dir },
                    Err(e) => {
                        self.ui.notify(e.to_string(), true);
                        return;
                    }
                }
            }
            None => {
                if let Err(e) = output::create_folder(&dir) {
                    self.ui.notify(e.to_string(), true);
                    return;
                }
                RecordSink::Pngs {
                    writer: PngWriter::new(2, Inputs::none()),
                    dir,
                }
            }
        };
        self.recording = Some(Recording {
            target: None,
            size: frame_size,
            sink,
            done: 0,
            total: frames,
        });
    }

    /// Paints the frame into `target` (the window's surface texture, or any texture of the
    /// format), and carries out pending screenshots and the recording.
    pub fn paint(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &wgpu::TextureView,
        frame: &UiFrame,
    ) {
        self.painter
            .prepare(device, queue, frame.size, &frame.egui, &mut self.textures);
        let scale = self.render_scale();
        self.paint_prepared(device, queue, target, frame, scale);
        for path in std::mem::take(&mut self.pending_screenshots) {
            let result = self
                .capture_painted(device, queue, frame)
                .and_then(|image| save_png(&path, &image));
            match result {
                Ok(()) => self.ui.notify(format!("saved {}", path.display()), false),
                Err(e) => self.ui.notify(format!("{e:#}"), true),
            }
        }
        self.record(device, queue, frame);
        self.painter.finish(&mut self.textures);
    }

    /// The texts the last frame drew reaching past the left or right side of the area they are
    /// clipped to (a panel, a scroll area, the window), so that part of them is not on the
    /// screen: a control's label or value cut at a narrow panel's edge. What a layout test asks
    /// of every mode and size; texts cut at the top or bottom are a scroll area's, by design.
    pub fn texts_cut(&self) -> &[String] {
        &self.cut_texts
    }

    /// The filled rectangles the last frame drew at most 14 points wide and at least 20 tall,
    /// where they show on screen (within their clip): a vertical scroll bar's track and handle.
    /// What a layout test asks to see a scroll bar drawn beside content that runs past it.
    pub fn upright_bars(&self) -> &[egui::Rect] {
        &self.upright_bars
    }

    /// How many meshes the 3D renderer holds: the running scene's, however many were loaded.
    pub fn mesh_count(&self) -> usize {
        self.painter.mesh_count()
    }

    /// Whether a recording is in progress.
    pub fn is_recording(&self) -> bool {
        self.recording.is_some()
    }

    /// Paints `frame` (egui's data already uploaded) with the UI's views and camera, the 3D
    /// view at `scale`.
    fn paint_prepared(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &wgpu::TextureView,
        frame: &UiFrame,
        scale: f32,
    ) {
        self.painter.paint(
            device,
            queue,
            target,
            frame.size,
            frame.scene_rect,
            &frame.status,
            &self.ui.views,
            &self.ui.view_options,
            scale,
        );
        self.ui.sculpt.pick_view = self.painter.pick_view();
    }

    /// Paints the frame again into an offscreen texture, always at full resolution, and reads
    /// it back (RGBA).
    fn capture_painted(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        frame: &UiFrame,
    ) -> Result<RgbaImage> {
        let target = OffscreenTarget::with_format(device, frame.size, self.format);
        self.paint_prepared(device, queue, &target.view, frame, 1.0);
        let pixels = target.read(device, queue)?;
        RgbaImage::from_raw(frame.size.0, frame.size.1, pixels)
            .ok_or_else(|| anyhow!("the screenshot readback returned a short buffer"))
    }

    /// Paints the frame offscreen and returns the pixels: the same picture the window shows.
    pub fn capture(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        frame: &UiFrame,
    ) -> Result<RgbaImage> {
        self.painter
            .prepare(device, queue, frame.size, &frame.egui, &mut self.textures);
        let image = self.capture_painted(device, queue, frame);
        self.painter.finish(&mut self.textures);
        image
    }

    fn record(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, frame: &UiFrame) {
        let Some(rec) = self.recording.as_mut() else {
            return;
        };
        let format = self.format;
        let rec_target = rec
            .target
            .get_or_insert_with(|| OffscreenTarget::with_format(device, rec.size, format));
        self.painter.paint_scene(
            &rec_target.view,
            rec_target.size,
            &frame.status,
            &self.ui.views,
            &self.ui.view_options,
        );
        let result = rec_target
            .read(device, queue)
            .map_err(anyhow::Error::from)
            .and_then(|pixels| {
                let (w, h) = rec_target.size;
                RgbaImage::from_raw(w, h, pixels).ok_or_else(|| anyhow!("short readback"))
            })
            .and_then(|image| rec.sink.write(rec.done, image));
        rec.done += 1;
        let finished = rec.done >= rec.total;
        if let Err(e) = result {
            self.ui.notify(format!("recording stopped: {e:#}"), true);
            self.recording = None;
        } else if finished && let Some(rec) = self.recording.take() {
            match rec.sink.close() {
                Ok(place) => self.ui.notify(
                    format!("recorded {} frames to {}", rec.done, place.display()),
                    false,
                ),
                Err(e) => self.ui.notify(format!("recording failed: {e:#}"), true),
            }
        }
    }
}

fn save_png(path: &Path, image: &RgbaImage) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        output::create_folder(dir)?;
    }
    write_png(path, image, &Inputs::none()).context("screenshot")
}

/// Every leaf shape among `shapes` (nested lists opened) with its clip rectangle, to `each`.
fn each_shape(
    shapes: &[egui::epaint::ClippedShape],
    mut each: impl FnMut(&egui::Shape, egui::Rect),
) {
    fn visit(
        shape: &egui::Shape,
        clip: egui::Rect,
        each: &mut impl FnMut(&egui::Shape, egui::Rect),
    ) {
        match shape {
            egui::Shape::Vec(shapes) => shapes.iter().for_each(|s| visit(s, clip, each)),
            leaf => each(leaf, clip),
        }
    }
    for clipped in shapes {
        visit(&clipped.shape, clipped.clip_rect, &mut each);
    }
}

/// The texts among `shapes` that reach past the left or right of their clip rectangle by more
/// than a pixel's rounding.
fn texts_cut_at_the_side(shapes: &[egui::epaint::ClippedShape]) -> Vec<String> {
    let mut cut = Vec::new();
    each_shape(shapes, |shape, clip| {
        if let egui::Shape::Text(text) = shape {
            let r = text.visual_bounding_rect();
            if r.is_positive() && (r.min.x < clip.min.x - 1.0 || r.max.x > clip.max.x + 1.0) {
                cut.push(text.galley.text().to_string());
            }
        }
    });
    cut
}

/// The filled, visible rectangles among `shapes` at most 14 points wide and at least 20 tall,
/// cut to their clip rectangle.
fn upright_bars(shapes: &[egui::epaint::ClippedShape]) -> Vec<egui::Rect> {
    let mut bars = Vec::new();
    each_shape(shapes, |shape, clip| {
        if let egui::Shape::Rect(r) = shape
            && r.fill.a() > 0
        {
            let shown = r.rect.intersect(clip);
            if shown.is_positive() && shown.width() <= 14.0 && shown.height() >= 20.0 {
                bars.push(shown);
            }
        }
    });
    bars
}

impl Drop for Workbench {
    fn drop(&mut self) {
        // Texture changes never uploaded (the window closed first) are dropped on purpose.
        self.textures.clear();
    }
}

/// The longest a frame that asked for a load (a sculpting stroke, undo, a scene opened) waits
/// for the simulation to take it, so that the frame draws the new run: the simulation's tick is
/// 8 ms, and a frame of a CPU renderer 55–100 ms.
pub const RESTART_WAIT: std::time::Duration = std::time::Duration::from_millis(40);

/// A point of the screen in egui's points, as the scripted input takes it (for callers without
/// egui of their own, such as `rollphase bench app`).
pub use egui::Pos2;

/// The input events of one frame, as [`offscreen_input`] takes them.
pub type UiEvents = Vec<egui::Event>;

/// A click at `pos` (screen points), the right button if `secondary`: the press (with the pointer
/// moved there) and the release, for two frames in turn. For benchmarks and scripted demos.
pub fn click_events(pos: egui::Pos2, secondary: bool) -> [UiEvents; 2] {
    let button = if secondary {
        egui::PointerButton::Secondary
    } else {
        egui::PointerButton::Primary
    };
    let event = |pressed| egui::Event::PointerButton {
        pos,
        button,
        pressed,
        modifiers: egui::Modifiers::NONE,
    };
    [
        vec![egui::Event::PointerMoved(pos), event(true)],
        vec![event(false)],
    ]
}

/// The pointer moved to `pos` (screen points), and the primary button pressed there (`Some(true)`)
/// or released (`Some(false)`): one frame of a drag. For benchmarks and scripted demos.
pub fn drag_events(pos: egui::Pos2, pressed: Option<bool>) -> UiEvents {
    let mut events = vec![egui::Event::PointerMoved(pos)];
    if let Some(pressed) = pressed {
        events.push(egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
    }
    events
}

/// egui input for a `size`-pixel offscreen target at one pixel per point, with `events`
/// (the windowless tests and `rollphase bench app` drive the UI with it).
pub fn offscreen_input(size: (u32, u32), time: f64, events: Vec<egui::Event>) -> egui::RawInput {
    egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(
            egui::Pos2::ZERO,
            egui::vec2(size.0 as f32, size.1 as f32),
        )),
        time: Some(time),
        events,
        focused: true,
        ..Default::default()
    }
}
