//! The outline a faceted print rolls on: its section's convex polygon
//! ([`super::facets::PrintedSection`]) with each corner rounded to a small circular arc, as a
//! radius function r(θ) with exact derivatives to r''' and the polygon's sides as the
//! [`super::hull::Bridge`]s of the hull model dented cylinders already roll on.
//!
//! Why rounded: the 2D models follow the contact angle θ, and a sharp corner is a single θ about
//! which the body turns; a corner of radius ρ is an arc the contact crosses while the body turns
//! by the corner's exterior angle, which the curve equations already describe. The viscous body
//! then pivots over each corner and tips instantly across each side
//! ([`crate::dynamics::disk2d`]); the inertial one strikes the ramp with each side's far end,
//! the rimless wheel's impact. A side resting on the ramp holds the body while the weight's line
//! falls inside it, up to atan(reach/height): for a regular N-gon of apothem d,
//! tan α* = (1 − ρ/d) tan(π/N), so α* is π/N to a relative 1e-4 at [`CORNER_RADIUS`]. Every
//! printer rounds its corners more than that (half a nozzle, 0.1–0.2 mm); the flats' rest angle
//! does not depend on it to that order.
//!
//! Why our own: a polygon's rounded outline is a few closed forms; its jets are taken with a
//! third-order Taylor arithmetic (four coefficients) rather than a crate for one square root and
//! one reciprocal.

use std::f64::consts::TAU;

use super::facets::PrintedSection;
use super::hull::Bridge;

/// Radius of each rounded corner, in units of ⟨r⟩ (0.01 mm on a 10 mm body), where the sides
/// allow it (a corner never takes more than 45 % of a side).
pub const CORNER_RADIUS: f64 = 1e-3;

/// How far past a corner's end (rad) its arc is still used: round-off in a bridge end's angle.
const END_SLACK: f64 = 1e-12;

/// A truncated Taylor series c₀ + c₁h + c₂h² + c₃h³.
#[derive(Debug, Clone, Copy)]
struct Taylor3([f64; 4]);

impl Taylor3 {
    fn add(self, o: Taylor3) -> Taylor3 {
        Taylor3(std::array::from_fn(|k| self.0[k] + o.0[k]))
    }

    fn mul(self, o: Taylor3) -> Taylor3 {
        Taylor3(std::array::from_fn(|k| {
            (0..=k).map(|i| self.0[i] * o.0[k - i]).sum()
        }))
    }

    fn scale(self, s: f64) -> Taylor3 {
        Taylor3(self.0.map(|c| c * s))
    }

    fn sqrt(self) -> Taylor3 {
        let a = self.0;
        let s0 = a[0].sqrt();
        let s1 = a[1] / (2.0 * s0);
        let s2 = (a[2] - s1 * s1) / (2.0 * s0);
        let s3 = (a[3] - 2.0 * s1 * s2) / (2.0 * s0);
        Taylor3([s0, s1, s2, s3])
    }

    fn recip(self) -> Taylor3 {
        let a = self.0;
        let mut q = [1.0 / a[0], 0.0, 0.0, 0.0];
        for k in 1..4 {
            q[k] = -(1..=k).map(|i| a[i] * q[k - i]).sum::<f64>() / a[0];
        }
        Taylor3(q)
    }

    /// The value and first three derivatives.
    fn derivatives(self) -> [f64; 4] {
        [self.0[0], self.0[1], 2.0 * self.0[2], 6.0 * self.0[3]]
    }
}

/// One rounded corner: the arc of the circle about `centre` of radius `radius`, met by contact
/// angles from `start` to `end`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Corner {
    start: f64,
    end: f64,
    centre: [f64; 2],
    radius: f64,
}

/// A flat side after corner `k`: the line at distance `distance` from the centre with outward
/// normal at angle `normal` (r = d / cos(θ − normal)).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Side {
    normal: f64,
    distance: f64,
}

/// A printed section's rounded outline (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct PrintedOutline {
    corners: Vec<Corner>,
    sides: Vec<Side>,
    bridges: Vec<Bridge>,
    perimeter: f64,
}

fn angle_of(p: [f64; 2]) -> f64 {
    p[1].atan2(p[0])
}

