//! Offscreen rendering of a scene to PNG frames through the same [`Renderer`] as the window:
//! `rollphase --headless --frames N`. Never creates a window or an event loop, so it runs with
//! no display; with no GPU it renders on Mesa's llvmpipe (GL backend).
//!
//! Frame k shows simulation time `start_time + k · speed / fps` (with a lesson's speed steps,
//! [`SceneSetup::frame_time`] walks them); the Poincaré field, when shown, is computed before
//! the frame that first needs it (again after a lesson step changes α or m/m0). So the same
//! scene and size give the same pixels on every run, whatever the machine's load. A lesson's
//! steps change the views and the caption as the simulation reaches them. PNG encoding runs on a writer thread, off the
//! render loop.

use std::path::Path;
use std::sync::Arc;

use anyhow::{Context, Result, anyhow, bail};
use image::RgbaImage;

use crate::analysis::orbits::poincare_field::FieldArrow;
use crate::clip::{ClipKind, ClipWriter};
use crate::dynamics::Ramp;
use crate::live::LiveRun;
use crate::live::history::{PlotHistory, PlotMeta};
use crate::live::{FieldCache, FieldWanted};
use crate::output::Inputs;
use crate::png::{PngWriter, frame_name};
use crate::render::gpu::OffscreenTarget;
use crate::render::types::Frame;
use crate::render::{GpuContext, Renderer};
use crate::scene::SceneSetup;
use crate::view::{SceneView, ViewOptions};

/// Largest frame side accepted (wgpu's default 2D texture limit is 8192).
pub const MAX_SIDE: u32 = 8192;

/// MSAA samples of headless frames by default (`--msaa 1` trades smooth edges for speed).
pub const SAMPLE_COUNT: u32 = 4;

/// A scene ready to render offscreen.
pub struct HeadlessRenderer {
    gpu: GpuContext,
    renderer: Renderer,
    target: OffscreenTarget,
    view: SceneView,
    sim: LiveRun,
    fields: FieldCache,
    /// The field drawn, and the ramp it belongs to.
    field: Option<(Ramp, Arc<Vec<FieldArrow>>)>,
    options: ViewOptions,
    /// What is said under each lesson step's caption whose claim the run does not bear out (by
    /// timeline index), as the app says it.
    claims_not_shown: Vec<Option<String>>,
}

/// A scene start time beyond this is simulated in slices with a progress bar.
const LONG_START_TIME: f64 = 1000.0;

/// Checks a frame size.
pub fn check_size(size: (u32, u32)) -> Result<()> {
    let (w, h) = size;
    if !(16..=MAX_SIDE).contains(&w) || !(16..=MAX_SIDE).contains(&h) {
        bail!("frame size {w}x{h} is not allowed (needs 16 ≤ width, height ≤ {MAX_SIDE})");
    }
    Ok(())
}

impl HeadlessRenderer {
    /// Sets up the GPU, the meshes and the simulation of `setup` for frames of `size`.
    pub fn new(setup: SceneSetup, size: (u32, u32), sample_count: u32) -> Result<Self> {
        check_size(size)?;
        if !matches!(sample_count, 1 | 4) {
            bail!("MSAA sample count {sample_count} is not allowed (needs 1 or 4)");
        }
        let gpu = GpuContext::headless()?;
        let mut renderer = Renderer::new(
            &gpu.device,
            &gpu.queue,
            crate::render::gpu::OFFSCREEN_FORMAT,
            sample_count,
        );
        let target = OffscreenTarget::new(&gpu.device, size);
        let view = SceneView::new(&mut renderer, &setup);
        let sim = LiveRun::new(setup);
        let mut renderer = Self {
            gpu,
            renderer,
            target,
            view,
            sim,
            fields: FieldCache::default(),
            field: None,
            options: ViewOptions::default(),
            claims_not_shown: Vec::new(),
        };
        renderer.update_field()?;
        Ok(renderer)
    }

