//! The period search of `track`, on tracks whose truth is known: synthetic periodic tracks from
//! 6 to 200 frames a period (noise, harmonics, fractional periods, two periods only), model
//! tracks of the printed sphere in every regime (m/m0 = 0.025 … 6) sampled at the authors'
//! 30 frames/s with noise and gaps, and smoothed random walks with drift, of which none may be
//! given a period.

use rollphase::analysis::experiment::prediction::{PredictOptions, predict};
use rollphase::analysis::experiment::tracking::{
    CleanTrack, ErrorSource, PeriodSearch, RepeatShown, TrackError, find_period, measure,
    repeat_shown,
};
use rollphase::geometry::Body;

/// A reproducible stream of standard normal numbers (Box–Muller over a 64-bit LCG).
pub(crate) struct Noise(pub(crate) u64);

impl Noise {
    pub(crate) fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    pub(crate) fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// A rolling-like track: drift down the ramp, the first two harmonics of the period in both
/// coordinates (the second `second` times the first), white noise of `noise` (in units of the
/// first harmonic's amplitude).
pub(crate) fn periodic(
    frames: usize,
    period: f64,
    second: f64,
    noise: f64,
    seed: u64,
) -> CleanTrack {
    let mut rng = Noise(seed);
    let w = std::f64::consts::TAU / period;
    let (p1, p2, p3) = (
        rng.uniform() * 6.3,
        rng.uniform() * 6.3,
        rng.uniform() * 6.3,
    );
    let advance = 3.0 + 2.0 * rng.uniform();
    let mut down = Vec::with_capacity(frames);
    let mut across = Vec::with_capacity(frames);
    for i in 0..frames {
        let t = i as f64;
        down.push(
            advance * t / period
                + (w * t + p1).sin()
                + second * (2.0 * w * t + p2).sin()
                + noise * rng.normal(),
        );
        across.push(
            0.6 * (w * t + p3).sin() + 0.6 * second * (2.0 * w * t).cos() - 0.001 * t
                + noise * rng.normal(),
        );
    }
    CleanTrack::on_frames(down, across)
}

pub(crate) fn search() -> PeriodSearch {
    PeriodSearch::default()
}

/// True periods from 6 to 200 frames at 30 frames/s (1500 frames, noise 5 % and 20 % of the
/// wobble): each comes back within its uncertainty bounds, never as 2T or T/2, with a finite
/// error.
#[test]
fn every_period_from_6_to_200_frames_comes_back_never_doubled_or_halved() {
    let mut rows = Vec::new();
    for (k, &period) in [
        6.0, 6.7, 8.0, 10.5, 13.0, 16.0, 18.3, 20.0, 20.5, 25.0, 30.0, 36.0, 45.0, 61.7, 80.0,
        100.0, 123.4, 150.0, 177.7, 200.0,
    ]
    .iter()
    .enumerate()
    {
        for (j, &noise) in [0.05, 0.2].iter().enumerate() {
            let frames = if period > 150.0 { 2000 } else { 1500 };
            let track = periodic(frames, period, 0.5, noise, 7 + 31 * k as u64 + j as u64);
            let fit = find_period(&track, &search(), &|_, _| {})
                .unwrap_or_else(|e| panic!("period {period}, noise {noise}: {e}"));
            rows.push(format!(
                "{period:>7.1} {noise:>5.2} → {:>8.3} ± {:.3} ({:?}, {} cycles, d′ {:.3} vs surrogates {:.3})",
                fit.period_frames,
                fit.period_error_frames,
                fit.period_error_from,
                fit.cycle_periods.len(),
                fit.significance.as_ref().unwrap().normalised_dip,
                fit.significance.as_ref().unwrap().surrogate_floor
            ));
            let err = fit.period_error_frames;
            assert!(err.is_finite() && err > 0.0, "{period}: error {err}");
            assert!(
                (fit.period_frames - period).abs() < (0.01 * period).max(5.0 * err),
                "period {period} noise {noise}: found {} ± {err}",
                fit.period_frames
            );
        }
    }
    eprintln!("true  noise → found\n{}", rows.join("\n"));
}

/// A track whose second harmonic dominates (the first at a third of its size) still comes back
/// at its period, not half of it; the answer is the same with one thread or many; a track with
/// two periods only gets a finite error from the dip; a period under 6 frames is refused.
#[test]
fn harmonics_and_two_period_tracks() {
    for period in [12.0, 40.0, 90.0] {
        let track = periodic(1200, period, 3.0, 0.05, 3);
        let fit = find_period(&track, &search(), &|_, _| {}).unwrap();
        assert!(
            (fit.period_frames - period).abs() < 0.02 * period,
            "{period}: {}",
            fit.period_frames
        );
    }
    // The same numbers on every run, whatever the thread count (the surrogates run in parallel,
    // each from its own seed).
    let track = periodic(1500, 20.5, 0.5, 0.2, 9);
    let many = find_period(&track, &search(), &|_, _| {}).unwrap();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| find_period(&track, &search(), &|_, _| {}).unwrap());
    assert_eq!(many, one);
    let track = periodic(401, 180.0, 0.5, 0.02, 11);
    let fit = find_period(&track, &search(), &|_, _| {}).unwrap();
    assert!(
        (fit.period_frames - 180.0).abs() < 1.0,
        "{}",
        fit.period_frames
    );
    // Two cycles: no spread to read, but the harmonic regression still gives an error.
    assert_eq!(fit.period_error_from, ErrorSource::Harmonics);
    assert!(fit.period_error_frames.is_finite() && fit.period_error_frames > 0.0);
    // Too fast for the frame rate: named, not answered with a multiple.
    let track = periodic(1200, 4.0, 0.3, 0.02, 5);
    match find_period(&track, &search(), &|_, _| {}) {
        Err(TrackError::TooFast { period_frames, .. }) => {
            assert!((period_frames - 4.0).abs() < 0.1)
        }
        other => panic!("{other:?}"),
    }
}

