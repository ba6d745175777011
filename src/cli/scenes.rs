//! `rollphase scenes`: the bundled presets, one line each (`--toml NAME` prints one in full, a
//! starting point for a scene file of your own).

use anyhow::Result;
use clap::Args;

use crate::scene::{DEFAULT_PRESET, PRESETS, Scene};

/// List the preset scenes (`--preset NAME`), or print one as TOML.
#[derive(Debug, Args)]
pub struct ScenesArgs {
    /// Print this preset's TOML instead of the list.
    #[arg(long)]
    pub toml: Option<String>,
}

/// Runs `scenes`.
pub fn run(a: ScenesArgs) -> Result<()> {
    if let Some(name) = a.toml {
        Scene::preset(&name)?;
        if let Some((_, text)) = PRESETS.iter().find(|(n, _)| *n == name) {
            super::write_output(None, text, &crate::output::Inputs::none())?;
        }
        return Ok(());
    }
    let width = PRESETS.iter().map(|(n, _)| n.len()).max().unwrap_or(0);
    for (name, _) in PRESETS {
        let scene = Scene::preset(name)?;
        let mark = if *name == DEFAULT_PRESET {
            " (default)".to_string()
        } else if scene.timeline.is_empty() {
            String::new()
        } else {
            let setup = scene.setup(None)?;
            let video = setup
                .frames_to_end()
                .map(|f| format!(", {:.0} s of video", f as f64 / scene.playback.fps))
                .unwrap_or_default();
            format!(" ({} steps{video})", scene.timeline.len())
        };
        outln!("{name:width$}  {}{mark}", scene.description)?;
    }
    outln!(
        "\nLessons (lesson-*) play their [[timeline]] steps with captions. In the app: N or Page \
         Down for the next step, B or Page Up for the previous one, Space to pause, C for class \
         mode. Headless: `rollphase --headless --preset NAME --frames all --mp4 lesson.mp4`."
    )?;
    Ok(())
}
