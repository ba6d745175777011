//! rollphase-output: the one output layer, a crate of its own so that every program built on
//! rollphase (the command line and app, and the Python module over the physics core) writes its
//! files through the same code. Its module [`output`] owns the rules; see its documentation.
//! `rollphase::output` is this module, re-exported.

pub mod output;
pub use output::*;