    /// Fetches the Poincaré field the simulation wants ([`FieldWanted`]), computing it here
    /// (frames wait for it); drops it when none is wanted.
    fn update_field(&mut self) -> Result<()> {
        match self.sim.field_wanted() {
            FieldWanted::Ramp(ramp) => {
                if self.field.as_ref().is_none_or(|(r, _)| *r != ramp) {
                    let arrows = self
                        .fields
                        .get_blocking(self.sim.setup(), &ramp)
                        .map_err(|e| anyhow!("computing the Poincaré field failed: {e}"))?;
                    self.field = Some((ramp, arrows));
                }
            }
            FieldWanted::Off | FieldWanted::NeedsViscous => self.field = None,
        }
        Ok(())
    }

    /// The adapter in use, e.g. "llvmpipe (LLVM 15.0.6, 256 bits) (Gl, Cpu)".
    pub fn adapter(&self) -> String {
        self.gpu.describe()
    }

    /// Simulates up to time `t` without drawing (e.g. the scene's start time, in slices).
    pub fn advance_to(&mut self, t: f64) -> Result<()> {
        self.sim
            .advance_to(t)
            .with_context(|| format!("simulating to t = {t}"))
    }

    /// The simulation (to inspect its snapshot).
    pub fn simulation(&self) -> &LiveRun {
        &self.sim
    }

    /// The plots' samples the simulation took since the last call (every
    /// [`PLOT_SAMPLE_DT`](crate::live::PLOT_SAMPLE_DT) of its time, whatever the frame rate).
    pub fn take_plot_samples(&mut self) -> Vec<crate::live::history::Sample> {
        self.sim.take_plot_samples()
    }

    /// Advances the simulation to frame `k`'s time and returns what that frame draws (the
    /// views with their cameras and viewports, and the panels), without drawing it.
    pub fn frame_data(&mut self, k: u64) -> Result<Frame> {
        let t = self.sim.setup().frame_time(k);
        self.sim
            .advance_to(t)
            .with_context(|| format!("simulating frame {k} (t = {t})"))?;
        self.update_field()?;
        let mut snap = self.sim.snapshot();
        // A claim the run does not bear out is said under its caption, never left standing.
        let step = snap.lesson.as_ref().and_then(|l| l.done.checked_sub(1));
        if let Some(Some(why)) = step.and_then(|k| self.claims_not_shown.get(k))
            && let Some(caption) = &mut snap.caption
        {
            caption.push_str(&format!(" ({why})"));
        }
        let v = &snap.views;
        self.view.set_views(v.body, v.ball, v.poincare, v.overlay);
        Ok(self.view.frame(
            &snap,
            self.field.as_ref().map(|(_, arrows)| arrows.as_slice()),
            self.target.size,
            &self.options,
        ))
    }

    /// What picking a body point in `frame` (one of this renderer's) needs: the body's view.
    pub fn pick_view(&self, frame: &Frame) -> Option<crate::view::pick::PickView> {
        self.view.pick_view(frame)
    }

    /// Checks each lesson step's claim against the lesson's own run from its start (the
    /// evidence the app measures ahead, `live::evidence`), so that the frames say under a
    /// caption whose claim the run does not bear out what it shows instead. Returns those
    /// steps, as "timeline[k]: claims …, but …". Nothing for a scene without claims or a resumed
    /// one (its run did not start at the lesson's start).
    pub fn check_claims(&mut self) -> Vec<String> {
        self.check_claims_reporting(|_, _| {})
    }

    /// [`Self::check_claims`], calling `report(t_done, t_end)` as the lesson's run goes (a
    /// hundred times in all): a stiff step (a tiny m/m0) can make it minutes.
    pub fn check_claims_reporting(&mut self, mut report: impl FnMut(f64, f64)) -> Vec<String> {
        let setup = self.sim.setup();
        if setup.resume.is_some() || setup.timeline.iter().all(|s| s.claim.is_none()) {
            return Vec::new();
        }
        let stop = std::sync::atomic::AtomicBool::new(false);
        let mut state = None;
        let every = crate::live::evidence::step_ends(setup)
            .last()
            .map_or(f64::INFINITY, |end| end / 100.0);
        crate::live::evidence::measure_evidence(setup, &stop, every, |s| {
            report(s.t_done, s.t_end);
            state = Some(s.clone());
        });
        let Some(state) = state else {
            return Vec::new();
        };
        self.claims_not_shown = vec![None; setup.timeline.len()];
        let mut said = Vec::new();
        for (k, claim, verdict) in crate::live::evidence::claims_checked(setup, &state) {
            if let Err(why) = verdict {
                said.push(format!(
                    "timeline[{k}]: claims \"{}\", but {why}",
                    claim.name()
                ));
                self.claims_not_shown[k] =
                    Some(crate::live::evidence::claim_not_shown(claim, &why));
            }
        }
        if let Some(why) = state.failed {
            said.push(format!(
                "the lesson's claims after t = {} could not be checked: {why}",
                state.t_done
            ));
        }
        said
    }