impl PrintedOutline {
    /// The outline of `section` (its hull's corners, counter-clockwise, around the origin);
    /// `None` when it is not a polygon around the centroid ([`PrintedSection::hull`]).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// use rollphase_core::geometry::outline::PrintedOutline;
    /// let n = 30;
    /// let prism = PrintedSection { vertices: (0..n).map(|k| {
    ///     let t = std::f64::consts::TAU * k as f64 / n as f64;
    ///     [t.cos(), t.sin()]
    /// }).collect() };
    /// let outline = PrintedOutline::of(&prism).unwrap();
    /// assert_eq!(outline.bridges().len(), 30);
    /// // Each side holds the body up to π/30, less the corners' rounding (1e-3 of it).
    /// let rest = outline.bridges()[0].rest_angle().unwrap();
    /// assert!((rest / (std::f64::consts::PI / 30.0) - 1.0).abs() < 1.5e-3);
    /// // Its corners lie on the polygon's circumcircle, its sides at the apothem.
    /// assert!((outline.jet(0.0)[0] - 1.0).abs() < 1e-3);
    /// let mid = std::f64::consts::PI / 30.0;
    /// assert!((outline.jet(mid)[0] - mid.cos()).abs() < 1e-12);
    /// ```
    pub fn of(section: &PrintedSection) -> Option<PrintedOutline> {
        section.hull().ok()?;
        let v = &section.vertices;
        let n = v.len();
        let edge = |k: usize| {
            let (p, q) = (v[k % n], v[(k + 1) % n]);
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            let length = dx.hypot(dy);
            ([dx / length, dy / length], length)
        };
        // Tangent points and centres of the rounded corners.
        let mut corners = Vec::with_capacity(n);
        let mut tangent = Vec::with_capacity(n);
        for (k, vertex) in v.iter().enumerate() {
            let (e_in, len_in) = edge(k + n - 1);
            let (e_out, len_out) = edge(k);
            // The exterior angle: how far the boundary turns at this corner.
            let turn = (e_in[0] * e_out[1] - e_in[1] * e_out[0])
                .atan2(e_in[0] * e_out[0] + e_in[1] * e_out[1]);
            // A corner that does not turn left (or a NaN) is no convex polygon's.
            if turn.is_nan() || turn <= 0.0 {
                return None;
            }
            let half = (0.5 * turn).tan();
            let radius = CORNER_RADIUS.min(0.45 * len_in.min(len_out) / half);
            let t = radius * half;
            let p_in = [vertex[0] - t * e_in[0], vertex[1] - t * e_in[1]];
            let p_out = [vertex[0] + t * e_out[0], vertex[1] + t * e_out[1]];
            // The centre is on the inner (left) side of both edges.
            let centre = [p_in[0] - radius * e_in[1], p_in[1] + radius * e_in[0]];
            tangent.push((p_in, p_out));
            corners.push(Corner {
                start: angle_of(p_in),
                end: angle_of(p_out),
                centre,
                radius,
            });
        }
        // Unwrap the angles into one turn from the first corner's start.
        let base = corners[0].start;
        let unwrap = |a: f64, after: f64| after + (a - after).rem_euclid(TAU);
        let mut last = base;
        for c in &mut corners {
            c.start = unwrap(c.start, last);
            c.end = unwrap(c.end, c.start);
            last = c.end;
        }
        if corners[n - 1].end >= base + TAU {
            return None;
        }
        let mut sides = Vec::with_capacity(n);
        let mut bridges = Vec::with_capacity(n);
        let mut perimeter = 0.0;
        for k in 0..n {
            let (e, _) = edge(k);
            let pa = tangent[k].1;
            let pb = tangent[(k + 1) % n].0;
            let length = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
            let height = e[1] * pa[0] - e[0] * pa[1];
            let foot = -(pa[0] * e[0] + pa[1] * e[1]);
            sides.push(Side {
                // The outward normal of a counter-clockwise edge e is (e_y, −e_x).
                normal: (-e[0]).atan2(e[1]),
                distance: height,
            });
            let theta_b = if k + 1 < n {
                corners[k + 1].start
            } else {
                corners[0].start + TAU
            };
            bridges.push(Bridge {
                theta_a: corners[k].end.rem_euclid(TAU),
                theta_b: corners[k].end.rem_euclid(TAU) + (theta_b - corners[k].end),
                length,
                height,
                foot,
                depth: 0.0,
            });
            let c = corners[k];
            let (e_in, _) = edge(k + n - 1);
            let turn = (e_in[0] * e[1] - e_in[1] * e[0]).atan2(e_in[0] * e[0] + e_in[1] * e[1]);
            perimeter += length + c.radius * turn;
        }
        Some(PrintedOutline {
            corners,
            sides,
            bridges,
            perimeter,
        })
    }

