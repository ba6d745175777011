//! The printed solid's own critical angle in 3D: α* of the convex hull of a mesh's vertices,
//! beside the smooth fit's.
//!
//! A sphere printed from an STL of a few thousand triangles is a polyhedron. On a ramp it rests
//! on a hull facet while the weight's line through the centroid meets the facet: tilted by α
//! with the facet's far point x downhill, the line meets the facet's plane at h·tan α from the
//! centroid's foot p on it (h the centroid's height above the plane), so the facet holds the
//! body up to atan(|x − p|/h), largest at one of its vertices. The print can rest on some
//! facet up to α* = max over facets and their vertices of atan(|v − p|/h). Coplanar triangles
//! of one flat face share p and h, so a triangulated hull gives the flat face's answer. A smooth
//! fit with a few degrees sees a round ball (its α* from the bumps alone); the facets add about
//! the facet's size over the radius: 1° for facets of 2 % of the radius. Rolling without
//! slipping is assumed, as in the model (a real print may slide first on a steep facet).
//!
//! The hull is quickhull (Barber, Dobkin and Huhdanpaa 1996), written here: the `chull` crate's
//! took 0.75 s on 10,242 points, 7.8 s on 40,962 and 127 s on 163,842 (an icosphere's
//! vertices, all on the hull, as a printed ball's are), where a CAD export holds 10⁴–10⁶; this
//! one 0.05 s, 0.25 s and 1.1 s, with the same α* to the last digit (2026-11-28). Points
//! within 1e-10 of the vertices' extent of a face's plane count as on it (a flat face's inner
//! points are not corners, and its corners are what α* reads).

use glam::DVec3;

/// The hull of a solid's vertices, and the angle it rests up to.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SolidHull {
    /// The vertices on the hull.
    pub vertices: usize,
    /// The hull's triangles (a flat face of k corners counts k − 2).
    pub triangles: usize,
    /// α* of the hull (rad): the steepest ramp on which some facet can hold the body, rolling
    /// without slipping.
    pub alpha_star: f64,
    /// The longest hull edge, in the points' units: how coarse the facets are.
    pub longest_edge: f64,
    /// Each hull triangle's farthest corner from the centroid's foot and the centroid's height
    /// above it (the points' units), for [`SolidHull::coated`].
    #[serde(skip)]
    pub facets: Vec<[f64; 2]>,
    /// Millimetres per unit of the points (1 unless the mesh fit says otherwise).
    #[serde(skip)]
    pub mm_per_unit: f64,
}

impl SolidHull {
    /// α* of the print under a coat `thickness` thick (the points' units): the hull grown by a
    /// ball keeps its flat faces, each moved out by the coat (its far corner as far from the
    /// centroid's foot, the centroid that much higher), and rounds its edges and corners, on
    /// which the body rolls. So max atan(d/(h + thickness)).
    ///
    /// ```
    /// use glam::DVec3;
    /// use rollphase_core::geometry::solid_hull::solid_hull;
    /// let corners: Vec<DVec3> = (0..8)
    ///     .map(|k| DVec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64) * 2.0 - 1.0)
    ///     .collect();
    /// let hull = solid_hull(&corners, DVec3::ZERO).unwrap();
    /// // A cube of side 2 under a coat of 1: its faces are 2 from the centre.
    /// assert!((hull.coated(1.0) - (2f64.sqrt() / 2.0).atan()).abs() < 1e-12);
    /// assert_eq!(hull.coated(0.0), hull.alpha_star);
    /// ```
    pub fn coated(&self, thickness: f64) -> f64 {
        self.facets
            .iter()
            .map(|[d, h]| d.atan2(h + thickness))
            .fold(0.0, f64::max)
    }
}

/// Fewest vertices a hull is computed from.
const MIN_POINTS: usize = 4;
/// How far outside a face's plane (in units of the points' extent) a point must be to count.
const HULL_TOLERANCE: f64 = 1e-10;

/// One face of the hull being built: counter-clockwise seen from outside.
struct Face {
    corners: [usize; 3],
    normal: DVec3,
    offset: f64,
    outside: Vec<usize>,
    alive: bool,
}

