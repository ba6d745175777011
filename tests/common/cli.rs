//! Running the `rollphase` binary from a test: its whole output, or its standard output with a
//! panic showing its standard error on failure. Included with `#[path = "common/cli.rs"] mod
//! cli;`.
#![allow(dead_code)] // each test file uses what it needs

use std::ffi::OsStr;
use std::process::{Command, Output};

/// Runs `rollphase ARGS` and returns its exit status and both streams, success or not.
pub fn rollphase<I, S>(args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    Command::new(env!("CARGO_BIN_EXE_rollphase"))
        .args(args)
        .output()
        .expect("the rollphase binary runs")
}

/// Runs `rollphase ARGS`, which must succeed, and returns what it printed on standard output.
pub fn rollphase_ok<I, S>(args: I) -> Vec<u8>
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    let args: Vec<S> = args.into_iter().collect();
    let out = Command::new(env!("CARGO_BIN_EXE_rollphase"))
        .args(&args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "rollphase {:?} failed: {}",
        args.iter().map(|a| a.as_ref()).collect::<Vec<_>>(),
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}
