//! A saved state's run again: [`LiveRun::replayed`] runs a scene from its start through its
//! `[[replay]]` (the model it started with, each change made by hand and each resume, at its
//! simulation time) and the lesson's steps, up to the saved time, with its progress reported
//! along the way ([`LiveRun::replayed_reporting`]). The live run's steps do not depend on where
//! it is stopped, so the replay is the saved run to the bit.

use crate::scene::SceneSetup;

use super::{LiveRun, SimError};

impl LiveRun {
    /// A saved state's run again from its scene's start: the model of its first `[[replay]]`
    /// entry, each later entry's model set at its time (as the hand changes and resumes were),
    /// the lesson's steps at theirs, up to the saved time. The run a replay gives is the saved
    /// run to the bit (the live run's steps do not depend on where its frames fell).
    ///
    /// # Errors
    /// `setup` has no `[resume]` or no `[[replay]]`, or the run fails on the way.
    pub fn replayed(setup: &SceneSetup) -> Result<LiveRun, SimError> {
        Self::replayed_reporting(setup, &mut |_, _| {})
    }

    /// [`Self::replayed`], calling `report(t, t_end)` about every hundredth of the saved time
    /// (never more than 1.5 hundredths apart; a long replay takes minutes). The run advances in
    /// those pieces as it would in one: its steps do not depend on where it is stopped, and each
    /// change is made at its own time, never at a piece's end.
    ///
    /// # Errors
    /// As [`Self::replayed`].
    pub fn replayed_reporting(
        setup: &SceneSetup,
        report: &mut dyn FnMut(f64, f64),
    ) -> Result<LiveRun, SimError> {
        let refused = |why: String| SimError::Refused(why);
        let resume = setup.resume.as_ref().ok_or_else(|| {
            refused("a replay goes to a saved state, and this scene has no [resume]".into())
        })?;
        let start = setup
            .replay_start()
            .map_err(|e| refused(e.to_string()))?
            .ok_or_else(|| {
                refused(
                    "this saved state has no [[replay]] (saved before replays were recorded, \
                     or resumed from such a file)"
                        .into(),
                )
            })?;
        let t_end = resume.t;
        let piece = (t_end / 100.0).max(f64::MIN_POSITIVE);
        let mut advance = |run: &mut LiveRun, to: f64| -> Result<(), SimError> {
            // Pieces that leave at least half a piece before `to`, then `to` itself: a piece
            // ending within rounding of `to` would leave the last call nothing to do, and the
            // change at `to` would be made a few ulps early.
            loop {
                let next = run.time() + piece;
                if next.is_nan() || next >= to - 0.5 * piece {
                    break;
                }
                let before = run.time();
                run.advance_to(next)?;
                report(run.time(), t_end);
                if run.time() <= before {
                    break;
                }
            }
            run.advance_to(to)?;
            report(run.time(), t_end);
            Ok(())
        };
        let mut run = LiveRun::new(start);
        for entry in &setup.scene.replay[1..] {
            advance(&mut run, entry.at)?;
            if entry.resumed {
                // As the app resumed the saved state: a new run from the state vector.
                let at = Some((entry.at, run.state().vector().to_vec()));
                let resumed = setup
                    .replay_setup(entry, at)
                    .map_err(|e| refused(e.to_string()))?;
                run = LiveRun::new(resumed);
            } else {
                let ramp = entry.ramp().map_err(|e| refused(e.to_string()))?;
                run.set_parameters(ramp, entry.integrator)?;
            }
        }
        advance(&mut run, resume.t)?;
        Ok(run)
    }
}

/// What a replay reached against the saved state ([`LiveRun::replay_check`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayCheck {
    /// `[[replay]]` entries the run went through.
    pub entries: usize,
    /// The saved state's time.
    pub saved_t: f64,
    /// The time the replay reached.
    pub reached_t: f64,
    /// The saved state's model (its registry name).
    pub saved_model: &'static str,
    /// The model the replay ends in: another than the saved state's where the file's
    /// `[[replay]]` does not lead to its `[resume]`'s model.
    pub reached_model: &'static str,
    /// The numbers of the saved state vector.
    pub numbers: usize,
    /// How many of them the replay's state differs in, bit for bit (−0 against +0 counts; all
    /// of them where the models differ).
    pub differing: usize,
    /// The largest difference (0 when none; NaN where the models differ, whose numbers are not
    /// the same quantities).
    pub worst: f64,
    /// The replay's state vector at its end.
    pub state: Vec<f64>,
}

impl ReplayCheck {
    /// Whether the replay reached the saved state to the bit: the same time, the same number
    /// of numbers, none different.
    pub fn to_the_bit(&self) -> bool {
        self.reached_t.to_bits() == self.saved_t.to_bits()
            && self.saved_model == self.reached_model
            && self.differing == 0
            && self.state.len() == self.numbers
    }
}

impl LiveRun {
    /// [`Self::replayed_reporting`], compared with the saved state number by number: the one
    /// check `rollphase replay` prints and Python's `replay` returns.
    ///
    /// # Errors
    /// As [`Self::replayed`].
    pub fn replay_check(
        setup: &SceneSetup,
        report: &mut dyn FnMut(f64, f64),
    ) -> Result<ReplayCheck, SimError> {
        let run = Self::replayed_reporting(setup, report)?;
        let resume = setup.resume.as_ref().ok_or_else(|| {
            SimError::Refused(
                "a replay goes to a saved state, and this scene has no [resume]".into(),
            )
        })?;
        let (saved, got) = (resume.state.vector(), run.state().vector());
        let (saved_model, reached_model) = (resume.state.kind().name(), run.state().kind().name());
        // Bit for bit: −0 and +0 differ, and so do two NaNs of other payloads.
        let differences: Vec<f64> = saved
            .iter()
            .zip(got)
            .filter(|(s, g)| s.to_bits() != g.to_bits())
            .map(|(s, g)| (s - g).abs())
            .collect();
        let same_model = saved_model == reached_model;
        Ok(ReplayCheck {
            entries: setup.scene.replay.len(),
            saved_t: resume.t,
            reached_t: run.time(),
            saved_model,
            reached_model,
            numbers: saved.len(),
            differing: if same_model {
                differences.len()
            } else {
                saved.len()
            },
            worst: if same_model {
                differences.iter().copied().fold(0.0, f64::max)
            } else {
                f64::NAN
            },
            state: got.to_vec(),
        })
    }
}