impl Face {
    fn new(points: &[DVec3], corners: [usize; 3]) -> Self {
        let [a, b, c] = corners.map(|i| points[i]);
        let normal = (b - a).cross(c - a).normalize_or_zero();
        Face {
            corners,
            normal,
            offset: normal.dot(a),
            outside: Vec::new(),
            alive: true,
        }
    }

    fn height(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }

    fn edges(&self) -> [(usize, usize); 3] {
        let [a, b, c] = self.corners;
        [(a, b), (b, c), (c, a)]
    }
}

/// The point of `candidates` farthest from `measure`, with its distance.
fn farthest(
    candidates: impl Iterator<Item = usize>,
    measure: impl Fn(usize) -> f64,
) -> Option<(usize, f64)> {
    candidates
        .map(|i| (i, measure(i)))
        .max_by(|x, y| x.1.total_cmp(&y.1))
}

/// The hull's triangles (indices into `points`, outward), or `None` when the points span no
/// volume beyond `eps`.
fn quickhull(points: &[DVec3], eps: f64) -> Option<Vec<[usize; 3]>> {
    use std::collections::HashMap;
    let all = 0..points.len();
    // A first tetrahedron from extreme points.
    let (i0, _) = farthest(all.clone(), |i| points[i].x)?;
    let (i1, d) = farthest(all.clone(), |i| (points[i] - points[i0]).length())?;
    if d <= eps {
        return None;
    }
    let axis = (points[i1] - points[i0]) / d;
    let (i2, d) = farthest(all.clone(), |i| {
        let v = points[i] - points[i0];
        (v - axis * v.dot(axis)).length()
    })?;
    if d <= eps {
        return None;
    }
    let base = Face::new(points, [i0, i1, i2]);
    let (i3, d) = farthest(all.clone(), |i| base.height(points[i]).abs())?;
    if d <= eps {
        return None;
    }
    let mut corners = [[i0, i1, i2], [i0, i3, i1], [i1, i3, i2], [i2, i3, i0]];
    if base.height(points[i3]) > 0.0 {
        for c in &mut corners {
            c.swap(0, 1);
        }
    }
    let mut faces: Vec<Face> = corners.iter().map(|&c| Face::new(points, c)).collect();
    let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
    for (k, f) in faces.iter().enumerate() {
        for e in f.edges() {
            edges.insert(e, k);
        }
    }
    let assign = |faces: &mut Vec<Face>, candidates: &[usize], new: &[usize]| {
        for &p in candidates {
            if let Some(&k) = new.iter().find(|&&k| faces[k].height(points[p]) > eps) {
                faces[k].outside.push(p);
            }
        }
    };
    let others: Vec<usize> = all.filter(|i| ![i0, i1, i2, i3].contains(i)).collect();
    assign(&mut faces, &others, &[0, 1, 2, 3]);
    let mut stack: Vec<usize> = (0..4).collect();
    while let Some(k) = stack.pop() {
        if !faces[k].alive || faces[k].outside.is_empty() {
            continue;
        }
        let (eye, _) = farthest(faces[k].outside.iter().copied(), |i| {
            faces[k].height(points[i])
        })?;
        let eye_point = points[eye];
        // The faces the eye sees, found across shared edges from the first.
        let mut visible = vec![k];
        let mut seen = std::collections::HashSet::from([k]);
        let mut at = 0;
        while at < visible.len() {
            for (a, b) in faces[visible[at]].edges() {
                let &n = edges.get(&(b, a))?;
                if seen.insert(n) && faces[n].height(eye_point) > eps {
                    visible.push(n);
                }
            }
            at += 1;
        }
        let visible_set: std::collections::HashSet<usize> = visible.iter().copied().collect();
        let mut horizon = Vec::new();
        let mut orphans = Vec::new();
        for &v in &visible {
            for (a, b) in faces[v].edges() {
                if !visible_set.contains(&edges[&(b, a)]) {
                    horizon.push((a, b));
                }
            }
            faces[v].alive = false;
            orphans.append(&mut faces[v].outside);
        }
        for &v in &visible {
            for e in faces[v].edges() {
                if edges.get(&e) == Some(&v) {
                    edges.remove(&e);
                }
            }
        }
        let mut new = Vec::with_capacity(horizon.len());
        for (a, b) in horizon {
            let f = Face::new(points, [a, b, eye]);
            let id = faces.len();
            for e in f.edges() {
                edges.insert(e, id);
            }
            faces.push(f);
            new.push(id);
        }
        orphans.retain(|&p| p != eye);
        assign(&mut faces, &orphans, &new);
        stack.extend(new);
    }
    Some(
        faces
            .iter()
            .filter(|f| f.alive)
            .map(|f| f.corners)
            .collect(),
    )
}

