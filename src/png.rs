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

use crate::output::{self, Inputs, OutputError};

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
    /// A writer thread stopped (after an error, reported by [`PngWriter::close`]) or panicked.
    #[error("a PNG writer stopped early{}", if *panicked { " (it panicked)" } else { "; see the error that follows" })]
    Stopped {
        /// Whether it panicked.
        panicked: bool,
    },
}

/// A pool of PNG writer threads fed through a bounded channel.
pub struct PngWriter {
    sender: Option<mpsc::SyncSender<(PathBuf, RgbaImage)>>,
    workers: Vec<JoinHandle<Result<(), PngError>>>,
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
                    .spawn(move || -> Result<(), PngError> {
                        loop {
                            let job = match rx.lock() {
                                Ok(guard) => guard.recv(),
                                Err(_) => return Err(PngError::Stopped { panicked: true }),
                            };
                            let Ok((path, image)) = job else {
                                return Ok(());
                            };
                            write_png(&path, &image, &inputs)?;
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

    /// Queues one image (blocks while the queue is full).
    pub fn write(&self, path: PathBuf, image: RgbaImage) -> Result<(), PngError> {
        self.sender
            .as_ref()
            .ok_or(PngError::Stopped { panicked: false })?
            .send((path, image))
            .map_err(|_| PngError::Stopped { panicked: false })
    }

    /// Waits for every queued image to be written; the first error wins.
    pub fn close(mut self) -> Result<(), PngError> {
        self.sender = None;
        for w in self.workers.drain(..) {
            w.join()
                .map_err(|_| PngError::Stopped { panicked: true })??;
        }
        Ok(())
    }
}

/// Writes `image` as a PNG file at `path` through the output layer.
pub fn write_png(path: &Path, image: &RgbaImage, inputs: &Inputs) -> Result<(), PngError> {
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
    Ok(output::write_bytes(path, &bytes, inputs)?)
}

/// The file name of frame `k`.
pub fn frame_name(k: u64) -> String {
    format!("frame_{k:05}.png")
}
