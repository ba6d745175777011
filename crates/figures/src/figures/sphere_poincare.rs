//! `sphere-poincare` — paper Fig. 3d: the Poincaré map of viscous 3D rolling on the boundary ∂Ω of
//! the SO(3) ball, for the paper's body at the paper's α = 0.15 > α* = 0.1387 by default (another
//! body: α = max(0.3, α* + 0.05), or `--alpha`).
//!
//! From N boundary points p (a Fibonacci lattice; antipodes identified, and V(−p) = −V(p) since
//! q and −q are the same orientation, so half the lattice is integrated) the body rolls until the
//! next crossing of ∂Ω ([`crate::analysis::orbits::poincare_field::poincare_step`]); V = P(p) − p. Its
//! attractors (stable closed orbits) are found by iterating P from a subset of starts until
//! |V| < 1e-9 and clustering the limits (antipodes identified): the paper finds two antipodal
//! pairs, i.e. two stable periodic orbits. Drawn as arrows on a flat (θ, φ) map and on the
//! sphere seen from +z, coloured by |V|.
//!
//! `--shard I/N` splits the field's starts and the iterated starts (one list); `merge` clusters.

use anyhow::Result;
use glam::DVec3;
use serde::Serialize;

use super::{Computed, FigureData, FigureOptions};
use crate::analysis::critical_angle;
use crate::analysis::orbits::poincare_field::{field_from_images, field_lattice, poincare_step};
use crate::analysis::orbits::sphere_orbits::{SAME_ORBIT, boundary_distance, cluster_antipodal};
use crate::chart::{Panel, Series, SeriesLabelPosition, Style};
use crate::colormap::viridis;
use crate::dynamics::Ramp;
use crate::geometry::Body;
use crate::geometry::sphere::{angles, fibonacci_sphere};

/// An attractor of the map.
#[derive(Debug, Clone, Serialize)]
pub struct Attractor {
    /// Boundary point (unit vector; its antipode is the same orientation).
    pub point: [f64; 3],
    /// Polar angle and azimuth of the point.
    pub theta: f64,
    /// Azimuth.
    pub phi: f64,
    /// Orbit period (time between crossings at the fixed point).
    pub period: f64,
    /// How many of the iterated starts ended here.
    pub basin_count: usize,
}

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// The body: the paper's by default, or `--seed`, or `--shape`.
    pub body: String,
    /// Seed of the body. (null for a `--shape` file).
    pub seed: Option<u64>,
    /// α* of the body.
    pub alpha_star: f64,
    /// α used.
    pub alpha: f64,
    /// Starts on ∂Ω (lattice points, both hemispheres).
    pub starts: usize,
    /// Starts from which the body halted before crossing again (0 above α*).
    pub halted: usize,
    /// Attractors of P, antipodes identified (the paper: 2).
    pub attractors: usize,
    /// Their details.
    pub attractor_list: Vec<Attractor>,
    /// Iterated starts that converged.
    pub converged_starts: usize,
}

/// The figure's ramp angle (above α* of the default body).
pub const ALPHA: f64 = 0.3;