    /// Sets the camera and text options (e.g. class mode's text scale) of the frames to come.
    pub fn set_view_options(&mut self, options: ViewOptions) {
        self.options = options;
    }

    /// Advances the simulation to frame `k`'s time and submits its drawing; does not wait.
    pub fn draw(&mut self, k: u64) -> Result<()> {
        let frame = self.frame_data(k)?;
        self.renderer
            .render(&self.target.view, self.target.size, &frame);
        Ok(())
    }

    /// Waits for the GPU to finish the submitted frame.
    pub fn finish(&self) -> Result<()> {
        Ok(self.target.wait(&self.gpu.device)?)
    }

    /// Draws frame `k` and reads it back.
    pub fn frame(&mut self, k: u64) -> Result<RgbaImage> {
        self.draw(k)?;
        let pixels = self.target.read(&self.gpu.device, &self.gpu.queue)?;
        let (w, h) = self.target.size;
        RgbaImage::from_raw(w, h, pixels).ok_or_else(|| anyhow!("readback returned a short buffer"))
    }
}

/// What a headless run did.
#[derive(Debug, Clone)]
pub struct HeadlessReport {
    /// The adapter used.
    pub adapter: String,
    /// Frames written.
    pub frames: u64,
    /// Simulation time of the first frame (a scene's `start_time`, or a saved state's time).
    pub t_first: f64,
    /// Simulation time of the last frame.
    pub t_last: f64,
    /// Why the model differs from the request, if it does.
    pub model_note: Option<String>,
    /// The lesson steps whose claims the run does not bear out, and why
    /// ([`HeadlessRenderer::check_claims`]).
    pub claims_not_shown: Vec<String>,
}

/// Where headless frames go.
#[derive(Debug, Clone, Copy)]
pub enum FrameSink<'a> {
    /// PNG files `frame_00000.png …` in this folder.
    Pngs(&'a Path),
    /// One clip file (GIF or MP4) at the scene's frames per second.
    Clip(ClipKind, &'a Path),
}

/// Renders `frames` frames of `setup` at `size` into `out/frame_00000.png …`.
pub fn write_frames(
    setup: SceneSetup,
    frames: u64,
    size: (u32, u32),
    sample_count: u32,
    out: &Path,
    progress: bool,
) -> Result<HeadlessReport> {
    render_to(
        setup,
        frames,
        size,
        sample_count,
        FrameSink::Pngs(out),
        &Inputs::none(),
        RenderExtras {
            progress,
            plot_data: None,
        },
    )
}

/// The open writer behind a [`FrameSink`].
enum Frames<'a> {
    Pngs(PngWriter, &'a Path),
    Clip(ClipWriter),
}

/// What a headless run does besides the frames.
#[derive(Debug, Clone, Copy, Default)]
pub struct RenderExtras<'a> {
    /// Show a progress bar.
    pub progress: bool,
    /// Also write the app's plot data (1/T against α, ∂Ω crossings against m/m0, the health
    /// history, collected frame by frame as the app collects them) as CSV into this folder.
    pub plot_data: Option<&'a Path>,
}

