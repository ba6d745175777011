//! rollphase-output: the one output layer, a crate of its own so that every program built on
//! rollphase (the command line and app, and the Python module over the physics core) writes its
//! files through the same code. Its module [`output`] owns the rules; see its documentation.
//! `rollphase::output` is this module, re-exported.
//!
//! Unix only: its promises rest on Unix file semantics (device and inode numbers, hard links,
//! `flock`, `/proc/self/fd` and `/dev/fd`), and it does not build elsewhere.

// The one crate allowed to create, write, rename and link files (clippy.toml's
// disallowed-methods refuses them everywhere else).
#![allow(
    clippy::disallowed_methods,
    reason = "the one output layer: the only place files are written"
)]

pub mod output;
pub use output::*;

#[cfg(not(unix))]
compile_error!(
    "rollphase-output is Unix-only: its promises rest on inodes, hard links, flock and /proc/self/fd"
);
