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
//! - over the budget, it *probes*: [`PROBE_WINDOWS`] windows at the scale in use, then as many
//!   at each coarser step of [`LEVELS`],
//!   stopping at the first that meets the budget and is at least [`WORTH`] faster than where the
//!   probe began (a window under the budget by noise alone is not a gain); if none is, it takes
//!   the fastest, again only when that is at least [`WORTH`] faster;
//! - a step so found is *confirmed*: the probe's start is measured again, and the step kept only
//!   if it is [`WORTH`] faster than both measurements of the start. A slow spell of the machine
//!   during the probe made the coarser steps look faster than they were (on 2026-11-28 a
//!   controller asking 10 % against a one-window start kept 70 % at 1280×720, where no scale
//!   pays; `docs/guide/accuracy.md` has the table);
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
pub const WORTH: f64 = 0.15;
/// Windows between the end of a probe and the next.
pub const COOLDOWN: usize = 120;
/// Windows a probe measures each step for (and the start again, to confirm).
pub const PROBE_WINDOWS: usize = 2;

/// A step found faster, being confirmed against a second measurement of the probe's start.
#[derive(Debug, Clone, Copy)]
struct Confirming {
    began: usize,
    start_median: f64,
    candidate: usize,
    candidate_median: f64,
}

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
    /// While confirming a step a probe found.
    confirming: Option<Confirming>,
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
            confirming: None,
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
        let probing = self.probe.is_some() || self.confirming.is_some();
        let needed = if probing {
            PROBE_WINDOWS * WINDOW
        } else {
            WINDOW
        };
        if self.frames.len() < needed {
            return;
        }
        self.frames.sort_by(f64::total_cmp);
        let median = self.frames[needed / 2];
        self.frames.clear();
        self.judge(median);
    }

    /// One window's median frame time, at the level in use.
    fn judge(&mut self, median: f64) {
        let over = median > FRAME_BUDGET_S;
        if let Some(c) = self.confirming.take() {
            // `median` is the start measured again.
            let start = c.start_median.min(median);
            self.level = if c.candidate_median < (1.0 - WORTH) * start {
                c.candidate
            } else {
                c.began
            };
            self.cooldown = COOLDOWN;
            return;
        }
        if let Some((began, mut medians)) = self.probe.take() {
            medians[self.level] = Some(median);
            if self.level == began {
                // The start measured over a probe's longer window; now the first coarser step.
                self.level += 1;
                self.probe = Some((began, medians));
                return;
            }
            let start = medians[began].unwrap_or(f64::INFINITY);
            let gain = median < (1.0 - WORTH) * start;
            if (over || !gain) && self.level + 1 < LEVELS.len() {
                self.level += 1;
                self.probe = Some((began, medians));
                return;
            }
            let candidate = if over || !gain {
                // No step met the budget with a gain: the fastest, if it is worth its coarser
                // picture.
                let (fastest, best) = medians
                    .iter()
                    .enumerate()
                    .filter_map(|(k, m)| m.map(|m| (k, m)))
                    .min_by(|a, b| a.1.total_cmp(&b.1))
                    .unwrap_or((began, start));
                if best < (1.0 - WORTH) * start {
                    fastest
                } else {
                    began
                }
            } else {
                self.level
            };
            if candidate == began {
                self.level = began;
                self.cooldown = COOLDOWN;
            } else {
                self.confirming = Some(Confirming {
                    began,
                    start_median: start,
                    candidate,
                    candidate_median: medians[candidate].unwrap_or(f64::INFINITY),
                });
                self.level = began;
            }
            return;
        }
        if over {
            if self.cooldown > 0 {
                self.cooldown -= 1;
            } else if self.level + 1 < LEVELS.len() {
                // The start is measured again over the probe's longer window first: one
                // window's median is too noisy to measure a 15 % gain against.
                self.probe = Some((self.level, [None; LEVELS.len()]));
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
    /// share of the view's pixels, plus `stretch` when scaled (the quad that stretches the small
    /// picture), each frame off by up to ±`noise` of itself (a seeded sequence); the scale after
    /// each window.
    fn run_noisy(
        s: &mut RenderScale,
        (base, view, stretch): (f64, f64, f64),
        noise: f64,
        windows: usize,
    ) -> Vec<f32> {
        let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
        let mut seen = Vec::new();
        for _ in 0..windows {
            for _ in 0..WINDOW {
                let k = f64::from(s.scale());
                let t = base + view * k * k + if k < 1.0 { stretch } else { 0.0 };
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
                s.record(t * (1.0 + noise * (2.0 * u - 1.0)));
            }
            seen.push(s.scale());
        }
        seen
    }

    fn run(s: &mut RenderScale, base: f64, view: f64, stretch: f64, windows: usize) -> Vec<f32> {
        run_noisy(s, (base, view, stretch), 0.0, windows)
    }

    #[test]
    fn a_probe_stops_at_the_first_step_that_meets_the_budget() {
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        // 45 ms in full; 0.7 gives 10 + 30·0.49 + 5 = 29.7 ms, 0.8 gives 34.2.
        let seen = run(&mut s, 0.010, 0.030, 0.005, 40);
        assert!(!seen.contains(&0.6), "the probe went past 0.7: {seen:?}");
        assert!(seen[20..].iter().all(|&k| k == 0.7), "{seen:?}");
        assert_eq!(s.shown().as_deref(), Some("3D at 70\u{a0}%"));
    }

    #[test]
    fn where_no_step_helps_enough_the_view_stays_in_full_and_is_left_alone() {
        // As at 1280×720 here: the stretch eats the saving.
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        let seen = run(&mut s, 0.024, 0.012, 0.008, 20 + COOLDOWN);
        // One probe: the start again, then every step (two windows each); then full
        // resolution, untouched for the cooldown.
        assert!(seen[..2].iter().all(|&k| k == 1.0), "{seen:?}");
        assert!(seen[2..12].iter().all(|&k| k < 1.0), "{seen:?}");
        assert!(
            seen[12..12 + COOLDOWN].iter().all(|&k| k == 1.0),
            "{seen:?}"
        );
    }

    #[test]
    fn where_no_step_meets_the_budget_the_fastest_is_kept_if_worth_it() {
        // As at 1920×1080 here: 55 ms in full, 45 at half.
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        let seen = run(&mut s, 0.032, 0.023, 0.007, 20 + COOLDOWN);
        assert!(seen[15..].iter().all(|&k| k == 0.5), "{seen:?}");
    }

    #[test]
    fn noise_alone_keeps_the_view_in_full_and_a_real_gain_is_found_through_it() {
        // ±15 % frame noise. Where the scale saves nothing (the stretch eats it), the view is in
        // full but while a probe or its confirmation runs.
        let mut flat = RenderScale::new(RenderScaleMode::Auto, true);
        let seen = run_noisy(&mut flat, (0.024, 0.012, 0.008), 0.15, 1000);
        let full = seen.iter().filter(|&&k| k == 1.0).count();
        assert!(
            full as f64 > 0.9 * seen.len() as f64,
            "{full} of {}",
            seen.len()
        );
        // Where half the pixels save 20 %, the view ends coarser and stays there.
        let mut gain = RenderScale::new(RenderScaleMode::Auto, true);
        let seen = run_noisy(&mut gain, (0.032, 0.023, 0.007), 0.15, 300);
        let coarse = seen[100..].iter().filter(|&&k| k < 1.0).count();
        assert!(
            coarse > 180,
            "{coarse} of 200 windows coarser: {:?}",
            &seen[..40]
        );
    }

    #[test]
    fn a_step_under_the_budget_by_noise_alone_is_not_kept() {
        // 34 ms in full, 33 at every coarser step: under the budget, but no gain.
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        feed(&mut s, 0.034, WINDOW + PROBE_WINDOWS * WINDOW);
        assert_eq!(s.scale(), 0.9, "probing");
        feed(&mut s, 0.033, 5 * PROBE_WINDOWS * WINDOW);
        assert_eq!(s.scale(), 1.0, "back to full: nothing gained");
    }

    #[test]
    fn a_fast_machine_steps_back_up_and_stays() {
        let mut s = RenderScale::new(RenderScaleMode::Auto, true);
        run(&mut s, 0.030, 0.030, 0.0, 20);
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
