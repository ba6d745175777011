//! `rollphase` with no subcommand, or `rollphase app`: the interactive window on a scene, with
//! the flags the CI smoke test uses to run it unattended.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use clap::Args;

use crate::cli::pick_scene;

/// Flags for running the window unattended (tests, benchmarks).
#[derive(Debug, Args, Default, Clone)]
pub struct WindowFlags {
    /// Save a PNG of the whole window (3D view and controls) after SECONDS of wall time.
    #[arg(long, num_args = 2, value_names = ["SECONDS", "FILE"])]
    pub screenshot_after: Option<Vec<String>>,
    /// Close the window after SECONDS of wall time and print a frame-time summary.
    #[arg(long, value_name = "SECONDS")]
    pub exit_after: Option<f64>,
    /// Open in presentation mode (F5 in the window): the 3D view fills the screen with large
    /// captions and no panels, for a projector; F5 or Esc leaves it.
    #[arg(long)]
    pub present: bool,
    /// Open in class mode (C in the window): full screen, large fonts for the overlay, the
    /// caption and the panels, with the controls and plots shown; C or Esc leaves it.
    #[arg(long, conflicts_with = "present")]
    pub class: bool,
    /// Start the measuring sweep (the controls' "sweep"): `alpha:STEP` adds STEP radians to α
    /// after each point, `mass:STEP` multiplies m/m0 by e^STEP; a negative STEP sweeps down;
    /// `:END` stops at END (`alpha:0.0005:0.07`). Each value is held until its run is
    /// measured, so the 1/T or crossing plot grows as it goes.
    #[arg(long, value_name = "alpha|mass:STEP[:END]", value_parser = parse_sweep)]
    pub sweep: Option<SweepFlag>,
    /// Start at this playback speed, in simulated time per second (0.05 to 1000).
    #[arg(long, value_name = "T_PER_S")]
    pub speed: Option<f64>,
    /// Open a lesson at its step K (1 is its first), as if N were pressed until it: the run is
    /// simulated up to the step and the step's evidence shown on its plot.
    #[arg(long, value_name = "K", allow_negative_numbers = true)]
    pub step: Option<usize>,
    /// How finely the 3D view is drawn: `auto` (the default: full on a GPU; on a CPU renderer
    /// such as llvmpipe, lowered in steps to as little as half the width and height while
    /// frames would take longer than 1/30 s, and said in the status bar as "3D at 70 %"), or a
    /// share from 0.5 to 1; `1` always draws it in full (as View ▸ 3D at full resolution).
    /// Text, panels and plots are always drawn in full, and screenshots and clips in full.
    #[arg(long, value_name = "auto|0.5..1", allow_negative_numbers = true)]
    pub render_scale: Option<String>,
}

/// A `--sweep`: what moves, by how much per point, and where it stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepFlag {
    /// α (else m/m0).
    pub alpha: bool,
    /// Radians (α) or ln of the factor (m/m0) per point.
    pub step: f64,
    /// The last value, if any.
    pub end: Option<f64>,
}

/// `--sweep alpha:STEP[:END]` or `mass:STEP[:END]`: a finite STEP with 0 < |STEP| ≤ 1, a finite
/// END > 0.
fn parse_sweep(text: &str) -> Result<SweepFlag, String> {
    let (what, rest) = text.split_once(':').ok_or_else(|| {
        format!("{text:?}: give alpha:STEP or mass:STEP (for example alpha:-0.002)")
    })?;
    let (step, end) = match rest.split_once(':') {
        Some((step, end)) => (step, Some(end)),
        None => (rest, None),
    };
    let end = end
        .map(|e| match e.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
            _ => Err(format!(
                "the end {e:?} is not allowed (needs a number > 0: the last α in radians or m/m0)"
            )),
        })
        .transpose()?;
    let alpha = match what {
        "alpha" => true,
        "mass" => false,
        _ => {
            return Err(format!(
                "{what:?} cannot be swept: alpha (radians per point) or mass (ln of the factor \
                 per point)"
            ));
        }
    };
    let step: f64 = step
        .trim()
        .parse()
        .map_err(|_| format!("the step {step:?} is not a number"))?;
    if !(step.is_finite() && step != 0.0 && step.abs() <= 1.0) {
        return Err(format!(
            "the step {step} is not allowed (needs a number with 0 < |step| ≤ 1)"
        ));
    }
    Ok(SweepFlag { alpha, step, end })
}

