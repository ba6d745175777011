//! The designed body on the bench: what the model predicts it does on each target's ramp (the
//! stable orbits, each with its share of the starts and that share's 95 % interval), in
//! millimetres and seconds at the printed scale, so the numbers can be checked against a film.
//!
//! Seconds need the time unit t0 = γ/(F⟨r⟩). With inertia the drive is the weight and
//! m/m0 = ⟨r⟩/(g t0²) fixes it: t0 = √(⟨r⟩/(g · m/m0)). In the viscous model t0 depends on the
//! liquid's drag, which the design does not know: times there stay in t0 (one filmed period
//! fixes t0; `track` does that).
//!
//! The share's interval is Wilson's score interval, written out here rather than taken from a
//! crate: it is three lines, and the statistics crates in the tree offer the binomial
//! distribution but not this interval.

use serde::Serialize;

use super::check::Band;
use super::targets::{ORBITS_STARTS, Setting, Target, TargetError, prediction};
use crate::analysis::experiment::tracking::model::{G, t0_for_mass_ratio};
use crate::dynamics::models::asks_for_inertia;
use crate::geometry::Body;

/// What the body does on one ramp.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RampPrediction {
    /// Why this ramp: the target it stands for.
    pub why: String,
    /// α (rad).
    pub alpha: f64,
    /// m/m0 (0: viscous).
    pub mass_ratio: f64,
    /// ⟨r⟩ (mm).
    pub scale_mm: f64,
    /// The time unit t0 (s) at this m/m0 and scale; `None` in the viscous model, where it
    /// depends on the liquid.
    pub t0_s: Option<f64>,
    /// Starts from rest run (random orientations for a sphere, spaced contact angles for a
    /// cylinder).
    pub starts: usize,
    /// Share of the starts that come to rest.
    pub halted: f64,
    /// Share of the starts that reach no stable orbit (an orbit off the model, a neutral one,
    /// or undecided).
    pub elsewhere: f64,
    /// The orbits the starts reach, most visited first.
    pub orbits: Vec<OrbitAtScale>,
}

/// One orbit, at the printed scale.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OrbitAtScale {
    /// 1, or 2 for a doubled orbit (its period and advances are per repeat).
    pub repeat: usize,
    /// It attracts and stays on the ramp.
    pub stable: bool,
    /// Starts that settle on it.
    pub starts: usize,
    /// Their share of the starts.
    pub share: f64,
    /// The share's 95 % interval (Wilson).
    pub share_95: [f64; 2],
    /// Time to repeat (t0).
    pub period_t0: f64,
    /// … in seconds, where t0 is known.
    pub period_s: Option<f64>,
    /// Advance down the ramp per repeat (mm).
    pub advance_down_mm: f64,
    /// Advance across per repeat (mm; + is the lab's y).
    pub advance_across_mm: f64,
    /// Mean speed down the ramp (mm/s), where t0 is known.
    pub speed_mm_s: Option<f64>,
    /// Heading off straight down, atan(across/down) (degrees).
    pub heading_deg: f64,
}

/// Wilson's 95 % score interval of a share `k` of `n`.
///
/// # Example
/// ```
/// use rollphase_core::analysis::design::at_scale::wilson_95;
/// // Newcombe (Stat. Med. 1998, table II): 81/263 → 0.2553–0.3662, 0/20 → 0–0.1611.
/// let [lo, hi] = wilson_95(81, 263);
/// assert!((lo - 0.2553).abs() < 1e-4 && (hi - 0.3662).abs() < 1e-4);
/// let [lo, hi] = wilson_95(0, 20);
/// assert!(lo == 0.0 && (hi - 0.1611).abs() < 1e-4);
/// assert_eq!(wilson_95(10, 10)[1], 1.0);
/// ```
pub fn wilson_95(k: usize, n: usize) -> [f64; 2] {
    if n == 0 {
        return [0.0, 1.0];
    }
    let (z, n) = (1.959_963_984_540_054, n as f64);
    let p = k as f64 / n;
    let centre = (p + z * z / (2.0 * n)) / (1.0 + z * z / n);
    let half = z / (1.0 + z * z / n) * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt();
    // At 0 of n and n of n the bounds are 0 and 1 exactly; rounding would leave 1e-16 off.
    [
        if k == 0 { 0.0 } else { centre - half },
        if k as f64 == n { 1.0 } else { centre + half },
    ]
}

