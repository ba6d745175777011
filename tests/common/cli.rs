//! Running the `rollphase` binary from a test: its standard output, or a panic showing its
//! standard error. Included with `#[path = "common/cli.rs"] mod cli;`.

use std::ffi::OsStr;
use std::process::Command;

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
