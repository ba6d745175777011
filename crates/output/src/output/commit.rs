//! Files committed together: each staged whole, then moved into place under an advisory lock on
//! every destination's folder, and put back if a later move fails.

use super::*;

/// Files that are committed together: all staged whole, then moved into place; a failed move
/// puts back those already moved.
#[derive(Default)]
pub struct OutputSet {
    pub(super) files: Vec<OutputFile>,
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
pub(super) struct DestinationLocks {
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
pub(super) struct Undo {
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

pub(super) fn move_into_place(temp: &Path, destination: &Path, in_place: bool) -> io::Result<Undo> {
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
