//! `rollphase replay STATE`: a saved state's run again from its scene's start, through its
//! `[[replay]]` (the model it started with, each change made by hand and each resume, at its
//! simulation time) and the lesson's steps, and whether it reaches the saved state to the bit.
//! The run and the check are the scene crate's (`LiveRun::replay_check`, which Python's `replay`
//! returns too); this file parses and prints.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, bail};
use clap::Args;

use crate::live::LiveRun;
use crate::scene::load_scene_file;

/// Run a saved state again from its scene's start and check it reaches the saved state.
#[derive(Debug, Args)]
#[command(
    long_about = "Run a saved state (the app's Save state: a scene with [resume] and \
    [[replay]]) again from its scene's start: the model it started with, each change made by \
    hand (α, m/m0, drag, drag law, integrator) and each resume at the simulation time it took \
    effect, and the lesson's steps. Says whether the run reaches the saved state to the bit, \
    and exits 1 if it does not (a file edited by hand, or written by another build).\n\n\
    Example: rollphase replay state.toml"
)]
pub struct ReplayArgs {
    /// The saved state (TOML with [resume] and [[replay]]).
    pub state: PathBuf,
}

/// Runs `replay`.
pub fn run(a: ReplayArgs) -> Result<()> {
    // The scene file named in every message, as `--scene` names it (a TOML error said only
    // "line 1, column 1").
    let setup = match load_scene_file(&a.state) {
        Ok(s) => s,
        Err(e @ crate::scene::SceneError::SceneIo { .. }) => return Err(e.into()),
        Err(e) => bail!("bad saved state {}: {e}", a.state.display()),
    };
    let Some(resume) = &setup.resume else {
        bail!(
            "{} has no [resume]: it is a scene, not a saved state (the app's Save state writes \
             one, with its [[replay]])",
            a.state.display()
        );
    };
    let started = Instant::now();
    // Progress on standard error, where a terminal shows it (hidden otherwise).
    let bar = indicatif::ProgressBar::new(1000);
    bar.set_style(
        indicatif::ProgressStyle::with_template("replaying {bar:40} t = {msg} {elapsed}/{eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let check = LiveRun::replay_check(&setup, &mut |t, end| {
        bar.set_position((1000.0 * t / end.max(f64::MIN_POSITIVE)) as u64);
        bar.set_message(crate::integrate::readable(t));
    });
    bar.finish_and_clear();
    let check = check?;
    let seconds = started.elapsed().as_secs_f64();
    let t = crate::integrate::readable(resume.t);
    let entries = match check.entries {
        1 => "1 [[replay]] entry".to_string(),
        n => format!("{n} [[replay]] entries"),
    };
    if check.to_the_bit() {
        outln!(
            "{}: replayed from t = 0 through {entries} to t = {t}: the saved state to the bit \
             ({} numbers), in {seconds:.2} s",
            a.state.display(),
            check.numbers
        )?;
        if !setup.lanes.is_empty() {
            // The replay is the scene's own body's; the others' states are only loaded.
            let others = match setup.lanes.len() {
                1 => "other body".to_string(),
                n => format!("other {n} bodies"),
            };
            outln!(
                "the scene's {others} ([[bodies]]): saved states loaded as written, not replayed"
            )?;
        }
        return Ok(());
    }
    if check.saved_model != check.reached_model {
        bail!(
            "{}: the replay ends in the {} model ({} numbers), but the saved state at t = {t} is \
             the {} model's ({} numbers): its [[replay]] does not lead to its [resume] (edited \
             by hand, or saved by another build)",
            a.state.display(),
            check.reached_model,
            check.state.len(),
            check.saved_model,
            check.numbers
        );
    }
    bail!(
        "{}: replayed to t = {}, the run differs from the saved state at t = {t} in {} of {} \
         numbers, by up to {:e}: its [[replay]] does not lead to its [resume] (edited by hand, or \
         saved by another build)",
        a.state.display(),
        crate::integrate::readable(check.reached_t),
        check.differing,
        check.numbers,
        check.worst
    )
}
