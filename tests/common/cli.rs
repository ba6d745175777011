//! Running the `rollphase` binary from a test: its whole output, or its standard output with a
//! panic showing its standard error on failure. Included with `#[path = "common/cli.rs"] mod
//! cli;`.
#![allow(dead_code)] // each test file uses what it needs

use std::ffi::OsStr;
use std::process::{Command, Output};

/// The binary under test: the file `ROLLPHASE_TEST_BINARY` names when it is set, else the one
/// Cargo built beside these tests. `.ci/run` sets it to the build without default features and
/// runs the bad-input tests and the physics tests that start the binary against that build, so
/// its test binaries need not be compiled a second time without those features.
pub fn binary() -> std::path::PathBuf {
    std::env::var_os("ROLLPHASE_TEST_BINARY")
        .map_or_else(|| env!("CARGO_BIN_EXE_rollphase").into(), Into::into)
}

/// Whether the binary under test was built with the `app` feature (its `--version` says).
pub fn binary_has_app() -> bool {
    let version = Command::new(binary())
        .arg("--version")
        .output()
        .expect("the rollphase binary runs");
    String::from_utf8_lossy(&version.stdout).contains("features: render, app")
}

/// Runs `rollphase ARGS` and returns its exit status and both streams, success or not.
pub fn rollphase<I, S>(args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    Command::new(binary())
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
    let out = Command::new(binary()).args(&args).output().unwrap();
    assert!(
        out.status.success(),
        "rollphase {:?} failed: {}",
        args.iter().map(|a| a.as_ref()).collect::<Vec<_>>(),
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

/// A file of `assets/data/` (the authors' printed bodies and tracked run).
pub fn data(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/data")
        .join(name)
}

/// A fresh, empty scratch folder of its own for each call (`tempfile`'s unique name under the
/// system's temporary folder, `rollphase-NAME-…`): the tests of one binary run in one process,
/// so a name made of the process id alone would be shared. It is kept after the test (a
/// failure's files can be read); the system's cleaner removes it.
pub fn scratch(name: &str) -> std::path::PathBuf {
    tempfile::Builder::new()
        .prefix(&format!("rollphase-{name}-"))
        .tempdir()
        .expect("a scratch folder under the temporary folder")
        .keep()
}

/// A folder path that does not exist yet, for a command to make: `NAME` under one scratch
/// folder of this test process (made with `tempfile` on first use). The same name gives the same
/// path, so a test can name a figure's output folder twice.
pub fn unmade_folder(name: &str) -> std::path::PathBuf {
    static ROOT: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    ROOT.get_or_init(|| scratch("outputs")).join(name)
}

/// The names in `dir`, sorted: what a refused command must leave as it found it.
pub fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}
