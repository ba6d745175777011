//! PNG files out of the renderer's frames: a pool of writer threads fed through a bounded
//! channel, so encoding overlaps rendering (headless frames, the app's recording), and the
//! frames' file names. No GPU: plain images in, files out through the output layer
//! ([`crate::output`], the only module of the crate it imports).

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use image::RgbaImage;
use thiserror::Error;

use crate::output::{self, Inputs, OutputError, OutputSet};

/// Why frames could not be written.
#[derive(Debug, Error)]
pub enum PngError {
    /// Encoding one frame failed.
    #[error("cannot encode {} as PNG: {error}", path.display())]
    Encode {
        /// The file.
        path: PathBuf,
        /// What the encoder said.
        error: image::ImageError,
    },
    /// Writing one file failed (or it is one of the command's inputs).
    #[error(transparent)]
    Write(#[from] OutputError),
    /// A writer thread stopped without saying why (it could not start, or it panicked).
    #[error("a PNG writer stopped early{}", if *panicked { " (it panicked)" } else { " (no writer thread could start)" })]
    Stopped {
        /// Whether it panicked.
        panicked: bool,
    },
}

/// A pool of PNG writer threads fed through a bounded channel. Each frame is encoded and staged
/// beside its destination as it comes; [`PngWriter::close`] moves them all into place as one
/// [`OutputSet`], so a folder of frames holds the old set or the new one, never a mix (a full
/// disk at frame 5 of 30 leaves frames 0–29 as they were).
pub struct PngWriter {
    sender: Option<mpsc::SyncSender<(PathBuf, RgbaImage)>>,
    workers: Vec<JoinHandle<Result<OutputSet, PngError>>>,
}

impl PngWriter {
    /// `threads` writers (at least 1); no frame may overwrite one of `inputs`.
    pub fn new(threads: usize, inputs: Inputs) -> Self {
        let inputs = Arc::new(inputs);
        let (sender, receiver) = mpsc::sync_channel::<(PathBuf, RgbaImage)>(4);
        let receiver = Arc::new(Mutex::new(receiver));
        let workers = (0..threads.max(1))
            .filter_map(|k| {
                let rx = receiver.clone();
                let inputs = inputs.clone();
                // A writer that cannot start leaves the others; with none, `write` reports the
                // pool as stopped.
                std::thread::Builder::new()
                    .name(format!("png writer {k}"))
                    .spawn(move || -> Result<OutputSet, PngError> {
                        let mut staged = OutputSet::new();
                        loop {
                            let job = match rx.lock() {
                                Ok(guard) => guard.recv(),
                                Err(_) => return Err(PngError::Stopped { panicked: true }),
                            };
                            let Ok((path, image)) = job else {
                                return Ok(staged);
                            };
                            staged.write(&path, &encode_png(&path, &image)?, &inputs)?;
                        }
                    })
                    .ok()
            })
            .collect();
        Self {
            sender: Some(sender),
            workers,
        }
    }

    /// Queues one image (blocks while the queue is full). If the writers have stopped, their
    /// error is returned (a full disk, a frame that is an input), not just that they stopped.
    pub fn write(&mut self, path: PathBuf, image: RgbaImage) -> Result<(), PngError> {
        let sent = match self.sender.as_ref() {
            Some(sender) => sender.send((path, image)).is_ok(),
            None => false,
        };
        if sent {
            return Ok(());
        }
        self.sender = None;
        Err(self
            .join_workers()
            .err()
            .unwrap_or(PngError::Stopped { panicked: false }))
    }

    /// Waits for every queued image, then moves every frame into place together; the first
    /// error wins, and then no frame is moved.
    pub fn close(mut self) -> Result<(), PngError> {
        self.sender = None;
        self.join_workers()?.commit()?;
        Ok(())
    }

    /// Joins the writers, merging what they staged.
    fn join_workers(&mut self) -> Result<OutputSet, PngError> {
        let mut all = OutputSet::new();
        let mut first_error = None;
        for w in self.workers.drain(..) {
            match w.join() {
                Ok(Ok(set)) => all.extend(set),
                Ok(Err(e)) => {
                    first_error.get_or_insert(e);
                }
                Err(_) => {
                    first_error.get_or_insert(PngError::Stopped { panicked: true });
                }
            }
        }
        match first_error {
            Some(e) => Err(e),
            None => Ok(all),
        }
    }
}

/// `image` as PNG bytes (`path` names it in an error).
fn encode_png(path: &Path, image: &RgbaImage) -> Result<Vec<u8>, PngError> {
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .map_err(|error| PngError::Encode {
            path: path.to_path_buf(),
            error,
        })?;
    Ok(bytes)
}

/// Writes `image` as a PNG file at `path` through the output layer.
pub fn write_png(path: &Path, image: &RgbaImage, inputs: &Inputs) -> Result<(), PngError> {
    Ok(output::write_bytes(
        path,
        &encode_png(path, image)?,
        inputs,
    )?)
}

/// The file name of frame `k`.
pub fn frame_name(k: u64) -> String {
    format!("frame_{k:05}.png")
}
