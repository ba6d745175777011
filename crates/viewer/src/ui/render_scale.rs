//! How finely the app's 3D view is drawn: at full resolution, or on a CPU renderer at a lower
//! one chosen from the frame time, so that a 1920×1080 window keeps 30 frames/s on llvmpipe
//! (the renderer's side is `render/scale.rs`). Only the drawing changes: the run, the panels,
//! the plots and the text are the same at any scale, and headless frames, screenshots and
//! clips are always drawn in full.
//!
//! Drawing smaller is not free: the small picture is stretched over the view by a textured
//! quad, which on llvmpipe costs about half of what the view's own pixels cost in full. At
//! 1280×720 that ate the whole saving (25.4 frames/s in full against 25.5 at half, 2026-11-28).
//! So the automatic scale goes by evidence, judging the median frame time of [`WINDOW`] frames
//! at a time against the budget ([`FRAME_BUDGET_S`]):
//! - over the budget, it *probes*: one window at each coarser step of [`LEVELS`], stopping at the
//!   first that meets the budget and is at least [`WORTH`] faster than where the probe began
//!   (a window under the budget by noise alone is not a gain); if none is, it keeps the
//!   fastest, again only when that is at least [`WORTH`] faster, and otherwise goes back;
//! - after a probe it waits [`COOLDOWN`] windows before probing again, so a picture that cannot
//!   be helped is not disturbed every few seconds;
//! - under [`UP_BELOW`] of the budget it steps one level finer. A step changes the pixels
//!   shaded by at most (0.6/0.5)² = 1.44, and 0.65 × 1.44 < 1, so a step up does not land over
//!   the budget by the view's own cost: the scale settles rather than flickering.

/// The scales the automatic choice steps through, finest first.
pub const LEVELS: [f32; 6] = [1.0, 0.9, 0.8, 0.7, 0.6, 0.5];
/// The frame time aimed for: 30 frames/s.
pub const FRAME_BUDGET_S: f64 = 1.0 / 30.0;
/// A step up is taken when the median frame is under this fraction of the budget.
pub const UP_BELOW: f64 = 0.65;
/// Frames judged together.
pub const WINDOW: usize = 15;
/// How much faster (as a fraction) a coarser scale must be than the one a probe began at to be
/// kept when none meets the budget.
pub const WORTH: f64 = 0.10;
/// Windows between the end of a probe and the next.
pub const COOLDOWN: usize = 120;

/// What the user asked for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RenderScaleMode {
    /// Full resolution on a GPU; on a CPU renderer, as the frame time allows (0.5 at least).
    Auto,
    /// This scale (0.5–1) whatever the adapter.
    Fixed(f32),
}

impl RenderScaleMode {
    /// Reads `--render-scale`: `auto`, or a number from 0.5 to 1.
    ///
    /// # Errors
    /// Anything else, with what is allowed.
    pub fn parse(text: &str) -> Result<Self, String> {
        let text = text.trim();
        if text.eq_ignore_ascii_case("auto") {
            return Ok(Self::Auto);
        }
        match text.parse::<f32>() {
            Ok(s) if (0.5..=1.0).contains(&s) => Ok(Self::Fixed(s)),
            _ => Err(format!(
                "render scale `{text}` is not allowed (needs `auto` or a number from 0.5 to 1: \
                 the share of the 3D view's width and height drawn; 1 is full resolution)"
            )),
        }
    }
}

/// The scale in use and the frame times it is judged on.
#[derive(Debug, Clone)]
pub struct RenderScale {
    mode: RenderScaleMode,
    cpu_adapter: bool,
    level: usize,
    frames: Vec<f64>,
    /// While probing: the level it began at and each level's median so far.
    probe: Option<(usize, [Option<f64>; LEVELS.len()])>,
    /// Windows to wait before the next probe.
    cooldown: usize,
}

impl RenderScale {
    /// `mode` on an adapter that is (or is not) a CPU renderer.
    pub fn new(mode: RenderScaleMode, cpu_adapter: bool) -> Self {
        Self {
            mode,
            cpu_adapter,
            level: 0,
            frames: Vec::with_capacity(WINDOW),
            probe: None,
            cooldown: 0,
        }
    }

