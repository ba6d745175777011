//! The physics, checked against exact results and the paper: laws (energy balance, exact disks and
//! spheres, convergence orders, critical angles), the paper's bodies and equations, the library's
//! typed API, studies and predictions, mesh import and tracked runs. No GPU.
//!
//! One test binary for the group (each binary links the whole crate and its GPU stack, so a
//! few binaries build and link in a fraction of the time of one per file); each module is one
//! former test file. Slow tests are `#[ignore = "slow: …"]`: `cargo test` leaves them out,
//! `cargo test -- --include-ignored` (the README's and `.ci/run`'s command) runs them.

// Tests write their fixtures (bodies, specs, damaged files, links) directly: the files under
// test are the program's, which go through the output layer.
#![allow(
    clippy::disallowed_methods,
    reason = "tests write their own fixtures directly"
)]

#[path = "../common/cli.rs"]
mod cli;
#[path = "../common/mod.rs"]
mod common;

mod constraint_drift;
mod contact_forces;
mod critical_angle;
mod dented_bodies;
mod design;
mod drag_laws;
mod energy_balance;
mod extremes;
mod fixed_step_check;
mod geometry_laws;
mod integrator_order;
mod library_use;
mod mesh_errors;
mod mesh_import;
mod mesh_prisms;
mod paper_bodies;
mod paper_equations;
mod perfect_bodies;
mod period_doubling;
mod predictions;
mod reproducibility;
mod studies;
mod track_chaos;
mod track_periods;
mod tracked_runs;
