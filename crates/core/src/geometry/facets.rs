//! The printed body's own critical angle: α* of a mesh's cross-section taken from the convex
//! hull of its vertices, not from the smooth fit.
//!
//! A printed prism is flat-sided. OpenSCAD's `cylinder(r = 10)` has 30 sides, and a regular
//! N-gon rests on a side up to α = π/N, while a Fourier fit with a few modes sees an almost
//! perfect circle (α* ≈ 0). The mesh fit reports both numbers and says when they disagree.
//!
//! The rule is the smooth one read on the hull's sides, for the body rolling forward (θ
//! increasing, counter-clockwise in the section's coordinates, as the fitted body's α* is): a
//! side at height h from the centroid rests on a ramp while the weight's line through the
//! centroid meets the ramp before the side's downhill end, the one reached later going
//! counter-clockwise, at distance t from the centroid's foot along the side: every α up to
//! atan(t/h) ([`super::hull::Bridge::rest_angle`]'s rule for a dent's flat). Andrew's monotone
//! chain gives the hull, O(n log n), written here because it is 30 lines and exact on the
//! section's own points.

/// How far (rad) a print's α* and its smooth fit's may differ before the facets count: 0.1°,
/// the resolution of a digital inclinometer setting a ramp, so a smaller difference cannot be
/// seen in an experiment.
pub const FACET_TOLERANCE: f64 = 0.1 * std::f64::consts::PI / 180.0;

/// The hull of a cross-section, and the angle it rests up to.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SectionHull {
    /// The hull's sides (the vertices that turn the boundary by more than round-off).
    pub sides: usize,
    /// α* of the hull (rad): the steepest ramp on which some side can hold the body rolling
    /// forward (θ increasing); 0 when none can.
    pub alpha_star: f64,
    /// The longest side, in the points' units: how coarse the facets are (2R sin(π/N) for a
    /// regular N-gon of circumradius R).
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
        // q is the downhill end rolling forward; a side whose foot lies past q never holds.
        let reach = (q[0] * dx + q[1] * dy) / length;
        best = best.max(reach.atan2(height));
    }
    Some(SectionHull {
        sides: hull.len(),
        alpha_star: best,
        longest_side: longest,
    })
}

/// The cross-section of a printed prism, kept in its shape file: the convex hull of the mesh's
/// section, in the fitted body's units (⟨r⟩ = 1) and frame (centroid at the origin, θ from
/// the fit's first section axis), counter-clockwise.
///
/// A disk that keeps one rolls on it ([`super::outline`]: the polygon with its corners rounded
/// to a hundredth of a millimetre), so every command answers for the print; its modes stay the
/// smooth fit, which `design` works on ([`PrintedSection::facets_matter`] says when the two
/// disagree on α*).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrintedSection {
    /// The hull's corners, [x, y] in units of ⟨r⟩, counter-clockwise.
    pub vertices: Vec<[f64; 2]>,
}

/// How far a printed section's mean radius may be from the fitted body's ⟨r⟩ = 1: a coat's
/// chamfered corners move it by 1e-4, a section scaled by hand by far more.
pub const MEAN_RADIUS_SLACK: f64 = 0.01;

/// The mean over θ of a convex polygon's radius (its corners counter-clockwise around the
/// origin): on each side at distance d, ∫ d / cos(θ − φ) dθ in closed form.
fn mean_radius(corners: &[[f64; 2]]) -> f64 {
    let n = corners.len();
    let total: f64 = (0..n)
        .map(|k| {
            let (p, q) = (corners[k], corners[(k + 1) % n]);
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            let length = dx.hypot(dy);
            let d = (p[0] * dy - p[1] * dx) / length;
            // The side's ends seen from the origin, at angles a and b from its normal foot.
            let (a, b) = (
                (p[0] * dx + p[1] * dy) / length,
                (q[0] * dx + q[1] * dy) / length,
            );
            // ∫ d sec u du from atan(a/d) to atan(b/d) = d [asinh(tan u)].
            d * ((b / d).asinh() - (a / d).asinh())
        })
        .sum();
    total / std::f64::consts::TAU
}

/// Most corners a printed section may have: the shape file stays under its 1 MiB limit (about
/// 60 bytes a corner), and a regular polygon this fine tips 0.02° above its smooth fit, under an
/// inclinometer's resolution, so `shape --from-mesh` keeps no section for it.
pub const MAX_PRINTED_CORNERS: usize = 8192;