/// The convex hull of `points` (a solid's vertices) and its α* about `centroid` (the solid's
/// centre of mass, inside the hull). `None` for fewer than four points, points that span no
/// volume, or a centroid outside the hull.
///
/// # Example
/// ```
/// use glam::DVec3;
/// use rollphase_core::geometry::solid_hull::solid_hull;
/// // A cube rests with a corner downhill up to atan √2 (54.7°), and with an edge downhill
/// // only up to 45°: the steepest is the corner's.
/// let corners: Vec<DVec3> = (0..8)
///     .map(|k| DVec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64) * 2.0 - 1.0)
///     .collect();
/// let hull = solid_hull(&corners, DVec3::ZERO).unwrap();
/// assert!((hull.alpha_star - 2f64.sqrt().atan()).abs() < 1e-12);
/// assert_eq!((hull.vertices, hull.triangles), (8, 12));
/// ```
pub fn solid_hull(points: &[DVec3], centroid: DVec3) -> Option<SolidHull> {
    if points.len() < MIN_POINTS || !points.iter().all(|p| p.is_finite()) {
        return None;
    }
    let size = points
        .iter()
        .map(|p| (*p - centroid).length())
        .fold(0.0, f64::max);
    if !(size.is_finite() && size > 0.0) {
        return None;
    }
    let scaled: Vec<DVec3> = points.iter().map(|p| (*p - centroid) / size).collect();
    let faces = quickhull(&scaled, HULL_TOLERANCE)?;
    let mut used: Vec<usize> = faces.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    let corner = |i: usize| scaled[i];
    // The mean of the hull's vertices is inside it: the side of each facet it is on is in.
    let inside = used.iter().map(|&i| scaled[i]).sum::<DVec3>() / used.len() as f64;
    let (mut alpha_star, mut longest) = (0.0f64, 0.0f64);
    let mut facets = Vec::with_capacity(faces.len());
    for triangle in &faces {
        let [a, b, c] = [
            corner(triangle[0]),
            corner(triangle[1]),
            corner(triangle[2]),
        ];
        let normal = (b - a).cross(c - a);
        let area = normal.length();
        if area <= 0.0 {
            continue;
        }
        // The outward normal, and the centroid's (the origin's) height above the facet's plane:
        // not positive, and the centroid is outside the hull (or on it).
        let mut n = normal / area;
        if n.dot(a - inside) < 0.0 {
            n = -n;
        }
        let h = n.dot(a);
        if h <= 1e-12 {
            return None;
        }
        let foot = h * n;
        let far = [a, b, c]
            .iter()
            .map(|&v| (v - foot).length())
            .fold(0.0, f64::max);
        alpha_star = alpha_star.max(far.atan2(h));
        facets.push([far * size, h * size]);
        longest = longest.max((b - a).length().max((c - b).length()).max((a - c).length()));
    }
    Some(SolidHull {
        vertices: used.len(),
        triangles: faces.len(),
        alpha_star,
        longest_edge: longest * size,
        facets,
        mm_per_unit: 1.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vertices of the icosphere the STL export writes, of `level` subdivisions (unit
    /// radius).
    fn icosphere(level: u32) -> Vec<DVec3> {
        crate::geometry::mesh::sphere_mesh(&crate::geometry::Sphere::perfect(), level)
            .positions
            .iter()
            .map(|p| DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])))
            .collect()
    }

    #[test]
    fn a_regular_tetrahedron_rests_up_to_atan_two_root_two() {
        let corners = [
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(-1.0, -1.0, 1.0),
        ];
        let hull = solid_hull(&corners, DVec3::ZERO).unwrap();
        assert!(
            (hull.alpha_star - (2.0 * 2f64.sqrt()).atan()).abs() < 1e-12,
            "{hull:?}"
        );
        assert_eq!(hull.triangles, 4);
        // Points inside change nothing.
        let mut more = corners.to_vec();
        more.extend([DVec3::new(0.1, 0.2, -0.1), DVec3::ZERO]);
        assert_eq!(
            solid_hull(&more, DVec3::ZERO).unwrap().alpha_star,
            hull.alpha_star
        );
    }

    #[test]
    fn finer_icospheres_rest_on_smaller_slopes_in_proportion_to_their_facets() {
        let mut last = f64::INFINITY;
        for level in 1..=4 {
            let points = icosphere(level);
            let hull = solid_hull(&points, DVec3::ZERO).unwrap();
            assert_eq!(hull.vertices, points.len());
            // A facet of edge e on the unit sphere: its far corner about e/√3 from the foot.
            let bound =
                (hull.longest_edge / 3f64.sqrt() / (1.0 - hull.longest_edge.powi(2))).atan();
            assert!(
                hull.alpha_star > 0.0 && hull.alpha_star <= bound * 1.01,
                "{level}: {hull:?} against {bound}"
            );
            assert!(
                hull.alpha_star < 0.6 * last,
                "{level}: {} after {last}",
                hull.alpha_star
            );
            last = hull.alpha_star;
        }
    }

    #[test]
    fn random_points_all_lie_inside_every_face_and_the_hull_is_closed() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let points: Vec<DVec3> = (0..3000)
            .map(|_| {
                let p = DVec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0;
                p * (1.0 + 0.3 * p.x * p.y)
            })
            .collect();
        let faces = quickhull(&points, HULL_TOLERANCE).unwrap();
        let mut used: Vec<usize> = faces.iter().flatten().copied().collect();
        used.sort_unstable();
        used.dedup();
        // A closed triangulated surface of genus 0: F = 2V − 4.
        assert_eq!(faces.len(), 2 * used.len() - 4);
        for f in &faces {
            let face = Face::new(&points, *f);
            let worst = points
                .iter()
                .map(|&p| face.height(p))
                .fold(f64::MIN, f64::max);
            assert!(worst <= 1e-9, "{f:?}: a point {worst} outside");
        }
    }

    #[test]
    fn points_on_a_cubes_faces_leave_its_corners_in_charge() {
        let mut points = Vec::new();
        for i in 0..=10 {
            for j in 0..=10 {
                let (u, v) = (i as f64 / 5.0 - 1.0, j as f64 / 5.0 - 1.0);
                for w in [-1.0, 1.0] {
                    points.extend([
                        DVec3::new(u, v, w),
                        DVec3::new(u, w, v),
                        DVec3::new(w, u, v),
                    ]);
                }
            }
        }
        let hull = solid_hull(&points, DVec3::ZERO).unwrap();
        assert!(
            (hull.alpha_star - 2f64.sqrt().atan()).abs() < 1e-9,
            "{hull:?}"
        );
    }

    #[test]
    fn degenerate_input_gives_none() {
        assert!(solid_hull(&[DVec3::ZERO; 3], DVec3::ZERO).is_none());
        let flat: Vec<DVec3> = (0..10)
            .map(|k| DVec3::new(k as f64, (k * k) as f64, 0.0))
            .collect();
        assert!(solid_hull(&flat, DVec3::ZERO).is_none());
        let square = [DVec3::X, DVec3::Y, DVec3::Z, DVec3::ONE];
        // The centroid outside the hull.
        assert!(solid_hull(&square, DVec3::splat(-5.0)).is_none());
        assert!(solid_hull(&[DVec3::NAN, DVec3::X, DVec3::Y, DVec3::Z], DVec3::ZERO).is_none());
    }
}
