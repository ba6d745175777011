//! Native Open and Save dialogs through `rfd`: on Linux the desktop's file chooser portal over
//! D-Bus (rfd loads libdbus at run time) with zenity as its fallback, elsewhere the system's
//! dialog. Each dialog runs on a thread of its own, so the window keeps drawing (and the
//! simulation keeps running) while it is open; the files panel collects the answer on a later
//! frame. Where no dialog can appear (Linux with neither a D-Bus session bus nor zenity: a
//! server, CI, a bare X session) [`FileDialogs::availability`] says why, and the panel keeps to
//! its path fields.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Receiver, TryRecvError};

/// What a dialog is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DialogPurpose {
    /// Open a scene (.toml).
    OpenScene,
    /// Save the scene (.toml).
    SaveScene,
    /// Open a shape (.json).
    OpenShape,
    /// Save the body's shape (.json).
    SaveShape,
}

impl DialogPurpose {
    fn saves(self) -> bool {
        matches!(self, DialogPurpose::SaveScene | DialogPurpose::SaveShape)
    }

    fn filter(self) -> (&'static str, &'static [&'static str]) {
        match self {
            DialogPurpose::OpenScene | DialogPurpose::SaveScene => ("rollphase scene", &["toml"]),
            DialogPurpose::OpenShape => {
                ("rollphase shape or a mesh", &["json", "stl", "obj", "ply"])
            }
            DialogPurpose::SaveShape => ("rollphase shape", &["json"]),
        }
    }

    fn title(self) -> &'static str {
        match self {
            DialogPurpose::OpenScene => "Open a scene",
            DialogPurpose::SaveScene => "Save the scene",
            DialogPurpose::OpenShape => "Open a shape",
            DialogPurpose::SaveShape => "Save the body's shape",
        }
    }
}

/// Whether a native dialog can appear, given what the environment offers (Linux): the portal
/// needs a D-Bus session bus, and rfd falls back to zenity without one.
pub fn availability(session_bus: bool, zenity: bool) -> Result<(), String> {
    if session_bus || zenity {
        Ok(())
    } else {
        Err(
            "no file dialog here: no D-Bus session bus to reach the desktop's file chooser, \
             and no zenity"
                .into(),
        )
    }
}

/// The app's file dialogs: at most one open at a time.
pub struct FileDialogs {
    availability: Result<(), String>,
    pending: Option<(DialogPurpose, Receiver<Option<PathBuf>>)>,
}

impl FileDialogs {
    /// Dialogs as this machine offers them.
    pub fn detect() -> Self {
        Self {
            availability: detect_availability(),
            pending: None,
        }
    }

    /// `Ok` where a dialog can appear, else why not (one line for the files panel).
    pub fn availability(&self) -> Result<(), &str> {
        self.availability
            .as_ref()
            .map(|_| ())
            .map_err(String::as_str)
    }

    /// A dialog is open.
    pub fn is_open(&self) -> bool {
        self.pending.is_some()
    }

    /// Opens a dialog for `purpose`, starting in the folder of `current` (the path field's
    /// value) with its file name suggested when saving. Does nothing while one is open.
    pub fn open(&mut self, purpose: DialogPurpose, current: &Path) {
        if self.pending.is_some() || self.availability.is_err() {
            return;
        }
        let (name, extensions) = purpose.filter();
        let mut dialog = rfd::FileDialog::new()
            .set_title(purpose.title())
            .add_filter(name, extensions);
        let folder = match current.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => std::env::current_dir().unwrap_or_default(),
        };
        dialog = dialog.set_directory(folder);
        if purpose.saves()
            && let Some(file) = current.file_name()
        {
            dialog = dialog.set_file_name(file.to_string_lossy());
        }
        let (tx, rx) = mpsc::channel();
        // A dialog that cannot start answers "cancelled": the sender is dropped with the closure.
        let _ = std::thread::Builder::new()
            .name("file dialog".into())
            .spawn(move || {
                let chosen = if purpose.saves() {
                    dialog.save_file()
                } else {
                    dialog.pick_file()
                };
                let _ = tx.send(chosen);
            });
        self.pending = Some((purpose, rx));
    }

    /// What the open dialog answered, once it has: `Some((purpose, Some(path)))` for a chosen
    /// file, `Some((purpose, None))` when it was cancelled or could not be shown.
    pub fn poll(&mut self) -> Option<(DialogPurpose, Option<PathBuf>)> {
        let (purpose, rx) = self.pending.as_ref()?;
        let answer = match rx.try_recv() {
            Ok(chosen) => chosen,
            Err(TryRecvError::Empty) => return None,
            Err(TryRecvError::Disconnected) => None,
        };
        let purpose = *purpose;
        self.pending = None;
        Some((purpose, answer))
    }

    /// For the tests: stands in for a dialog that answered `chosen`, so the panel's handling
    /// of the answer runs as it does after a real one.
    #[doc(hidden)]
    pub fn answer(&mut self, purpose: DialogPurpose, chosen: Option<PathBuf>) {
        let (tx, rx) = mpsc::channel();
        let _ = tx.send(chosen);
        self.pending = Some((purpose, rx));
    }
}

/// On Linux and the BSDs a dialog needs the portal's session bus or zenity; elsewhere the
/// system always has one.
fn detect_availability() -> Result<(), String> {
    let portal_platform = cfg!(any(
        target_os = "linux",
        target_os = "freebsd",
        target_os = "dragonfly",
        target_os = "netbsd",
        target_os = "openbsd"
    ));
    if !portal_platform {
        return Ok(());
    }
    let session_bus = std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_some_and(|v| !v.is_empty())
        || std::env::var_os("XDG_RUNTIME_DIR")
            .is_some_and(|dir| Path::new(&dir).join("bus").exists());
    let zenity = std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|dir| dir.join("zenity").is_file()));
    availability(session_bus, zenity)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dialog_needs_a_session_bus_or_zenity() {
        assert!(availability(true, false).is_ok());
        assert!(availability(false, true).is_ok());
        let why = availability(false, false).unwrap_err();
        assert!(why.contains("D-Bus") && why.contains("zenity"), "{why}");
    }

    #[test]
    fn an_answer_is_collected_once() {
        let mut d = FileDialogs {
            availability: Ok(()),
            pending: None,
        };
        assert_eq!(d.poll(), None);
        d.answer(DialogPurpose::SaveShape, Some(PathBuf::from("a.json")));
        assert!(d.is_open());
        assert_eq!(
            d.poll(),
            Some((DialogPurpose::SaveShape, Some(PathBuf::from("a.json"))))
        );
        assert!(!d.is_open());
        assert_eq!(d.poll(), None);
    }
}
