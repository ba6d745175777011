//! Clips out of the renderer's frames, for a slide: an animated GIF (the `image` crate's GIF
//! encoder) or, where `ffmpeg` is on PATH, an H.264 MP4 (frames piped to it as raw RGBA).
//! Encoding runs on a writer thread fed through a bounded channel, so it overlaps rendering.
//! The clip goes through the output layer ([`crate::output`], the only module of the crate it
//! imports): staged and moved into place only when complete, so a failed or interrupted run
//! leaves no half clip, and a device or link is kept. No GPU: images in, a file out.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::thread::JoinHandle;

use image::RgbaImage;
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame};
use thiserror::Error;

use crate::output::{Inputs, OutputError, OutputFile, ProgramOutput};

/// GIF quantisation speed (1 best … 30 fastest); 10 is the gif crate's own suggestion for
/// photos and keeps a 10 s clip at 640×360 to a few seconds of encoding.
const GIF_SPEED: i32 = 10;

/// Why a clip could not be written.
#[derive(Debug, Error)]
pub enum ClipError {
    /// `--mp4` without ffmpeg.
    #[error(
        "--mp4 needs ffmpeg on PATH, and none was found; install it (e.g. `apt install ffmpeg`) or write a GIF with --gif"
    )]
    NoFfmpeg,
    /// The file could not be created, written or moved into place.
    #[error("cannot write {}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the OS said.
        error: std::io::Error,
    },
    /// The GIF encoder failed.
    #[error("cannot encode the GIF {}: {error}", path.display())]
    Gif {
        /// The file.
        path: PathBuf,
        /// What the encoder said.
        error: image::ImageError,
    },
    /// ffmpeg failed.
    #[error("ffmpeg could not write {} (exit status {status}): {stderr}", path.display())]
    Ffmpeg {
        /// The file.
        path: PathBuf,
        /// Its exit status.
        status: String,
        /// The end of what it printed.
        stderr: String,
    },
    /// A frame of another size than the clip's.
    #[error("frame {index} is {got:?} pixels, but the clip is {want:?}")]
    FrameSize {
        /// Which frame.
        index: u64,
        /// Its size.
        got: (u32, u32),
        /// The clip's size.
        want: (u32, u32),
    },
    /// The output layer refused or failed (an input as output, a folder, a full disk).
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The writer thread stopped early (its own error follows from `finish`) or panicked.
    #[error("the clip writer stopped early")]
    Stopped,
}

/// The kinds of clip.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClipKind {
    /// Animated GIF, looping.
    Gif,
    /// H.264 MP4 through ffmpeg.
    Mp4,
}