/// Runs the figure: computes it, then writes OUT/sphere-poincare/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("sphere-poincare")?;
    super::written(compute(opts)?, &dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<Computed<FigureData<Summary>>> {
    let fig = opts.sphere("sphere-poincare")?;
    let (body, seed) = (fig.body.clone(), fig.seed);
    let a_star = critical_angle(&Body::Sphere(body.clone())).alpha_star;
    super::refuse_perfect_sphere(
        "sphere-poincare",
        a_star,
        "it rolls at constant speed on a great circle from every orientation, so every point of \
         ∂Ω lies on a periodic orbit and the return map has no attractors to find",
    )?;
    // The paper's α = 0.15 on its body; on another, 0.3 or just above its α*.
    let default_alpha = if fig.is_paper {
        super::PAPER_ALPHA
    } else {
        ALPHA.max(a_star + 0.05)
    };
    let alpha = opts.single_alpha("sphere-poincare", default_alpha)?;
    let ramp = Ramp::new(alpha, 0.0)?;
    let n: usize = if opts.quick { 400 } else { 5000 };
    // One ensemble: the attractor search (iterating P from a sub-lattice until |V| < 1e-9; the
    // slow members, so they start first), then the field's steps from the upper half of the
    // lattice (V(−p) = −V(p)).
    let upper = field_lattice(n);
    let m = if opts.quick { 24 } else { 120 };
    let seeds: Vec<DVec3> = fibonacci_sphere(2 * m)
        .into_iter()
        .filter(|p| p.z >= 0.0)
        .collect();
    let jobs = upper.len() + seeds.len();
    let images = super::all_runs!(opts.ensemble(
        "sphere-poincare",
        jobs,
        "map and iterate P",
        |k| -> Result<Option<(DVec3, f64)>> {
            if k >= seeds.len() {
                let start = upper[k - seeds.len()];
                return Ok(poincare_step(&body, &ramp, start, 2000.0, 1e-10)?);
            }
            let mut p = seeds[k];
            for _ in 0..200 {
                match poincare_step(&body, &ramp, p, 2000.0, 1e-11)? {
                    Some((q, t)) => {
                        if boundary_distance(p, q) < 1e-9 {
                            return Ok(Some((q, t)));
                        }
                        p = q;
                    }
                    None => return Ok(None),
                }
            }
            Ok(None)
        },
    ));
    let (limits, field_images) = images.split_at(seeds.len());
    let field: Vec<(DVec3, Option<(DVec3, f64)>)> = field_from_images(&upper, field_images)
        .into_iter()
        .map(|a| (a.start, a.end.map(|e| (e, a.time))))
        .collect();
    let halted = field.iter().filter(|f| f.1.is_none()).count();
    let limits: Vec<(DVec3, f64)> = limits.iter().flatten().copied().collect();
    let clusters = cluster_antipodal(&limits.iter().map(|l| l.0).collect::<Vec<_>>(), SAME_ORBIT);
    let attractor_list: Vec<Attractor> = clusters
        .iter()
        .map(|(c, count)| {
            let period = limits
                .iter()
                .find(|l| boundary_distance(l.0, *c) < SAME_ORBIT)
                .map(|l| l.1)
                .unwrap_or(f64::NAN);
            let c = if c.z < 0.0 { -*c } else { *c };
            let (theta, phi) = angles(c);
            Attractor {
                point: c.to_array(),
                theta,
                phi,
                period,
                basin_count: *count,
            }
        })
        .collect();
    let mut rows = Vec::new();
    for (p, r) in &field {
        let (v, t) = match r {
            Some((q, t)) => (*q - *p, *t),
            None => (DVec3::splat(f64::NAN), f64::NAN),
        };
        rows.push(vec![p.x, p.y, p.z, v.x, v.y, v.z, v.length(), t]);
    }
    let csv_header = "px,py,pz,vx,vy,vz,v_norm,return_time";
    let summary = Summary {
        body: fig.label,
        seed,
        alpha_star: a_star,
        alpha,
        starts: field.len(),
        halted,
        attractors: attractor_list.len(),
        attractor_list,
        converged_starts: limits.len(),
    };
    Ok(Computed::Figure(FigureData {
        panels: plot(&field, &summary),
        columns: 2,
        size: (1900, 760),
        header: csv_header,
        rows,
        summary,
    }))
}

/// The chart: the field on ∂Ω and the attractors.
fn plot(field: &[(DVec3, Option<(DVec3, f64)>)], s: &Summary) -> Vec<Panel> {
    let vmax = field
        .iter()
        .filter_map(|f| f.1.map(|(q, _)| (q - f.0).length()))
        .fold(0.0, f64::max)
        .max(1e-12);
    let bins = 6;
    let mut flat: Vec<Vec<(f64, f64)>> = vec![Vec::new(); bins];
    let mut disk: Vec<Vec<(f64, f64)>> = vec![Vec::new(); bins];
    for (p, r) in field {
        let Some((q, _)) = r else { continue };
        let v = *q - *p;
        let bin = ((v.length() / vmax) * bins as f64).min(bins as f64 - 1.0) as usize;
        // Flat map: unit-length arrows in (φ, θ).
        let (theta, phi) = angles(*p);
        let e_theta = DVec3::new(
            theta.cos() * phi.cos(),
            theta.cos() * phi.sin(),
            -theta.sin(),
        );
        let e_phi = DVec3::new(-phi.sin(), phi.cos(), 0.0);
        let (dt, dp) = (v.dot(e_theta), v.dot(e_phi));
        let len = (dt * dt + dp * dp).sqrt().max(1e-300);
        let k = 0.07 / len;
        flat[bin].push((phi, theta));
        flat[bin].push((phi + dp * k, theta + dt * k));
        // Sphere seen from +z: the upper hemisphere, arrows projected.
        if p.z > 0.0 {
            let tangent = v - v.dot(*p) * *p;
            let tl = tangent.length().max(1e-300);
            let e = tangent * (0.035 / tl);
            disk[bin].push((p.x, p.y));
            disk[bin].push((p.x + e.x, p.y + e.y));
        }
    }
    let to_series = |bins_pts: Vec<Vec<(f64, f64)>>| -> Vec<Series> {
        bins_pts
            .into_iter()
            .enumerate()
            .map(|(b, pts)| Series {
                label: format!("|V| ≈ {:.2}", (b as f64 + 0.5) / bins as f64 * vmax),
                points: pts,
                color: viridis(b as f64 / (bins - 1) as f64),
                style: Style::Arrows,
            })
            .collect()
    };
    let mut flat_series = to_series(flat);
    let mut disk_series = to_series(disk);
    let mut att_flat = Vec::new();
    let mut att_disk = Vec::new();
    for a in &s.attractor_list {
        let p = DVec3::from_array(a.point);
        for q in [p, -p] {
            let (t, ph) = angles(q);
            att_flat.push((ph, t));
            if q.z >= 0.0 {
                att_disk.push((q.x, q.y));
            }
        }
    }
    flat_series.push(Series {
        label: "attractors (closed orbits)".into(),
        points: att_flat,
        color: (214, 39, 40),
        style: Style::Markers,
    });
    disk_series.push(Series {
        label: "attractors".into(),
        points: att_disk,
        color: (214, 39, 40),
        style: Style::Markers,
    });
    let rim: Vec<(f64, f64)> = (0..=120)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 120.0;
            (a.cos(), a.sin())
        })
        .collect();
    disk_series.push(Series {
        label: String::new(),
        points: rim,
        color: (0, 0, 0),
        style: Style::Line,
    });
    let panels = vec![
        Panel {
            title: format!(
                "Poincaré map V on ∂Ω, α = {:.3} (α* = {:.3}): {} attractors (antipodes identified)",
                s.alpha, s.alpha_star, s.attractors
            ),
            x_label: "azimuth φ of the boundary point (rad)".into(),
            y_label: "polar angle θ (rad)".into(),
            log_x: false,
            log_y: false,
            series: flat_series,
            legend: SeriesLabelPosition::LowerRight,
            equal_aspect: false,
        },
        Panel {
            title: "∂Ω seen from +z (upper hemisphere)".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            log_x: false,
            log_y: false,
            series: disk_series,
            legend: SeriesLabelPosition::UpperRight,
            equal_aspect: true,
        },
    ];
    panels
}
