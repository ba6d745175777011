//! The module's exception tree, so a caller can tell bad input from a run that failed without
//! reading messages:
//!
//! | class | bases | raised for |
//! |---|---|---|
//! | `RollphaseError` | `Exception` | nothing directly: catch it to catch all of the below |
//! | `InputError` | `RollphaseError`, `ValueError` | bad input, refused before any work (the command line's message) |
//! | `RunError` | `RollphaseError`, `RuntimeError` | a run that started and could not finish: step budget spent, step too small, state no longer finite, fixed step too coarse |
//! | `LeftModelError` | `RunError` | a run stopped where rolling stops holding (lift-off or slip, `on_invalid="stop"`) |
//! | `InternalError` | `RollphaseError`, `RuntimeError` | a bug in rollphase (a panic in a worker): please report it |
//!
//! `InputError` is also a `ValueError` and the two run errors are `RuntimeError`s, so code
//! written against the built-in classes keeps working. pyo3's `create_exception!` takes one
//! base, so the classes are made by Python's `type(name, bases, namespace)` on first use and
//! kept for the interpreter's life.

use pyo3::exceptions::{PyException, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};
use rollphase_core::analysis::orbits::orbit_diagram::OrbitDiagramError;
use rollphase_core::analysis::studies::sphere::StudyError;
use rollphase_core::dynamics::ModelError;
use rollphase_core::integrate::IntegrateError;
use rollphase_core::simulate::RunError;
use rollphase_core::simulate::period::PeriodError;

/// One class of the tree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ErrorClass {
    /// `RollphaseError`.
    Base,
    /// `InputError`.
    Input,
    /// `RunError`.
    Run,
    /// `LeftModelError`.
    LeftModel,
    /// `InternalError`.
    Internal,
}

impl ErrorClass {
    /// Every class, bases before the classes built on them.
    pub(crate) const ALL: [ErrorClass; 5] = [
        ErrorClass::Base,
        ErrorClass::Input,
        ErrorClass::Run,
        ErrorClass::LeftModel,
        ErrorClass::Internal,
    ];

    /// The Python name.
    pub(crate) fn name(self) -> &'static str {
        match self {
            ErrorClass::Base => "RollphaseError",
            ErrorClass::Input => "InputError",
            ErrorClass::Run => "RunError",
            ErrorClass::LeftModel => "LeftModelError",
            ErrorClass::Internal => "InternalError",
        }
    }

    fn doc(self) -> &'static str {
        match self {
            ErrorClass::Base => "Base of every error rollphase raises.",
            ErrorClass::Input => {
                "Bad input, refused before any work; also a ValueError. The message is the \
                 command line's for the same mistake, with the Python argument's name."
            }
            ErrorClass::Run => {
                "A run that started and could not finish (step budget spent, step too small, \
                 state no longer finite, fixed step too coarse); also a RuntimeError."
            }
            ErrorClass::LeftModel => {
                "A run stopped where the rolling model stops holding (lift-off or slip, with \
                 on_invalid=\"stop\"); a RunError."
            }
            ErrorClass::Internal => {
                "A bug in rollphase (a worker panicked); also a RuntimeError. Please report it."
            }
        }
    }

    fn slot(self) -> &'static PyOnceLock<Py<PyType>> {
        static SLOTS: [PyOnceLock<Py<PyType>>; 5] = [
            PyOnceLock::new(),
            PyOnceLock::new(),
            PyOnceLock::new(),
            PyOnceLock::new(),
            PyOnceLock::new(),
        ];
        &SLOTS[self as usize]
    }

    /// The class itself, made on first use.
    pub(crate) fn class<'py>(self, py: Python<'py>) -> PyResult<Bound<'py, PyType>> {
        let made = self
            .slot()
            .get_or_try_init(py, || -> PyResult<Py<PyType>> {
                let bases: Vec<Bound<'py, PyType>> = match self {
                    ErrorClass::Base => vec![py.get_type::<PyException>()],
                    ErrorClass::Input => {
                        vec![ErrorClass::Base.class(py)?, py.get_type::<PyValueError>()]
                    }
                    ErrorClass::Run | ErrorClass::Internal => {
                        vec![ErrorClass::Base.class(py)?, py.get_type::<PyRuntimeError>()]
                    }
                    ErrorClass::LeftModel => vec![ErrorClass::Run.class(py)?],
                };
                let namespace = PyDict::new(py);
                namespace.set_item("__module__", "rollphase")?;
                namespace.set_item("__doc__", self.doc())?;
                let made = py.get_type::<PyType>().call1((
                    self.name(),
                    PyTuple::new(py, bases)?,
                    namespace,
                ))?;
                Ok(made.cast_into::<PyType>()?.unbind())
            })?;
        Ok(made.bind(py).clone())
    }

    /// An exception of this class with `message`. Should the class fail to be made (it cannot,
    /// short of memory), the built-in class it stands in for carries the message instead.
    pub(crate) fn err(self, message: impl Into<String>) -> PyErr {
        let message = message.into();
        Python::attach(|py| match self.class(py) {
            Ok(class) => PyErr::from_type(class, message),
            Err(_) => match self {
                ErrorClass::Input => PyValueError::new_err(message),
                _ => PyRuntimeError::new_err(message),
            },
        })
    }
}

