//! The one output layer: every byte rollphase writes to a file goes through here, so the promise
//! "output files are never damaged" is kept by structure rather than writer by writer
//! (`tests/command_line/output_layer.rs` fails if any other module creates, writes, renames or saves a file).
//!
//! - `-` is standard output. A path that names one of this process's open descriptors
//!   (`/dev/stdout`, `/dev/stderr`, `/dev/fd/N`, `/proc/self/fd/N`, through any links) is written
//!   through that descriptor, never replaced: `-o /proc/self/fd/1 >> log.txt` appends to the log
//!   as `-` would ([`descriptor_of`], [`is_standard_output`]).
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
//!   [`check_file`] and [`check_folder`] let a command do that before its first expensive step,
//!   and [`check_distinct`] that no two of its outputs name one file.
//! - A regular file that this user may not write (mode 0444 as a non-root user) is refused, as
//!   a shell's `>` refuses it, rather than replaced by a rename.
//! - Commits are serialised per destination: each [`OutputSet::commit`] holds an advisory lock
//!   (`flock`) on every destination's folder, and on a file rewritten in place, so two commands
//!   writing one folder or one file leave one command's set, never a mix.
//! - A commit is one critical section with the interrupt handler: [`remove_partial_outputs`]
//!   waits for a commit under way (which restores the old files if it fails) and then keeps any
//!   other from starting, so Ctrl-C never cuts a file mid-copy or removes the backup it needs.
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
    /// Two outputs of one command are one file.
    #[error("{first} and {second} both name {place}; give each output its own file")]
    Collide {
        /// The first output's flag (or name).
        first: String,
        /// The second output's flag (or name).
        second: String,
        /// The file as the second named it, or "standard output".
        place: String,
    },
    /// The folder an output goes into takes no new files (read-only, or no permission).
    #[error(
        "cannot write {}: its folder {} takes no new files ({error}); rollphase writes a new \
         file beside the old one and moves it into place, so the folder must be writable",
        path.display(), folder.display()
    )]
    FolderNotWritable {
        /// The output as given.
        path: PathBuf,
        /// Its folder.
        folder: PathBuf,
        /// What the OS said.
        error: io::Error,
    },
    /// A folder named by a symbolic link whose target does not exist.
    #[error(
        "{} is a link to {}, which does not exist; make that folder, or give another",
        path.display(), target.display()
    )]
    DanglingFolderLink {
        /// The link.
        path: PathBuf,
        /// Where it points.
        target: PathBuf,
    },
    /// Standard output refused (a closed pipe, a full disk behind it).
    #[error("cannot write to standard output: {0}")]
    Stdout(io::Error),
    /// Standard error refused.
    #[error("cannot write to standard error: {0}")]
    Stderr(io::Error),
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
            Self::Stdout(e) | Self::Stderr(e) | Self::Io { error: e, .. } => {
                e.kind() == io::ErrorKind::BrokenPipe
            }
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
/// A set, not a list: a run that stages a million frames forgets each in constant time.
static PARTIAL_OUTPUTS: std::sync::LazyLock<Mutex<std::collections::HashSet<PathBuf>>> =
    std::sync::LazyLock::new(|| Mutex::new(std::collections::HashSet::new()));

/// The scratch folders alive now ([`ScratchFolder`]), removed with the partial outputs on Ctrl-C.
static SCRATCH_FOLDERS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// A folder of scratch files in the system's temporary folder (a benchmark's frames): removed
/// with everything in it when dropped, and by [`remove_partial_outputs`] on Ctrl-C, so nothing
/// is left behind either way.
pub struct ScratchFolder {
    path: PathBuf,
}

impl ScratchFolder {
    /// Creates `TMP/rollphase-WHAT-PID-K`.
    pub fn create(what: &str) -> Result<Self> {
        let k = NEXT_TEMP.fetch_add(1, Ordering::Relaxed);
        let path =
            std::env::temp_dir().join(format!("rollphase-{what}-{}-{k}", std::process::id()));
        SCRATCH_FOLDERS
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(path.clone());
        let made = std::fs::create_dir_all(&path).map_err(|e| OutputError::io(&path, e));
        let folder = Self { path };
        made.map(|()| folder)
    }