    /// Its flat sides, as the bridges of its hull (by θ_a).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// use rollphase_core::geometry::outline::PrintedOutline;
    /// let square = PrintedSection { vertices: vec![[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]] };
    /// let o = PrintedOutline::of(&square).unwrap();
    /// assert!(o.bridges().iter().all(|b| (b.height - 1.0).abs() < 1e-15 && b.length < 2.0));
    /// ```
    pub fn bridges(&self) -> &[Bridge] {
        &self.bridges
    }

    /// The length of the outline: what the body advances down the ramp per turn.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// use rollphase_core::geometry::outline::PrintedOutline;
    /// let square = PrintedSection { vertices: vec![[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]] };
    /// // Four sides of 2, less 2ρ each, plus a circle of radius ρ.
    /// let rho = rollphase_core::geometry::outline::CORNER_RADIUS;
    /// let p = PrintedOutline::of(&square).unwrap().perimeter();
    /// assert!((p - (8.0 - 8.0 * rho + std::f64::consts::TAU * rho)).abs() < 1e-12);
    /// ```
    pub fn perimeter(&self) -> f64 {
        self.perimeter
    }

    /// Contact angles on its corners, a few per corner (ends and middle): where a search over
    /// the curve must look, since the corners are far narrower than any fixed grid.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// use rollphase_core::geometry::outline::PrintedOutline;
    /// let square = PrintedSection { vertices: vec![[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]] };
    /// let o = PrintedOutline::of(&square).unwrap();
    /// assert_eq!(o.corner_samples(5).len(), 20);
    /// ```
    pub fn corner_samples(&self, per_corner: usize) -> Vec<f64> {
        let m = per_corner.max(2);
        self.corners
            .iter()
            .flat_map(|c| {
                (0..m).map(move |i| {
                    (c.start + (c.end - c.start) * i as f64 / (m - 1) as f64).rem_euclid(TAU)
                })
            })
            .collect()
    }

