//! The mesh fit's 3D path: each triangle's solid angle about the centroid summed into
//! equal-area direction cells (96 bands in cos θ × 192 in φ), each cell keeping the surface
//! point seen nearest its centre; the real spherical harmonics fitted to those points for every
//! degree at once; and the fitted body measured against every triangle and vertex.

use super::*;

/// One direction cell: the solid angle the surface covers in it, and one exact point of the
/// surface there (the piece seen nearest the cell's centre). Points rather than averages keep
/// the least squares consistent: a band-limited body is fitted exactly, where a cell's mean
/// radius assigned to its mean direction is off by the radius's curvature times the cell's
/// size squared (2e-5 of ⟨r⟩ on the paper's body, measured).
#[derive(Debug, Clone, Copy)]
struct Cell {
    weight: f64,
    /// 1 − cos(angle to the cell's centre) of the point kept.
    distance: f64,
    direction: DVec3,
    radius: f64,
}

impl Default for Cell {
    fn default() -> Self {
        Cell {
            weight: 0.0,
            distance: f64::INFINITY,
            direction: DVec3::Z,
            radius: 0.0,
        }
    }
}

fn cell_of(u: DVec3) -> usize {
    let band = (((u.z + 1.0) / 2.0 * BANDS as f64) as usize).min(BANDS - 1);
    let phi = u.y.atan2(u.x).rem_euclid(TAU);
    let sector = ((phi / TAU * SECTORS as f64) as usize).min(SECTORS - 1);
    band * SECTORS + sector
}

fn cell_centre(index: usize) -> DVec3 {
    let (band, sector) = (index / SECTORS, index % SECTORS);
    let z = (band as f64 + 0.5) / BANDS as f64 * 2.0 - 1.0;
    let phi = (sector as f64 + 0.5) / SECTORS as f64 * TAU;
    let s = (1.0 - z * z).sqrt();
    DVec3::new(s * phi.cos(), s * phi.sin(), z)
}

/// A triangle seen from the centroid across more than this angle (rad) is cut into four by its
/// edges' midpoints, and so on, so that a long facet (a cylinder's side) is sampled along its
/// length and not only at its centre: about two cells' width.
const PIECE_ANGLE: f64 = 0.05;

/// Calls `f` on the pieces of the flat triangle `t` (about the centroid, the origin), each seen
/// across at most [`PIECE_ANGLE`] (or cut 10 times).
fn pieces(t: [DVec3; 3], f: &mut impl FnMut([DVec3; 3])) {
    fn cut(t: [DVec3; 3], depth: u32, f: &mut impl FnMut([DVec3; 3])) {
        let u = t.map(|p| p.normalize_or_zero());
        let widest = u[0]
            .angle_between(u[1])
            .max(u[1].angle_between(u[2]))
            .max(u[2].angle_between(u[0]));
        if depth >= 10 || widest.is_nan() || widest <= PIECE_ANGLE {
            f(t);
            return;
        }
        let [a, b, c] = t;
        let (ab, bc, ca) = ((a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0);
        for piece in [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]] {
            cut(piece, depth + 1, f);
        }
    }
    cut(t, 0, f);
}

/// Solid angle of the triangle (a, b, c) seen from the origin, signed by its winding
/// (Van Oosterom and Strackee, 1983).
fn solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c));
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * num.atan2(den)
}

fn angles_text(u: DVec3) -> String {
    let (theta, phi) = crate::geometry::sphere::angles(u);
    format!("θ = {theta:.4}, φ = {phi:.4}")
}

