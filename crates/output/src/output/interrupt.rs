//! The files being written now and what an interrupt does with them: the staging names beside
//! each destination, the set of partial files that Ctrl-C removes, and the lock a commit holds so
//! that an interrupt never lands mid-move.

use super::*;

/// Tells apart the temporary files of one process.
pub(super) static NEXT_TEMP: AtomicU64 = AtomicU64::new(0);

/// Held by a commit while it moves files into place (and puts them back on failure), and by
/// [`remove_partial_outputs`], so an interrupt never lands mid-move.
pub(super) static COMMITTING: Mutex<()> = Mutex::new(());

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
pub(super) static INTERRUPTED: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

/// Whether an interrupt is ending the process: a command that finished meanwhile leaves the
/// exit (and its status, 130) to the interrupt handler rather than exiting with 0.
pub fn interrupt_pending() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

pub(super) fn remember_partial(temp: &Path) {
    PARTIAL_OUTPUTS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .insert(temp.to_path_buf());
}

pub(super) fn forget_partial(temp: &Path) {
    PARTIAL_OUTPUTS
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .remove(temp);
}

/// Bytes of the destination's name kept in a staging name, so that `.NAME.partial-PID-K` fits
/// the 255-byte limit of a file name whatever the destination's legal name.
pub(super) const STAGED_NAME_BYTES: usize = 160;

/// A hidden name beside `destination`, unique in this process: `.NAME.partial-PID-K` (NAME cut
/// to [`STAGED_NAME_BYTES`]).
pub(super) fn temp_beside(destination: &Path, what: &str) -> PathBuf {
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