    /// Where it is.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for ScratchFolder {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.path);
        SCRATCH_FOLDERS
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .retain(|p| *p != self.path);
    }
}

/// Tells apart the temporary files of one process.
static NEXT_TEMP: AtomicU64 = AtomicU64::new(0);

/// Held by a commit while it moves files into place (and puts them back on failure), and by
/// [`remove_partial_outputs`], so an interrupt never lands mid-move.
static COMMITTING: Mutex<()> = Mutex::new(());

/// Removes every output still being written (called from the Ctrl-C handler in `main.rs`, just
/// before the process exits). A commit under way is waited for, so the files it moves are whole
/// (all new, or all old if it failed), and no commit starts afterwards: the process is ending.
/// Returns whether it waited for a commit (whose files are then complete and in place).
pub fn remove_partial_outputs() -> Interrupted {
    INTERRUPTED.store(true, Ordering::SeqCst);
    let (commits, waited) = match COMMITTING.try_lock() {
        Ok(guard) => (guard, false),
        Err(std::sync::TryLockError::Poisoned(e)) => (e.into_inner(), false),
        Err(std::sync::TryLockError::WouldBlock) => {
            (COMMITTING.lock().unwrap_or_else(|e| e.into_inner()), true)
        }
    };
    // Held until the process exits: a commit the command starts after this would race the exit.
    std::mem::forget(commits);
    let files = PARTIAL_OUTPUTS.lock().unwrap_or_else(|e| e.into_inner());
    for f in files.iter() {
        let _ = std::fs::remove_file(f);
    }
    let folders = SCRATCH_FOLDERS.lock().unwrap_or_else(|e| e.into_inner());
    for d in folders.iter() {
        let _ = std::fs::remove_dir_all(d);
    }
    if waited {
        Interrupted::AfterCommit
    } else {
        Interrupted::BeforeCommit
    }
}

/// Where an interrupt found the command's outputs ([`remove_partial_outputs`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interrupted {
    /// Nothing was being moved into place: every destination keeps its old contents.
    BeforeCommit,
    /// A commit was under way and was let finish: its files are complete, with new contents.
    AfterCommit,
}

impl Interrupted {
    /// The line a command prints on an interrupt.
    pub fn message(self) -> &'static str {
        match self {
            Interrupted::BeforeCommit => "interrupted; no partial output was left",
            Interrupted::AfterCommit => {
                "interrupted while the output was being moved into place; it was let finish, \
                 so the files written are complete, and no partial output was left"
            }
        }
    }
}

/// Set by [`remove_partial_outputs`]: the process is ending on an interrupt.
static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether an interrupt is ending the process: a command that finished meanwhile leaves the
/// exit (and its status, 130) to the interrupt handler rather than exiting with 0.
pub fn interrupt_pending() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

fn remember_partial(temp: &Path) {
    PARTIAL_OUTPUTS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(temp.to_path_buf());
}

fn forget_partial(temp: &Path) {
    PARTIAL_OUTPUTS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .remove(temp);
}

/// Bytes of the destination's name kept in a staging name, so that `.NAME.partial-PID-K` fits
/// the 255-byte limit of a file name whatever the destination's legal name.
const STAGED_NAME_BYTES: usize = 160;

/// A hidden name beside `destination`, unique in this process: `.NAME.partial-PID-K` (NAME cut
/// to [`STAGED_NAME_BYTES`]).
fn temp_beside(destination: &Path, what: &str) -> PathBuf {
    let mut name = destination
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    if name.len() > STAGED_NAME_BYTES {
        let mut cut = STAGED_NAME_BYTES;
        while !name.is_char_boundary(cut) {
            cut -= 1;
        }
        name.truncate(cut);
    }
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
    // A bare name's folder is the working folder, so `run.csv` and `./run.csv` are one place.
    match (p.parent(), p.file_name()) {
        (Some(dir), Some(name)) => {
            let dir = if dir.as_os_str().is_empty() {
                Path::new(".")
            } else {
                dir
            };
            std::fs::canonicalize(dir)
                .map(|d| d.join(name))
                .unwrap_or(p)
        }
        _ => p,
    }
}