impl PrintedSection {
    /// The hull of a section's `points` (centroid at the origin) scaled by 1/`unit`; `None`
    /// when they do not enclose the origin with positive area.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// let square = [[10.0, 10.0], [-10.0, 10.0], [-10.0, -10.0], [10.0, -10.0], [0.0, 10.0]];
    /// let section = PrintedSection::from_points(&square, 10.0).unwrap();
    /// assert_eq!(section.vertices.len(), 4);
    /// assert!(section.vertices.iter().all(|v| v[0].abs() == 1.0 && v[1].abs() == 1.0));
    /// ```
    pub fn from_points(points: &[[f64; 2]], unit: f64) -> Option<Self> {
        section_hull(points)?;
        let vertices = convex_hull(points)
            .into_iter()
            .map(|p| [p[0] / unit, p[1] / unit])
            .collect();
        Some(Self { vertices })
    }

    /// Its sides and the angle it rests up to rolling forward ([`section_hull`] of its
    /// corners); an error naming what is wrong for a section that is not a polygon around the
    /// centroid (a hand-edited file).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// let triangle = PrintedSection { vertices: vec![[1.0, 0.0], [-0.5, 0.866], [-0.5, -0.866]] };
    /// assert_eq!(triangle.hull()?.sides, 3);
    /// let outside = PrintedSection { vertices: vec![[1.0, 1.0], [2.0, 1.0], [1.0, 2.0]] };
    /// assert!(outside.hull().unwrap_err().contains("centroid"));
    /// # Ok::<(), String>(())
    /// ```
    pub fn hull(&self) -> Result<SectionHull, String> {
        let n = self.vertices.len();
        if !(3..=MAX_PRINTED_CORNERS).contains(&n) {
            return Err(format!(
                "printed_section has {n} vertices (needs 3 to {MAX_PRINTED_CORNERS})"
            ));
        }
        if let Some((i, v)) = self
            .vertices
            .iter()
            .enumerate()
            .find(|(_, v)| !v.iter().all(|x| x.is_finite() && x.abs() <= 100.0))
        {
            return Err(format!(
                "printed_section.vertices[{i}] = [{}, {}] is not allowed (needs finite \
                 coordinates within 100 ⟨r⟩ of the centroid)",
                v[0], v[1]
            ));
        }
        let hull = section_hull(&self.vertices).ok_or_else(|| {
            "printed_section does not enclose the centroid with positive area (needs the \
             section's corners around its centroid, in units of ⟨r⟩)"
                .to_string()
        })?;
        // The corners as `shape --from-mesh` writes them: the hull itself, counter-clockwise,
        // no corner inside it or on a side, none twice. Anything else is a different polygon
        // from the one given, which a hand edit must not get silently.
        let canonical = convex_hull(&self.vertices);
        if canonical.len() != n {
            return Err(format!(
                "printed_section is not a convex polygon of its {n} vertices: its convex hull \
                 has {} (a vertex inside, on a side or listed twice); give the hull's corners \
                 only",
                canonical.len()
            ));
        }
        let start = canonical
            .iter()
            .position(|c| *c == self.vertices[0])
            .unwrap_or(0);
        if (0..n).any(|k| canonical[(start + k) % n] != self.vertices[k]) {
            return Err(
                "printed_section's vertices are not in counter-clockwise order around the \
                 centroid (as `shape --from-mesh` writes them)"
                    .to_string(),
            );
        }
        Ok(hull)
    }

