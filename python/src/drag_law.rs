//! The drag law as Python gives it: keyword arguments named after the core's registered
//! parameters (`KEY=VALUE`), so a new law needs no code here; `drag_parameters()` lists
//! them. `models()` lists the core's registered rolling models the same way.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use rollphase_core::dynamics::drag::{DragLaw, REGISTERED};

use crate::errors::{bad_input, input_error};

/// The law the keyword arguments `extra` ask for; a keyword that is no registered parameter is
/// an `InputError` naming it and the parameters there are.
pub(crate) fn from_keywords(
    function: &str,
    extra: Option<&Bound<'_, PyDict>>,
) -> PyResult<DragLaw> {
    let Some(extra) = extra else {
        return Ok(DragLaw::LINEAR);
    };
    let mut law = DragLaw::LINEAR;
    for (key, value) in extra.iter() {
        let key: String = key.extract()?;
        if !REGISTERED.iter().any(|p| p.key == key) {
            let known: Vec<_> = REGISTERED.iter().map(|p| p.key).collect();
            return Err(input_error(format!(
                "{function}() got an unexpected keyword argument {key:?} (besides its own, it \
                 takes the drag-law parameters: {})",
                known.join(", ")
            )));
        }
        let value: f64 = value
            .extract()
            .map_err(|_| input_error(format!("{key} must be a number")))?;
        law = law.with(&key, value).map_err(bad_input)?;
    }
    Ok(law)
}

/// The drag-law parameters `simulate`, `simulate_many`, `period` and `predict` take as
/// keyword arguments: a list of dicts with key, help, default, min and max. Every run's
/// summary carries each key with its value.
#[pyfunction]
pub fn drag_parameters(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for p in REGISTERED {
        let d = PyDict::new(py);
        d.set_item("key", p.key)?;
        d.set_item("help", p.help)?;
        d.set_item("default", p.default)?;
        d.set_item("min", p.min)?;
        d.set_item("max", p.max)?;
        list.append(d)?;
    }
    Ok(list)
}

/// The rolling models there are, from the core's registry: a list of dicts with name (the name
/// every summary, CSV and command uses), dimension (2: a cylinder, 3: a sphere), inertial
/// (whether it carries m/m0 > 0), about and state (its integrated state, in order). A run's
/// model follows from the body's dimension and its mass_ratio (0: viscous).
#[pyfunction]
pub fn models(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for m in rollphase_core::dynamics::models::REGISTERED {
        let d = PyDict::new(py);
        d.set_item("name", m.name)?;
        d.set_item("dimension", m.dimension)?;
        d.set_item("inertial", m.inertial)?;
        d.set_item("about", m.about)?;
        d.set_item("state", m.state.split(", ").collect::<Vec<_>>())?;
        list.append(d)?;
    }
    Ok(list)
}