/// One of this process's open descriptors, named by a path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Descriptor {
    /// Its number.
    pub fd: u32,
    /// Whether it is this process's (`self`, or this process's id), not another's.
    pub own: bool,
}

/// The descriptor `path` names, if any: `/dev/stdin`, `/dev/stdout`, `/dev/stderr`, `/dev/fd/N`
/// or `/proc/(self|thread-self|PID)[/task/TID]/fd/N`, as given or through links (of the path or
/// of its folder). Such a path opened and renamed over would replace the file behind the
/// descriptor (a shell's redirection target); it is written through instead.
pub fn descriptor_of(path: &Path) -> Option<Descriptor> {
    let mut p = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().ok()?.join(path)
    };
    for _ in 0..40 {
        if let Some(d) = names_descriptor(&p) {
            return Some(d);
        }
        if let (Some(dir), Some(name)) = (p.parent(), p.file_name())
            && let Ok(real_dir) = std::fs::canonicalize(dir)
            && let Some(d) = names_descriptor(&real_dir.join(name))
        {
            return Some(d);
        }
        let next = std::fs::read_link(&p).ok()?;
        p = match p.parent() {
            Some(dir) if next.is_relative() => dir.join(next),
            _ => next,
        };
    }
    None
}

/// [`descriptor_of`] on the path's text alone.
fn names_descriptor(p: &Path) -> Option<Descriptor> {
    let text = p.to_str()?;
    let own = |fd| Some(Descriptor { fd, own: true });
    match text {
        "/dev/stdin" => return own(0),
        "/dev/stdout" => return own(1),
        "/dev/stderr" => return own(2),
        _ => {}
    }
    if let Some(n) = text.strip_prefix("/dev/fd/") {
        return own(n.parse().ok()?);
    }
    let parts: Vec<&str> = text.strip_prefix("/proc/")?.split('/').collect();
    let (who, fd) = match parts.as_slice() {
        [who, "fd", n] | [who, "task", _, "fd", n] => (*who, n.parse().ok()?),
        _ => return None,
    };
    let pid = std::process::id().to_string();
    let own = who == "self" || who == "thread-self" || who == pid;
    if !own && who.parse::<u32>().is_err() {
        return None;
    }
    Some(Descriptor { fd, own })
}

/// Whether `path` is this process's standard output: `-`, or a path naming descriptor 1. A
/// command that writes data there sends its status lines to standard error.
pub fn is_standard_output(path: &Path) -> bool {
    path.as_os_str() == "-" || descriptor_of(path).is_some_and(|d| d.own && d.fd == 1)
}

/// Refuses two outputs of one command that are one file: the same path after links, or two names
/// of one file, or two uses of standard output (`-`, `/dev/stdout`, …). A character device (the
/// null device) may take several. `outputs` are (flag, path) in the order the command takes them.
pub fn check_distinct(outputs: &[(&str, &Path)]) -> Result<()> {
    use std::os::unix::fs::FileTypeExt;
    // (flag, where it lands, device and inode if it exists)
    type Seen<'a> = (&'a str, PathBuf, Option<(u64, u64)>);
    let mut seen: Vec<Seen> = Vec::new();
    for &(flag, path) in outputs {
        if std::fs::metadata(path).is_ok_and(|m| m.file_type().is_char_device()) {
            continue;
        }
        let real = if is_standard_output(path) {
            PathBuf::from("-")
        } else if let Some(d) = descriptor_of(path) {
            PathBuf::from(format!(
                "/proc/{}/fd/{}",
                if d.own { "self" } else { "other" },
                d.fd
            ))
        } else {
            real_path(path)
        };
        let id = std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()));
        if let Some((first, ..)) = seen
            .iter()
            .find(|(_, r, i)| *r == real || (id.is_some() && *i == id))
        {
            let place = if real.as_os_str() == "-" {
                "standard output".to_string()
            } else {
                path.display().to_string()
            };
            return Err(OutputError::Collide {
                first: (*first).to_string(),
                second: flag.to_string(),
                place,
            });
        }
        seen.push((flag, real, id));
    }
    Ok(())
}