    /// [`PrintedSection::hull`], and the section in its shape file's units: its mean radius
    /// over θ lies between the fitted body's ⟨r⟩ = 1 and its convex hull's, `smooth_hull_mean`
    /// (more than 1 for a dented body, whose hull bridges the dents), each widened by
    /// [`MEAN_RADIUS_SLACK`], so a section scaled by hand or taken from another body is refused
    /// before any run.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// let n = 30;
    /// let prism = PrintedSection { vertices: (0..n).map(|k| {
    ///     let t = std::f64::consts::TAU * k as f64 / n as f64;
    ///     [t.cos(), t.sin()]
    /// }).collect() };
    /// assert!(prism.check_for_shape_file(1.0).is_ok());
    /// let doubled = PrintedSection { vertices: prism.vertices.iter().map(|v| [2.0 * v[0], 2.0 * v[1]]).collect() };
    /// assert!(doubled.check_for_shape_file(1.0).unwrap_err().contains("mean radius"));
    /// ```
    pub fn check_for_shape_file(&self, smooth_hull_mean: f64) -> Result<SectionHull, String> {
        let hull = self.hull()?;
        let mean = mean_radius(&self.vertices);
        // The print's hull holds the section (mean radius 1 within the fit's residuals), and
        // where the section is not convex it bridges dents, as the fit's own hull does.
        let (low, high) = (
            1.0 - MEAN_RADIUS_SLACK,
            smooth_hull_mean.max(1.0) * (1.0 + MEAN_RADIUS_SLACK),
        );
        if !(low..=high).contains(&mean) {
            return Err(format!(
                "printed_section's mean radius is {mean:.6} ⟨r⟩, but the section is in units of \
                 the fitted body's mean radius: its hull's needs {low} to {high:.6} (1 less \
                 {MEAN_RADIUS_SLACK}, to the fitted body's own hull's, {smooth_hull_mean:.6}, \
                 plus {MEAN_RADIUS_SLACK}; a section scaled or from another body)"
            ));
        }
        Ok(hull)
    }

    /// The mean radius over θ of the convex hull of the closed curve r(θ) (sampled at 4096
    /// angles): 1 for a convex body of ⟨r⟩ = 1, more where the hull bridges dents.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// let round = PrintedSection::hull_mean_radius(|_| 1.0);
    /// assert!((round - 1.0).abs() < 1e-6);
    /// ```
    pub fn hull_mean_radius(r: impl Fn(f64) -> f64) -> f64 {
        let points: Vec<[f64; 2]> = (0..4096)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 4096.0;
                let rt = r(t);
                [rt * t.cos(), rt * t.sin()]
            })
            .collect();
        mean_radius(&convex_hull(&points))
    }

    /// The same section seen from the cylinder's other end (θ → −θ), as
    /// [`super::Disk::turned`] turns the fit.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// let s = PrintedSection { vertices: vec![[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0]] };
    /// assert_eq!(s.turned().turned(), s);
    /// ```
    pub fn turned(&self) -> Self {
        Self {
            vertices: self.vertices.iter().rev().map(|v| [v[0], -v[1]]).collect(),
        }
    }

    /// The section under a coat of `thickness` (in its own units), in units `unit` times its
    /// own: each side moved out along its normal by the coat, its ends kept as the flat's
    /// ends (the coat rounds the corners between them, which the chords between the moved ends
    /// stand for; a body resting on a flat tips at the flat's end).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// let square = PrintedSection { vertices: vec![[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]] };
    /// let coated = square.coated(0.5, 1.0).unwrap();
    /// assert_eq!(coated.vertices.len(), 8);
    /// // A side 2 long at height 1.5 now: it holds the body up to atan(1/1.5).
    /// assert!((coated.hull()?.alpha_star - (1.0f64 / 1.5).atan()).abs() < 1e-12);
    /// # Ok::<(), String>(())
    /// ```
    pub fn coated(&self, thickness: f64, unit: f64) -> Option<Self> {
        let n = self.vertices.len();
        let moved: Vec<[f64; 2]> = (0..n)
            .flat_map(|k| {
                let (p, q) = (self.vertices[k], self.vertices[(k + 1) % n]);
                let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
                let length = dx.hypot(dy);
                // Counter-clockwise: the outward normal is the side's direction turned right.
                let (nx, ny) = (dy / length * thickness, -dx / length * thickness);
                [[p[0] + nx, p[1] + ny], [q[0] + nx, q[1] + ny]]
            })
            .collect();
        Self::from_points(&moved, unit)
    }

    /// The print's α* against the fit's, when they differ by more than
    /// [`FACET_TOLERANCE`] (an inclinometer's 0.1°): the facets then matter to
    /// where the body rests, and the fit cannot speak for the print below the larger of the two.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// let n = 30;
    /// let prism = PrintedSection { vertices: (0..n).map(|k| {
    ///     let t = std::f64::consts::TAU * k as f64 / n as f64;
    ///     [t.cos(), t.sin()]
    /// }).collect() };
    /// // A 30-sided prism rests up to π/30 = 6°; a smooth circle's fit has α* = 0.
    /// let gap = prism.facets_matter(0.0).unwrap();
    /// assert_eq!(gap.sides, 30);
    /// assert!((gap.print_alpha_star - std::f64::consts::PI / 30.0).abs() < 1e-12);
    /// assert!(prism.facets_matter(std::f64::consts::PI / 30.0).is_none());
    /// ```
    pub fn facets_matter(&self, fit_alpha_star: f64) -> Option<FacetGap> {
        let hull = self.hull().ok()?;
        ((hull.alpha_star - fit_alpha_star).abs() > FACET_TOLERANCE).then_some(FacetGap {
            sides: hull.sides,
            print_alpha_star: hull.alpha_star,
            fit_alpha_star,
        })
    }
}

