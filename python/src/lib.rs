//! The Python module `rollphase`: the physics core (`rollphase-core`) with numpy arrays in and
//! out, built by maturin (`pip install ./python`).
//!
//! Every call checks its arguments before any work and raises `InputError` (a `ValueError`) with
//! the message the command line gives for the same mistake (the core's own messages; only the names of the
//! arguments differ: `mass_ratio=` for `--mass`). Long calls run with the GIL released on a
//! worker thread while the calling thread watches for Ctrl-C ([`interruptible`]), so
//! KeyboardInterrupt stops them; a panic in the worker becomes `InternalError`, never a crash of
//! the interpreter. The exception tree is [`errors`]'s. Files are written through the one output layer (`rollphase-output`).
//!
//! | module | owns |
//! |---|---|
//! | [`body`] | `Body`: the paper's and random bodies, shape files, r(θ) and r(u) over arrays |
//! | [`errors`] | the exception tree: `RollphaseError`, `InputError`, `RunError`, `LeftModelError`, `InternalError` |
//! | [`run`] | `simulate` and its `DiskTrajectory` / `SphereTrajectory`, `simulate_many` and its `SphereRuns` |
//! | [`studies`] | `critical_angle`, `period`, `poincare_map`, `cruising_fraction`, `periodic_orbits`, `period_counts` |
//! | [`design`] | `design` (a printable body for chosen targets, checked over a bench's band) and `check_design` (the same check of a body you have) |
//! | [`scene`] | `replay` (a saved state of the app run again from its scene's start, checked to the bit, as `rollphase replay`) |
//! | [`experiment`] | `read_track_table` (a tracker's table, as `track` reads it), `measure_track` (a filmed run's period with its evidence), `compare_with_model` (m/m0 and t0 from it) |

// Python functions take their settings as keyword-only arguments with defaults (as SciPy's and
// rapier's bindings do); each is one Rust parameter.
#![allow(clippy::too_many_arguments)]

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use pyo3::prelude::*;

use crate::errors::{ErrorClass, input_error};

mod body;
mod design;
mod drag_law;
mod errors;
mod experiment;
mod run;
mod scene;
mod studies;

/// `array` as a 2-D view, or a ValueError in Python's words naming `name` and what it must be
/// (numpy's own extraction says "dimensionality mismatch: from=1, to=2").
pub(crate) fn two_dimensional<'a>(
    name: &str,
    what: &str,
    array: numpy::ndarray::ArrayViewD<'a, f64>,
) -> PyResult<numpy::ndarray::ArrayView2<'a, f64>> {
    let shape = array.shape().to_vec();
    array
        .into_dimensionality::<numpy::ndarray::Ix2>()
        .map_err(|_| {
            input_error(format!(
                "{name} must be an {what}, not an array of shape {}",
                match shape.as_slice() {
                    [n] => format!("({n},)"),
                    dims => format!(
                        "({})",
                        dims.iter()
                            .map(usize::to_string)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                }
            ))
        })
}

/// How often the calling thread looks for Ctrl-C while a worker computes.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs `work` on a named worker thread with the GIL released, while this (the calling) thread
/// checks Python's signals every [`SIGNAL_POLL`]: on Ctrl-C (or any signal handler that raises)
/// it sets the stop flag `work` receives, waits for the worker to wind down and raises that
/// exception. The result comes back as soon as the worker finishes, with no polling delay.
pub(crate) fn interruptible<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> T + Send,
) -> PyResult<T> {
    let stop = AtomicBool::new(false);
    let (outcome, interrupt) = py.detach(|| {
        let (done, finished) = mpsc::channel::<()>();
        std::thread::scope(|scope| {
            let worker = std::thread::Builder::new()
                .name("rollphase-worker".into())
                .spawn_scoped(scope, || {
                    let out = work(&stop);
                    let _ = done.send(());
                    out
                });
            let worker = match worker {
                Ok(w) => w,
                Err(e) => {
                    return (
                        None,
                        Some(
                            ErrorClass::Internal.err(format!("cannot start a worker thread: {e}")),
                        ),
                    );
                }
            };
            let mut interrupt = None;
            loop {
                match finished.recv_timeout(SIGNAL_POLL) {
                    // Finished, or panicked (the sender dropped without a message).
                    Ok(()) | Err(mpsc::RecvTimeoutError::Disconnected) => break,
                    Err(mpsc::RecvTimeoutError::Timeout) => {
                        if interrupt.is_none()
                            && let Err(e) = Python::attach(|py| py.check_signals())
                        {
                            stop.store(true, Ordering::Relaxed);
                            interrupt = Some(e);
                        }
                    }
                }
            }
            (Some(worker.join()), interrupt)
        })
    });
    if let Some(e) = interrupt {
        return Err(e);
    }
    match outcome {
        Some(Ok(value)) => Ok(value),
        Some(Err(panic)) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(ErrorClass::Internal.err(format!(
                "internal error in rollphase (please report it): {what}"
            )))
        }
        None => Err(ErrorClass::Internal.err("the worker thread did not start")),
    }
}