/// Whether `ffmpeg` can be started.
pub fn ffmpeg_available() -> bool {
    Command::new("ffmpeg")
        .arg("-version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// A clip being written: push frames in order, then [`ClipWriter::finish`].
pub struct ClipWriter {
    sender: Option<mpsc::SyncSender<RgbaImage>>,
    worker: Option<JoinHandle<Result<Option<OutputFile>, ClipError>>>,
    /// The MP4's output, which ffmpeg writes by path.
    program: Option<ProgramOutput>,
    size: (u32, u32),
    pushed: u64,
    path: PathBuf,
}

impl ClipWriter {
    /// Starts a clip of `kind` at `path`, `size` pixels, `fps` frames per second; `path` may
    /// not be one of `inputs`.
    pub fn new(
        kind: ClipKind,
        path: &Path,
        size: (u32, u32),
        fps: f64,
        inputs: &Inputs,
    ) -> Result<Self, ClipError> {
        let (sender, receiver) = mpsc::sync_channel::<RgbaImage>(4);
        let (worker, program) = match kind {
            ClipKind::Gif => {
                let file = OutputFile::create(path, inputs)?;
                let target = path.to_path_buf();
                let worker = std::thread::Builder::new()
                    .name("gif writer".into())
                    .spawn(move || write_gif(file, &target, receiver, fps).map(Some))
                    .map_err(|source| ClipError::Io {
                        path: path.to_path_buf(),
                        error: source,
                    })?;
                (worker, None)
            }
            ClipKind::Mp4 => {
                if !ffmpeg_available() {
                    return Err(ClipError::NoFfmpeg);
                }
                let program = ProgramOutput::create(path, inputs)?;
                let io = |source| ClipError::Io {
                    path: path.to_path_buf(),
                    error: source,
                };
                let child = spawn_ffmpeg(program.path(), size, fps).map_err(io)?;
                let target = path.to_path_buf();
                let worker = std::thread::Builder::new()
                    .name("mp4 writer".into())
                    .spawn(move || write_mp4(child, &target, receiver).map(|()| None))
                    .map_err(io)?;
                (worker, Some(program))
            }
        };
        Ok(Self {
            sender: Some(sender),
            worker: Some(worker),
            program,
            size,
            pushed: 0,
            path: path.to_path_buf(),
        })
    }

    /// Queues the next frame (blocks while the queue is full).
    pub fn push(&mut self, frame: RgbaImage) -> Result<(), ClipError> {
        if frame.dimensions() != self.size {
            return Err(ClipError::FrameSize {
                index: self.pushed,
                got: frame.dimensions(),
                want: self.size,
            });
        }
        self.pushed += 1;
        let sent = self.sender.as_ref().map(|s| s.send(frame));
        if matches!(sent, Some(Ok(()))) {
            return Ok(());
        }
        // The writer stopped: its own error says why.
        self.sender = None;
        match self.worker.take().map(|w| w.join()) {
            Some(Ok(Err(e))) => Err(e),
            _ => Err(ClipError::Stopped),
        }
    }

    /// Frames pushed so far.
    pub fn frames(&self) -> u64 {
        self.pushed
    }

    /// The clip's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Finishes the clip and moves it into place.
    pub fn finish(mut self) -> Result<(), ClipError> {
        self.sender = None;
        let file = match self.worker.take().map(|w| w.join()) {
            Some(Ok(Ok(file))) => file,
            Some(Ok(Err(e))) => return Err(e),
            _ => return Err(ClipError::Stopped),
        };
        if let Some(file) = file {
            file.commit()?;
        }
        if let Some(program) = self.program.take() {
            program.commit()?;
        }
        Ok(())
    }
}

impl Drop for ClipWriter {
    fn drop(&mut self) {
        // Unfinished (an error elsewhere, or Ctrl-C unwinding): stop the writer; the output
        // layer removes the partial file when its handle drops.
        if self.worker.is_some() {
            self.sender = None;
            if let Some(w) = self.worker.take() {
                let _ = w.join();
            }
        }
    }
}

/// Centiseconds shown by frame k at `fps`: rounded on the running total, so the clip keeps
/// time (30 fps alternates 3, 3 and 4 cs) instead of drifting (a constant 3 cs would be 33 fps).
pub fn gif_delay_cs(k: u64, fps: f64) -> u32 {
    let at = |k: u64| (100.0 * k as f64 / fps).round();
    (at(k + 1) - at(k)).max(1.0) as u32
}

fn write_gif(
    mut file: OutputFile,
    path: &Path,
    frames: mpsc::Receiver<RgbaImage>,
    fps: f64,
) -> Result<OutputFile, ClipError> {
    let gif_err = |error| ClipError::Gif {
        path: path.to_path_buf(),
        error,
    };
    let mut encoder = GifEncoder::new_with_speed(&mut file, GIF_SPEED);
    encoder.set_repeat(Repeat::Infinite).map_err(gif_err)?;
    for (k, image) in frames.iter().enumerate() {
        let delay = Delay::from_numer_denom_ms(10 * gif_delay_cs(k as u64, fps), 1);
        encoder
            .encode_frame(Frame::from_parts(image, 0, 0, delay))
            .map_err(gif_err)?;
    }
    drop(encoder);
    Ok(file)
}

/// Bytes of ffmpeg's standard error kept for the message of a failed encode.
const STDERR_TAIL_BYTES: usize = 16 * 1024;

fn spawn_ffmpeg(path: &Path, size: (u32, u32), fps: f64) -> std::io::Result<Child> {
    Command::new("ffmpeg")
        .args([
            "-y",
            "-loglevel",
            "error",
            "-f",
            "rawvideo",
            "-pix_fmt",
            "rgba",
        ])
        .args(["-s", &format!("{}x{}", size.0, size.1)])
        .args(["-r", &format!("{fps}"), "-i", "-"])
        // yuv420p needs even sides; pad by one pixel where they are odd.
        .args(["-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2"])
        .args([
            "-c:v",
            "libx264",
            "-pix_fmt",
            "yuv420p",
            "-movflags",
            "+faststart",
        ])
        .args(["-f", "mp4"])
        .arg(path)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
}

fn write_mp4(
    mut child: Child,
    path: &Path,
    frames: mpsc::Receiver<RgbaImage>,
) -> Result<(), ClipError> {
    let io = |source| ClipError::Io {
        path: path.to_path_buf(),
        error: source,
    };
    // ffmpeg's standard error is read on its own thread while the frames go in: a pipe holds
    // 64 KiB, and an ffmpeg that writes more (warnings per frame) would block on it while we
    // block on its full stdin.
    let stderr_reader = child.stderr.take().map(|mut pipe| {
        std::thread::spawn(move || {
            let mut tail = Vec::new();
            let mut chunk = [0u8; 8192];
            while let Ok(n) = std::io::Read::read(&mut pipe, &mut chunk) {
                if n == 0 {
                    break;
                }
                tail.extend_from_slice(&chunk[..n]);
                // Only the end is shown; keep memory flat however much ffmpeg says.
                if tail.len() > STDERR_TAIL_BYTES * 2 {
                    tail.drain(..tail.len() - STDERR_TAIL_BYTES);
                }
            }
            tail
        })
    });
    if let Some(mut stdin) = child.stdin.take() {
        for image in frames.iter() {
            if let Err(e) = stdin.write_all(image.as_raw()) {
                // ffmpeg quit early; its message (below) says why.
                if e.kind() == std::io::ErrorKind::BrokenPipe {
                    break;
                }
                return Err(io(e));
            }
        }
    }
    let status = child.wait().map_err(io)?;
    let stderr = stderr_reader
        .and_then(|r| r.join().ok())
        .unwrap_or_default();
    if !status.success() {
        let text = String::from_utf8_lossy(&stderr);
        let tail: String = text.lines().rev().take(3).collect::<Vec<_>>().join(" | ");
        return Err(ClipError::Ffmpeg {
            path: path.to_path_buf(),
            status: status.to_string(),
            stderr: tail,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gif_delays_keep_time_at_any_rate() {
        for fps in [10.0, 24.0, 25.0, 30.0, 60.0] {
            let total: u32 = (0..600).map(|k| gif_delay_cs(k, fps)).sum();
            let want = (100.0 * 600.0 / fps).round() as u32;
            assert_eq!(total, want, "{fps} fps");
        }
        assert_eq!(
            (0..3).map(|k| gif_delay_cs(k, 30.0)).collect::<Vec<_>>(),
            [3, 4, 3]
        );
    }
}