/// A smoothed random walk with drift: steps of 1 ± 3 (down) and ± 3 (across), averaged over
/// `smooth` frames.
fn random_walk(frames: usize, smooth: usize, seed: u64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = Noise(seed);
    let raw: Vec<(f64, f64)> = (0..frames + smooth)
        .scan((0.0, 0.0), |p, _| {
            p.0 += 1.0 + 3.0 * rng.normal();
            p.1 += 3.0 * rng.normal();
            Some(*p)
        })
        .collect();
    let mut down = Vec::new();
    let mut across = Vec::new();
    for i in 0..frames {
        let w = &raw[i..i + smooth];
        down.push(w.iter().map(|p| p.0).sum::<f64>() / smooth as f64);
        across.push(w.iter().map(|p| p.1).sum::<f64>() / smooth as f64);
    }
    ((0..frames).map(|i| i as f64).collect(), down, across)
}

/// Sixty smoothed random walks with drift (smoothing 1 to 60 frames): none is given a period.
#[test]
fn no_random_walk_is_given_a_period() {
    let mut stated = Vec::new();
    for k in 0..60u64 {
        let smooth = 1 + (k as usize % 12) * 5;
        let (f, d, a) = random_walk(1500, smooth, 1000 + k);
        match measure(&f, &d, &a, &|_, _| {}) {
            Ok((_, fit)) => stated.push(format!(
                "walk {k} (smoothed over {smooth}): {:.2} ± {:.2} frames",
                fit.period_frames, fit.period_error_frames
            )),
            Err(e) => assert!(
                matches!(
                    e,
                    TrackError::NoPeriod { .. }
                        | TrackError::MostlyUnsteady { .. }
                        | TrackError::Damaged(_)
                        | TrackError::TooFast { .. }
                ),
                "{e}"
            ),
        }
    }
    assert!(stated.is_empty(), "{}", stated.join("\n"));
}

/// The printed sphere (the generator's seed 6, σ = 0.25, 4 modes, ⟨r⟩ = 1 cm) at sin α = 0.2 on
/// its most visited stable orbit at `mass` (the viscous model below 0.1), over `periods` of it,
/// filmed at 30 frames/s: t0 = √(⟨r⟩/(g·m/m0)) with the weight driving, the orbit's path
/// resampled at whole frames (linearly, from 400 samples a repeat), `noise_cm` of Gaussian
/// tracking noise on each coordinate, the frames in `gap` left out.
pub(crate) struct FilmedOrbit {
    /// The model's period (frames).
    pub true_frames: f64,
    /// The orbit's advance down the ramp per repeat (cm).
    pub advance_down: f64,
    /// (frame, down, across), cm.
    pub rows: Vec<(f64, f64, f64)>,
}

