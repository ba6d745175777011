//! The one output layer: every byte rollphase writes to a file goes through here, so the promise
//! "output files are never damaged" is kept by structure rather than writer by writer
//! (`tests/output_layer.rs` fails if any other module creates, writes, renames or saves a file).
//!
//! - `-` is standard output.
//! - A path that exists and is neither a regular file nor a folder (a device, a FIFO, a socket)
//!   is written through, as a shell redirection would: renaming over it would replace the node.
//! - A regular file (or a path that does not exist yet) is staged in a hidden file beside its
//!   real location and moved into place only on [`OutputFile::commit`], so a failed or
//!   interrupted run leaves the old file whole. Symbolic links are followed to their target, so
//!   a link stays a link; a file with several hard links is rewritten in place at the end, so
//!   every name sees the new contents.
//! - Several files that belong together (a figure's data.csv, summary.json and figure.png) go
//!   into one [`OutputSet`]: each is staged whole before any is moved, and if a move fails the
//!   ones already moved are put back, so a folder holds the old set or the new one, never a mix.
//! - Every output is checked against the command's [`Inputs`] after resolving links (and by
//!   device and inode, which catches hard links) and refused before anything is written.
//!   [`check_file`] and [`check_folder`] let a command do that before its first expensive step.
//!
//! Its own crate (rollphase-output, re-exported as `rollphase::output`), depending on nothing of
//! rollphase: it sits at the bottom of the layers, below `png`, `clip`,
//! `figures`, `headless`, `ui` and `cli`.

use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

use thiserror::Error;

/// Why an output could not be written. Each message names the path and what to do.
#[derive(Debug, Error)]
pub enum OutputError {
    /// The output is one of the command's inputs.
    #[error(
        "{} is also an input of this command ({}); refusing to overwrite it (write elsewhere, then move the file)",
        path.display(), input.display()
    )]
    IsInput {
        /// The output as given.
        path: PathBuf,
        /// The input it is (as the command named it).
        input: PathBuf,
    },
    /// A file was asked for where a folder is.
    #[error("{} is a folder; give a file name", path.display())]
    IsFolder {
        /// The path.
        path: PathBuf,
    },
    /// A folder was asked for where something else is.
    #[error("{} exists and is not a folder", path.display())]
    NotFolder {
        /// The path.
        path: PathBuf,
    },
    /// The OS refused (no such folder, no permission, a full disk, …).
    // The OS error is part of the message, not a chained source, so `{:#}` prints it once.
    #[error("cannot write {}: {error}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What the OS said.
        error: io::Error,
    },
    /// Standard output refused (a closed pipe, a full disk behind it).
    #[error("cannot write to standard output: {0}")]
    Stdout(io::Error),
}

impl OutputError {
    fn io(path: &Path, source: io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            error: source,
        }
    }

    /// Whether this is a closed standard output (the reader went away), which a command treats
    /// as a quiet end rather than an error.
    pub fn is_broken_pipe(&self) -> bool {
        match self {
            Self::Stdout(e) | Self::Io { error: e, .. } => e.kind() == io::ErrorKind::BrokenPipe,
            _ => false,
        }
    }
}

/// Shorthand for this module's results.
pub type Result<T, E = OutputError> = std::result::Result<T, E>;

/// The files a command reads, which none of its outputs may be.
#[derive(Debug, Clone, Default)]
pub struct Inputs {
    files: Vec<InputFile>,
}

#[derive(Debug, Clone)]
struct InputFile {
    named: PathBuf,
    real: Option<PathBuf>,
    id: Option<(u64, u64)>,
}

impl Inputs {
    /// No inputs.
    pub fn none() -> Self {
        Self::default()
    }

    /// The inputs `paths` (standard input, `-`, is skipped).
    pub fn of<P: AsRef<Path>>(paths: impl IntoIterator<Item = P>) -> Self {
        let mut inputs = Self::default();
        for p in paths {
            inputs.add(p.as_ref());
        }
        inputs
    }

