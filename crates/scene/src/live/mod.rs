//! The simulation of one scene, advanced to a requested time and observed as a plain
//! [`Snapshot`]: the body's pose, the contact point, the trails (contact path on the ramp, contact
//! trail on the body, the orientation's path in the SO(3) ball), the measured period and the
//! numerical health. Headless frames and the app's simulation thread both drive it.
//!
//! Time is an argument ([`LiveRun::advance_to`]): the same scene and the same sequence of
//! target times give the same numbers on every run. Each call restarts the integrator from the
//! stored state, so a run's values depend (within the tolerance) on the frame times it was
//! advanced through, never on wall-clock time.
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
//! | `simulation` | [`LiveRun`], [`Snapshot`], health (the running model is [`crate::simulate::ModelState`]) |
//! | `controller` | [`Controller`], [`SimCommand`] |
//! | `thread` | [`SimThread`], [`SimStatus`] |
//! | `field` | [`FieldCache`]: Poincaré fields computed off the render thread |
//! | `history` | [`history::PlotHistory`]: the plotted series accumulated from snapshots, and their CSV |

mod controller;
mod field;
pub mod history;
mod live_run;
mod thread;

pub use controller::{Controller, SimCommand};
pub use field::FieldCache;
pub use live_run::*;
pub use thread::{SimStatus, SimThread, TICK_INTERVAL};