/// What kind of place an output path is.
enum Place {
    Stdout,
    Stderr,
    /// A device, FIFO or socket, or another open descriptor: written through.
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
    match descriptor_of(path) {
        Some(Descriptor { fd: 1, own: true }) => return Ok(Place::Stdout),
        Some(Descriptor { fd: 2, own: true }) => return Ok(Place::Stderr),
        Some(_) => return Ok(Place::Direct),
        None => {}
    }
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(OutputError::IsFolder {
            path: path.to_path_buf(),
        }),
        Ok(m) if !m.is_file() => Ok(Place::Direct),
        Ok(m) => {
            // As `>` would: a file this user may not write is refused, not renamed over.
            // (Opened without truncation, so nothing changes.)
            if let Err(e) = OpenOptions::new().write(true).open(path) {
                return Err(OutputError::io(path, e));
            }
            Ok(Place::Staged {
                destination: real_path(path),
                in_place: m.nlink() > 1,
            })
        }
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(Place::Staged {
            destination: real_path(path),
            in_place: false,
        }),
        Err(e) => Err(OutputError::io(path, e)),
    }
}

/// Checks, before a command's expensive work, that `path` can be written: not one of `inputs`,
/// not a folder, and its folder exists and takes new files (the output is staged there). Only a
/// probe file is made and removed at once.
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
        probe_writable(&dir, path)?;
    }
    Ok(())
}