pub(crate) fn filmed_orbit(
    mass: f64,
    periods: usize,
    noise_cm: f64,
    seed: u64,
    gap: std::ops::Range<usize>,
) -> FilmedOrbit {
    let body = Body::paper_sphere(6, 0.25, 4).unwrap();
    let options = PredictOptions {
        starts: 6,
        periods_drawn: periods,
        samples_per_period: 400,
        ..PredictOptions::default()
    };
    let model = if mass < 0.1 { 0.0 } else { mass };
    let p = predict(&body, 0.2f64.asin(), model, &options).unwrap();
    let orbit = p
        .orbits
        .iter()
        .max_by(|a, b| a.fraction.total_cmp(&b.fraction))
        .unwrap();
    let frames_per_t0 = 30.0 * (0.01 / (9.81 * mass)).sqrt();
    let dt = orbit.period / 400.0;
    let total = (orbit.path.len() - 1) as f64 * dt * frames_per_t0;
    let mut rng = Noise(seed);
    let rows = (0..total.floor() as usize)
        .filter(|i| !gap.contains(i))
        .map(|i| {
            let x = i as f64 / frames_per_t0 / dt;
            let j = (x.floor() as usize).min(orbit.path.len() - 2);
            let s = x - j as f64;
            let at = |c: usize| orbit.path[j][c] + s * (orbit.path[j + 1][c] - orbit.path[j][c]);
            let down = at(0) + noise_cm * rng.normal();
            (i as f64, down, at(1) + noise_cm * rng.normal())
        })
        .collect();
    FilmedOrbit {
        true_frames: orbit.period * frames_per_t0,
        advance_down: orbit.advance_down,
        rows,
    }
}

/// The printed sphere on its stable orbit at m/m0 = 0.025, 0.5, 2.5 and 6 ([`filmed_orbit`]),
/// with 0.1 mm of tracking noise and a gap: the period comes back within its error of the
/// model's, from 13 to 230 frames. (At m/m0 = 6 the centre wobbles by only ≈ 0.5 mm about its
/// steady drift: with 0.3 mm of noise, about a pixel of the authors' video, the cycles do not
/// repeat on their own and no period is stated.)
#[test]
fn model_tracks_of_the_printed_sphere_in_every_regime() {
    for (k, mass) in [0.025, 0.5, 2.5, 6.0].into_iter().enumerate() {
        let film = filmed_orbit(mass, 100, 0.01, 77 + k as u64, 300..304);
        let true_frames = film.true_frames;
        let f: Vec<f64> = film.rows.iter().map(|r| r.0).collect();
        let d: Vec<f64> = film.rows.iter().map(|r| r.1).collect();
        let a: Vec<f64> = film.rows.iter().map(|r| r.2).collect();
        let (track, fit) = measure(&f, &d, &a, &|_, _| {})
            .unwrap_or_else(|e| panic!("m/m0 = {mass} (period {true_frames:.2} frames): {e}"));
        // The model's orbit repeats exactly: only the tracking noise is left unrepeated.
        let shown = repeat_shown(&film.rows, &track, &fit, None);
        assert!(
            matches!(shown, RepeatShown::Closely { .. }),
            "m/m0 = {mass}: {shown:?}"
        );
        eprintln!(
            "m/m0 {mass}: model period {true_frames:.3} frames, found {:.3} ± {:.3}",
            fit.period_frames, fit.period_error_frames
        );
        assert!(
            (fit.period_frames - true_frames).abs()
                < (4.0 * fit.period_error_frames).max(0.002 * true_frames),
            "m/m0 = {mass}: model {true_frames}, found {} ± {}",
            fit.period_frames,
            fit.period_error_frames
        );
        assert!(
            (fit.advance_down - film.advance_down).abs() < 0.01 * film.advance_down,
            "{} against {}",
            fit.advance_down,
            film.advance_down
        );
    }
}

