//! The video clock of a scene: which simulation time each video frame shows, through a
//! lesson's speed steps and from a saved state's time. (Apart from `timeline`, which validates
//! the steps, so that `setup` can use `timeline` without `timeline` using `setup`.)

use super::setup::SceneSetup;

impl SceneSetup {
    /// Simulation time of video frame `k`: frame 0 at `playback.start_time` (or a saved
    /// state's time, `[resume]`, if later), then `1/fps`
    /// seconds of video per frame at the playback speed in force, which timeline steps may
    /// change. Between speed steps this is `start_time + k · speed / fps`. The frame that shows
    /// a scene's end ([`Self::frames_to_end`]'s last) shows `end_time` itself, not the time a
    /// whole frame step would reach past it.
    pub fn frame_time(&self, k: u64) -> f64 {
        let t = self.time_after_video(k as f64 / self.scene.playback.fps);
        match (self.scene.playback.end_time, self.frames_to_end()) {
            // (Not for a scene resumed past its end, whose first frame is already later.)
            (Some(end), Some(frames)) if k + 1 == frames && self.time_after_video(0.0) <= end => {
                t.min(end)
            }
            _ => t,
        }
    }

    /// The playback speed in force at simulation time `t` (the scene's, or the last speed step
    /// at or before `t`).
    pub fn speed_at(&self, t: f64) -> f64 {
        self.timeline
            .iter()
            .take_while(|s| s.at <= t)
            .filter_map(|s| s.speed)
            .last()
            .unwrap_or(self.scene.playback.speed)
    }

    /// The pieces of the video clock from `start_time` on: (simulation time where a piece
    /// starts, its playback speed). A new piece starts at each speed step.
    fn clock_pieces(&self) -> Vec<(f64, f64)> {
        // A saved state's video starts where it was saved (or later, at start_time).
        let resumed_at = self.resume.as_ref().map_or(0.0, |r| r.t);
        let start = self.scene.playback.start_time.max(resumed_at);
        let mut pieces = vec![(start, self.speed_at(start))];
        pieces.extend(
            self.timeline
                .iter()
                .filter(|s| s.at > start)
                .filter_map(|s| Some((s.at, s.speed?))),
        );
        pieces
    }

    /// Simulation time reached after `video` seconds of playback from `start_time`.
    pub fn time_after_video(&self, video: f64) -> f64 {
        let pieces = self.clock_pieces();
        let mut piece = pieces[0];
        let mut left = video;
        for &next in &pieces[1..] {
            let needed = (next.0 - piece.0) / piece.1;
            if needed > left {
                break;
            }
            left -= needed;
            piece = next;
        }
        piece.0 + left * piece.1
    }

    /// Seconds of video from `start_time` until simulation time `t` (the inverse of
    /// [`Self::time_after_video`]).
    pub fn video_time_at(&self, t: f64) -> f64 {
        let pieces = self.clock_pieces();
        let mut piece = pieces[0];
        let mut video = 0.0;
        for &next in pieces[1..].iter().take_while(|p| p.0 < t) {
            video += (next.0 - piece.0) / piece.1;
            piece = next;
        }
        video + (t - piece.0).max(0.0) / piece.1
    }

    /// Frames needed to show the scene up to `playback.end_time` (frame 0 included); `None`
    /// when the scene sets no end.
    pub fn frames_to_end(&self) -> Option<u64> {
        let video = self.video_time_at(self.scene.playback.end_time?);
        // Rounding must not drop the frame that shows the end.
        let frames = (video * self.scene.playback.fps - 1e-9).ceil().max(0.0) as u64;
        Some(frames + 1)
    }
}