    /// Adds one input.
    pub fn add(&mut self, path: &Path) {
        if path.as_os_str() == "-" {
            return;
        }
        self.files.push(InputFile {
            named: path.to_path_buf(),
            real: std::fs::canonicalize(path).ok(),
            id: std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino())),
        });
    }

    /// The same inputs plus all of `other`'s.
    pub fn extend(mut self, other: &Inputs) -> Self {
        self.files.extend(other.files.iter().cloned());
        self
    }

    /// The same inputs plus `path`.
    pub fn with(mut self, path: &Path) -> Self {
        self.add(path);
        self
    }

    /// Refuses `output` when it is one of the inputs: the same file after links are resolved,
    /// or another name of it (a hard link).
    pub fn refuse(&self, output: &Path) -> Result<()> {
        if output.as_os_str() == "-" || self.files.is_empty() {
            return Ok(());
        }
        let real = real_path(output);
        let id = std::fs::metadata(output).ok().map(|m| (m.dev(), m.ino()));
        for input in &self.files {
            let same_id = id.is_some() && input.id == id;
            let same_path = input.real.as_deref() == Some(real.as_path());
            if same_id || same_path {
                return Err(OutputError::IsInput {
                    path: output.to_path_buf(),
                    input: input.named.clone(),
                });
            }
        }
        Ok(())
    }
}

/// The temporary files being written now, removed by [`remove_partial_outputs`] when the user
/// interrupts the command (Ctrl-C), so an interrupted run leaves nothing behind.
static PARTIAL_OUTPUTS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Tells apart the temporary files of one process.
static NEXT_TEMP: AtomicU64 = AtomicU64::new(0);

/// Removes every output still being written (called from the Ctrl-C handler in `main.rs`).
pub fn remove_partial_outputs() {
    let files = PARTIAL_OUTPUTS.lock().unwrap_or_else(|e| e.into_inner());
    for f in files.iter() {
        let _ = std::fs::remove_file(f);
    }
}

fn remember_partial(temp: &Path) {
    PARTIAL_OUTPUTS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(temp.to_path_buf());
}

fn forget_partial(temp: &Path) {
    PARTIAL_OUTPUTS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .retain(|p| p != temp);
}

/// A hidden name beside `destination`, unique in this process: `.NAME.partial-PID-K`.
fn temp_beside(destination: &Path, what: &str) -> PathBuf {
    let name = destination
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    let k = NEXT_TEMP.fetch_add(1, Ordering::Relaxed);
    destination.with_file_name(format!(".{name}.{what}-{}-{k}", std::process::id()))
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
    // A path that does not exist yet: its folder resolved, so an output named through a linked
    // folder is compared with the inputs by where it lands.
    match (p.parent(), p.file_name()) {
        (Some(dir), Some(name)) if !dir.as_os_str().is_empty() => std::fs::canonicalize(dir)
            .map(|d| d.join(name))
            .unwrap_or(p),
        _ => p,
    }
}

/// What kind of place an output path is.
enum Place {
    Stdout,
    /// A device, FIFO or socket: written through.
    Direct,
    /// A regular file or a new name: staged, then moved (or copied, for hard links) into place.
    Staged {
        destination: PathBuf,
        in_place: bool,
    },
}

fn place_of(path: &Path) -> Result<Place> {
    if path.as_os_str() == "-" {
        return Ok(Place::Stdout);
    }
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(OutputError::IsFolder {
            path: path.to_path_buf(),
        }),
        Ok(m) if !m.is_file() => Ok(Place::Direct),
        Ok(m) => Ok(Place::Staged {
            destination: real_path(path),
            in_place: m.nlink() > 1,
        }),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(Place::Staged {
            destination: real_path(path),
            in_place: false,
        }),
        Err(e) => Err(OutputError::io(path, e)),
    }
}

/// Checks, before a command's expensive work, that `path` can be written: not one of `inputs`,
/// not a folder, and its folder exists. Nothing is created.
pub fn check_file(path: &Path, inputs: &Inputs) -> Result<()> {
    inputs.refuse(path)?;
    if let Place::Staged { destination, .. } = place_of(path)? {
        let dir = match destination.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        match std::fs::metadata(&dir) {
            Ok(m) if m.is_dir() => {}
            Ok(_) => return Err(OutputError::NotFolder { path: dir }),
            Err(e) => return Err(OutputError::io(path, e)),
        }
    }
    Ok(())
}

