//! The command line and the project's own rules: bad input refused with a clear message, the
//! figure, scan, shard and merge commands, scenes and presets, the guide's and README's commands
//! run as written, the output layer and the module layering.
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
#[path = "../common/source.rs"]
mod source;

mod architecture;
mod bad_input;
mod bench_outputs;
mod design;
mod drag_law;
mod figures;
mod guide_commands;
mod lesson_evidence;
mod presets;
mod readme_commands;
mod scene_simulation;
mod scenes;
mod shard;