/// A whole-number argument taken as Python gives it (any size, any sign) and checked here, so
/// a negative or huge value is a `ValueError` naming the argument rather than pyo3's
/// `OverflowError`; the core then checks the range that matters.
pub(crate) fn whole<T: TryFrom<i128>>(name: &str, v: i128) -> PyResult<T> {
    T::try_from(v).map_err(|_| {
        input_error(format!(
            "{name} = {v} is not allowed (needs a whole number from 0 to {})",
            match std::mem::size_of::<T>() {
                4 => u32::MAX.to_string(),
                _ => u64::MAX.to_string(),
            }
        ))
    })
}

/// `samples` as a count, with the run's own bounds in the message (2 ≤ samples ≤ 10⁷) rather
/// than the integer type's.
pub(crate) fn sample_count(samples: i128) -> PyResult<usize> {
    let max = rollphase_core::simulate::MAX_SAMPLES;
    usize::try_from(samples)
        .ok()
        .filter(|n| (2..=max).contains(n))
        .ok_or_else(|| {
            input_error(format!(
                "samples = {samples} is not allowed (needs 2 ≤ samples ≤ {max}: t = 0, t_end and \
                 rows between)"
            ))
        })
}

/// Irregular cylinders and spheres rolling down a ramp (Qian, Jung & Mahadevan, PNAS 2025):
/// bodies, the four rolling models and the paper's analyses, on numpy arrays.
///
/// Units: the force F, the drag γ and the mean radius ⟨r⟩ are 1; angles are in radians; mass is
/// m/m0 (0: the viscous model). Orientations are body-to-lab unit quaternions (w, x, y, z); the
/// ramp frame has x downhill and z along the ramp's normal.
#[pymodule]
fn rollphase(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<body::Body>()?;
    m.add_class::<run::Trajectory>()?;
    m.add_class::<run::DiskTrajectory>()?;
    m.add_class::<run::SphereTrajectory>()?;
    m.add_class::<run::SphereRuns>()?;
    errors::register(m)?;
    m.add_function(wrap_pyfunction!(run::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(run::simulate_many, m)?)?;
    m.add_function(wrap_pyfunction!(studies::critical_angle, m)?)?;
    m.add_function(wrap_pyfunction!(studies::period, m)?)?;
    m.add_function(wrap_pyfunction!(studies::poincare_map, m)?)?;
    m.add_function(wrap_pyfunction!(studies::cruising_fraction, m)?)?;
    m.add_function(wrap_pyfunction!(studies::periodic_orbits, m)?)?;
    m.add_function(wrap_pyfunction!(studies::predict, m)?)?;
    m.add_function(wrap_pyfunction!(studies::period_counts, m)?)?;
    m.add_function(wrap_pyfunction!(studies::mass_bifurcation, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::read_track_table, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::measure_track, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::compare_with_model, m)?)?;
    m.add_function(wrap_pyfunction!(design::design, m)?)?;
    m.add_function(wrap_pyfunction!(design::check_design, m)?)?;
    m.add_function(wrap_pyfunction!(drag_law::drag_parameters, m)?)?;
    m.add_function(wrap_pyfunction!(drag_law::models, m)?)?;
    m.add_function(wrap_pyfunction!(scene::replay, m)?)?;
    Ok(())
}
