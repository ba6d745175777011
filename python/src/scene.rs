//! A saved state of the app run again: `replay`, the check `rollphase replay` prints, on the
//! scene crate's run (`LiveRun::replay_check`), so Python and the command line give one answer.

use std::path::PathBuf;

use numpy::IntoPyArray;
use numpy::ndarray::Array1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rollphase_scene::live::{LiveRun, SimError};
use rollphase_scene::scene::{SceneError, load_scene_file};

use crate::errors::{ErrorClass, input_error};
use crate::interruptible;

/// A saved state (the app's Save state: a scene with [resume] and [[replay]]) run again from its
/// scene's start: the model it started with, each change made by hand (α, m/m0, drag, drag law,
/// integrator) and each resume at the simulation time it took effect, and the lesson's steps,
/// as `rollphase replay STATE` runs it. Returns a dict (ReplayCheck): to_the_bit (whether the
/// run reaches the saved state exactly: the same time and model, every number the same bits),
/// entries (the [[replay]] entries gone through), saved_t, reached_t, saved_model and
/// reached_model (the models' registry names), numbers (of the saved state vector), differing
/// (how many differ; all where the models differ), worst (the largest difference; NaN where
/// the models differ), state (the replay's state vector at its end, an array) and
/// bodies_not_replayed (how many other bodies the scene holds in [[bodies]]: the replay is the
/// scene's own body's, and their saved states are loaded as written, not checked). A file that
/// is not a saved state raises InputError naming what is missing; a run that fails on the way,
/// RunError.
#[pyfunction]
pub fn replay<'py>(py: Python<'py>, state: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    // The file named in every message, as the command line names it.
    let setup = load_scene_file(&state).map_err(|e| match e {
        e @ SceneError::SceneIo { .. } => input_error(e.to_string()),
        e => input_error(format!("bad saved state {}: {e}", state.display())),
    })?;
    if setup.resume.is_none() {
        return Err(input_error(format!(
            "{} has no [resume]: it is a scene, not a saved state (the app's Save state writes \
             one, with its [[replay]])",
            state.display()
        )));
    }
    let check = interruptible(py, |_| LiveRun::replay_check(&setup, &mut |_, _| {}))?.map_err(
        |e| match e {
            SimError::Refused(why) => input_error(format!("{}: {why}", state.display())),
            e @ SimError::Integrate { .. } => ErrorClass::Run.err(e.to_string()),
        },
    )?;
    let d = PyDict::new(py);
    d.set_item("to_the_bit", check.to_the_bit())?;
    d.set_item("entries", check.entries)?;
    d.set_item("saved_t", check.saved_t)?;
    d.set_item("reached_t", check.reached_t)?;
    d.set_item("saved_model", check.saved_model)?;
    d.set_item("reached_model", check.reached_model)?;
    d.set_item("numbers", check.numbers)?;
    d.set_item("differing", check.differing)?;
    d.set_item("worst", check.worst)?;
    d.set_item("state", Array1::from_vec(check.state).into_pyarray(py))?;
    d.set_item("bodies_not_replayed", setup.lanes.len())?;
    Ok(d)
}
