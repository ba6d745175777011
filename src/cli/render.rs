//! The top-level render flags: `rollphase --headless --frames N [--out DIR] [--scene FILE |
//! --preset NAME] [--size WxH]`, and the scene they pick (shared with the app).

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;

use crate::cli::pick_scene;
#[cfg(feature = "render")]
use crate::scene::SceneSetup;

/// Most frames one headless run writes.
pub const MAX_FRAMES: u64 = 1_000_000;

/// Flags of the headless renderer and the app (used when no subcommand is given).
#[derive(Debug, Args, Default)]
pub struct RenderArgs {
    /// Render PNG frames offscreen instead of opening a window (no display or GPU needed).
    #[arg(long)]
    pub headless: bool,
    /// Number of frames to write (--headless), or `all`: up to the scene's end
    /// (playback.end_time; every lesson preset has one).
    #[arg(long, default_value = "1", value_parser = parse_frames)]
    pub frames: FrameCount,
    /// Output folder for frame_00000.png … (--headless).
    #[arg(long, default_value = "frames")]
    pub out: PathBuf,
    /// A scene file (TOML); shape paths in it are relative to its folder.
    #[arg(long, conflicts_with = "preset")]
    pub scene: Option<PathBuf>,
    /// A bundled scene (`rollphase scenes` lists them) [default: sphere-cruising].
    #[arg(long)]
    pub preset: Option<String>,
    /// Frame size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Anti-aliasing samples per pixel: 4 (smooth edges) or 1 (about 2.5× faster on a CPU
    /// renderer such as llvmpipe; see `rollphase bench render`).
    #[arg(long, default_value_t = 4, value_parser = parse_msaa)]
    pub msaa: u32,
    /// Write the frames as one looping animated GIF at the scene's frames per second instead
    /// of PNG files (--headless). GIFs are large and a little slower to write than PNGs; --mp4
    /// is many times smaller (measured sizes and times: docs/guide/scenes.md, "Clips").
    #[arg(long, value_name = "FILE", conflicts_with = "mp4")]
    pub gif: Option<PathBuf>,
    /// Write the frames as an H.264 MP4 instead of PNG files (--headless); needs ffmpeg on PATH.
    #[arg(long, value_name = "FILE")]
    pub mp4: Option<PathBuf>,
    /// Also write the plotted data the app shows (1/T against α as sweep-alpha.csv, ∂Ω crossings
    /// against m/m0 as sweep-mass.csv, the numerical health as health.csv, the contact force
    /// N/F and the friction needed as contact-force.csv), collected frame by frame, into this
    /// folder: a --headless run's, collected frame by frame (a lesson that sweeps α or m/m0
    /// gives its sweep), or the window's as it closes.
    #[arg(long, value_name = "DIR")]
    pub plot_data: Option<PathBuf>,
    /// Window only: the smoke-test flags.
    #[command(flatten)]
    pub window: crate::cli::app::WindowFlags,
}

/// How many frames `--frames` asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameCount {
    /// This many.
    Count(u64),
    /// Up to the scene's `playback.end_time`.
    All,
}

impl Default for FrameCount {
    fn default() -> Self {
        FrameCount::Count(1)
    }
}

/// Parses "120" or "all".
pub fn parse_frames(s: &str) -> Result<FrameCount, String> {
    let s = s.trim();
    if s.eq_ignore_ascii_case("all") {
        return Ok(FrameCount::All);
    }
    s.parse().map(FrameCount::Count).map_err(|_| {
        format!(
            "--frames {s:?} is not a number of frames (e.g. 120) or `all` (up to the scene's end)"
        )
    })
}

/// Parses "1280x720".
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let err = || format!("size {s:?} is not WIDTHxHEIGHT in pixels, e.g. 1280x720");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(err)?;
    let w: u32 = w.trim().parse().map_err(|_| err())?;
    let h: u32 = h.trim().parse().map_err(|_| err())?;
    #[cfg(feature = "render")]
    crate::headless::check_size((w, h)).map_err(|e| e.to_string())?;
    Ok((w, h))
}

/// Parses "1" or "4".
pub fn parse_msaa(s: &str) -> Result<u32, String> {
    match s.trim() {
        "1" => Ok(1),
        "4" => Ok(4),
        _ => Err(format!(
            "--msaa {s} is not allowed (needs 1 or 4 samples per pixel)"
        )),
    }
}

/// `--headless`: writes the frames and says where.
pub fn run_headless(a: &RenderArgs) -> Result<()> {
    if let FrameCount::Count(n) = a.frames {
        check_frames(n)?;
    }
    let setup = pick_scene(a.scene.as_deref(), a.preset.as_deref())?;
    let frames = match a.frames {
        FrameCount::Count(n) => n,
        FrameCount::All => {
            let n = setup.frames_to_end().with_context(|| {
                format!(
                    "--frames all renders up to the scene's end, and {} sets none: add \
                     playback.end_time (a simulation time) to the scene, or give a number of frames",
                    setup.scene.name
                )
            })?;
            let (start, end) = (setup.time_after_video(0.0), setup.scene.playback.end_time);
            if let Some(end) = end.filter(|&end| start > end) {
                bail!(
                    "--frames all renders up to the scene's end, t = {end}, but it starts after \
                     it, at t = {start} (its saved state's time or its start_time): give a number \
                     of frames to render on from there",
                    end = super::short(end),
                    start = super::short(start)
                );
            }
            check_frames(n)?;
            n
        }
    };
    #[cfg(not(feature = "render"))]
    {
        let _ = (setup, frames);
        Err(super::missing_feature("render", "--headless"))
    }
    #[cfg(feature = "render")]
    write_headless(a, setup, frames)
}