    /// [r, r', r'', r'''] at contact angle θ: on a corner's arc (its ends included) or on a
    /// side ([`super::Disk::jet`] gives them as a [`super::RadiusJet`]).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// use rollphase_core::geometry::outline::PrintedOutline;
    /// let tri = PrintedSection { vertices: vec![[1.0, 0.0], [-0.5, 0.9], [-0.5, -0.8]] };
    /// let o = PrintedOutline::of(&tri).unwrap();
    /// // Derivatives against differences, on a side.
    /// let (t, h) = (1.0, 1e-5);
    /// let j = o.jet(t);
    /// assert!((j[1] - (o.jet(t + h)[0] - o.jet(t - h)[0]) / (2.0 * h)).abs() < 1e-8);
    /// assert!((j[3] - (o.jet(t + h)[2] - o.jet(t - h)[2]) / (2.0 * h)).abs() < 1e-5);
    /// ```
    pub fn jet(&self, theta: f64) -> [f64; 4] {
        let base = self.corners[0].start;
        let t = base + (theta - base).rem_euclid(TAU);
        // The last corner whose start is at or before t.
        let k = self
            .corners
            .partition_point(|c| c.start <= t)
            .saturating_sub(1);
        let n = self.corners.len();
        let next_start = if k + 1 < n {
            self.corners[k + 1].start
        } else {
            self.corners[0].start + TAU
        };
        // A side's ends belong to the corners: a contact angle within round-off of an end (a
        // bridge's end reached through its own arithmetic) takes the corner's arc, never the
        // side's zero curvature, on which the rolling equations divide by zero.
        let corner = if t <= self.corners[k].end + END_SLACK {
            Some(self.corners[k])
        } else if next_start - t <= END_SLACK {
            Some(self.corners[(k + 1) % n])
        } else {
            None
        };
        let (s, co) = theta.sin_cos();
        if let Some(c) = corner {
            // r = a + √(ρ² − b²), a = u·C, b = u × C, with a' = b, b' = −a.
            let a = c.centre[0] * co + c.centre[1] * s;
            let b = c.centre[1] * co - c.centre[0] * s;
            let a_t = Taylor3([a, b, -a / 2.0, -b / 6.0]);
            let b_t = Taylor3([b, -a, -b / 2.0, a / 6.0]);
            let inside =
                Taylor3([c.radius * c.radius, 0.0, 0.0, 0.0]).add(b_t.mul(b_t).scale(-1.0));
            a_t.add(inside.sqrt()).derivatives()
        } else {
            let side = self.sides[k];
            let (ss, cs) = (theta - side.normal).sin_cos();
            let cos_t = Taylor3([cs, -ss, -cs / 2.0, ss / 6.0]);
            cos_t.recip().scale(side.distance).derivatives()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle() -> PrintedSection {
        PrintedSection {
            vertices: vec![[1.0, 0.0], [-0.5, 0.9], [-0.5, -0.8]],
        }
    }

    #[test]
    fn the_outline_seen_from_the_other_end_is_its_mirror() {
        let (o, m) = (
            PrintedOutline::of(&triangle()).unwrap(),
            PrintedOutline::of(&triangle().turned()).unwrap(),
        );
        for t in [0.3, 1.0, 2.5, 4.0] {
            assert!((o.jet(t)[0] - m.jet(-t)[0]).abs() < 1e-12);
        }
    }

    #[test]
    fn corner_jets_match_differences_and_the_curve_is_continuous() {
        let o = PrintedOutline::of(&triangle()).unwrap();
        for c in &o.corners {
            let t = 0.5 * (c.start + c.end);
            let h = 1e-3 * (c.end - c.start);
            let j = o.jet(t);
            let d1 = (o.jet(t + h)[0] - o.jet(t - h)[0]) / (2.0 * h);
            let d2 = (o.jet(t + h)[1] - o.jet(t - h)[1]) / (2.0 * h);
            assert!((j[1] - d1).abs() < 1e-6 * j[1].abs().max(1.0));
            assert!((j[2] - d2).abs() < 1e-5 * j[2].abs().max(1.0));
            // Convex on the arc (a circle of radius ρ): r² + 2r'² − r r'' > 0.
            assert!(j[0] * j[0] + 2.0 * j[1] * j[1] - j[0] * j[2] > 0.0);
            // r and r' continuous at both ends: across 2δ they move by r' 2δ and r'' 2δ.
            let delta = 1e-10;
            for end in [c.start, c.end] {
                let (a, b) = (o.jet(end - delta), o.jet(end + delta));
                let (slope, bend) = (a[1].abs().max(b[1].abs()), a[2].abs().max(b[2].abs()));
                assert!(
                    (a[0] - b[0]).abs() <= 1e-12 + 2.1 * delta * slope
                        && (a[1] - b[1]).abs() <= 1e-12 + 2.1 * delta * bend,
                    "{a:?} {b:?}"
                );
            }
        }
    }

    #[test]
    fn a_regular_polygon_rests_up_to_pi_over_n_less_the_rounding() {
        for n in [3usize, 4, 7, 30, 31, 97, 512] {
            let section = PrintedSection {
                vertices: (0..n)
                    .map(|k| {
                        let t = TAU * k as f64 / n as f64 + 0.2;
                        [t.cos(), t.sin()]
                    })
                    .collect(),
            };
            let o = PrintedOutline::of(&section).unwrap();
            let half = std::f64::consts::PI / n as f64;
            let d = half.cos();
            let expected = ((1.0 - CORNER_RADIUS / d) * half.tan()).atan();
            for b in o.bridges() {
                assert!(
                    (b.rest_angle().unwrap() - expected).abs() < 1e-12,
                    "{n}: {b:?}"
                );
            }
        }
    }
}
