//! No code. This crate only pins the features of the physics core's dependencies, so that they
//! build the same whichever workspace package a command selects (`pip install ./python`, the
//! test builds with and without the GPU features, clippy over the workspace): one build of the
//! core's tree serves them all. Cargo.toml says why and how to keep it true.
