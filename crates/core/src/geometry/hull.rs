//! The convex hull of a 2D body that is not convex (issue 34): a real cylinder with a dent
//! rolls on its hull, on the curve where the curve is on the hull and across a dent on the
//! straight **bridge** that spans it (a flat of the hull, tangent to the curve at both ends).
//!
//! A bridge is found on a dense sample of the curve (Andrew's monotone chain: samples skipped
//! by the hull lie under a bridge), then its two tangent points are refined by Newton's method
//! on the bitangent condition p′(θ_a) × (p_b − p_a) = 0 = p′(θ_b) × (p_b − p_a), to round-off.
//! Why our own: the hull of one closed star-shaped curve sampled in angle order is twenty lines,
//! and the refinement needs the curve's exact derivatives, which no hull crate takes.

use std::f64::consts::TAU;

use super::disk::Disk;

/// Samples of the curve the hull is found on (then refined): 4096, a spacing of 1.5e-3 rad, far
/// below the width of any dent a mode l ≤ 64 can make.
const HULL_GRID: usize = 4096;

/// One flat of the hull: the segment from the body point at θ_a to the one at θ_b (θ_b > θ_a,
/// less than a turn later), tangent to the curve at both ends. While the body rolls forward (θ
/// increasing) the contact reaches θ_a first; P_b is then the downhill end.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Bridge {
    /// Where the bridge leaves the curve, in [0, 2π).
    pub theta_a: f64,
    /// Where it meets the curve again, θ_a < θ_b < θ_a + 2π.
    pub theta_b: f64,
    /// Its length |P_b − P_a|.
    pub length: f64,
    /// The centre's distance from the bridge's line (the centre's height when the bridge lies on
    /// the ramp).
    pub height: f64,
    /// Where the centre's normal foot lies along the bridge, from P_a towards P_b.
    pub foot: f64,
    /// How far the curve dips below the bridge at its deepest (the dent's depth).
    pub depth: f64,
}

impl Bridge {
    /// Whether contact angle θ (any turn) lies strictly inside the bridge's span of the body.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::hull::Bridge;
    /// let b = Bridge { theta_a: 6.0, theta_b: 6.5, length: 0.5, height: 0.9, foot: 0.2, depth: 0.01 };
    /// assert!(b.spans(6.2) && b.spans(0.1) && !b.spans(0.3) && !b.spans(6.0));
    /// ```
    pub fn spans(&self, theta: f64) -> bool {
        let t = (theta - self.theta_a).rem_euclid(TAU);
        t > 0.0 && t < self.theta_b - self.theta_a
    }

    /// The largest α at which the body can rest on this bridge while it rolls forward: the
    /// weight's line through the centre still meets the ramp before the downhill end P_b,
    /// tan α = (L − foot)/height (`None` if it never can). A regular N-gon gives π/N.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::hull::Bridge;
    /// // A square's side: length 2 sin(π/4) at height cos(π/4), the foot at its middle.
    /// let s = std::f64::consts::FRAC_PI_4;
    /// let b = Bridge { theta_a: 0.0, theta_b: 1.0, length: 2.0 * s.sin(), height: s.cos(), foot: s.sin(), depth: 0.1 };
    /// assert!((b.rest_angle().unwrap() - s).abs() < 1e-15);
    /// ```
    pub fn rest_angle(&self) -> Option<f64> {
        let reach = self.length - self.foot;
        (reach > 0.0).then(|| reach.atan2(self.height))
    }
}

/// The convex hull of a 2D body, as the bridges over its dents (none for a convex body).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DiskHull {
    bridges: Vec<Bridge>,
}

