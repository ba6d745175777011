//! `rollphase` with no subcommand, or `rollphase app`: the interactive window on a scene, with
//! the flags the CI smoke test uses to run it unattended.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use clap::Args;

use crate::cli::render::pick_scene;

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
    /// Unattended-run flags.
    #[command(flatten)]
    pub window: WindowFlags,
}

/// Runs `rollphase app`.
pub fn run(a: AppArgs) -> Result<()> {
    run_window(a.scene.as_deref(), a.preset.as_deref(), &a.window)
}

/// Opens the window on the scene picked by --scene / --preset.
pub fn run_window(scene: Option<&Path>, preset: Option<&str>, flags: &WindowFlags) -> Result<()> {
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
    let setup = pick_scene(scene, preset)?;
    #[cfg(feature = "app")]
    {
        crate::app::run(crate::app::AppOptions {
            setup,
            base: scene.and_then(Path::parent).map(Path::to_path_buf),
            screenshot_after,
            exit_after,
            present: flags.present,
            class: flags.class,
        })
    }
    #[cfg(not(feature = "app"))]
    {
        let _ = (setup, screenshot_after, exit_after);
        Err(super::missing_feature("app", "the interactive window"))
    }
}

fn check_seconds(flag: &str, s: f64) -> Result<f64> {
    if !(s.is_finite() && s >= 0.0) {
        bail!("{flag} {s} is not allowed (needs a finite number of seconds ≥ 0)");
    }
    Ok(s)
}
