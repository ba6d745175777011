//! The printed body's own critical angle: α* of a mesh's cross-section taken from the convex
//! hull of its vertices, not from the smooth fit.
//!
//! A printed prism is flat-sided. OpenSCAD's `cylinder(r = 10)` has 30 sides, and a regular
//! N-gon rests on a side up to α = π/N, while a Fourier fit with a few modes sees an almost
//! perfect circle (α* ≈ 0). The mesh fit reports both numbers and says when they disagree.
//!
//! The rule is the smooth one, α* = atan max |r′/r|, read on the hull's sides. A side at height
//! h from the centroid, with its ends at distances t₁ and t₂ along it from the centroid's foot,
//! rests on a ramp while the weight's line through the centroid meets the ramp between its ends.
//! That holds for every α up to atan(max(|t₁|, |t₂|)/h). Andrew's monotone chain gives the hull,
//! O(n log n), written here because it is 30 lines and exact on the section's own points.

/// The hull of a cross-section, and the angle it rests up to.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SectionHull {
    /// The hull's sides (the vertices that turn the boundary by more than round-off).
    pub sides: usize,
    /// α* of the hull (rad): the steepest ramp on which some side can hold the body.
    pub alpha_star: f64,
    /// The longest side over the mean distance of the hull's vertices from the centroid: how
    /// coarse the facets are (2 sin(π/N) for a regular N-gon).
    pub longest_side: f64,
}

/// The convex hull of `points` (a section's vertices, with the area centroid at the origin)
/// and its α*. `None` when the points do not enclose the origin with positive area.
///
/// # Example
/// ```
/// use rollphase_core::geometry::facets::section_hull;
/// // A regular 31-gon rests on a side up to π/31 (OpenSCAD's cylinder has 30 sides).
/// let n = 31;
/// let points: Vec<[f64; 2]> = (0..n)
///     .map(|k| {
///         let t = std::f64::consts::TAU * k as f64 / n as f64;
///         [10.0 * t.cos(), 10.0 * t.sin()]
///     })
///     .collect();
/// let hull = section_hull(&points).unwrap();
/// assert_eq!(hull.sides, 31);
/// assert!((hull.alpha_star - std::f64::consts::PI / 31.0).abs() < 1e-12);
/// ```
pub fn section_hull(points: &[[f64; 2]]) -> Option<SectionHull> {
    let hull = convex_hull(points);
    if hull.len() < 3 {
        return None;
    }
    let mean_radius = hull.iter().map(|p| p[0].hypot(p[1])).sum::<f64>() / hull.len() as f64;
    let (mut best, mut longest) = (0.0f64, 0.0f64);
    for (k, p) in hull.iter().enumerate() {
        let q = hull[(k + 1) % hull.len()];
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let length = dx.hypot(dy);
        longest = longest.max(length);
        // Counter-clockwise hull: the origin is on the left of every side, at height h.
        let height = (p[0] * dy - p[1] * dx) / length;
        if height <= 0.0 {
            return None;
        }
        let (tp, tq) = (
            (p[0] * dx + p[1] * dy) / length,
            (q[0] * dx + q[1] * dy) / length,
        );
        best = best.max(tp.abs().max(tq.abs()).atan2(height));
    }
    Some(SectionHull {
        sides: hull.len(),
        alpha_star: best,
        longest_side: longest / mean_radius,
    })
}

/// Andrew's monotone chain, counter-clockwise, collinear and repeated points dropped. A turn
/// counts only above 1e-12 of the squared extent, so the vertices of a side cut into pieces
/// (a mesh that splits a long facet) do not count as sides.
fn convex_hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut sorted: Vec<[f64; 2]> = points
        .iter()
        .copied()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    sorted.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    sorted.dedup();
    if sorted.len() < 3 {
        return sorted;
    }
    let extent = sorted
        .iter()
        .map(|p| p[0] * p[0] + p[1] * p[1])
        .fold(0.0f64, f64::max);
    let turn = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let left = |o, a, b| turn(o, a, b) > 1e-12 * extent;
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * sorted.len());
    for pass in [
        &sorted[..],
        &sorted.iter().rev().copied().collect::<Vec<_>>()[..],
    ] {
        let start = hull.len();
        for &p in pass {
            while hull.len() >= start + 2 && !left(hull[hull.len() - 2], hull[hull.len() - 1], p) {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    fn polygon(n: usize, radius: f64, phase: f64) -> Vec<[f64; 2]> {
        (0..n)
            .map(|k| {
                let t = phase + TAU * k as f64 / n as f64;
                [radius * t.cos(), radius * t.sin()]
            })
            .collect()
    }

    #[test]
    fn a_regular_polygon_rests_up_to_pi_over_n() {
        for n in [3, 4, 5, 13, 30, 31, 97, 256, 512] {
            let hull = section_hull(&polygon(n, 7.0, 0.3)).unwrap();
            assert_eq!(hull.sides, n);
            assert!(
                (hull.alpha_star - PI / n as f64).abs() < 1e-12,
                "{n}: {}",
                hull.alpha_star
            );
            assert!((hull.longest_side - 2.0 * (PI / n as f64).sin()).abs() < 1e-12);
        }
    }

    #[test]
    fn points_inside_and_on_the_sides_do_not_count() {
        let mut points = polygon(6, 1.0, 0.0);
        // Midpoints of every side, and points inside.
        for k in 0..6 {
            let (p, q) = (points[k], points[(k + 1) % 6]);
            points.push([(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0]);
            points.push([0.3 * p[0], 0.2 * q[1]]);
        }
        let hull = section_hull(&points).unwrap();
        assert_eq!(hull.sides, 6);
        assert!((hull.alpha_star - PI / 6.0).abs() < 1e-12);
    }

    #[test]
    fn an_off_centre_square_rests_longest_on_its_nearest_side() {
        // A unit square with the centroid 0.2 left of its centre. The sides below and above,
        // at height 0.5 with ends 0.3 and 0.7 away, hold up to atan(0.7/0.5); the left side, at
        // height 0.3 with ends 0.5 away, up to atan(0.5/0.3), which is α*.
        let points = [[-0.3, -0.5], [0.7, -0.5], [0.7, 0.5], [-0.3, 0.5]];
        let hull = section_hull(&points).unwrap();
        assert!((hull.alpha_star - 0.5f64.atan2(0.3)).abs() < 1e-12);
    }

    #[test]
    fn a_degenerate_or_outside_section_has_no_hull() {
        assert!(section_hull(&[[0.0, 1.0], [1.0, 1.0]]).is_none());
        assert!(section_hull(&[[0.0, 1.0], [1.0, 1.0], [2.0, 1.0]]).is_none());
        // The origin outside the points.
        assert!(section_hull(&[[1.0, 1.0], [2.0, 1.0], [1.0, 2.0]]).is_none());
        assert!(section_hull(&[[f64::NAN, 0.0], [1.0, 0.0]]).is_none());
    }
}