/// The stated error covers the truth: 20 tracks each of true period 30, 100, 177.7 and 200
/// frames with noise 20 % of the wobble. Until 2026-11-26 the period was the whole track's dip
/// while its error came from the cycles' spread: it lay 1.5–2.0 errors from the truth (rms),
/// 177.7 came back as 176.28 ± 0.41. The cycles' mean then gave 0.6–1.0; since 2026-11-28 the
/// harmonic regression gives period and error (`bench calibration` has its coverage).
#[test]
fn the_stated_error_covers_the_truth() {
    for period in [30.0, 100.0, 177.7, 200.0] {
        let z: Vec<f64> = (0..20u64)
            .map(|seed| {
                let frames = if period > 150.0 { 2000 } else { 1500 };
                let track = periodic(frames, period, 0.5, 0.2, 1000 + seed);
                let fit = find_period(&track, &search(), &|_, _| {}).unwrap();
                // The regression, unless the block check read the turns as varying (under 1 %
                // of such tracks by chance, `bench calibration`).
                let varying = fit.block_check.is_some_and(|b| b.turns_vary);
                assert_eq!(
                    fit.period_error_from,
                    if varying {
                        ErrorSource::Cycles
                    } else {
                        ErrorSource::Harmonics
                    }
                );
                (fit.period_frames - period) / fit.period_error_frames
            })
            .collect();
        let rms = (z.iter().map(|x| x * x).sum::<f64>() / z.len() as f64).sqrt();
        let far = z.iter().filter(|x| x.abs() > 3.0).count();
        assert!(
            rms < 1.25 && far == 0,
            "period {period}: rms z {rms:.2}, {far} beyond 3"
        );
    }
}

/// The short periods whose cycles' shifts were all biased the same way (7.3 frames came back as
/// 7.2467 ± 0.0011, 47 errors off): 150 synthetic tracks each at 6.3, 7.3 and 10.4 frames,
/// noise 2 % and 20 %. The stated ±1.96σ interval holds the truth 88–99 % of the time (95 % ±
/// 1.8 % sampling, with margin) and the mean offset is under a third of an error. The
/// cycles' mean, on the same tracks, fails both. The advance per period and the speed, with
/// the errors stated beside them, are held to the same.
#[test]
fn short_periods_are_unbiased_and_their_errors_calibrated() {
    use rollphase::analysis::experiment::tracking::calibration::{TrackCase, calibrate_case};
    for period in [6.3, 7.3, 10.4] {
        for noise in [0.02, 0.2] {
            let case = TrackCase {
                period_frames: period,
                noise,
                cycles: 20.0,
            };
            let c = calibrate_case(&case, 150, 500);
            assert_eq!(c.refused, 0, "{case:?}");
            let s = c.stated;
            assert!(
                (0.88..=0.99).contains(&s.coverage) && s.bias_in_errors.abs() < 1.0 / 3.0,
                "{case:?}: coverage {:.3}, bias {:.2} errors",
                s.coverage,
                s.bias_in_errors
            );
            // The advance per period and the speed, from the same regression's slope.
            for (what, k) in [
                ("advance down", c.advance_down),
                ("advance across", c.advance_across),
                ("speed", c.speed),
            ] {
                assert!(
                    k.estimates == 150
                        && (0.88..=0.99).contains(&k.coverage)
                        && k.bias_in_errors.abs() < 1.0 / 3.0,
                    "{case:?} {what}: {k:?}"
                );
            }
            if noise == 0.02 {
                assert!(
                    c.cycles_mean.coverage < 0.8,
                    "{case:?}: {:?}",
                    c.cycles_mean
                );
            }
        }
    }
}

/// Turns whose times vary by 3–5 % (a real ramp; the authors' run) line up again by chance
/// after several turns: 6–17 % of such tracks were stated as a period of 5–8 turns, with
/// errors thousands of times too small (a helper's finding, 2026-11-28). The period is now the
/// mean turn, and its error (the cycles', each spanning two turns) holds the process's mean.
#[test]
fn turns_of_varying_time_never_make_a_multiple_of_the_period() {
    let (turn, turns) = (60.0, 20);
    let mut held = 0;
    let draws = 30;
    for seed in 0..draws {
        let mut rng = Noise(4000 + seed);
        let jitter = if seed % 2 == 0 { 0.03 } else { 0.05 };
        let mut edges = vec![0.0];
        for _ in 0..turns {
            edges.push(edges.last().unwrap() + turn * (1.0 + jitter * rng.normal()));
        }
        let frames = *edges.last().unwrap() as usize;
        let (a, p) = (0.2 + 0.6 * rng.uniform(), rng.uniform() * 6.3);
        let (mut down, mut across) = (Vec::new(), Vec::new());
        for t in 0..frames {
            let t = t as f64;
            let k = edges.partition_point(|&e| e <= t) - 1;
            let phase = k as f64 + (t - edges[k]) / (edges[k + 1] - edges[k]);
            let w = std::f64::consts::TAU * phase;
            down.push(3.0 * phase + (w + p).sin() + a * (2.0 * w).cos() + 0.05 * rng.normal());
            across.push(0.6 * (w + 2.0 * p).cos() + 0.05 * rng.normal());
        }
        let track = CleanTrack::on_frames(down, across);
        let fit = find_period(&track, &search(), &|_, _| {}).unwrap();
        assert!(
            (fit.period_frames - turn).abs() < 0.1 * turn,
            "seed {seed}: stated {} frames for turns of {turn}",
            fit.period_frames
        );
        held += usize::from((fit.period_frames - turn).abs() <= 1.96 * fit.period_error_frames);
    }
    assert!(
        held >= 24,
        "the process's mean held {held} of {draws} times"
    );
}

