//! The simulation of one scene, advanced to a requested time and observed as a plain
//! [`Snapshot`]: the body's pose, the contact point, the trails (contact path on the ramp, contact
//! trail on the body, the orientation's path in the SO(3) ball), the measured period and the
//! numerical health. Headless frames and the app's simulation thread both drive it.
//!
//! Time is an argument ([`LiveRun::advance_to`]), and the run is put down between calls and
//! taken up again bit for bit: its steps are the integrator's own, never cut where a frame
//! falls, so the trajectory is `simulate`'s for the same scene at any frame rate, paused or not.
//!
//! Only what the views need is computed: the SO(3) trail only when the ball is shown.
//!
//! [`Controller`] is the app's simulation side as a clock-free state machine ([`SimCommand`]s
//! in, `tick(wall_seconds)` to advance): live α and m/m0 changes, pause, step, reset, load.
//! [`SimThread`] runs a controller on its own thread, reads the wall clock, catches panics and
//! publishes [`SimStatus`] for the app's UI.
//! Imports the core and `scene`; no GPU, no window.
//!
//! | file | owns |
//! |---|---|
//! | `live_run` | [`LiveRun`]: the run kept across frames, the lesson's steps, trails, crossings (the running model is [`crate::simulate::ModelState`]) |
//! | `lanes` | the scene's other bodies (`[[bodies]]`) run beside its own on the same clock, α and integrator; each body's fate in the verdict's words ([`Snapshot::fate`]) |
//! | `replay` | [`LiveRun::replayed`]: a saved state's run again from the scene's start, to the bit |
//! | `snapshot` | [`Snapshot`], [`Health`], [`SimError`]: what a run shows |
//! | `controller` | [`Controller`], [`SimCommand`] |
//! | `thread` | [`SimThread`], [`SimStatus`] |
//! | `evidence` | [`evidence::LessonEvidence`]: a lesson's plots measured ahead, step by step, on a worker thread, and each step's claim checked against them |
//! | `field` | [`FieldCache`]: Poincaré fields computed off the render thread |
//! | `history` | [`history::PlotHistory`]: the plotted series accumulated from snapshots, and their CSV |

mod controller;
pub mod evidence;
mod field;
pub mod history;
mod lanes;
mod live_run;
mod replay;
mod snapshot;
mod thread;

pub use controller::{Controller, SimCommand};
pub use field::FieldCache;
pub use live_run::*;
pub use replay::ReplayCheck;
pub use snapshot::*;
pub use thread::{SimStatus, SimThread, TICK_INTERVAL};