/// Renders `frames` frames of `setup` at `size` into `sink`, through the output layer; no
/// frame or clip may overwrite one of `inputs` (the scene and its shape file).
pub fn render_to(
    setup: SceneSetup,
    frames: u64,
    size: (u32, u32),
    sample_count: u32,
    sink: FrameSink,
    inputs: &Inputs,
    extras: RenderExtras,
) -> Result<HeadlessReport> {
    if frames == 0 {
        bail!("--frames 0 renders nothing (needs at least 1)");
    }
    let progress = extras.progress;
    if let Some(dir) = extras.plot_data {
        PlotHistory::check_folder(dir, 1 + setup.lanes.len(), inputs).context("--plot-data")?;
    }
    let mut history = PlotHistory::of_setup(&setup);
    let fps = setup.scene.playback.fps;
    // PNG files in a folder (written by a pool of threads), or one clip.
    let mut writer = match sink {
        FrameSink::Pngs(out) => {
            crate::output::create_folder(out)?;
            Frames::Pngs(PngWriter::new(2, inputs.clone()), out)
        }
        FrameSink::Clip(kind, path) => {
            Frames::Clip(ClipWriter::new(kind, path, size, fps, inputs)?)
        }
    };
    let model_note = setup.model_note.clone();
    let mut hr = HeadlessRenderer::new(setup, size, sample_count)?;
    let bar = if progress {
        indicatif::ProgressBar::new(frames)
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} {bar:40} {pos}/{len} {elapsed}/{eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    // The lesson's run from its start, for its claims: about a second for the bundled ones,
    // minutes where a step is stiff (m/m0 = 1e-6), so it shows its progress too.
    bar.set_length(100);
    bar.set_message("checking the lesson's claims on its run from t = 0");
    let claims_not_shown = hr.check_claims_reporting(|done, end| {
        bar.set_position((100.0 * done / end.max(f64::MIN_POSITIVE)).clamp(0.0, 100.0) as u64);
    });
    bar.set_length(frames);
    bar.set_position(0);
    // The scene's start_time is simulated before frame 0; a long one (start_time = 1e6) shows
    // its progress in 100 slices instead of a silent wait. Short ones (every preset) run in one
    // piece, so their frames are exactly those of the app and the tests.
    let start = hr.simulation().setup().frame_time(0);
    let from = hr.simulation().time();
    if extras.plot_data.is_some() && start > from {
        // The plots collect from snapshots (a lesson's crossings at each m/m0 it steps
        // through, its 1/T points): taken at every frame step up to the start, as frames from
        // t = 0 would take them, so starting late loses none of them (the run is the same
        // however it is cut).
        bar.set_length(100);
        bar.set_message(format!("simulating to t = {start} (collecting the plots)"));
        let fps = hr.simulation().setup().scene.playback.fps;
        let mut t = from;
        while t < start {
            t = (t + hr.simulation().setup().speed_at(t) / fps).min(start);
            hr.advance_to(t)?;
            history.push(&hr.simulation().snapshot());
            history.push_samples(hr.take_plot_samples());
            bar.set_position((100.0 * (t - from) / (start - from)) as u64);
        }
        bar.set_length(frames);
        bar.set_position(0);
    } else if start > LONG_START_TIME {
        bar.set_length(100);
        bar.set_message(format!("simulating to t = {start}"));
        for i in 1..=100u64 {
            hr.advance_to(start * i as f64 / 100.0)?;
            bar.set_position(i);
        }
        bar.set_length(frames);
        bar.set_position(0);
    }
    bar.set_message("rendering");
    let mut t_first = f64::NAN;
    for k in 0..frames {
        let image = hr.frame(k)?;
        if k == 0 {
            t_first = hr.simulation().time();
        }
        if extras.plot_data.is_some() {
            history.push(&hr.simulation().snapshot());
            history.push_samples(hr.take_plot_samples());
        }
        match &mut writer {
            Frames::Clip(clip) => clip.push(image)?,
            Frames::Pngs(pngs, out) => pngs.write(out.join(frame_name(k)), image)?,
        }
        bar.inc(1);
    }
    match writer {
        Frames::Clip(clip) => {
            bar.set_message("finishing the clip");
            clip.finish()?;
        }
        Frames::Pngs(pngs, _) => pngs.close()?,
    }
    if let Some(dir) = extras.plot_data {
        let snapshot = hr.simulation().snapshot();
        let meta = PlotMeta::of(&snapshot, hr.simulation().setup(), hr.simulation().method());
        history
            .write_csv_files(dir, snapshot.health.measured, &meta, inputs)
            .context("--plot-data")?;
    }
    bar.finish_and_clear();
    Ok(HeadlessReport {
        adapter: hr.adapter(),
        frames,
        t_first,
        t_last: hr.simulation().time(),
        model_note,
        claims_not_shown,
    })
}
