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

mod checks;
mod commit;
mod interrupt;
mod paths;

pub use checks::*;
pub use commit::*;
pub use interrupt::*;
pub use paths::*;

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