/// A slow drift under a large wobble is steady rolling: its windowed speed scatters by more than
/// 15 % of itself, and a track advancing 1 unit a period under a wobble of 10 was cut to 1 % of
/// its frames and refused ("repeats only over frames 451–451", a helper's finding). The
/// windowed speeds' own scatter now sets the band where it is wider; the advance comes back.
#[test]
fn a_slow_drift_under_a_large_wobble_is_measured() {
    for drift in [0.0, 0.01, 0.1] {
        let mut rng = Noise(77);
        let w = std::f64::consts::TAU / 40.0;
        let frames: Vec<f64> = (0..800).map(f64::from).collect();
        let down: Vec<f64> = frames
            .iter()
            .map(|&t| {
                drift * t / 40.0 + (w * t).sin() + 0.3 * (2.0 * w * t).cos() + 0.005 * rng.normal()
            })
            .collect();
        let across: Vec<f64> = frames
            .iter()
            .map(|&t| 0.6 * (w * t + 0.4).cos() + 0.005 * rng.normal())
            .collect();
        let (_, fit) = measure(&frames, &down, &across, &|_, _| {}).unwrap();
        assert!(
            (fit.period_frames - 40.0).abs() < 0.01,
            "{drift}: {}",
            fit.period_frames
        );
        let error = fit.advance_error.unwrap()[0];
        assert!(
            (fit.advance_down - drift).abs() < 4.0 * error,
            "{drift}: {} ± {error}",
            fit.advance_down
        );
    }
}

/// Down and across measured with different noise (a camera's two axes, or `--scale`'s two
/// factors): each coordinate's error is its own. With one residual variance shared by both,
/// noise 4 times larger down than across held the advance down 87 % of the time and across
/// 100 % (a helper's finding, 2026-11-28); now each of the period, the advances and the speed
/// holds 88–99 % over 150 tracks, either way round.
#[test]
fn unequal_noise_down_and_across_keeps_every_error_honest() {
    use rollphase::analysis::experiment::tracking::calibration::{
        TrackCase, synthetic_track_and_advance,
    };
    let case = TrackCase {
        period_frames: 30.0,
        noise: 0.0,
        cycles: 20.0,
    };
    let search = PeriodSearch {
        surrogates: 0,
        ..PeriodSearch::default()
    };
    for (down_noise, across_noise) in [(0.2, 0.05), (0.05, 0.2)] {
        let mut held = [0usize; 4];
        let draws = 150;
        for seed in 0..draws {
            let (mut track, advance) = synthetic_track_and_advance(&case, 900 + seed);
            let mut rng = Noise(seed + 1);
            for (d, a) in track.down.iter_mut().zip(track.across.iter_mut()) {
                *d += down_noise * rng.normal();
                *a += across_noise * rng.normal();
            }
            let fit = find_period(&track, &search, &|_, _| {}).unwrap();
            let e = fit.advance_error.unwrap();
            let (v, ve) = fit.velocity.unwrap();
            let checks = [
                (fit.period_frames - 30.0) / fit.period_error_frames,
                (fit.advance_down - advance) / e[0],
                fit.advance_across / e[1],
                (v[0] - advance / 30.0) / ve[0],
            ];
            for (h, z) in held.iter_mut().zip(checks) {
                *h += usize::from(z.abs() <= 1.96);
            }
        }
        for (what, h) in ["period", "advance down", "advance across", "speed"]
            .iter()
            .zip(held)
        {
            let share = h as f64 / draws as f64;
            assert!(
                (0.88..=0.99).contains(&share),
                "noise {down_noise} down, {across_noise} across: {what} holds {share}"
            );
        }
    }
}

