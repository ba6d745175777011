//! Output files that never damage what is already there.
//!
//! - `-` is standard output.
//! - A path that exists and is not a regular file (a device, a FIFO, a terminal) is written
//!   directly, as a shell redirection would: renaming over it would replace the device node.
//! - A regular file (or a path that does not exist yet) is written to a temporary file beside its
//!   real location and moved into place only when the command succeeds, so a failed run leaves
//!   the old file as it was. Symbolic links are followed to their target, so the link stays a
//!   link; a file with several hard links is rewritten in place at the end, so every link sees
//!   the new contents.
//! - An output that is one of the command's inputs is refused before anything is written.
//!
//! Standard output itself: [`stdout_line`] writes one line and returns the error instead of
//! panicking as `println!` does, so a closed pipe or a full disk reaches `main.rs` as an error.

use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

/// The temporary files being written now, removed by [`remove_partial_outputs`] when the user
/// interrupts the command (Ctrl-C), so an interrupted run leaves nothing behind.
static PARTIAL_OUTPUTS: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Removes every output still being written (called from the Ctrl-C handler in `main.rs`).
pub fn remove_partial_outputs() {
    let files = PARTIAL_OUTPUTS.lock().unwrap_or_else(|e| e.into_inner());
    for f in files.iter() {
        let _ = std::fs::remove_file(f);
    }
}

fn forget_partial(temp: &Path) {
    PARTIAL_OUTPUTS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .retain(|p| p != temp);
}

/// Where an output goes, open for writing.
pub struct OutputFile {
    target: Target,
    writer: BufWriter<Box<dyn Write>>,
}

enum Target {
    Stdout,
    Direct,
    Staged {
        temp: PathBuf,
        destination: PathBuf,
        in_place: bool,
    },
}

impl OutputFile {
    /// Opens `path` for writing (see the module doc); `inputs` are the files the command reads,
    /// which it must not overwrite; `flag` names the option in messages (e.g. "-o").
    pub fn create(path: &Path, inputs: &[&Path], flag: &str) -> Result<Self> {
        if path.as_os_str() == "-" {
            return Ok(Self {
                target: Target::Stdout,
                writer: BufWriter::new(Box::new(io::stdout())),
            });
        }
        let destination = real_path(path);
        for input in inputs {
            if let (Ok(a), Ok(b)) = (std::fs::canonicalize(input), std::fs::canonicalize(path))
                && a == b
            {
                bail!(
                    "{flag} {} is also an input of this command; refusing to overwrite it (write \
                     elsewhere, then move the file)",
                    path.display()
                );
            }
        }
        match std::fs::metadata(path) {
            Ok(m) if !m.is_file() && !m.is_dir() => {
                let file = OpenOptions::new()
                    .write(true)
                    .open(path)
                    .with_context(|| format!("{flag}: cannot open {}", path.display()))?;
                Ok(Self {
                    target: Target::Direct,
                    writer: BufWriter::new(Box::new(file)),
                })
            }
            Ok(m) if m.is_dir() => bail!("{flag} {} is a folder; give a file name", path.display()),
            existing => {
                let in_place = existing.is_ok_and(|m| m.nlink() > 1);
                let name = destination
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "output".into());
                let temp =
                    destination.with_file_name(format!(".{name}.partial-{}", std::process::id()));
                PARTIAL_OUTPUTS
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .push(temp.clone());
                let file = File::create(&temp).with_context(|| {
                    format!(
                        "{flag}: cannot create {} (beside {})",
                        temp.display(),
                        path.display()
                    )
                })?;
                Ok(Self {
                    target: Target::Staged {
                        temp,
                        destination,
                        in_place,
                    },
                    writer: BufWriter::new(Box::new(file)),
                })
            }
        }
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut dyn Write {
        &mut self.writer
    }

    /// Flushes and moves the output into place.
    pub fn commit(mut self) -> Result<()> {
        let what = match &self.target {
            Target::Stdout => "cannot write to standard output".to_string(),
            Target::Direct | Target::Staged { .. } => "cannot write the output file".to_string(),
        };
        self.writer.flush().context(what)?;
        let target = std::mem::replace(&mut self.target, Target::Stdout);
        drop(self);
        if let Target::Staged {
            temp,
            destination,
            in_place,
        } = target
        {
            let moved = if in_place {
                std::fs::copy(&temp, &destination).map(|_| ())
            } else {
                std::fs::rename(&temp, &destination)
            };
            let _ = std::fs::remove_file(&temp);
            forget_partial(&temp);
            moved.with_context(|| format!("cannot write {}", destination.display()))?;
        }
        Ok(())
    }

    /// Gives up: the temporary file is removed and the destination left as it was.
    pub fn abort(self) {}
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        if let Target::Staged { temp, .. } = &self.target {
            let _ = std::fs::remove_file(temp);
            forget_partial(temp);
        }
    }
}

/// Where `path` really is: symbolic links followed (also a dangling one, to the file it names).
pub fn real_path(path: &Path) -> PathBuf {
    if let Ok(p) = std::fs::canonicalize(path) {
        return p;
    }
    let mut p = path.to_owned();
    for _ in 0..40 {
        match std::fs::read_link(&p) {
            Ok(next) => {
                p = match p.parent() {
                    Some(dir) if next.is_relative() => dir.join(next),
                    _ => next,
                }
            }
            Err(_) => break,
        }
    }
    p
}

/// Writes `text` to `path` (or standard output for `None` or "-") through [`OutputFile`].
pub fn write_text(path: Option<&Path>, text: &str, inputs: &[&Path], flag: &str) -> Result<()> {
    let path = path.unwrap_or(Path::new("-"));
    let mut out = OutputFile::create(path, inputs, flag)?;
    out.writer().write_all(text.as_bytes()).with_context(|| {
        if path.as_os_str() == "-" {
            "cannot write to standard output".to_string()
        } else {
            format!("cannot write {}", path.display())
        }
    })?;
    out.commit()
}

/// Writes one line to standard output, returning the error (a closed pipe, a full disk) instead
/// of panicking.
pub fn stdout_line(text: &str) -> Result<()> {
    let mut out = io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.write_all(b"\n"))
        .context("cannot write to standard output")
}