/// Checks, before a command's expensive work, that the files `names` can be written into the
/// folder `dir` (created later by [`create_folder`]): no part of `dir` is a file, and no file
/// is a folder or one of `inputs`. Nothing is created.
pub fn check_folder(dir: &Path, names: &[&str], inputs: &Inputs) -> Result<()> {
    let mut existing = dir;
    loop {
        match std::fs::metadata(existing) {
            Ok(m) if m.is_dir() => break,
            Ok(_) => {
                return Err(OutputError::NotFolder {
                    path: existing.to_path_buf(),
                });
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::NotFound | io::ErrorKind::NotADirectory
                ) =>
            {
                match existing.parent() {
                    Some(p) if !p.as_os_str().is_empty() => existing = p,
                    _ => break,
                }
            }
            Err(e) => return Err(OutputError::io(existing, e)),
        }
    }
    for name in names {
        let path = dir.join(name);
        inputs.refuse(&path)?;
        place_of(&path)?;
    }
    Ok(())
}

/// Creates the folder `dir` and its parents (an existing folder is fine).
pub fn create_folder(dir: &Path) -> Result<()> {
    if let Ok(m) = std::fs::metadata(dir)
        && !m.is_dir()
    {
        return Err(OutputError::NotFolder {
            path: dir.to_path_buf(),
        });
    }
    std::fs::create_dir_all(dir).map_err(|e| OutputError::io(dir, e))
}

/// Where an output goes, open for writing (see the module doc). Implements [`Write`].
pub struct OutputFile {
    path: PathBuf,
    target: Target,
    writer: Option<BufWriter<Box<dyn Write + Send>>>,
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
    /// Opens `path` for writing; `inputs` are the files the command reads.
    pub fn create(path: &Path, inputs: &Inputs) -> Result<Self> {
        inputs.refuse(path)?;
        let (target, sink): (Target, Box<dyn Write + Send>) = match place_of(path)? {
            Place::Stdout => (Target::Stdout, Box::new(io::stdout())),
            Place::Direct => {
                let file = OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(|e| OutputError::io(path, e))?;
                (Target::Direct, Box::new(file))
            }
            Place::Staged {
                destination,
                in_place,
            } => {
                let temp = temp_beside(&destination, "partial");
                remember_partial(&temp);
                let file = File::create(&temp).map_err(|e| {
                    forget_partial(&temp);
                    OutputError::io(path, e)
                })?;
                // A file replaced keeps its permission bits (a private 0600 result stays
                // private); a new one gets the umask's, as a shell redirection would.
                if let Ok(m) = std::fs::metadata(&destination) {
                    let _ = std::fs::set_permissions(&temp, m.permissions());
                }
                (
                    Target::Staged {
                        temp,
                        destination,
                        in_place,
                    },
                    Box::new(file),
                )
            }
        };
        Ok(Self {
            path: path.to_path_buf(),
            target,
            writer: Some(BufWriter::with_capacity(1 << 16, sink)),
        })
    }

    /// The path as the command named it.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn error(&self, e: io::Error) -> OutputError {
        match self.target {
            Target::Stdout => OutputError::Stdout(e),
            _ => OutputError::io(&self.path, e),
        }
    }

    /// Writes all of `bytes`, naming the file in the error.
    pub fn write_bytes(&mut self, bytes: &[u8]) -> Result<()> {
        let r = match self.writer.as_mut() {
            Some(w) => w.write_all(bytes),
            None => Ok(()),
        };
        r.map_err(|e| self.error(e))
    }

    /// Writes everything out (and to disk, for a staged file) without moving it into place.
    fn finish_writing(&mut self) -> Result<()> {
        let Some(w) = self.writer.take() else {
            return Ok(());
        };
        let sink = w.into_inner().map_err(|e| self.error(e.into_error()))?;
        drop(sink);
        if let Target::Staged { temp, .. } = &self.target {
            // The bytes on disk before the old file is replaced: a crash after the rename must
            // not leave an empty file where the old one was.
            File::open(temp)
                .and_then(|f| f.sync_all())
                .map_err(|e| OutputError::io(&self.path, e))?;
        }
        Ok(())
    }

    /// Flushes and moves the output into place.
    pub fn commit(mut self) -> Result<()> {
        self.finish_writing()?;
        let mut set = OutputSet::new();
        set.files.push(self);
        set.commit()
    }

    /// Gives up: the temporary file is removed and the destination left as it was.
    pub fn abort(self) {}
}

impl Write for OutputFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self.writer.as_mut() {
            Some(w) => w.write(buf),
            None => Err(io::Error::other("output already finished")),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match self.writer.as_mut() {
            Some(w) => w.flush(),
            None => Ok(()),
        }
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        if let Target::Staged { temp, .. } = &self.target {
            self.writer = None;
            let _ = std::fs::remove_file(temp);
            forget_partial(temp);
        }
    }
}