/// A track of `frames` frames: a drift, then for each (period, amplitudes) a motion with those
/// harmonics (k-th at `amplitudes[k - 1]`, phases from the seed), white noise `noise`.
fn motions(frames: usize, parts: &[(f64, &[f64])], noise: f64, seed: u64) -> CleanTrack {
    let mut rng = Noise(seed);
    let phases: Vec<[f64; 2]> = (0..parts.len() * 8)
        .map(|_| [rng.uniform() * 6.3, rng.uniform() * 6.3])
        .collect();
    let (mut down, mut across) = (Vec::with_capacity(frames), Vec::with_capacity(frames));
    for i in 0..frames {
        let t = i as f64;
        let (mut d, mut a) = (0.3 * t, 0.0);
        for (j, (period, amplitudes)) in parts.iter().enumerate() {
            for (k, amplitude) in amplitudes.iter().enumerate() {
                let arg = std::f64::consts::TAU * (k + 1) as f64 * t / period;
                let [p, q] = phases[8 * j + k];
                d += amplitude * (arg + p).sin();
                a += 0.6 * amplitude * (arg + q).cos();
            }
        }
        down.push(d + noise * rng.normal());
        across.push(a + noise * rng.normal());
    }
    CleanTrack::on_frames(down, across)
}

/// One test of "it repeats", the harmonics' (found by a hostile tester, 2026-11-28):
/// - two incommensurate motions (30 frames and 30·φ, 30·√2) nearly repeat after 240 frames
///   (8 turns of one against 5 of the other) but no one period describes them: no period over
///   100 turns (over 40, 5 near repeats, the mismatch stays within a period's resolution and
///   the near repeat is stated: a known limit);
/// - a 3.5-frame motion repeats exactly after 7 frames sampled once a frame: too fast, never 7;
/// - a 300-frame motion whose third harmonic dominates is 300 frames, not 100;
/// - a noiseless track's interval holds its period.
#[test]
fn the_harmonics_decide_what_repeats() {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    for (other, seed) in [(30.0 * phi, 1), (30.0 * phi, 2), (30.0 * 2f64.sqrt(), 3)] {
        let track = motions(
            3000,
            &[(30.0, &[1.0, 0.3, 0.1]), (other, &[0.8, 0.2])],
            0.05,
            seed,
        );
        match find_period(&track, &search(), &|_, _| {}) {
            Err(TrackError::NoPeriod { .. }) => {}
            Err(e) => panic!("quasi-periodic ({seed}): {e}"),
            Ok(fit) => panic!(
                "quasi-periodic ({seed}): {} ± {}",
                fit.period_frames, fit.period_error_frames
            ),
        }
    }
    for seed in 0..5 {
        let track = motions(600, &[(3.5, &[1.0, 0.3, 0.1])], 0.02, 40 + seed);
        match find_period(&track, &search(), &|_, _| {}) {
            Err(TrackError::TooFast { period_frames, .. }) => {
                assert!((period_frames - 3.5).abs() < 0.01, "{period_frames}")
            }
            Err(e) => panic!("3.5 frames ({seed}): {e}"),
            Ok(fit) => panic!("3.5 frames ({seed}): {}", fit.period_frames),
        }
    }
    for seed in 0..3 {
        let track = motions(3000, &[(300.0, &[0.05, 0.0, 0.6])], 0.03, 60 + seed);
        let fit = find_period(&track, &search(), &|_, _| {}).unwrap();
        assert!(
            (fit.period_frames - 300.0).abs() < 4.0 * fit.period_error_frames,
            "third harmonic ({seed}): {} ± {}",
            fit.period_frames,
            fit.period_error_frames
        );
    }
    let track = motions(1010, &[(50.5, &[1.0, 0.4])], 0.0, 7);
    let fit = find_period(&track, &search(), &|_, _| {}).unwrap();
    assert!(
        (fit.period_frames - 50.5).abs() < 1.96 * fit.period_error_frames,
        "noiseless: {} ± {}",
        fit.period_frames,
        fit.period_error_frames
    );
    assert!(!fit.block_check.is_some_and(|b| b.turns_vary));
}