/// The ramps a design's report predicts on, one per target, each once: a 3D target's own
/// (α, m/m0); for a cylinder's α* or hysteresis target, just above the design's `alpha_star`
/// (by the band's δα, at least 0.005 rad), viscous or at the hysteresis target's m/m0, where
/// the check says it rolls.
///
/// # Example
/// ```
/// use rollphase_core::analysis::design::{Band, Target, at_scale::ramps};
/// let band = Band { delta_alpha: 0.01, mass_fraction: 0.2, surface_mm: 0.05, draws: 4, seed: 1 };
/// let targets = [Target::AlphaStar { alpha: 0.2 }, Target::Doubling { mass: 2.5, alpha: 0.2014 }];
/// let r = ramps(&targets, 0.2, &band);
/// assert!((r[0].1 - 0.21).abs() < 1e-15 && r[0].2 == 0.0);
/// assert_eq!((r[1].1, r[1].2), (0.2014, 2.5));
/// ```
pub fn ramps(targets: &[Target], alpha_star: f64, band: &Band) -> Vec<(String, f64, f64)> {
    let above = alpha_star + band.delta_alpha.max(0.005);
    let mut out: Vec<(String, f64, f64)> = Vec::new();
    for t in targets {
        let (alpha, mass) = match *t {
            Target::AlphaStar { .. } => (above, 0.0),
            Target::Hysteresis { mass, .. } => (above, mass),
            Target::Doubling { mass, alpha } => (alpha, mass),
            Target::Drift { alpha, mass, .. } | Target::Orbits { alpha, mass, .. } => (alpha, mass),
        };
        if !out.iter().any(|(_, a, m)| *a == alpha && *m == mass) {
            out.push((t.describe(), alpha, mass));
        }
    }
    out
}

/// What `body` does at (`alpha`, `mass`) at `setting` ([`ORBITS_STARTS`] times its starts), at
/// `scale_mm` per ⟨r⟩.
///
/// # Example
/// ```
/// use rollphase_core::analysis::design::{Setting, at_scale::predict_at_scale};
/// use rollphase_core::geometry::Body;
/// // The paper's sphere at 10 mm, sin α = 0.2, m/m0 = 2.5: t0 = √(1 cm / (g · 2.5)) ≈ 20 ms.
/// let body = Body::paper_sphere(219, 0.25, 5)?;
/// let p = predict_at_scale(&body, "", 0.2014, 2.5, 10.0, &Setting::FAST)?;
/// assert!((p.t0_s.unwrap() - 0.02019).abs() < 1e-5);
/// let o = &p.orbits[0];
/// assert!((o.period_s.unwrap() - o.period_t0 * p.t0_s.unwrap()).abs() < 1e-12);
/// assert!(o.advance_down_mm > 0.0 && o.share_95[0] <= o.share && o.share <= o.share_95[1]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn predict_at_scale(
    body: &Body,
    why: &str,
    alpha: f64,
    mass: f64,
    scale_mm: f64,
    setting: &Setting,
) -> Result<RampPrediction, TargetError> {
    let p = prediction(body, alpha, mass, ORBITS_STARTS, setting)?;
    let t0_s = asks_for_inertia(mass).then(|| t0_for_mass_ratio(mass, scale_mm / 1000.0, G));
    let n = p.starts;
    let orbits: Vec<OrbitAtScale> = p
        .orbits
        .iter()
        .map(|o| OrbitAtScale {
            repeat: o.repeat,
            stable: o.stable,
            starts: o.starts,
            share: o.fraction,
            share_95: wilson_95(o.starts, n),
            period_t0: o.period,
            period_s: t0_s.map(|t0| o.period * t0),
            advance_down_mm: o.advance_down * scale_mm,
            advance_across_mm: o.advance_across * scale_mm,
            speed_mm_s: t0_s.map(|t0| o.advance_down * scale_mm / (o.period * t0)),
            heading_deg: o.advance_across.atan2(o.advance_down).to_degrees(),
        })
        .collect();
    let on_stable: usize = orbits.iter().filter(|o| o.stable).map(|o| o.starts).sum();
    Ok(RampPrediction {
        why: why.to_string(),
        alpha,
        mass_ratio: mass,
        scale_mm,
        t0_s,
        starts: n,
        halted: p.fates.halted,
        elsewhere: (1.0 - p.fates.halted - on_stable as f64 / n.max(1) as f64).max(0.0),
        orbits,
    })
}