/// Files that are committed together: all staged whole, then moved into place; a failed move
/// puts back those already moved.
#[derive(Default)]
pub struct OutputSet {
    files: Vec<OutputFile>,
}

impl OutputSet {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a file whose bytes are all written.
    pub fn add(&mut self, mut file: OutputFile) -> Result<()> {
        file.finish_writing()?;
        self.files.push(file);
        Ok(())
    }

    /// Stages `bytes` for `path` (see [`write_bytes`]).
    pub fn write(&mut self, path: &Path, bytes: &[u8], inputs: &Inputs) -> Result<()> {
        let mut file = OutputFile::create(path, inputs)?;
        file.write_bytes(bytes)?;
        self.add(file)
    }

    /// Moves every file into place, or none: if one move fails, the files moved before it get
    /// their old contents back and the error is returned.
    pub fn commit(mut self) -> Result<()> {
        for f in &mut self.files {
            f.finish_writing()?;
        }
        let mut done: Vec<Undo> = Vec::new();
        let mut failure = None;
        for f in &self.files {
            let Target::Staged {
                temp,
                destination,
                in_place,
            } = &f.target
            else {
                continue;
            };
            match move_into_place(temp, destination, *in_place) {
                Ok(undo) => done.push(undo),
                Err(e) => {
                    failure = Some(OutputError::io(&f.path, e));
                    break;
                }
            }
        }
        match failure {
            None => {
                for undo in done {
                    undo.forget();
                }
                Ok(())
            }
            Some(e) => {
                for undo in done.into_iter().rev() {
                    undo.restore();
                }
                Err(e)
            }
        }
    }
}

/// How to put back the file a move replaced.
struct Undo {
    destination: PathBuf,
    /// A hard link to the old file (or a copy of it, for a file rewritten in place); `None`
    /// when there was no old file.
    backup: Option<PathBuf>,
    in_place: bool,
}

impl Undo {
    fn restore(self) {
        match &self.backup {
            Some(b) if self.in_place => {
                let _ = std::fs::copy(b, &self.destination);
                let _ = std::fs::remove_file(b);
            }
            Some(b) => {
                let _ = std::fs::rename(b, &self.destination);
            }
            None => {
                let _ = std::fs::remove_file(&self.destination);
            }
        }
        if let Some(b) = &self.backup {
            forget_partial(b);
        }
    }

    fn forget(self) {
        if let Some(b) = &self.backup {
            let _ = std::fs::remove_file(b);
            forget_partial(b);
        }
    }
}

fn move_into_place(temp: &Path, destination: &Path, in_place: bool) -> io::Result<Undo> {
    let exists = std::fs::symlink_metadata(destination).is_ok();
    let backup = if exists {
        let b = temp_beside(destination, "previous");
        remember_partial(&b);
        let made = if in_place {
            std::fs::copy(destination, &b).map(|_| ())
        } else {
            std::fs::hard_link(destination, &b)
        };
        match made {
            Ok(()) => Some(b),
            Err(e) => {
                forget_partial(&b);
                let _ = std::fs::remove_file(&b);
                return Err(e);
            }
        }
    } else {
        None
    };
    let undo = Undo {
        destination: destination.to_path_buf(),
        backup,
        in_place,
    };
    let moved = if in_place {
        // Every hard link sees the new contents: the file keeps its inode.
        std::fs::copy(temp, destination).map(|_| ())
    } else {
        std::fs::rename(temp, destination)
    };
    match moved {
        Ok(()) => {
            let _ = std::fs::remove_file(temp);
            forget_partial(temp);
            Ok(undo)
        }
        Err(e) => {
            undo.restore();
            Err(e)
        }
    }
}

/// Writes `bytes` to `path` (`-` is standard output) through an [`OutputFile`].
pub fn write_bytes(path: &Path, bytes: &[u8], inputs: &Inputs) -> Result<()> {
    let mut out = OutputFile::create(path, inputs)?;
    out.write_bytes(bytes)?;
    out.commit()
}

/// An output written by another program (ffmpeg) to a path it is given: [`Self::path`] is that
/// path, a staging file; [`Self::commit`] moves or copies the result to the real output.
pub struct ProgramOutput {
    out: OutputFile,
    scratch: Option<Scratch>,
}

/// A scratch file outside the destination's folder, removed when dropped.
struct Scratch(PathBuf);

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
        forget_partial(&self.0);
    }
}