#[expect(
    clippy::too_many_lines,
    reason = "the coverage pass, its three failure modes, the least-squares fit over all degrees \
              and the residual pass share the cells and the centroid; split, they would pass a \
              dozen values between them"
)]
pub(super) fn fit_sphere(
    source: &MeshSource,
    totals: &Totals,
    orientation: f64,
    options: &FitOptions,
    progress: Progress,
) -> Result<(Body, ShapeFile, FitReport), MeshError> {
    let c = totals.centroid;
    let mut cells = vec![Cell::default(); BANDS * SECTORS];
    let centres: Vec<DVec3> = (0..BANDS * SECTORS).map(cell_centre).collect();
    let (mut covered, mut negative, mut folded) = (0.0, 0.0, 0usize);
    let mut worst_fold: Option<(f64, usize, DVec3)> = None;
    let total = source.triangles();
    source.for_each(|i, t| {
        tick(progress, "measuring", i, total);
        let [a, b, d] = t.map(|p| p - c);
        let omega = orientation * solid_angle(a, b, d);
        covered += omega;
        let mid = (a + b + d).normalize_or_zero();
        if omega < 0.0 {
            negative -= omega;
            folded += 1;
            if worst_fold.is_none_or(|w| -omega > w.0) {
                worst_fold = Some((-omega, i, mid));
            }
        }
        if omega > 0.0 {
            let normal = (b - a).cross(d - a);
            let plane = normal.dot(a);
            pieces([a, b, d], &mut |[p, q, r]| {
                let mid = (p + q + r).normalize_or_zero();
                let along = normal.dot(mid);
                if along != 0.0 && mid != DVec3::ZERO {
                    let w = orientation * solid_angle(p, q, r);
                    let k = cell_of(mid);
                    let distance = 1.0 - mid.dot(centres[k]);
                    let cell = &mut cells[k];
                    cell.weight += w;
                    if distance < cell.distance {
                        cell.distance = distance;
                        cell.direction = mid;
                        cell.radius = plane / along;
                    }
                }
            });
        }
        Ok(())
    })?;
    progress("measuring", total, total);
    let sphere_area = 4.0 * PI;
    if (covered - sphere_area).abs() > COVERAGE_TOL * sphere_area {
        // The cell whose coverage is furthest from once names the place.
        let cell_area = sphere_area / (BANDS * SECTORS) as f64;
        let (k, _) = cells
            .iter()
            .enumerate()
            .map(|(k, cell)| (k, (cell.weight / cell_area - 1.0).abs()))
            .max_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap_or((0, 0.0));
        let what = match Topology::of(source)?.trouble() {
            Some(trouble) => trouble,
            None if covered < sphere_area => "the mesh is open (a hole)".to_string(),
            None => "triangles overlap (duplicated faces, or a second shell)".to_string(),
        };
        return Err(shape_error(
            source,
            format!(
                "seen from its centroid the surface covers {:.6} of the sphere's 4π, not exactly \
                 once: {what}, near {}",
                covered / sphere_area,
                angles_text(cell_centre(k))
            ),
        ));
    }
    let mut warnings = Vec::new();
    if let Some((_, index, at)) = worst_fold
        && negative > FOLD_TOL * sphere_area
    {
        return Err(shape_error(
            source,
            format!(
                "the mesh is not star-shaped about its centroid: a ray from it meets the surface \
                 more than once near {} (triangle {index} faces the centroid; {:.3e} of the \
                 sphere is folded over); the models need r(θ, φ) single-valued",
                angles_text(at),
                negative / sphere_area
            ),
        ));
    }
    if let Some((_, index, at)) = worst_fold
        && negative > 0.0
    {
        warnings.push(format!(
            "{folded} triangle(s) face the centroid, covering {:.1e} of the sphere (slivers, the \
             largest triangle {index} near {}); left out of the fit",
            negative / sphere_area,
            angles_text(at)
        ));
    }
    // The least-squares fit on the cells, every degree from one Gram matrix.
    let samples: Vec<(DVec3, f64, f64)> = cells
        .iter()
        .filter(|cell| cell.weight > 0.0 && cell.distance.is_finite())
        .map(|cell| (cell.direction, cell.radius, cell.weight))
        .collect();
    let top = options.modes.unwrap_or(AUTO_MAX_3D).max(AUTO_MAX_3D);
    let basis = ((top + 1) * (top + 1)) as usize;
    let (gram, rhs, r2) = samples
        .par_chunks(512)
        .map(|chunk| {
            let mut g = vec![0.0; basis * basis];
            let mut h = vec![0.0; basis];
            let mut r2 = 0.0;
            let mut y = vec![0.0; basis];
            for &(u, r, w) in chunk {
                real_harmonics(top, u, &mut y);
                for i in 0..basis {
                    let wy = w * y[i];
                    h[i] += wy * r;
                    for j in i..basis {
                        g[i * basis + j] += wy * y[j];
                    }
                }
                r2 += w * r * r;
            }
            (g, h, r2)
        })
        // Summed in chunk order, not as rayon's work-stealing tree would: the same bits on
        // every run and thread count.
        .collect::<Vec<_>>()
        .into_iter()
        .fold(
            (vec![0.0; basis * basis], vec![0.0; basis], 0.0),
            |mut x, y| {
                x.0.iter_mut().zip(&y.0).for_each(|(a, b)| *a += b);
                x.1.iter_mut().zip(&y.1).for_each(|(a, b)| *a += b);
                (x.0, x.1, x.2 + y.2)
            },
        );
    let weight: f64 = samples.iter().map(|s| s.2).sum();
    let solve = |l: u32| -> Option<(Vec<f64>, f64)> {
        let k = ((l + 1) * (l + 1)) as usize;
        let g = DMatrix::from_fn(k, k, |i, j| gram[i.min(j) * basis + i.max(j)]);
        let h = DVector::from_fn(k, |i, _| rhs[i]);
        let x = g.clone().cholesky()?.solve(&h);
        // Σ w (r − yᵀx)² = Σ w r² − 2 xᵀh + xᵀ G x.
        let sq = r2 - 2.0 * x.dot(&h) + x.dot(&(&g * &x));
        Some((x.iter().copied().collect(), sq.max(0.0)))
    };
    let mut fits = Vec::new();
    for l in 2..=top {
        let Some((x, sq)) = solve(l) else {
            return Err(shape_error(
                source,
                format!(
                    "the directions the mesh covers do not determine a degree-{l} fit (too few \
                     triangles for that degree); give a lower --modes"
                ),
            ));
        };
        fits.push((l, x, sq));
    }
    let mean = fits[0].1[0] * (0.25 / PI).sqrt();
    let degree_residuals: Vec<DegreeResidual> = fits
        .iter()
        .map(|(l, _, sq)| DegreeResidual {
            modes: *l,
            rms: (sq / weight).sqrt() / mean,
        })
        .collect();
    let (modes, rule) = match options.modes {
        Some(m) => (m, "given".to_string()),
        None => (
            choose(&degree_residuals, AUTO_MAX_3D),
            AUTO_RULE.to_string(),
        ),
    };
    let x = &fits[(modes - 2) as usize].1;
    let mean = x[0] * (0.25 / PI).sqrt();
    let l1 = (x[1] * x[1] + x[2] * x[2] + x[3] * x[3]).sqrt() * (0.75 / PI).sqrt() / mean;
    let coeffs = sphere_coeffs(x, modes, mean);
    let scale_mm = mean * options.mm_per_unit;
    let shape = ShapeFile::Sphere {
        coeffs,
        scale_mm: Some(scale_mm),
    };
    let body = Body::from_shape(&shape).map_err(|e| shape_error(source, e.to_string()))?;
    let Body::Sphere(sphere) = &body else {
        unreachable!("a sphere shape file gives a sphere")
    };
    // The body against every triangle (along the ray through its centre) and every vertex.
    let mut chunk: Vec<[DVec3; 3]> = Vec::with_capacity(1 << 16);
    let (mut sum2, mut sum_w, mut worst, mut worst_at) = (0.0, 0.0, 0.0f64, DVec3::Z);
    let mut measure = |chunk: &mut Vec<[DVec3; 3]>| {
        let (s2, sw, w, at) = chunk
            .par_iter()
            .map(|t| {
                let [a, b, d] = t.map(|p| p - c);
                let omega = orientation * solid_angle(a, b, d);
                let normal = (b - a).cross(d - a);
                let plane = normal.dot(a);
                let (mut s2, mut sw) = (0.0, 0.0);
                if omega > 0.0 {
                    pieces([a, b, d], &mut |[p, q, r]| {
                        let mid = (p + q + r).normalize_or_zero();
                        let along = normal.dot(mid);
                        if along != 0.0 && mid != DVec3::ZERO {
                            let w = orientation * solid_angle(p, q, r);
                            let e = plane / along / mean - sphere.radius(mid);
                            s2 += w * e * e;
                            sw += w;
                        }
                    });
                }
                let (mut w, mut at) = (0.0f64, DVec3::Z);
                for p in [a, b, d] {
                    let len = p.length();
                    let e = (len / mean - sphere.radius(p / len)).abs();
                    if e > w {
                        (w, at) = (e, p / len);
                    }
                }
                (s2, sw, w, at)
            })
            // In triangle order (see the Gram matrix above).
            .collect::<Vec<_>>()
            .into_iter()
            .fold((0.0, 0.0, 0.0, DVec3::Z), |x, y| {
                let (w, at) = if y.2 > x.2 { (y.2, y.3) } else { (x.2, x.3) };
                (x.0 + y.0, x.1 + y.1, w, at)
            });
        sum2 += s2;
        sum_w += sw;
        if w > worst {
            (worst, worst_at) = (w, at);
        }
        chunk.clear();
    };
    // The distinct vertices (about the centroid), for the print's own hull.
    let collect = !options.ignore_facets;
    let mut distinct: std::collections::HashSet<[u64; 3]> = std::collections::HashSet::new();
    let mut corners: Vec<DVec3> = Vec::new();
    source.for_each(|i, t| {
        tick(progress, "measuring the fit", i, total);
        if collect && distinct.len() <= MAX_HULL_VERTICES {
            for p in t {
                if distinct.insert(p.to_array().map(f64::to_bits)) {
                    corners.push(p - c);
                }
            }
        }
        chunk.push(t);
        if chunk.len() == chunk.capacity() {
            measure(&mut chunk);
        }
        Ok(())
    })?;
    measure(&mut chunk);
    progress("measuring the fit", total, total);
    let rms = (sum2 / sum_w).sqrt();
    let convex = body.check_convex();
    if let Err(e) = &convex {
        // In a mesh user's words: the generator's advice (lower σ, fewer modes) is not theirs.
        let what = match e {
            crate::geometry::ShapeError::NotConvex {
                measure,
                value,
                place,
            } => format!(
                "it is not convex ({measure} {value:.6} at {place}; the contact model needs a \
                 strictly convex body, and a dent in the printed body itself cannot roll as the \
                 model assumes)"
            ),
            other => other.to_string(),
        };
        return Err(shape_error(
            source,
            format!(
                "the degree-{modes} fit cannot be rolled: {what}. A lower --modes smooths it (the \
                 rms residual of each degree: {})",
                degree_residuals
                    .iter()
                    .map(|d| format!("L = {}: {:.2e}", d.modes, d.rms))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    let errors = options
        .errors
        .then(|| {
            errors::sphere_errors(&samples, x, modes, total, |xs| {
                crate::geometry::Sphere::new(sphere_coeffs(xs, modes, xs[0] * (0.25 / PI).sqrt()))
            })
        })
        .flatten();
    let solid_hull = printed_hull(
        &corners,
        (collect, options.mm_per_unit),
        &body,
        &mut warnings,
    );
    let report = FitReport {
        file: source.path().display().to_string(),
        format: format_name(source.format()),
        triangles: total,
        dimension: 3,
        modes,
        modes_rule: rule,
        scale_mm,
        scale_mm_error: errors.map(|e| e.mean * options.mm_per_unit),
        size_mm: totals.volume.abs() * options.mm_per_unit.powi(3),
        centroid: c.to_array(),
        axis: None,
        section_axes: None,
        rms_residual: rms,
        rms_residual_mm: rms * scale_mm,
        max_residual: worst,
        max_residual_mm: worst * scale_mm,
        max_residual_at: angles_text(worst_at),
        l1_part: l1,
        l1_offset_mm: l1 * scale_mm,
        degree_residuals,
        convex: true,
        alpha_star: body.alpha_star(),
        alpha_star_error: errors.and_then(|e| e.alpha_star).map(|a| a.0),
        alpha_star_bias: errors.and_then(|e| e.alpha_star).map(|a| a.1),
        error_blocks: errors.map(|e| e.blocks),
        mesh_hull: None,
        solid_hull,
        warnings,
        coat: None,
    };
    Ok((body, shape, report))
}

/// The print's own hull from its distinct vertices `corners` (about the centroid; `collect`
/// false with `ignore_facets`), and a warning where its α* and the smooth fit's differ by more
/// than [`FACET_TOLERANCE`], or where the mesh is too fine for it to be computed.
fn printed_hull(
    corners: &[DVec3],
    (collect, mm_per_unit): (bool, f64),
    body: &Body,
    warnings: &mut Vec<String>,
) -> Option<crate::geometry::solid_hull::SolidHull> {
    if !collect {
        return None;
    }
    if corners.len() > MAX_HULL_VERTICES {
        warnings.push(format!(
            "the mesh has over {MAX_HULL_VERTICES} distinct vertices: its own hull (the α* its \
             facets give) is not computed; facets that fine tip a ball by about half a degree or \
             less"
        ));
        return None;
    }
    let mut hull = crate::geometry::solid_hull::solid_hull(corners, DVec3::ZERO)?;
    hull.mm_per_unit = mm_per_unit;
    warnings.extend(facet_warning(
        &hull,
        hull.alpha_star,
        body.alpha_star(),
        mm_per_unit,
    ));
    Some(hull)
}

/// The warning where a print's own α* (`printed`, rad: its hull's, or the coated hull's) is
/// more than [`FACET_TOLERANCE`] above the smooth fit's (`fitted`).
pub(super) fn facet_warning(
    hull: &crate::geometry::solid_hull::SolidHull,
    printed: f64,
    fitted: f64,
    mm_per_unit: f64,
) -> Option<String> {
    (printed - fitted > FACET_TOLERANCE).then(|| {
        format!(
            "the mesh's hull has {} triangles, on which the printed body rests up to α = {:.4} \
             rad ({:.2}°), but the smooth fit's α* is {:.4} rad ({:.2}°): the fit does not see \
             the facets (up to {:.2} mm across; a printer reproduces facets wider than its \
             nozzle). In 3D every command rolls the smooth fit, so below {:.4} rad the print \
             may rest where they say it rolls; export a finer mesh, or use --ignore-facets for \
             a round part the mesh only approximates",
            hull.triangles,
            printed,
            printed.to_degrees(),
            fitted,
            fitted.to_degrees(),
            hull.longest_edge * mm_per_unit,
            printed
        )
    })
}

/// The shape file's coefficients A_lm (m ≥ 0) of the real-basis fit `x` (mesh units), up to
/// degree `modes`, relative to ⟨r⟩ = `mean`. The file's r = 1 + Re Σ A_lm Y_lm/(l(l+1)) and
/// Re(A Y_lm) = re Re Y − im Im Y, against the basis √2 Re Y_lm (m > 0), √2 Im Y_l|m| (m < 0).
fn sphere_coeffs(x: &[f64], modes: u32, mean: f64) -> Vec<SphereCoeff> {
    let mut out = Vec::new();
    for l in 2..=modes {
        let ll = (l * (l + 1)) as f64;
        let base = (l * l + l) as i64;
        for m in 0..=l as i32 {
            let (re, im) = if m == 0 {
                (ll * x[base as usize] / mean, 0.0)
            } else {
                let cos_part = x[(base + m as i64) as usize] / mean;
                let sin_part = x[(base - m as i64) as usize] / mean;
                (
                    ll * std::f64::consts::SQRT_2 * cos_part,
                    -ll * std::f64::consts::SQRT_2 * sin_part,
                )
            };
            out.push(SphereCoeff { l, m, re, im });
        }
    }
    out
}

/// The orthonormal real spherical harmonics up to degree `top` at the unit vector `u`, into
/// `out[l² + l + m]`: Y_l0, √2 Re Y_lm for m > 0, √2 Im Y_l|m| for m < 0, with Y_lm the complex
/// harmonics of [`crate::geometry::harmonics::spherical_harmonic`] (Condon–Shortley phase). By the
/// recurrence in z for P_l^m / sin^m θ, times (x + iy)^m: O(L²) a point, no trigonometry.
///
/// # Example
/// ```
/// use rollphase_core::geometry::harmonics::spherical_harmonic;
/// use rollphase_core::geometry::mesh_fit::real_harmonics;
/// use rollphase_core::glam::DVec3;
/// let u = DVec3::new(0.3, -0.5, 0.8).normalize();
/// let mut y = vec![0.0; 16];
/// real_harmonics(3, u, &mut y);
/// let (re, im) = spherical_harmonic(3, 2).eval(u.x, u.y, u.z);
/// assert!((y[9 + 3 + 2] - std::f64::consts::SQRT_2 * re).abs() < 1e-14);
/// assert!((y[9 + 3 - 2] - std::f64::consts::SQRT_2 * im).abs() < 1e-14);
/// ```
pub fn real_harmonics(top: u32, u: DVec3, out: &mut [f64]) {
    let top = top as usize;
    debug_assert!(out.len() >= (top + 1) * (top + 1));
    let (mut cr, mut ci) = (1.0, 0.0); // (x + iy)^m
    let mut pmm = 1.0; // P̃_m^m = (−1)^m (2m − 1)!!
    for m in 0..=top {
        if m > 0 {
            (cr, ci) = (cr * u.x - ci * u.y, cr * u.y + ci * u.x);
            pmm *= -((2 * m - 1) as f64);
        }
        let (mut p_prev, mut p) = (0.0, pmm);
        for l in m..=top {
            if l == m + 1 {
                (p_prev, p) = (p, u.z * (2 * m + 1) as f64 * pmm);
            } else if l > m + 1 {
                let next =
                    ((2 * l - 1) as f64 * u.z * p - (l + m - 1) as f64 * p_prev) / (l - m) as f64;
                (p_prev, p) = (p, next);
            }
            let norm = ((2 * l + 1) as f64 / (4.0 * PI) * factorial_ratio(l, m)).sqrt();
            let centre = l * l + l;
            if m == 0 {
                out[centre] = norm * p;
            } else {
                let k = std::f64::consts::SQRT_2 * norm * p;
                out[centre + m] = k * cr;
                out[centre - m] = k * ci;
            }
        }
    }
}

/// (l − m)! / (l + m)!.
fn factorial_ratio(l: usize, m: usize) -> f64 {
    ((l - m + 1)..=(l + m)).fold(1.0, |acc, k| acc / k as f64)
}
