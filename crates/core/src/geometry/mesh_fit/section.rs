//! The mesh fit's 2D path: the extrusion sliced at mid-length across its axis, the slice's
//! oriented segments giving the section's area centroid, r(θ) at 4,096 angles (each ray must
//! meet the boundary once) and its discrete Fourier series, the residuals, and the section's
//! own hull beside the smooth fit ([`crate::geometry::facets`]).

use super::*;

fn section_basis(axis: DVec3) -> (DVec3, DVec3) {
    let world = [DVec3::X, DVec3::Y, DVec3::Z];
    let w = world
        .into_iter()
        .min_by(|p, q| p.dot(axis).abs().total_cmp(&q.dot(axis).abs()))
        .unwrap_or(DVec3::X);
    let e1 = (w - w.dot(axis) * axis).normalize();
    (e1, axis.cross(e1))
}

fn cross2(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

#[expect(
    clippy::too_many_lines,
    reason = "one pass that slices the mesh, then the section's checks, samples, Fourier fit, \
              degree rule and report, which share a dozen local quantities"
)]
pub(super) fn fit_section(
    source: &MeshSource,
    totals: &Totals,
    axis: DVec3,
    orientation: f64,
    options: &FitOptions,
    progress: Progress,
) -> Result<(Body, ShapeFile, FitReport), MeshError> {
    let (e1, e2) = section_basis(axis);
    let c3 = totals.centroid;
    // The slice through the centroid: for a uniform extrusion its area centroid is the
    // centroid's projection, and it is as far from both caps as the mesh allows.
    let mut segments: Vec<([f64; 2], [f64; 2])> = Vec::new();
    let total = source.triangles();
    source.for_each(|i, t| {
        tick(progress, "slicing", i, total);
        let d = t.map(|p| (p - c3).dot(axis));
        let above = d.map(|h| h >= 0.0);
        if above.iter().all(|&x| x) || above.iter().all(|&x| !x) {
            return Ok(());
        }
        let mut points = Vec::with_capacity(2);
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            if above[i] != above[j] {
                // From the edge's lexicographically smaller end, so that the two triangles
                // sharing the edge (which list it in opposite orders) get the same bits: a point
                // that differs in its last bit between its two segments can fall on either side
                // of a sample ray, counted twice or not at all.
                let (i, j) = if t[i].to_array() < t[j].to_array() {
                    (i, j)
                } else {
                    (j, i)
                };
                let p = t[i] + (t[j] - t[i]) * (d[i] / (d[i] - d[j]));
                let q = p - c3;
                points.push([q.dot(e1), q.dot(e2)]);
            }
        }
        if points.len() != 2 {
            return Ok(());
        }
        let n = orientation * (t[1] - t[0]).cross(t[2] - t[0]);
        let n2 = [n.dot(e1), n.dot(e2)];
        let (p, q) = (points[0], points[1]);
        // Outward normal of the edge p → q of a counter-clockwise boundary is (dy, −dx).
        let out = [q[1] - p[1], -(q[0] - p[0])];
        if out[0] * n2[0] + out[1] * n2[1] >= 0.0 {
            segments.push((p, q));
        } else {
            segments.push((q, p));
        }
        Ok(())
    })?;
    progress("slicing", total, total);
    if segments.len() < 3 {
        return Err(shape_error(
            source,
            format!(
                "the slice across the axis {:?} through the centroid meets {} edges: the mesh is \
                 not a closed cylinder along that axis",
                axis.to_array(),
                segments.len()
            ),
        ));
    }
    // Area and area centroid by Green's theorem (needs no ordering of the segments).
    let (mut area2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for (p, q) in &segments {
        let w = cross2(*p, *q);
        area2 += w;
        cx += (p[0] + q[0]) * w;
        cy += (p[1] + q[1]) * w;
    }
    let area = area2 / 2.0;
    if area <= 0.0 {
        return Err(shape_error(
            source,
            "the section's boundary encloses no area: the mesh is open or wound inconsistently"
                .into(),
        ));
    }
    let centre = [cx / (3.0 * area2), cy / (3.0 * area2)];
    let rel: Vec<([f64; 2], [f64; 2])> = segments
        .iter()
        .map(|(p, q)| {
            (
                [p[0] - centre[0], p[1] - centre[1]],
                [q[0] - centre[0], q[1] - centre[1]],
            )
        })
        .collect();
    // r(θ) at equally spaced angles; each ray from the centre must meet the boundary once.
    let n = SECTION_SAMPLES;
    let step = TAU / n as f64;
    let mut radius = vec![0.0f64; n];
    let mut hits = vec![0i32; n];
    let mut folds = vec![0u32; n];
    for (p, q) in &rel {
        let swept = cross2(*p, *q).atan2(p[0] * q[0] + p[1] * q[1]);
        // Each segment takes the sample rays in [start, end) counter-clockwise, with both ends'
        // angles from the points themselves: a vertex shared by two segments has one angle, so
        // a ray through it goes to exactly one of them (start + sweep, rounded differently, put
        // rays through the vertices of OpenSCAD's cylinders in both or neither).
        let (start, end) = if swept >= 0.0 { (p, q) } else { (q, p) };
        let (from, to) = (start[1].atan2(start[0]), end[1].atan2(end[0]));
        let first = (from / step).ceil() as i64;
        let mut last = (to / step).ceil() as i64;
        if last < first {
            if from - to > std::f64::consts::PI {
                // Across the cut at ±π.
                last += n as i64;
            } else {
                // A sliver whose end angle rounded below its start: it meets no ray.
                last = first;
            }
        }
        let dq = [q[0] - p[0], q[1] - p[1]];
        for k in first..last {
            let th = k as f64 * step;
            let u = [th.cos(), th.sin()];
            let den = cross2(u, dq);
            if den == 0.0 {
                continue;
            }
            let r = cross2(*p, dq) / den;
            let idx = k.rem_euclid(n as i64) as usize;
            if swept >= 0.0 {
                hits[idx] += 1;
                radius[idx] = r;
            } else {
                hits[idx] -= 1;
                folds[idx] += 1;
            }
        }
    }
    if let Some(k) = (0..n).find(|&k| folds[k] > 0 || hits[k] > 1) {
        return Err(shape_error(
            source,
            format!(
                "the section is not star-shaped about its centroid: the ray at θ = {:.4} meets \
                 its boundary more than once; the models need r(θ) single-valued",
                k as f64 * step
            ),
        ));
    }
    if let Some(k) = (0..n).find(|&k| hits[k] != 1) {
        return Err(shape_error(
            source,
            format!(
                "the section is open: the ray at θ = {:.4} from its centroid meets no boundary \
                 (a hole in the side wall)",
                k as f64 * step
            ),
        ));
    }
    let mean = radius.iter().sum::<f64>() / n as f64;
    // Fourier coefficients of r/⟨r⟩ − 1: cos (b) and sin (c) parts, l = 1 … top; the rest of
    // the variance (Parseval) is what a fit to degree M leaves.
    let top = (MAX_FIT_DISK_L as usize).max(options.modes.unwrap_or(0) as usize);
    let variance = radius.iter().map(|r| (r / mean - 1.0).powi(2)).sum::<f64>() / n as f64;
    let mut b = vec![0.0; top + 1];
    let mut c = vec![0.0; top + 1];
    for (l, (bl, cl)) in b.iter_mut().zip(c.iter_mut()).enumerate().skip(1) {
        let (mut sb, mut sc) = (0.0, 0.0);
        for (k, r) in radius.iter().enumerate() {
            let a = (l * k % n) as f64 * step;
            sb += r * a.cos();
            sc += r * a.sin();
        }
        *bl = 2.0 * sb / (n as f64 * mean);
        *cl = 2.0 * sc / (n as f64 * mean);
    }
    let tail = |from: usize| -> f64 {
        let kept: f64 = (1..from).map(|l| (b[l] * b[l] + c[l] * c[l]) / 2.0).sum();
        (variance - kept).max(0.0).sqrt()
    };
    let tried = options.modes.unwrap_or(AUTO_MAX_2D);
    let degree_residuals: Vec<DegreeResidual> = (2..=tried.max(AUTO_MAX_2D))
        .map(|m| DegreeResidual {
            modes: m,
            rms: tail(m as usize + 1),
        })
        .collect();
    let (modes, rule) = match options.modes {
        Some(m) => (m, "given".to_string()),
        None => (
            choose(&degree_residuals, AUTO_MAX_2D),
            AUTO_RULE.to_string(),
        ),
    };
    let disk_modes: Vec<DiskMode> = (2..=modes as usize)
        .map(|l| {
            let lf = l as f64;
            DiskMode {
                l: l as u32,
                a: lf * lf * b[l].hypot(c[l]),
                phase: (-b[l]).atan2(c[l]) / lf,
            }
        })
        .collect();
    let scale_mm = mean * options.mm_per_unit;
    let corners: Vec<[f64; 2]> = rel.iter().flat_map(|(p, q)| [*p, *q]).collect();
    let smooth_shape = ShapeFile::Disk {
        modes: disk_modes,
        scale_mm: Some(scale_mm),
        printed_section: None,
    };
    // The report is the smooth fit's (its residuals, convexity and α*); the body returned rolls
    // on the print's outline when the section is kept (below).
    let body = Body::from_shape(&smooth_shape).map_err(|e| shape_error(source, e.to_string()))?;
    let Body::Disk(disk) = &body else {
        unreachable!("a disk shape file gives a disk")
    };
    let (mut sum2, mut worst, mut worst_at) = (0.0, 0.0f64, 0.0);
    for (k, r) in radius.iter().enumerate() {
        let th = k as f64 * step;
        let e = r / mean - disk.jet(th).r;
        sum2 += e * e;
        if e.abs() > worst {
            (worst, worst_at) = (e.abs(), th);
        }
    }
    let rms = (sum2 / n as f64).sqrt();
    let l1 = b[1].hypot(c[1]);
    let mut warnings = Vec::new();
    let convex = body.check_convex().is_ok();
    if !convex {
        let dents = disk.hull().bridges().len();
        warnings.push(format!(
            "the fitted section is not convex ({dents} dent(s)); `simulate`, and `period` and \
             `predict` without inertia, roll it on its convex hull; the figures and `design` \
             refuse it"
        ));
    }
    let alpha_star = body.alpha_star();
    let errors = options
        .errors
        .then(|| errors::section_errors(&radius, (mean, &b, &c), modes as usize, rel.len()))
        .flatten();
    let mesh_hull = section_hull(&corners);
    if let Some(hull) = mesh_hull.filter(|h| (h.alpha_star - alpha_star).abs() > FACET_TOLERANCE) {
        warnings.push(format!(
            "the section's hull has {} flat sides, on which the printed body rests up to α = \
             {:.4} rad ({:.2}°), but the smooth fit's α* is {alpha_star:.4} rad ({:.2}°): the \
             fit does not see the facets (a printer reproduces facets wider than its nozzle; \
             these are {:.2} mm at most). {}",
            hull.sides,
            hull.alpha_star,
            hull.alpha_star.to_degrees(),
            alpha_star.to_degrees(),
            hull.longest_side * options.mm_per_unit,
            if options.ignore_facets {
                "With --ignore-facets the shape file keeps no section: every command rolls the \
                 smooth fit, as for a round body"
            } else {
                "The shape file keeps the section, and every command rolls the print: its \
                 sides flat, its corners rounded to 0.001 ⟨r⟩"
            }
        ));
    }
    let report = FitReport {
        file: source.path().display().to_string(),
        format: format_name(source.format()),
        triangles: source.triangles(),
        dimension: 2,
        modes,
        modes_rule: rule,
        scale_mm,
        scale_mm_error: errors.map(|e| e.mean * options.mm_per_unit),
        size_mm: area * options.mm_per_unit.powi(2),
        centroid: (c3 + centre[0] * e1 + centre[1] * e2).to_array(),
        axis: Some(axis.to_array()),
        section_axes: Some([e1.to_array(), e2.to_array()]),
        rms_residual: rms,
        rms_residual_mm: rms * scale_mm,
        max_residual: worst,
        max_residual_mm: worst * scale_mm,
        max_residual_at: format!("θ = {worst_at:.4}"),
        l1_part: l1,
        l1_offset_mm: l1 * scale_mm,
        degree_residuals,
        convex,
        alpha_star,
        alpha_star_error: errors.and_then(|e| e.alpha_star).map(|a| a.0),
        alpha_star_bias: errors.and_then(|e| e.alpha_star).map(|a| a.1),
        error_blocks: errors.map(|e| e.blocks),
        mesh_hull,
        solid_hull: None,
        warnings,
        coat: None,
    };
    // The print's section is kept where its flats move α* beyond an inclinometer's 0.1° (a
    // finer polygon rolls as its smooth fit does, within what a ramp can be set to), unless told
    // the facets are tessellation, and where the shape file can hold it.
    let printed_section = mesh_hull
        .filter(|h| {
            !options.ignore_facets
                && (h.alpha_star - alpha_star).abs() > FACET_TOLERANCE
                && h.sides <= MAX_PRINTED_CORNERS
        })
        .and_then(|_| PrintedSection::from_points(&corners, mean));
    let shape = smooth_shape.with_printed_section(printed_section);
    let rolled = Body::from_shape(&shape).map_err(|e| shape_error(source, e.to_string()))?;
    Ok((rolled, shape, report))
}