impl ProgramOutput {
    /// Prepares `path` as [`OutputFile::create`] does.
    pub fn create(path: &Path, inputs: &Inputs) -> Result<Self> {
        let out = OutputFile::create(path, inputs)?;
        let scratch = match &out.target {
            Target::Staged { .. } => None,
            // A device or standard output: the program writes a scratch file, copied through
            // at the end.
            _ => {
                let k = NEXT_TEMP.fetch_add(1, Ordering::Relaxed);
                let s = std::env::temp_dir()
                    .join(format!(".rollphase-{}-{k}.partial", std::process::id()));
                remember_partial(&s);
                Some(Scratch(s))
            }
        };
        Ok(Self { out, scratch })
    }

    /// Where the program writes.
    pub fn path(&self) -> &Path {
        match (&self.scratch, &self.out.target) {
            (Some(s), _) => &s.0,
            (None, Target::Staged { temp, .. }) => temp,
            (None, _) => &self.out.path,
        }
    }

    /// The output as the command named it.
    pub fn named(&self) -> &Path {
        self.out.path()
    }

    /// Moves the program's file into place.
    pub fn commit(mut self) -> Result<()> {
        if let Some(s) = self.scratch.take() {
            let copied = File::open(&s.0).and_then(|mut f| {
                let w = self.out.writer.as_mut().ok_or(io::ErrorKind::Other)?;
                io::copy(&mut f, w).map(|_| ())
            });
            drop(s);
            copied.map_err(|e| self.out.error(e))?;
            return self.out.commit();
        }
        // The program replaced the staged file: its bytes are what we move.
        self.out.writer = None;
        self.out.commit()
    }
}

