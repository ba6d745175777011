//! PNG files out of the renderer's frames: a pool of writer threads fed through a bounded
//! channel, so encoding overlaps rendering (headless frames, the app's recording), and the
//! frames' file names. No GPU: plain images in, files out. Imports nothing else of the crate.

use std::path::PathBuf;
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use image::RgbaImage;
use thiserror::Error;

/// Why frames could not be written.
#[derive(Debug, Error)]
pub enum PngError {
    /// Encoding or writing one file failed.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// What the encoder or the file system said.
        source: image::ImageError,
    },
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
    /// `threads` writers (at least 1).
    pub fn new(threads: usize) -> Self {
        let (sender, receiver) = mpsc::sync_channel::<(PathBuf, RgbaImage)>(4);
        let receiver = Arc::new(Mutex::new(receiver));
        let workers = (0..threads.max(1))
            .map(|_| {
                let rx = receiver.clone();
                std::thread::spawn(move || -> Result<(), PngError> {
                    loop {
                        let job = match rx.lock() {
                            Ok(guard) => guard.recv(),
                            Err(_) => return Err(PngError::Stopped { panicked: true }),
                        };
                        let Ok((path, image)) = job else {
                            return Ok(());
                        };
                        if let Err(source) = image.save_with_format(&path, image::ImageFormat::Png)
                        {
                            return Err(PngError::Write { path, source });
                        }
                    }
                })
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

/// The file name of frame `k`.
pub fn frame_name(k: u64) -> String {
    format!("frame_{k:05}.png")
}