/// Refuses, before rendering, a scene (or its shape file) that sits in --out under the name of
/// one of the frames to be written (frame_00003.png): the frame would be refused as an input
/// only when its turn came, after the work.
#[cfg(feature = "render")]
fn refuse_inputs_named_like_frames(a: &RenderArgs, setup: &SceneSetup, frames: u64) -> Result<()> {
    let Some(scene) = &a.scene else {
        return Ok(());
    };
    let mut files = vec![scene.clone()];
    for shape in setup.shape_paths() {
        files.push(
            scene
                .parent()
                .unwrap_or(std::path::Path::new("."))
                .join(shape),
        );
    }
    let out = crate::output::real_path(&a.out);
    for f in files {
        let real = crate::output::real_path(&f);
        let index = real
            .file_name()
            .and_then(|n| n.to_str())
            .and_then(|n| n.strip_prefix("frame_"))
            .and_then(|n| n.strip_suffix(".png"))
            .and_then(|n| n.parse::<u64>().ok());
        if let Some(k) = index
            && k < frames
            && real.parent() == Some(out.as_path())
            && real.file_name().and_then(|n| n.to_str()) == Some(crate::png::frame_name(k).as_str())
        {
            bail!(
                "{} is an input of this command and is named like frame {k} in --out {}; the \
                 frame would overwrite it. Move the file, or give another --out",
                f.display(),
                a.out.display()
            );
        }
    }
    Ok(())
}

fn check_frames(n: u64) -> Result<()> {
    if !(1..=MAX_FRAMES).contains(&n) {
        bail!(
            "--frames {n} is not allowed (needs 1 ≤ frames ≤ {MAX_FRAMES}: 0 renders nothing, and \
             {MAX_FRAMES} is over nine hours of video at 30 frames/s)"
        );
    }
    Ok(())
}

#[cfg(feature = "render")]
fn write_headless(a: &RenderArgs, setup: SceneSetup, frames: u64) -> Result<()> {
    use crate::clip::ClipKind;
    use crate::headless::FrameSink;
    let name = setup.scene.name.clone();
    let clip = match (&a.gif, &a.mp4) {
        (Some(p), _) => Some((ClipKind::Gif, "--gif", p)),
        (None, Some(p)) => Some((ClipKind::Mp4, "--mp4", p)),
        (None, None) => None,
    };
    // The scene and its shape file are inputs: no frame or clip may overwrite them. Checked
    // here, before the renderer starts.
    let mut inputs = crate::output::Inputs::none();
    if let Some(scene) = &a.scene {
        inputs.add(scene);
        let base = scene.parent().unwrap_or(std::path::Path::new("."));
        for shape in setup.shape_paths() {
            inputs.add(&base.join(shape));
        }
    }
    let clip = match clip {
        Some((kind, flag, p)) => {
            crate::output::check_file(p, &inputs).with_context(|| flag.to_string())?;
            if let Some(dir) = &a.plot_data {
                for name in crate::live::history::PlotHistory::file_names(1 + setup.lanes.len()) {
                    let file = dir.join(name);
                    crate::output::check_distinct(&[(flag, p), ("--plot-data", &file)])?;
                }
            }
            if kind == ClipKind::Mp4 && !crate::clip::ffmpeg_available() {
                return Err(crate::clip::ClipError::NoFfmpeg.into());
            }
            Some((kind, p.clone()))
        }
        None => {
            crate::output::check_folder(&a.out, &[], &inputs).context("--out")?;
            refuse_inputs_named_like_frames(a, &setup, frames)?;
            None
        }
    };
    let sink = match &clip {
        Some((kind, p)) => FrameSink::Clip(*kind, p),
        None => FrameSink::Pngs(&a.out),
    };
    let extras = crate::headless::RenderExtras {
        progress: true,
        plot_data: a.plot_data.as_deref(),
    };
    let report = crate::headless::render_to(setup, frames, a.size, a.msaa, sink, &inputs, extras)?;
    if let Some(note) = &report.model_note {
        eprintln!("note: {note}");
    }
    // The frames say it under the caption too; a clip's maker should not have to watch for it.
    for said in &report.claims_not_shown {
        eprintln!("warning: the lesson's run does not bear out its caption: {said}");
    }
    let written = match &clip {
        Some((_, p)) => format!(
            "{} ({} kB)",
            p.display(),
            std::fs::metadata(p).map(|m| m.len() / 1024).unwrap_or(0)
        ),
        None => a.out.display().to_string(),
    };
    let status = format!(
        "wrote {} frame(s) of {name} at {}x{} to {written} (t = {:.3} … {:.3}) on {}",
        report.frames, a.size.0, a.size.1, report.t_first, report.t_last, report.adapter
    );
    // A clip on standard output: nothing but its bytes may go there.
    if clip
        .as_ref()
        .is_some_and(|(_, p)| crate::output::is_standard_output(p))
    {
        eprintln!("{status}");
    } else {
        outln!("{status}")?;
    }
    Ok(())
}