    /// The scale to draw the 3D view at now.
    pub fn scale(&self) -> f32 {
        match self.mode {
            RenderScaleMode::Fixed(s) => s,
            RenderScaleMode::Auto if self.cpu_adapter => LEVELS[self.level],
            RenderScaleMode::Auto => 1.0,
        }
    }

    /// The mode asked for.
    pub fn mode(&self) -> RenderScaleMode {
        self.mode
    }

    /// Counts one frame's time (seconds, the UI and the paint); every [`WINDOW`] frames the
    /// automatic scale may move a step. A non-finite or negative time is not counted.
    pub fn record(&mut self, frame_seconds: f64) {
        if self.mode != RenderScaleMode::Auto || !self.cpu_adapter {
            return;
        }
        if !(frame_seconds.is_finite() && frame_seconds >= 0.0) {
            return;
        }
        self.frames.push(frame_seconds);
        if self.frames.len() < WINDOW {
            return;
        }
        self.frames.sort_by(f64::total_cmp);
        let median = self.frames[WINDOW / 2];
        self.frames.clear();
        self.judge(median);
    }

    /// One window's median frame time, at the level in use.
    fn judge(&mut self, median: f64) {
        let over = median > FRAME_BUDGET_S;
        if let Some((began, mut medians)) = self.probe.take() {
            medians[self.level] = Some(median);
            let start = medians[began].unwrap_or(f64::INFINITY);
            let gain = median < (1.0 - WORTH) * start;
            if (over || !gain) && self.level + 1 < LEVELS.len() {
                self.level += 1;
                self.probe = Some((began, medians));
                return;
            }
            if over || !gain {
                // No step met the budget with a gain: the fastest, if it is worth its coarser
                // picture.
                let (fastest, best) = medians
                    .iter()
                    .enumerate()
                    .filter_map(|(k, m)| m.map(|m| (k, m)))
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .unwrap_or((began, start));
                self.level = if best < (1.0 - WORTH) * start {
                    fastest
                } else {
                    began
                };
            }
            self.cooldown = COOLDOWN;
            return;
        }
        if over {
            if self.cooldown > 0 {
                self.cooldown -= 1;
            } else if self.level + 1 < LEVELS.len() {
                let mut medians = [None; LEVELS.len()];
                medians[self.level] = Some(median);
                self.probe = Some((self.level, medians));
                self.level += 1;
            }
        } else if median < UP_BELOW * FRAME_BUDGET_S && self.level > 0 {
            self.level -= 1;
        } else {
            self.cooldown = self.cooldown.saturating_sub(1);
        }
    }