/// `rollphase app`.
#[derive(Debug, Args)]
pub struct AppArgs {
    /// A scene file (TOML); shape paths in it are relative to its folder.
    #[arg(long, conflicts_with = "preset")]
    pub scene: Option<PathBuf>,
    /// A bundled scene (`rollphase scenes` lists them) [default: sphere-cruising].
    #[arg(long)]
    pub preset: Option<String>,
    /// Write the plots' data (the CSVs and plot-data.json of File → Export plot data) into DIR
    /// when the window closes; the folder is checked before the window opens.
    #[arg(long, value_name = "DIR")]
    pub plot_data: Option<PathBuf>,
    /// Unattended-run flags.
    #[command(flatten)]
    pub window: WindowFlags,
}

/// Runs `rollphase app`.
pub fn run(a: AppArgs) -> Result<()> {
    run_window(
        a.scene.as_deref(),
        a.preset.as_deref(),
        &a.window,
        a.plot_data.as_deref(),
    )
}

/// Opens the window on the scene picked by --scene / --preset.
pub fn run_window(
    scene: Option<&Path>,
    preset: Option<&str>,
    flags: &WindowFlags,
    plot_data: Option<&Path>,
) -> Result<()> {
    let screenshot_after = match &flags.screenshot_after {
        Some(v) => {
            let [seconds, file] = v.as_slice() else {
                bail!("--screenshot-after needs SECONDS FILE, got {v:?}");
            };
            let s: f64 = seconds.parse().map_err(|_| {
                anyhow::anyhow!("--screenshot-after {seconds:?} is not a number of seconds")
            })?;
            Some((check_seconds("--screenshot-after", s)?, PathBuf::from(file)))
        }
        None => None,
    };
    let exit_after = flags
        .exit_after
        .map(|s| check_seconds("--exit-after", s))
        .transpose()?;
    let speed = flags
        .speed
        .map(|s| {
            if s.is_finite() && (0.05..=1000.0).contains(&s) {
                Ok(s)
            } else {
                Err(anyhow::anyhow!(
                    "--speed {s} is not allowed (needs 0.05 to 1000 simulated time per second)"
                ))
            }
        })
        .transpose()?;
    #[cfg(feature = "app")]
    let render_scale = match &flags.render_scale {
        Some(text) => crate::ui::render_scale::RenderScaleMode::parse(text)
            .map_err(|e| anyhow::anyhow!("--render-scale: {e}"))?,
        None => crate::ui::render_scale::RenderScaleMode::Auto,
    };
    let setup = pick_scene(scene, preset)?;
    if let Some(k) = flags.step {
        let steps = setup.timeline.len();
        if steps == 0 {
            bail!(
                "--step {k} needs a lesson (a scene with [[timeline]] steps); \"{}\" has none \
                 (the lessons: --preset lesson-critical-angle, lesson-inertia-hysteresis, \
                 lesson-period-doubling)",
                setup.scene.name
            );
        }
        if k == 0 || k > steps {
            bail!(
                "--step {k} is not a step of \"{}\" (it has {steps}: give 1 to {steps})",
                setup.scene.name
            );
        }
    }
    if let Some(dir) = plot_data {
        let inputs = crate::output::Inputs::of(scene);
        crate::live::history::PlotHistory::check_folder(dir, 1 + setup.lanes.len(), &inputs)
            .map_err(|e| anyhow::anyhow!("--plot-data: {e}"))?;
    }
    #[cfg(feature = "app")]
    {
        crate::app::run(crate::app::AppOptions {
            setup,
            base: scene.and_then(Path::parent).map(Path::to_path_buf),
            screenshot_after,
            exit_after,
            present: flags.present,
            class: flags.class,
            sweep: flags
                .sweep
                .map(|f| crate::ui::measuring_sweep::MeasuringSweep {
                    target: if f.alpha {
                        crate::ui::measuring_sweep::SweepTarget::Alpha
                    } else {
                        crate::ui::measuring_sweep::SweepTarget::MassRatio
                    },
                    step: f.step,
                    end: f.end,
                }),
            speed,
            step: flags.step,
            plot_data: plot_data.map(Path::to_path_buf),
            render_scale,
        })
    }
    #[cfg(not(feature = "app"))]
    {
        let _ = (setup, screenshot_after, exit_after, speed);
        Err(super::missing_feature("app", "the interactive window"))
    }
}

fn check_seconds(flag: &str, s: f64) -> Result<f64> {
    if !(s.is_finite() && s >= 0.0) {
        bail!("{flag} {s} is not allowed (needs a finite number of seconds ≥ 0)");
    }
    Ok(s)
}
