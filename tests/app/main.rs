//! The interactive app and the renderer: the live run and its thread, the egui workbench and
//! renderer, lessons, the window under Xvfb, headless frames against golden images, the render
//! command and the shaders (llvmpipe where there is no GPU).
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

mod app_state;
mod app_thread;
mod app_ui;
mod app_window;
mod bodies;
mod egui_panels;
mod headless_snapshots;
mod lesson_claims;
mod lessons;
mod presentation;
mod render_cli;
mod render_scale;
mod sculpt;
mod shaders;
mod teachers_pace;