/// Whether new files can be made in the folder `dir` (for the output `named`): a probe file is
/// created and removed. A read-only folder or file system is found here, before the work,
/// rather than when the finished output is staged.
fn probe_writable(dir: &Path, named: &Path) -> Result<()> {
    let k = NEXT_TEMP.fetch_add(1, Ordering::Relaxed);
    let probe = dir.join(format!(".rollphase-probe-{}-{k}", std::process::id()));
    match OpenOptions::new().write(true).create_new(true).open(&probe) {
        Ok(f) => {
            drop(f);
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(OutputError::FolderNotWritable {
            path: named.to_path_buf(),
            folder: dir.to_path_buf(),
            error: e,
        }),
    }
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
                // A link to nowhere: making the folder would fail with "File exists", after
                // the work.
                if std::fs::symlink_metadata(existing).is_ok_and(|m| m.file_type().is_symlink()) {
                    return Err(OutputError::DanglingFolderLink {
                        path: existing.to_path_buf(),
                        target: std::fs::read_link(existing).unwrap_or_default(),
                    });
                }
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
    // The folder the files go into, or the nearest one that exists (where it will be made; a
    // relative path with no existing part is made in the working folder).
    if !std::fs::metadata(existing).is_ok_and(|m| m.is_dir()) {
        existing = Path::new(".");
    }
    probe_writable(existing, dir)?;
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
    Stderr,
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
            Place::Stderr => (Target::Stderr, Box::new(io::stderr())),
            Place::Direct => {
                // Appending: a descriptor path reopens its file, which must not be cut or
                // written over from its start (a log opened with `>>`); a device or FIFO is the
                // same either way.
                let append = descriptor_of(path).is_some();
                let file = OpenOptions::new()
                    .write(true)
                    .append(append)
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
            Target::Stderr => OutputError::Stderr(e),
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

    /// Adds every file of `other` (staged by another thread, say) to this set.
    pub fn extend(&mut self, other: OutputSet) {
        self.files.extend(other.files);
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
        let _locks = DestinationLocks::take(&self.files);
        // An interrupt waits for the moves (and their undoing) to end; see `remove_partial_outputs`.
        let _committing = COMMITTING.lock().unwrap_or_else(|e| e.into_inner());
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

/// Advisory locks (`flock`) on every folder a set moves files into, and on each file it rewrites
/// in place, taken in one order (by device and inode) so two commits never wait on each other in
/// a circle; released when dropped. A place that cannot be opened for a lock (a folder without
/// read permission) is committed unlocked, as before.
struct DestinationLocks {
    /// Held, not read: closing a file releases its lock.
    _held: Vec<File>,
}

impl DestinationLocks {
    fn take(files: &[OutputFile]) -> Self {
        let mut places: Vec<PathBuf> = Vec::new();
        for f in files {
            if let Target::Staged {
                destination,
                in_place,
                ..
            } = &f.target
            {
                let dir = match destination.parent() {
                    Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
                    _ => PathBuf::from("."),
                };
                places.push(dir);
                if *in_place {
                    places.push(destination.clone());
                }
            }
        }
        let mut opened: Vec<((u64, u64), File)> = places
            .iter()
            .filter_map(|p| {
                let f = File::open(p).ok()?;
                let m = f.metadata().ok()?;
                Some(((m.dev(), m.ino()), f))
            })
            .collect();
        opened.sort_by_key(|(id, _)| *id);
        opened.dedup_by_key(|(id, _)| *id);
        let locked = opened
            .into_iter()
            .filter_map(|(_, f)| f.lock().ok().map(|()| f))
            .collect();
        Self { _held: locked }
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
    fn descriptor_paths_are_recognised_through_links() {
        let d = temp_dir("descriptors");
        assert_eq!(
            descriptor_of(Path::new("/dev/stdout")),
            Some(Descriptor { fd: 1, own: true })
        );
        assert_eq!(
            descriptor_of(Path::new("/proc/self/fd/2")),
            Some(Descriptor { fd: 2, own: true })
        );
        let own_pid = format!("/proc/{}/fd/7", std::process::id());
        assert_eq!(
            descriptor_of(Path::new(&own_pid)),
            Some(Descriptor { fd: 7, own: true })
        );
        // A link to the descriptor folder, and a link to a descriptor.
        std::os::unix::fs::symlink("/proc/self/fd", d.join("fds")).unwrap();
        assert_eq!(
            descriptor_of(&d.join("fds").join("1")),
            Some(Descriptor { fd: 1, own: true })
        );
        std::os::unix::fs::symlink("/dev/stderr", d.join("err")).unwrap();
        assert_eq!(
            descriptor_of(&d.join("err")),
            Some(Descriptor { fd: 2, own: true })
        );
        assert!(is_standard_output(Path::new("-")));
        assert!(is_standard_output(Path::new("/dev/fd/1")));
        assert!(!is_standard_output(Path::new("/dev/null")));
        assert_eq!(descriptor_of(Path::new("/dev/null")), None);
        assert_eq!(descriptor_of(&d.join("plain.csv")), None);
    }

    #[test]
    fn a_descriptor_path_appends_through_the_descriptor_instead_of_replacing_its_file() {
        use std::os::fd::AsRawFd;
        let d = temp_dir("descriptor-write");
        let log = d.join("log.txt");
        std::fs::write(&log, "IMPORTANT\n").unwrap();
        // As `>> log.txt` would open it for the command.
        let held = OpenOptions::new().append(true).open(&log).unwrap();
        let path = PathBuf::from(format!("/proc/self/fd/{}", held.as_raw_fd()));
        check_file(&path, &Inputs::none()).unwrap();
        write_bytes(&path, b"data\n", &Inputs::none()).unwrap();
        assert_eq!(std::fs::read_to_string(&log).unwrap(), "IMPORTANT\ndata\n");
        drop(held);
        assert!(leftovers(&d).is_empty(), "{:?}", leftovers(&d));
    }

    #[test]
    fn two_outputs_naming_one_file_collide_but_the_null_device_takes_both() {
        let d = temp_dir("collide");
        // A bare name and ./name in the working folder, neither existing yet (nothing is made).
        let bare = format!("rollphase-collide-{}.csv", std::process::id());
        let dotted = format!("./{bare}");
        let e = check_distinct(&[("-o", Path::new(&bare)), ("--summary", Path::new(&dotted))])
            .unwrap_err();
        assert!(matches!(e, OutputError::Collide { .. }), "{e}");
        assert!(
            e.to_string()
                .contains(&format!("-o and --summary both name {dotted}")),
            "{e}"
        );
        assert!(!Path::new(&bare).exists());
        std::fs::write(d.join("a.csv"), "x").unwrap();
        std::fs::hard_link(d.join("a.csv"), d.join("b.csv")).unwrap();
        assert!(
            check_distinct(&[("-o", &d.join("a.csv")), ("--summary", &d.join("b.csv"))]).is_err()
        );
        let e = check_distinct(&[
            ("-o", Path::new("-")),
            ("--summary", Path::new("/dev/stdout")),
        ])
        .unwrap_err();
        assert!(e.to_string().contains("standard output"), "{e}");
        let null = Path::new("/dev/null");
        check_distinct(&[("-o", null), ("--summary", null)]).unwrap();
        check_distinct(&[("-o", &d.join("a.csv")), ("--summary", &d.join("c.csv"))]).unwrap();
    }

    #[test]
    fn a_file_this_user_may_not_write_is_refused_as_a_redirection_refuses_it() {
        use std::os::unix::fs::PermissionsExt;
        let d = temp_dir("read-only");
        let f = d.join("ro.csv");
        std::fs::write(&f, "protected").unwrap();
        std::fs::set_permissions(&f, std::fs::Permissions::from_mode(0o444)).unwrap();
        // What `>` would do: root may write a 0444 file, any other user may not.
        let shell_may = OpenOptions::new().write(true).open(&f).is_ok();
        let ours = write_bytes(&f, b"new", &Inputs::none());
        assert_eq!(ours.is_ok(), shell_may, "{ours:?}");
        if shell_may {
            assert_eq!(std::fs::read(&f).unwrap(), b"new");
        } else {
            assert!(ours.unwrap_err().to_string().contains("ro.csv"));
            assert_eq!(std::fs::read(&f).unwrap(), b"protected");
            assert!(check_file(&f, &Inputs::none()).is_err());
        }
        assert!(leftovers(&d).is_empty(), "{:?}", leftovers(&d));
    }

    #[test]
    fn the_longest_legal_file_name_can_be_staged() {
        let d = temp_dir("long-name");
        let name = format!("{}.csv", "é".repeat(125)); // 254 bytes
        assert_eq!(name.len(), 254);
        write_bytes(&d.join(&name), b"x", &Inputs::none()).unwrap();
        assert_eq!(std::fs::read(d.join(&name)).unwrap(), b"x");
        write_bytes(&d.join(&name), b"again", &Inputs::none()).unwrap();
        assert_eq!(std::fs::read(d.join(&name)).unwrap(), b"again");
        assert!(leftovers(&d).is_empty(), "{:?}", leftovers(&d));
    }

    /// One writer process of the test below: commits sets of three files into
    /// `ROLLPHASE_OUTPUT_WRITER_DIR`, each set's files holding one text.
    #[test]
    #[ignore = "a child process of concurrent_processes_writing_one_folder_leave_one_writers_set"]
    fn concurrent_writer_process() {
        // `cargo test -- --include-ignored` runs it outside its parent test, with no folder to
        // write: nothing to do there (the parent test checks what the writers did).
        let Some(d) = std::env::var_os("ROLLPHASE_OUTPUT_WRITER_DIR").map(PathBuf::from) else {
            return;
        };
        let me = std::process::id();
        for round in 0..30 {
            let text = format!("writer {me} round {round}");
            let mut set = OutputSet::new();
            for name in ["data.csv", "summary.json", "figure.png"] {
                set.write(&d.join(name), text.as_bytes(), &Inputs::none())
                    .unwrap();
            }
            set.commit().unwrap();
        }
    }

    #[test]
    fn concurrent_processes_writing_one_folder_leave_one_writers_set() {
        let d = temp_dir("concurrent");
        let exe = std::env::current_exe().unwrap();
        let children: Vec<_> = (0..4)
            .map(|_| {
                std::process::Command::new(&exe)
                    .args(["--exact", "output::tests::concurrent_writer_process"])
                    .args(["--ignored", "--quiet", "--test-threads=1"])
                    .env("ROLLPHASE_OUTPUT_WRITER_DIR", &d)
                    .spawn()
                    .unwrap()
            })
            .collect();
        for mut c in children {
            assert!(c.wait().unwrap().success());
        }
        let read = |n: &str| std::fs::read_to_string(d.join(n)).unwrap();
        let texts = [read("data.csv"), read("summary.json"), read("figure.png")];
        assert!(texts[0].starts_with("writer"), "{texts:?}");
        assert!(texts.iter().all(|t| *t == texts[0]), "{texts:?}");
        assert!(leftovers(&d).is_empty(), "{:?}", leftovers(&d));
    }

    #[test]
    fn a_set_waits_for_another_process_holding_its_folder() {
        let d = temp_dir("held");
        // Another process's commit, as flock sees it: a lock on the folder by another open file.
        let holder = File::open(&d).unwrap();
        holder.lock().unwrap();
        let (tx, rx) = std::sync::mpsc::channel();
        let writer = {
            let d = d.clone();
            std::thread::spawn(move || {
                let mut set = OutputSet::new();
                set.write(&d.join("a.csv"), b"new", &Inputs::none())
                    .unwrap();
                set.commit().unwrap();
                tx.send(()).unwrap();
            })
        };
        // While the folder is held the set is not moved in.
        assert!(
            rx.recv_timeout(std::time::Duration::from_millis(300))
                .is_err()
        );
        assert!(!d.join("a.csv").exists());
        holder.unlock().unwrap();
        rx.recv().unwrap();
        writer.join().unwrap();
        assert_eq!(std::fs::read(d.join("a.csv")).unwrap(), b"new");
    }

    #[test]
    fn an_unusable_output_folder_is_found_before_the_work() {
        use std::os::unix::fs::PermissionsExt;
        let d = temp_dir("unusable");
        std::os::unix::fs::symlink(d.join("nowhere"), d.join("dangling")).unwrap();
        let e =
            check_folder(&d.join("dangling").join("fig"), &["a.csv"], &Inputs::none()).unwrap_err();
        assert!(matches!(e, OutputError::DanglingFolderLink { .. }), "{e}");
        assert!(e.to_string().contains("nowhere"), "{e}");
        // A folder without write permission: refused up front as a new file there would be
        // (root may write anyway, and then so does the check).
        let ro = d.join("ro");
        std::fs::create_dir(&ro).unwrap();
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
        let can = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(ro.join("try"))
            .is_ok();
        let _ = std::fs::remove_file(ro.join("try"));
        let file_check = check_file(&ro.join("out.csv"), &Inputs::none());
        let folder_check = check_folder(&ro.join("fig"), &["a.csv"], &Inputs::none());
        assert_eq!(file_check.is_ok(), can, "{file_check:?}");
        assert_eq!(folder_check.is_ok(), can, "{folder_check:?}");
        if !can {
            let e = file_check.unwrap_err();
            assert!(e.to_string().contains("takes no new files"), "{e}");
        }
        assert_eq!(
            std::fs::read_dir(&ro).unwrap().count(),
            0,
            "the probe is gone"
        );
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
    }

    #[test]
    fn a_scratch_folder_is_gone_when_dropped() {
        let scratch = ScratchFolder::create("test").unwrap();
        let path = scratch.path().to_path_buf();
        write_bytes(&path.join("frame.png"), b"png", &Inputs::none()).unwrap();
        assert!(path.join("frame.png").is_file());
        drop(scratch);
        assert!(!path.exists());
        assert!(!SCRATCH_FOLDERS.lock().unwrap().contains(&path));
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
