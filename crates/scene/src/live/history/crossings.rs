//! One body's settled crossings of ∂Ω against m/m0, the points of the mass sweep's plot
//! (the orbit diagram): taken from its snapshots once the run has found its cycle, one point
//! per crossing that a pixel could tell from the ones already kept.

use std::collections::{BTreeMap, VecDeque};

use super::super::Snapshot;
use super::{Regime, SettledCycle, sweep_bin};

/// Crossing points kept for the mass sweep (a saved state's may give no more).
pub(super) use crate::scene::MAX_CROSSING_POINTS;

/// A settled crossing this close (rad of the plotted angle, far below a pixel at any plot size)
/// to one already kept at the same m/m0 adds nothing: a run held at one value repeats its
/// cycle's points for ever (a sweep that ended at m/m0 = 50 piled ~1,400 near-duplicates
/// there, 67 KB in a saved state).
const SAME_CROSSING: f64 = 1e-3;

/// How many of the latest points a new one is compared with: more than the points of any
/// cycle the app tells apart.
const CROSSINGS_COMPARED: usize = 256;

/// One body's settled crossings: (m/m0, polar angle of the crossing point with p_z ≥ 0),
/// oldest first, each with the drag law it was measured under (a point at one m/m0 under
/// another law is another orbit: kept apart, as the 1/T plot keeps its regimes), and the time
/// of the last crossing taken.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct Crossings {
    pub(super) points: VecDeque<[f64; 2]>,
    /// The drag law of each point ([`crate::dynamics::DragLaw::label`]), in `points`' order.
    pub(super) laws: VecDeque<String>,
    last_t: Option<f64>,
    /// The run's latest decided cycle at each α (its sweep bin) and regime, from the live run's
    /// one test of a repeat: what a lesson's period claim is checked against. Not kept in a
    /// saved state.
    pub(super) cycles: BTreeMap<(Regime, i64), SettledCycle>,
    /// Where the body first left the model (lift-off, slip) at each α and regime: why no cycle
    /// is claimed there. Not kept in a saved state.
    pub(super) left_model: BTreeMap<(Regime, i64), String>,
}

impl Crossings {
    /// Points as a saved state keeps them (the newest [`MAX_CROSSING_POINTS`]), each under its
    /// law in `laws` (one per point), or under `law` where the file names none.
    pub(super) fn from_points(points: &[[f64; 2]], laws: &[String], law: &str) -> Self {
        let skip = points.len().saturating_sub(MAX_CROSSING_POINTS);
        let laws: VecDeque<String> = if laws.len() == points.len() {
            laws[skip..].iter().cloned().collect()
        } else {
            vec![law.to_string(); points.len() - skip].into()
        };
        Self {
            points: points[skip..].iter().copied().collect(),
            laws,
            last_t: None,
            cycles: BTreeMap::new(),
            left_model: BTreeMap::new(),
        }
    }

    /// Takes in the crossings of the cycle `snap` shows that are new since the last call, once
    /// its run's cycle is decided (`period_multiplicity`) and while the body is within the model
    /// (no lift-off or slip). All the cycle's new crossings count, so a plot fed at sparse
    /// frames (a headless render of three frames) shows every branch the verdict names. Also
    /// notes the cycle itself, or the body leaving the model, at the snapshot's α and regime.
    pub(super) fn take(&mut self, snap: &Snapshot) {
        let key = (Regime::of(snap), sweep_bin(snap.alpha_rad));
        if let Some(why) = &snap.validity {
            self.left_model.entry(key).or_insert_with(|| why.clone());
            return;
        }
        let Some(k) = snap.period_multiplicity else {
            return;
        };
        if let Some(period) = snap.cycle_period {
            let n = snap.cycle_crossings.len();
            self.cycles.insert(
                key,
                SettledCycle {
                    multiplicity: k,
                    period,
                    seen_at: snap.t,
                    angles: snap.cycle_crossings[n.saturating_sub(k)..]
                        .iter()
                        .map(|&(_, p)| polar_angle(p))
                        .collect(),
                },
            );
        }
        for &(t, p) in &snap.cycle_crossings {
            if self.last_t.is_some_and(|last| t <= last) {
                continue;
            }
            self.take_point(snap.mass_ratio, &snap.drag_law.label(), p);
            self.last_t = Some(t);
        }
    }

    fn take_point(&mut self, mass_ratio: f64, law: &str, p: glam::DVec3) {
        // The viscous model is the massless limit: its crossings are the diagram's points at
        // m/m0 = 0 (a lesson's first step claims period 1 there).
        let point = [mass_ratio, polar_angle(p)];
        let seen = self
            .points
            .iter()
            .zip(&self.laws)
            .rev()
            .take(CROSSINGS_COMPARED)
            .any(|(q, l)| q[0] == point[0] && l == law && (q[1] - point[1]).abs() < SAME_CROSSING);
        if !seen {
            self.points.push_back(point);
            self.laws.push_back(law.to_string());
            while self.points.len() > MAX_CROSSING_POINTS {
                self.points.pop_front();
                self.laws.pop_front();
            }
        }
    }

    /// The points measured under the drag law `law`.
    pub(super) fn under(&self, law: &str) -> Vec<[f64; 2]> {
        self.points
            .iter()
            .zip(&self.laws)
            .filter(|(_, l)| *l == law)
            .map(|(p, _)| *p)
            .collect()
    }
}

/// The plotted angle of a crossing point of ∂Ω: its polar angle, antipodes identified (p_z ≥ 0).
fn polar_angle(p: glam::DVec3) -> f64 {
    let p = if p.z < 0.0 { -p } else { p };
    p.z.clamp(-1.0, 1.0).acos()
}