/// The point of the curve at θ and its first two θ-derivatives.
fn curve(d: &Disk, theta: f64) -> ([f64; 2], [f64; 2], [f64; 2]) {
    let j = d.jet(theta);
    let (s, c) = theta.sin_cos();
    let p = [j.r * c, j.r * s];
    let p1 = [j.r1 * c - j.r * s, j.r1 * s + j.r * c];
    let p2 = [
        (j.r2 - j.r) * c - 2.0 * j.r1 * s,
        (j.r2 - j.r) * s + 2.0 * j.r1 * c,
    ];
    (p, p1, p2)
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

impl DiskHull {
    /// The hull of `disk`.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode, hull::DiskHull};
    /// // A strong l = 3 mode dents the circle three times: three bridges.
    /// let dented = Disk::new(vec![DiskMode { l: 3, a: 2.0, phase: 0.0 }]);
    /// assert_eq!(DiskHull::of(&dented).bridges().len(), 3);
    /// assert!(DiskHull::of(&Disk::perfect()).bridges().is_empty());
    /// ```
    pub fn of(disk: &Disk) -> DiskHull {
        let n = HULL_GRID;
        // A convex curve is its own hull: only a dented one pays for the search.
        if (0..n).all(|i| disk.jet(i as f64 * TAU / n as f64).convexity() > 0.0) {
            return DiskHull::default();
        }
        let pts: Vec<[f64; 2]> = (0..n)
            .map(|i| curve(disk, i as f64 * TAU / n as f64).0)
            .collect();
        let on_hull = hull_vertices(&pts);
        if on_hull.len() == n {
            return DiskHull::default();
        }
        // Runs of samples the hull skips: each lies under one bridge from the hull vertex
        // before it to the one after.
        let start = (0..n).find(|&i| on_hull.contains(&i)).unwrap_or(0);
        let mut bridges = Vec::new();
        let mut prev = start;
        for k in 1..=n {
            let i = (start + k) % n;
            if !on_hull.contains(&i) {
                continue;
            }
            let gap = (i + n - prev) % n;
            if gap > 1 {
                let ta = prev as f64 * TAU / n as f64;
                let tb = ta + gap as f64 * TAU / n as f64;
                if let Some(b) = refine(disk, ta, tb) {
                    bridges.push(b);
                }
            }
            prev = i;
        }
        bridges.sort_by(|a, b| a.theta_a.total_cmp(&b.theta_a));
        DiskHull { bridges }
    }

    /// A hull given by its bridges (a printed polygon's sides, [`super::outline`]), sorted by
    /// θ_a.
    pub(crate) fn from_bridges(mut bridges: Vec<Bridge>) -> DiskHull {
        bridges.sort_by(|a, b| a.theta_a.total_cmp(&b.theta_a));
        DiskHull { bridges }
    }

    /// Its bridges, by θ_a.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode, hull::DiskHull};
    /// let dented = Disk::new(vec![DiskMode { l: 2, a: 1.6, phase: 0.0 }]);
    /// let hull = DiskHull::of(&dented);
    /// assert!(hull.bridges().iter().all(|b| b.depth > 0.0 && b.length > 0.0));
    /// ```
    pub fn bridges(&self) -> &[Bridge] {
        &self.bridges
    }

    /// The bridge whose span holds contact angle θ, if any.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode, hull::DiskHull};
    /// let dented = Disk::new(vec![DiskMode { l: 3, a: 2.0, phase: 0.0 }]);
    /// let hull = DiskHull::of(&dented);
    /// let b = hull.bridges()[0];
    /// assert_eq!(hull.bridge_at(0.5 * (b.theta_a + b.theta_b)), Some(&b));
    /// assert_eq!(hull.bridge_at(b.theta_a - 0.01), None);
    /// ```
    pub fn bridge_at(&self, theta: f64) -> Option<&Bridge> {
        self.bridges.iter().find(|b| b.spans(theta))
    }
}

/// Indices of the samples on the convex hull (Andrew's monotone chain). Points within round-off
/// of a hull edge count as on it, so a convex curve keeps every sample.
fn hull_vertices(pts: &[[f64; 2]]) -> std::collections::HashSet<usize> {
    let mut order: Vec<usize> = (0..pts.len()).collect();
    order.sort_by(|&a, &b| {
        pts[a][0]
            .total_cmp(&pts[b][0])
            .then(pts[a][1].total_cmp(&pts[b][1]))
    });
    let turn = |o: usize, a: usize, b: usize| cross(sub(pts[a], pts[o]), sub(pts[b], pts[o]));
    let chain = |iter: &mut dyn Iterator<Item = usize>| {
        let mut h: Vec<usize> = Vec::new();
        for i in iter {
            while h.len() >= 2 && turn(h[h.len() - 2], h[h.len() - 1], i) < -1e-13 {
                h.pop();
            }
            h.push(i);
        }
        h
    };
    let lower = chain(&mut order.iter().copied());
    let upper = chain(&mut order.iter().rev().copied());
    lower.into_iter().chain(upper).collect()
}

/// The bridge between the sampled hull vertices at `ta` and `tb`, its tangent points refined by
/// Newton's method on the bitangent condition; `None` for a gap that round-off made.
fn refine(d: &Disk, mut ta: f64, mut tb: f64) -> Option<Bridge> {
    for _ in 0..60 {
        let (pa, a1, a2) = curve(d, ta);
        let (pb, b1, b2) = curve(d, tb);
        let chord = sub(pb, pa);
        let f = [cross(a1, chord), cross(b1, chord)];
        let j = [
            [cross(a2, chord), cross(a1, b1)],
            [cross(a1, b1), cross(b2, chord)],
        ];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if det == 0.0 || !det.is_finite() {
            break;
        }
        let da = (f[0] * j[1][1] - f[1] * j[0][1]) / det;
        let db = (j[0][0] * f[1] - j[1][0] * f[0]) / det;
        // Newton from within a sample spacing: steps stay small.
        let limit = 4.0 * TAU / HULL_GRID as f64;
        ta -= da.clamp(-limit, limit);
        tb -= db.clamp(-limit, limit);
        if da.abs().max(db.abs()) < 1e-15 {
            break;
        }
    }
    let (pa, _, _) = curve(d, ta);
    let (pb, _, _) = curve(d, tb);
    let chord = sub(pb, pa);
    let length = chord[0].hypot(chord[1]);
    if length.is_nan() || length <= 1e-9 || tb <= ta {
        return None;
    }
    let u = [chord[0] / length, chord[1] / length];
    // The centre (origin) lies on the inner side: its distance from the line, and its foot.
    let height = cross(u, sub([0.0, 0.0], pa)).abs();
    let foot = -(pa[0] * u[0] + pa[1] * u[1]);
    let depth = (1..64)
        .map(|k| {
            let p = curve(d, ta + (tb - ta) * k as f64 / 64.0).0;
            cross(u, sub(p, pa)).abs()
        })
        .fold(0.0, f64::max);
    if depth < 1e-12 {
        return None;
    }
    let theta_a = ta.rem_euclid(TAU);
    Some(Bridge {
        theta_a,
        theta_b: theta_a + (tb - ta),
        length,
        height,
        foot,
        depth,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::DiskMode;

    #[test]
    fn bridges_are_tangent_at_both_ends_and_the_curve_stays_inside() {
        for (l, a, phase) in [(3, 2.0, 0.0), (2, 1.6, 0.4), (5, 4.0, 1.0)] {
            let d = Disk::new(vec![DiskMode { l, a, phase }]);
            let hull = DiskHull::of(&d);
            assert_eq!(hull.bridges().len(), l as usize, "l = {l}");
            for b in hull.bridges() {
                let (pa, a1, _) = curve(&d, b.theta_a);
                let (pb, b1, _) = curve(&d, b.theta_b);
                let chord = sub(pb, pa);
                let unit = |v: [f64; 2]| {
                    let n = v[0].hypot(v[1]);
                    [v[0] / n, v[1] / n]
                };
                assert!(cross(unit(a1), unit(chord)).abs() < 1e-12);
                assert!(cross(unit(b1), unit(chord)).abs() < 1e-12);
                // Every point of the curve lies on the centre's side of the bridge's line.
                for i in 0..2000 {
                    let p = curve(&d, i as f64 * TAU / 2000.0).0;
                    assert!(cross(chord, sub(p, pa)) >= -1e-12);
                }
                assert!((b.length - chord[0].hypot(chord[1])).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn a_three_lobed_body_rests_on_its_flats_up_to_the_triangle_angle() {
        // l = 3 with a large amplitude: lobes at the corners of a near-triangle. The flats'
        // rest angle is the same for all three (symmetry), a little under π/3 (the lobes are
        // round, not corners).
        let d = Disk::new(vec![DiskMode {
            l: 3,
            a: 2.0,
            phase: 0.0,
        }]);
        let angles: Vec<f64> = DiskHull::of(&d)
            .bridges()
            .iter()
            .map(|b| b.rest_angle().unwrap())
            .collect();
        assert!(angles.iter().all(|a| (a - angles[0]).abs() < 1e-9));
        assert!(angles[0] > 0.3 && angles[0] < std::f64::consts::FRAC_PI_3);
    }
}