    /// "3D at 70 %" while the view is drawn below full resolution.
    pub fn shown(&self) -> Option<String> {
        let scale = self.scale();
        (scale < 1.0).then(|| format!("3D at {:.0}\u{a0}%", scale * 100.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn feed(scale: &mut RenderScale, seconds: f64, frames: usize) {
        for _ in 0..frames {
            scale.record(seconds);
        }
    }

    /// Frames of a machine whose frame takes `base` seconds plus `view` at full scale times the
    /// share of the view's pixels, plus `stretch` times the view's full pixels when scaled: the
    /// cost of the quad that stretches the small picture.
    fn run(s: &mut RenderScale, base: f64, view: f64, stretch: f64, windows: usize) -> Vec<f32> {
        let mut seen = Vec::new();
        for _ in 0..windows {
            let k = f64::from(s.scale());
            let t = base + view * k * k + if k < 1.0 { stretch } else { 0.0 };
            feed(s, t, WINDOW);
            seen.push(s.scale());
        }
        seen
    }

    #[test]
    fn a_probe_stops_at_the_first_step_that_meets_the_budget() {
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        // 45 ms in full; 0.7 gives 10 + 30·0.49 + 5 = 29.7 ms, 0.8 gives 34.2.
        let seen = run(&mut s, 0.010, 0.030, 0.005, 50);
        assert_eq!(&seen[..3], &[0.9, 0.8, 0.7]);
        assert!(seen[3..].iter().all(|&k| k == 0.7), "{seen:?}");
        assert_eq!(s.shown().as_deref(), Some("3D at 70\u{a0}%"));
    }

    #[test]
    fn where_no_step_helps_enough_the_view_stays_in_full_and_is_left_alone() {
        // As at 1280×720 here: the stretch eats the saving.
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        let seen = run(&mut s, 0.024, 0.012, 0.008, 10 + COOLDOWN);
        // One probe through every step, then full resolution for the cooldown.
        assert_eq!(&seen[..5], &[0.9, 0.8, 0.7, 0.6, 0.5]);
        assert!(seen[5..5 + COOLDOWN].iter().all(|&k| k == 1.0), "{seen:?}");
    }

    #[test]
    fn a_step_under_the_budget_by_noise_alone_is_not_kept() {
        // 34 ms in full, 33 at every coarser step: under the budget, but no gain.
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        feed(&mut s, 0.034, WINDOW);
        assert_eq!(s.scale(), 0.9, "probing");
        for _ in 0..5 {
            feed(&mut s, 0.033, WINDOW);
        }
        assert_eq!(s.scale(), 1.0, "back to full: nothing gained");
    }

    #[test]
    fn where_no_step_meets_the_budget_the_fastest_is_kept_if_worth_it() {
        // As at 1920×1080 here: 55 ms in full, 45 at half.
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        let seen = run(&mut s, 0.032, 0.023, 0.007, 10 + COOLDOWN);
        assert_eq!(seen[5], 0.5, "{seen:?}");
        assert!(seen[5..].iter().all(|&k| k == 0.5), "{seen:?}");
    }

    #[test]
    fn a_fast_machine_steps_back_up_and_stays() {
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        run(&mut s, 0.030, 0.030, 0.0, 6);
        assert_eq!(s.scale(), 0.5);
        // 0.8 of the budget: neither over it nor under 0.65 of it.
        feed(&mut s, 0.8 * FRAME_BUDGET_S, 10 * WINDOW);
        assert_eq!(s.scale(), 0.5);
        feed(&mut s, 0.5 * FRAME_BUDGET_S, WINDOW);
        assert_eq!(s.scale(), 0.6);
        feed(&mut s, 0.5 * FRAME_BUDGET_S, 10 * WINDOW);
        assert_eq!(s.scale(), 1.0);
        assert_eq!(s.shown(), None);
    }

    #[test]
    fn one_slow_frame_in_a_window_moves_nothing() {
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        feed(&mut s, 0.050, WINDOW - 1);
        assert_eq!(s.scale(), 1.0, "judged only on a whole window");
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        for k in 0..5 * WINDOW {
            s.record(if k % WINDOW == 3 { 0.5 } else { 0.02 });
        }
        assert_eq!(s.scale(), 1.0);
    }

    #[test]
    fn a_gpu_or_a_fixed_scale_never_moves() {
        let mut gpu = RenderScale::new(RenderScaleMode::Auto, false);
        feed(&mut gpu, 0.1, 10 * WINDOW);
        assert_eq!(gpu.scale(), 1.0);
        let mut full = RenderScale::new(RenderScaleMode::Fixed(1.0), true);
        feed(&mut full, 0.1, 10 * WINDOW);
        assert_eq!(full.scale(), 1.0);
        let mut fixed = RenderScale::new(RenderScaleMode::Fixed(0.6), false);
        feed(&mut fixed, 0.001, 10 * WINDOW);
        assert_eq!(fixed.scale(), 0.6);
        let mut auto = RenderScale::new(RenderScaleMode::Auto, true);
        feed(&mut auto, f64::NAN, 10 * WINDOW);
        feed(&mut auto, -1.0, 10 * WINDOW);
        assert_eq!(auto.scale(), 1.0);
    }

    #[test]
    fn the_option_reads_auto_and_half_to_one_and_names_the_rest() {
        assert_eq!(RenderScaleMode::parse("auto"), Ok(RenderScaleMode::Auto));
        assert_eq!(RenderScaleMode::parse("1"), Ok(RenderScaleMode::Fixed(1.0)));
        assert_eq!(
            RenderScaleMode::parse("0.5"),
            Ok(RenderScaleMode::Fixed(0.5))
        );
        for bad in ["0.49", "0", "-1", "1.01", "NaN", "inf", "", "full"] {
            let e = RenderScaleMode::parse(bad).unwrap_err();
            assert!(e.contains("0.5 to 1"), "{bad}: {e}");
        }
    }
}
