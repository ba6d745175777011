//! Where a path really goes: symbolic links followed, and the paths that name one of this
//! process's open descriptors (`-`, `/dev/stdout`, `/dev/fd/N`, `/proc/self/fd/N`).

use super::*;

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
pub(super) fn names_descriptor(p: &Path) -> Option<Descriptor> {
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