/// A noise-free track whose wobble grows by 1 % over 53 turns (a transient still settling, as a
/// simulated run gives) is refused, and the refusal names the drift as a cause beside a second
/// period; with tracking noise 2 % of the wobble, the drift is within what the noise explains
/// and the period (37.3 frames) is read, within its uncertainty.
#[test]
fn a_noise_free_track_whose_wobble_drifts_is_refused_naming_the_drift() {
    let track = |noise: f64| {
        let mut rng = Noise(11);
        let w = std::f64::consts::TAU / 37.3;
        let (mut down, mut across) = (Vec::new(), Vec::new());
        for i in 0..2000 {
            let (t, grow) = (i as f64, 1.0 + 0.01 * i as f64 / 2000.0);
            down.push(0.13 * t + 3.0 * grow * (w * t).sin() + 0.7 * (2.0 * w * t + 0.4).sin());
            across.push(2.0 * grow * (w * t + 0.3).cos());
        }
        for v in down.iter_mut().chain(across.iter_mut()) {
            *v += noise * 3.0 * rng.normal();
        }
        CleanTrack::on_frames(down, across)
    };
    match find_period(&track(0.0), &search(), &|_, _| {}) {
        Err(e @ TrackError::NoPeriod { .. }) => {
            let why = e.to_string();
            assert!(why.contains("a transient not yet settled"), "{why}");
            assert!(why.contains("quasi-periodic"), "{why}");
        }
        Err(e) => panic!("refused for another reason: {e}"),
        Ok(fit) => panic!(
            "read as {} ± {}",
            fit.period_frames, fit.period_error_frames
        ),
    }
    let fit = find_period(&track(0.02), &search(), &|_, _| {}).unwrap();
    assert!(
        (fit.period_frames - 37.3).abs() < 1.96 * fit.period_error_frames,
        "{} ± {}",
        fit.period_frames,
        fit.period_error_frames
    );
}

/// A periodic track in absurd units is refused by name, not read as a straight line at
/// constant speed (once its squares overflowed to infinity, and the period search said so).
#[test]
fn a_track_too_large_to_square_is_refused_by_name() {
    use rollphase::analysis::experiment::tracking::{MAX_POSITION, clean};
    let t = periodic(600, 20.0, 0.5, 0.05, 3);
    let scaled = |k: f64| -> Vec<f64> { t.down.iter().map(|v| v * k).collect() };
    let e = clean(&t.frames, &scaled(1e300), &t.across).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("too large for the period search") && text.contains("1e100"),
        "{text}"
    );
    // At the bound's scale the track is still a track, and its period the same.
    let k = 0.5 * MAX_POSITION / t.down.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let big = clean(&t.frames, &scaled(k), &t.across).unwrap();
    let fit = find_period(&big, &search(), &|_, _| {}).unwrap();
    assert!(
        (fit.period_frames - 20.0).abs() < 0.2,
        "{}",
        fit.period_frames
    );
}

/// Gaps that recur are bridged the same way each time, so on their own they repeat: a 12.5-frame
/// track with one frame missing every 20 repeated best after 50 frames and was stated so, exit 0.
/// Where a fraction of the period repeats as well on the measured frames alone, no period is
/// stated and the error names the fraction; gaps once a turn (a marker hidden at the same phase)
/// and gaps on a track whose period the search already finds leave the answer as it was.
#[test]
fn recurring_gaps_never_make_a_multiple_of_the_period() {
    let with_gaps = |period: f64, every: usize, missing: usize| {
        let t = periodic(1500, period, 0.4, 0.01, 7);
        let keep: Vec<usize> = (0..1500).filter(|i| i % every >= missing).collect();
        let pick = |v: &[f64]| keep.iter().map(|&i| v[i]).collect::<Vec<f64>>();
        measure(
            &pick(&t.frames),
            &pick(&t.down),
            &pick(&t.across),
            &|_, _| {},
        )
    };
    let mut refused = 0;
    for (period, every, missing) in [(12.5, 20, 1), (12.5, 20, 2), (8.3, 15, 1), (6.5, 10, 1)] {
        match with_gaps(period, every, missing) {
            Err(TrackError::NoPeriod { why, .. }) => {
                assert!(
                    why.contains("measured frames alone") && why.contains(&format!("{period:.2}")),
                    "{period}: {why}"
                );
                refused += 1;
            }
            Ok((_, fit)) => assert!(
                (fit.period_frames - period).abs() < 0.05,
                "{period} with {missing} missing every {every}: stated {}",
                fit.period_frames
            ),
            Err(e) => panic!("{period}: {e}"),
        }
    }
    // These seeded tracks: until 2026-12-04 two were refused (a fraction of the search's repeat
    // repeated as well on the measured frames). Since the multiples of a multiple are tried in
    // turn, the search reaches the gaps' common repeat with the turns (100 frames for 12.5 and
    // 20), seen too few times for a period of eight turns, and the turn is the period: all four
    // come back right (the arm above holds each to 0.05 frames), none refused.
    assert_eq!(refused, 0);
    // The same gaps written as empty cells (rows kept, NaN where the tracker lost the body), as
    // Tracker and trackpy export them: refused alike.
    let t = periodic(1500, 12.5, 0.4, 0.01, 7);
    let blank = |v: &[f64]| -> Vec<f64> {
        v.iter()
            .enumerate()
            .map(|(i, &x)| if i % 20 == 0 { f64::NAN } else { x })
            .collect()
    };
    match measure(&t.frames, &blank(&t.down), &blank(&t.across), &|_, _| {}) {
        Err(TrackError::NoPeriod { why, .. }) => assert!(why.contains("12.50"), "{why}"),
        Ok((_, fit)) => assert!(
            (fit.period_frames - 12.5).abs() < 0.05,
            "{}",
            fit.period_frames
        ),
        Err(e) => panic!("{e}"),
    }
    for (period, every, missing) in [(20.0, 20, 1), (40.0, 40, 2), (30.0, 40, 3), (17.3, 25, 2)] {
        let (_, fit) = with_gaps(period, every, missing).unwrap();
        assert!(
            (fit.period_frames - period).abs() < 0.05,
            "{period}: {}",
            fit.period_frames
        );
    }
}