/// `InputError` (a `ValueError`) with `message`: the argument, why, what is allowed.
pub(crate) fn input_error(message: impl Into<String>) -> PyErr {
    ErrorClass::Input.err(message)
}

/// `InputError` (a `ValueError`) with an error's message (the command line's text for the same
/// mistake).
pub(crate) fn bad_input(e: impl std::fmt::Display) -> PyErr {
    input_error(e.to_string())
}

/// `InternalError` for what cannot happen short of a bug (an array whose shape the code built
/// itself does not fit, a report that does not serialise).
pub(crate) fn internal_error(e: impl std::fmt::Display) -> PyErr {
    ErrorClass::Internal.err(format!(
        "internal error in rollphase (please report it): {e}"
    ))
}

/// Adds every class of the tree to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    for class in ErrorClass::ALL {
        m.add(class.name(), class.class(m.py())?)?;
    }
    Ok(())
}

/// A core error that knows which class of the tree it raises. Every variant is matched by
/// name, so a variant added to the core cannot reach Python unclassified.
pub(crate) trait Classified: std::fmt::Display {
    /// Its class.
    fn class(&self) -> ErrorClass;
}

/// The Python exception for a core error: its class, its message.
pub(crate) fn raise<E: Classified>(e: E) -> PyErr {
    e.class().err(e.to_string())
}

impl Classified for IntegrateError {
    fn class(&self) -> ErrorClass {
        match self {
            IntegrateError::BadParameter { .. } => ErrorClass::Input,
            IntegrateError::NonFinite { .. }
            | IntegrateError::StepTooSmall { .. }
            | IntegrateError::StepTooCoarse { .. }
            | IntegrateError::TooManySteps { .. } => ErrorClass::Run,
        }
    }
}

impl Classified for RunError {
    fn class(&self) -> ErrorClass {
        match self {
            RunError::Integrate(e) => e.class(),
            RunError::Model(_)
            | RunError::Shape(_)
            | RunError::Mismatch(_)
            | RunError::UnstableStep { .. }
            | RunError::InitialStateDoesNotFit { .. } => ErrorClass::Input,
            RunError::Unhealthy { .. }
            | RunError::NonFiniteOutput { .. }
            | RunError::Stopped { .. } => ErrorClass::Run,
            RunError::LeftModel { .. } => ErrorClass::LeftModel,
        }
    }
}

impl Classified for PeriodError {
    fn class(&self) -> ErrorClass {
        match self {
            PeriodError::Run(e) => e.class(),
            PeriodError::Integrate(e) => e.class(),
            PeriodError::NotADisk | PeriodError::OnHull(_) => ErrorClass::Input,
        }
    }
}

impl Classified for StudyError {
    fn class(&self) -> ErrorClass {
        match self {
            StudyError::Integrate(e) => e.class(),
            StudyError::NotASphere(_)
            | StudyError::Model(_)
            | StudyError::BadStart { .. }
            | StudyError::BadArgument(_)
            | StudyError::Shape(_)
            | StudyError::BadCycle { .. } => ErrorClass::Input,
            StudyError::NoFixedPoint { .. } | StudyError::Stopped => ErrorClass::Run,
        }
    }
}

impl Classified for OrbitDiagramError {
    fn class(&self) -> ErrorClass {
        match self {
            OrbitDiagramError::Integrate(e) => e.class(),
            OrbitDiagramError::Model(_)
            | OrbitDiagramError::GridMismatch { .. }
            | OrbitDiagramError::EmptyGrid { .. }
            | OrbitDiagramError::BadArgument(_)
            | OrbitDiagramError::BadPeriod { .. } => ErrorClass::Input,
            OrbitDiagramError::NoPeriodOneOrbit { .. } | OrbitDiagramError::Stopped => {
                ErrorClass::Run
            }
        }
    }
}

impl Classified for ModelError {
    fn class(&self) -> ErrorClass {
        ErrorClass::Input
    }
}