/// Writes one line to standard output, returning the error (a closed pipe, a full disk) instead
/// of panicking as `println!` does.
pub fn stdout_line(text: &str) -> Result<()> {
    let mut out = io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.write_all(b"\n"))
        .and_then(|()| out.flush())
        .map_err(OutputError::Stdout)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let d =
            std::env::temp_dir().join(format!("rollphase-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn leftovers(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with('.'))
            .collect()
    }

    #[test]
    fn a_set_whose_last_move_fails_leaves_the_old_set_whole() {
        let d = temp_dir("set-rollback");
        std::fs::write(d.join("a.csv"), "old a").unwrap();
        std::fs::write(d.join("b.json"), "old b").unwrap();
        let mut set = OutputSet::new();
        set.write(&d.join("a.csv"), b"new a", &Inputs::none())
            .unwrap();
        set.write(&d.join("b.json"), b"new b", &Inputs::none())
            .unwrap();
        set.write(&d.join("c.png"), b"new c", &Inputs::none())
            .unwrap();
        // c.png becomes a folder after staging: its move fails, so a and b must come back.
        std::fs::create_dir(d.join("c.png")).unwrap();
        std::fs::write(d.join("c.png").join("inside"), "x").unwrap();
        let e = set.commit().unwrap_err();
        assert!(e.to_string().contains("c.png"), "{e}");
        assert_eq!(std::fs::read_to_string(d.join("a.csv")).unwrap(), "old a");
        assert_eq!(std::fs::read_to_string(d.join("b.json")).unwrap(), "old b");
        assert!(leftovers(&d).is_empty(), "{:?}", leftovers(&d));
    }

    #[test]
    fn a_new_file_in_a_failed_set_is_removed_again() {
        let d = temp_dir("set-new");
        let mut set = OutputSet::new();
        set.write(&d.join("a.csv"), b"new a", &Inputs::none())
            .unwrap();
        set.write(&d.join("b"), b"new b", &Inputs::none()).unwrap();
        std::fs::create_dir(d.join("b")).unwrap();
        std::fs::write(d.join("b").join("inside"), "x").unwrap();
        assert!(set.commit().is_err());
        assert!(!d.join("a.csv").exists());
        assert!(leftovers(&d).is_empty(), "{:?}", leftovers(&d));
    }

    #[test]
    fn links_stay_links_and_hard_links_share_the_new_contents() {
        let d = temp_dir("links");
        std::fs::write(d.join("target"), "old").unwrap();
        std::os::unix::fs::symlink(d.join("target"), d.join("link")).unwrap();
        write_bytes(&d.join("link"), b"via link", &Inputs::none()).unwrap();
        assert!(
            std::fs::symlink_metadata(d.join("link"))
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read(d.join("target")).unwrap(), b"via link");
        std::fs::hard_link(d.join("target"), d.join("second")).unwrap();
        write_bytes(&d.join("target"), b"both", &Inputs::none()).unwrap();
        assert_eq!(std::fs::read(d.join("second")).unwrap(), b"both");
        assert!(leftovers(&d).is_empty(), "{:?}", leftovers(&d));
    }

    #[test]
    fn an_input_is_refused_by_any_of_its_names() {
        let d = temp_dir("inputs");
        std::fs::write(d.join("in.toml"), "x").unwrap();
        std::os::unix::fs::symlink(d.join("in.toml"), d.join("sym")).unwrap();
        std::fs::hard_link(d.join("in.toml"), d.join("hard")).unwrap();
        let inputs = Inputs::of([d.join("in.toml")]);
        for name in ["in.toml", "sym", "hard"] {
            let e = write_bytes(&d.join(name), b"y", &inputs).unwrap_err();
            assert!(matches!(e, OutputError::IsInput { .. }), "{name}: {e}");
            assert!(check_file(&d.join(name), &inputs).is_err());
        }
        let e = check_folder(&d, &["in.toml"], &inputs).unwrap_err();
        assert!(e.to_string().contains("is also an input"), "{e}");
        assert_eq!(std::fs::read(d.join("in.toml")).unwrap(), b"x");
    }

    #[test]
    fn a_character_device_is_written_through_not_replaced() {
        use std::os::unix::fs::FileTypeExt;
        let null = Path::new("/dev/null");
        if !null.exists() {
            return;
        }
        write_bytes(null, b"gone", &Inputs::none()).unwrap();
        let p = ProgramOutput::create(null, &Inputs::none()).unwrap();
        assert!(p.path() != null);
        std::fs::write(p.path(), b"from a program").unwrap();
        p.commit().unwrap();
        assert!(
            std::fs::metadata(null)
                .unwrap()
                .file_type()
                .is_char_device()
        );
        if let Ok(m) = std::fs::metadata("/dev/full") {
            assert!(write_bytes(Path::new("/dev/full"), &[0; 70000], &Inputs::none()).is_err());
            assert!(m.file_type().is_char_device());
            assert!(
                std::fs::metadata("/dev/full")
                    .unwrap()
                    .file_type()
                    .is_char_device()
            );
        }
    }

    #[test]
    fn folders_are_checked_before_anything_is_made() {
        let d = temp_dir("folders");
        std::fs::write(d.join("afile"), "x").unwrap();
        let e = check_folder(&d.join("afile/sub"), &["a.csv"], &Inputs::none()).unwrap_err();
        assert!(matches!(e, OutputError::NotFolder { .. }), "{e}");
        std::fs::create_dir_all(d.join("out/figure.png")).unwrap();
        let e = check_folder(&d.join("out"), &["figure.png"], &Inputs::none()).unwrap_err();
        assert!(matches!(e, OutputError::IsFolder { .. }), "{e}");
        assert!(check_folder(&d.join("new/deeper"), &["a.csv"], &Inputs::none()).is_ok());
        assert!(!d.join("new").exists());
        let e = check_file(&d.join("nodir/x.gif"), &Inputs::none()).unwrap_err();
        assert!(e.to_string().contains("nodir"), "{e}");
    }

    #[test]
    fn a_replaced_file_keeps_its_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let d = temp_dir("mode");
        let f = d.join("private.csv");
        std::fs::write(&f, "old").unwrap();
        std::fs::set_permissions(&f, std::fs::Permissions::from_mode(0o600)).unwrap();
        write_bytes(&f, b"new", &Inputs::none()).unwrap();
        assert_eq!(std::fs::read(&f).unwrap(), b"new");
        assert_eq!(
            std::fs::metadata(&f).unwrap().permissions().mode() & 0o777,
            0o600
        );
    }

    #[test]
    fn a_dropped_output_leaves_nothing_and_the_old_file_whole() {
        let d = temp_dir("drop");
        std::fs::write(d.join("keep.csv"), "old").unwrap();
        let mut f = OutputFile::create(&d.join("keep.csv"), &Inputs::none()).unwrap();
        f.write_bytes(b"half").unwrap();
        drop(f);
        assert_eq!(std::fs::read(d.join("keep.csv")).unwrap(), b"old");
        assert!(leftovers(&d).is_empty(), "{:?}", leftovers(&d));
    }
}
