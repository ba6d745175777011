//! `rollphase scenes`: the bundled presets, one line each (`--toml NAME` prints one in full, a
//! starting point for a scene file of your own).

use anyhow::Result;
use clap::Args;

use crate::geometry::ShapeFile;
use crate::scene::{DEFAULT_PRESET, PRESETS, Scene, bundled_shape};

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
        let scene = Scene::preset(&name)?;
        if let Some((_, text)) = PRESETS.iter().find(|(n, _)| *n == name) {
            let text = standalone(text, &scene)?;
            super::write_output(None, &text, &crate::output::Inputs::none())?;
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

/// The preset's text made to stand alone: a bundled shape (`shape = "../shapes/NAME"`, which
/// only a preset can name) is written out inline as `[body.inline]`, so the printed file works
/// as `--scene FILE` from any folder, with the same body to the last digit.
pub fn standalone(text: &str, scene: &Scene) -> Result<String> {
    let Some(path) = &scene.body.shape else {
        return Ok(text.to_string());
    };
    let shape = ShapeFile::from_json(bundled_shape(path)?)?;
    let value = toml::Value::try_from(&shape)?;
    let toml::Value::Table(table) = value else {
        anyhow::bail!("the shape {} is not a table", path.display());
    };
    let mut inline = format!(
        "# {}, bundled with rollphase, written out so that this file stands alone\n[body.inline]\n",
        path.display()
    );
    for (key, value) in &table {
        match value {
            toml::Value::Array(items) => {
                inline.push_str(&format!("{key} = [\n"));
                for item in items {
                    inline.push_str(&format!("    {},\n", toml_inline(item)));
                }
                inline.push_str("]\n");
            }
            other => inline.push_str(&format!("{key} = {}\n", toml_inline(other))),
        }
    }
    let mut out = String::new();
    let mut replaced = false;
    for line in text.lines() {
        let is_shape_line = line
            .trim_start()
            .strip_prefix("shape")
            .and_then(|rest| rest.trim_start().strip_prefix('='))
            .is_some_and(|v| {
                v.split('#').next().unwrap_or("").trim().trim_matches('"') == path.to_string_lossy()
            });
        if is_shape_line && !replaced {
            out.push_str(&inline);
            replaced = true;
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    anyhow::ensure!(
        replaced,
        "no shape line for {} in the preset",
        path.display()
    );
    Ok(out)
}

/// A TOML value on one line (tables as inline tables).
fn toml_inline(v: &toml::Value) -> String {
    match v {
        toml::Value::Table(t) => {
            let fields: Vec<String> = t
                .iter()
                .map(|(k, v)| format!("{k} = {}", toml_inline(v)))
                .collect();
            format!("{{ {} }}", fields.join(", "))
        }
        toml::Value::Array(a) => {
            let items: Vec<String> = a.iter().map(toml_inline).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}