/// Where a printed section and its smooth fit disagree on α* ([`PrintedSection::facets_matter`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FacetGap {
    /// The print's flat sides.
    pub sides: usize,
    /// α* of the print's hull (rad).
    pub print_alpha_star: f64,
    /// α* of the smooth fit (rad).
    pub fit_alpha_star: f64,
}

/// Andrew's monotone chain, counter-clockwise, collinear and repeated points dropped. A point
/// counts as a corner only where it lies more than 1e-6 of the extent off the line through its
/// neighbours on the hull, so the vertices of a side cut into pieces (a mesh that splits a long
/// facet) do not count as sides, even where the mesh's single-precision coordinates, turned, put
/// them 1e-7 off it (a turned 10 × 20 bar was read as 6 sides). A regular N-gon's corners lie
/// 20/N² of its radius off that line: 7.5e-5 at N = 512, 6e-6 at the 1,800 sides past which
/// facets no longer move α* by 0.1°.
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
    let reach = extent.sqrt();
    let left = |o: [f64; 2], a, b: [f64; 2]| {
        turn(o, a, b) > 1e-6 * reach * (b[0] - o[0]).hypot(b[1] - o[1])
    };
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
            assert!((hull.longest_side - 14.0 * (PI / n as f64).sin()).abs() < 1e-12);
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
    fn an_off_centre_rectangle_rests_by_its_forward_ends() {
        // A rectangle with the centroid off its centre. Rolling forward (counter-clockwise),
        // each side's downhill end is its later corner: the bottom side (height 0.5) reaches
        // 0.7, the right (0.7) 0.5, the top (0.5) 0.3, the left (0.3) 0.5.
        let points = [[-0.3, -0.5], [0.7, -0.5], [0.7, 0.5], [-0.3, 0.5]];
        let hull = section_hull(&points).unwrap();
        assert!((hull.alpha_star - 0.5f64.atan2(0.3)).abs() < 1e-12);
        // Its mirror image rolls the other way round: the left side (height 0.7 now) reaches
        // 0.5, the top (0.5) 0.7, the right (0.3) 0.5, the bottom (0.5) 0.3.
        let mirror: Vec<[f64; 2]> = points.iter().map(|p| [-p[0], p[1]]).collect();
        let hull = section_hull(&mirror).unwrap();
        assert!((hull.alpha_star - 0.5f64.atan2(0.3)).abs() < 1e-12);
        // A right triangle, centroid at the origin, rolls differently each way round.
        // Forward, the side along the bottom (height 2/3) reaches its corner 2 along: atan 3.
        // Backward (its mirror image forward), the hypotenuse (height 2/√13) reaches 22/(3√13)
        // back along it: atan(11/3).
        let triangle = [[-1.0, -2.0 / 3.0], [2.0, -2.0 / 3.0], [-1.0, 4.0 / 3.0]];
        let forward = section_hull(&triangle).unwrap().alpha_star;
        let mirrored: Vec<[f64; 2]> = triangle.iter().map(|p| [-p[0], p[1]]).collect();
        let backward = section_hull(&mirrored).unwrap().alpha_star;
        assert!((forward - 3f64.atan()).abs() < 1e-12, "{forward}");
        assert!(
            (backward - (11.0f64 / 3.0).atan()).abs() < 1e-12,
            "{backward}"
        );
    }

    #[test]
    fn a_polygons_mean_radius_is_its_closed_form() {
        // A square of apothem 1: (4/2π) · 2 asinh(1).
        let square = [[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]];
        let exact = 8.0 * 1f64.asinh() / TAU;
        assert!((mean_radius(&square) - exact).abs() < 1e-14);
        // A fine polygon of circumradius 1 is nearly the unit circle.
        let fine = polygon(4096, 1.0, 0.3);
        assert!((mean_radius(&fine) - 1.0).abs() < 1e-6);
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