/// A tracker that writes whole pixels moves a slow body by 0 or 1 of them a frame: the median
/// step is 0, and every pixel step was called a jump ("1390 of 3000 frames jump …: the tracker
/// lost the body too often", a helper's finding, for a 3-pixel wobble of 61.7 frames). The
/// positions' quantum is now the least scale of a jump; the period comes back, shown closely
/// from a 3-pixel wobble up. (The rounding of a 1.5-pixel wobble is not white noise: it leaves
/// 3.2 times what its third differences explain, and reads `roughly`.)
#[test]
fn whole_pixel_tracks_of_a_slow_body_are_read() {
    for (wobble, period) in [(1.5, 61.7), (3.0, 61.7), (5.0, 150.3)] {
        let w = std::f64::consts::TAU / period;
        let frames: Vec<f64> = (0..3000).map(f64::from).collect();
        let down: Vec<f64> = frames
            .iter()
            .map(|&t| (2.0 * wobble * t / period + wobble * (w * t).sin()).round())
            .collect();
        let across: Vec<f64> = frames
            .iter()
            .map(|&t| (0.7 * wobble * (w * t).cos()).round())
            .collect();
        let (track, fit) = measure(&frames, &down, &across, &|_, _| {})
            .unwrap_or_else(|e| panic!("{wobble} px, {period} frames: {e}"));
        assert!(
            (fit.period_frames - period).abs() < 0.01 * period,
            "{wobble} px: {} frames for {period}",
            fit.period_frames
        );
        let rows: Vec<(f64, f64, f64)> =
            (0..3000).map(|i| (frames[i], down[i], across[i])).collect();
        let shown = repeat_shown(&rows, &track, &fit, None);
        assert!(
            wobble < 2.0 || matches!(shown, RepeatShown::Closely { .. }),
            "{wobble} px, {period} frames: {shown:?}"
        );
    }
}

/// A noise-free circle written to six decimals repeats exactly only after a whole number of
/// frames (the file's rounding repeats with the samples): 29.4 frames came back as 147, 21.7 as
/// 43.4 and 12.3 as 24.6, `closely`, with errors of 1e-8 s, and 20.16 was refused (a helper's
/// finding, 2026-12-04). The rounding's harmonics, a millionth of the circle's power, are no
/// longer significant, and every period comes back.
#[test]
fn a_noise_free_circle_in_a_rounded_file_gets_its_own_period() {
    for period in [7.84, 12.3, 18.62, 20.16, 21.7, 29.4, 32.48, 35.56, 37.1] {
        let w = std::f64::consts::TAU / period;
        let frames: Vec<f64> = (0..3000).map(f64::from).collect();
        let six = |v: f64| (v * 1e6).round() / 1e6;
        let down: Vec<f64> = frames
            .iter()
            .map(|&t| six(0.1 * t + 0.5 * (w * t).cos()))
            .collect();
        let across: Vec<f64> = frames.iter().map(|&t| six(0.5 * (w * t).sin())).collect();
        let (_, fit) = measure(&frames, &down, &across, &|_, _| {})
            .unwrap_or_else(|e| panic!("{period} frames: {e}"));
        assert!(
            (fit.period_frames - period).abs() < 1e-4,
            "{period} frames came back as {}",
            fit.period_frames
        );
    }
}
