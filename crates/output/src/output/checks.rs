//! The checks made before anything is written: two outputs that name one file, what kind of
//! place a path is (standard output, a device written through, a file staged and moved), a
//! file or folder this user cannot write, and the folders an output set needs.

use super::*;

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
pub(super) enum Place {
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

pub(super) fn place_of(path: &Path) -> Result<Place> {
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
pub(super) fn probe_writable(dir: &Path, named: &Path) -> Result<()> {
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
