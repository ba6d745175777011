//! `sphere-halting` — SI §2D–2E: the halting loops of viscous 3D rolling and their stability, on
//! the default body at α = 0.5, 0.75 and 0.9 α*.
//!
//! The body can rest on contact point u iff Q(u) = |∇_s ln r| = tan α (r parallel to F), so the
//! rest states are the level sets Q = tan α (marching squares on a (θ, φ) grid), each a loop of
//! rest orientations in SO(3). At every loop point the rest orientation is built (the body put on
//! u, then turned about the ramp normal until r points along F), and the viscous flow
//! q̇ = ½ω(q)q is linearised there: μ̇ = Jμ with J = ∂ω/∂μ for small rotations exp(μ)q (central
//! differences). One eigenvalue of J is ≈ 0, along the loop of rest states; the point is stable
//! when the other two have negative real parts. The classification is checked by simulation:
//! sampled points, perturbed by a small rotation, must come back to rest (stable) or roll away
//! (unstable).
//!
//! Note: the SI argues that a spin on the spot always grows, since d|μ|²/dt > 0 along μ ∥ n. That
//! shows μ·Jμ > 0 for one direction, which for a non-normal J does not imply an unstable
//! eigenvalue. Stable rest points exist, and viscous runs do halt (`sphere-cruising`).

use anyhow::Result;
use glam::{DMat3, DQuat, DVec3};
use serde::Serialize;

use super::{FigureData, FigureOptions, par_map, progress};
use crate::analysis::critical_angle;
use crate::dynamics::sphere3d::DOWN;
use crate::dynamics::{Ramp, SphereViscous};
use crate::geometry::sphere::{angles, direction};
use crate::geometry::{Body, Sphere};
use crate::integrate::{self, Method};
use crate::numeric::contour::level_set;
use crate::plot::{PALETTE, Panel, Series, SeriesLabelPosition, Style};

/// Per-α result.
#[derive(Debug, Clone, Serialize)]
pub struct LevelResult {
    /// α/α*.
    pub alpha_over_alpha_star: f64,
    /// α.
    pub alpha: f64,
    /// Loop segments found.
    pub segments: usize,
    /// Fraction of loop points classified stable.
    pub stable_fraction: f64,
    /// Perturbed stable points that came back to rest nearby / tried.
    pub stable_confirmed: [usize; 2],
    /// Perturbed unstable points that left / tried.
    pub unstable_confirmed: [usize; 2],
}

/// Headline numbers.
#[derive(Debug, Serialize)]
pub struct Summary {
    /// The body: the paper's by default, or `--seed`, or `--shape`.
    pub body: String,
    /// Seed.
    pub seed: u64,
    /// α*.
    pub alpha_star: f64,
    /// Per α.
    pub levels: Vec<LevelResult>,
}

/// Rest orientation on contact direction u at α: put u on the ramp, then turn about +z until the
/// lab contact vector's horizontal part points downhill (+x), i.e. r ∥ F when Q(u) = tan α.
pub fn rest_orientation(body: &Sphere, u: DVec3) -> DQuat {
    let sp = body.surface(u);
    let tilt = DQuat::from_rotation_arc(sp.normal, DOWN);
    let r = tilt * sp.p;
    (DQuat::from_rotation_z(-r.y.atan2(r.x)) * tilt).normalize()
}

/// J = ∂ω/∂μ at q for the viscous model (central differences, ε = 1e-6).
fn jacobian(model: &SphereViscous, q: DQuat) -> DMat3 {
    let eps = 1e-6;
    let omega = |q: DQuat| model.observe(&SphereViscous::initial_state(q)).omega;
    let cols: Vec<DVec3> = [DVec3::X, DVec3::Y, DVec3::Z]
        .iter()
        .map(|e| {
            let plus = omega(DQuat::from_scaled_axis(*e * eps) * q);
            let minus = omega(DQuat::from_scaled_axis(-*e * eps) * q);
            (plus - minus) / (2.0 * eps)
        })
        .collect();
    DMat3::from_cols(cols[0], cols[1], cols[2])
}

/// Real parts of the eigenvalues of a 3×3 matrix (nalgebra's Schur decomposition).
pub fn eigen_real_parts(m: DMat3) -> [f64; 3] {
    let cols = m.to_cols_array();
    let e = crate::numeric::linalg::eigenvalues(&nalgebra::DMatrix::from_column_slice(3, 3, &cols));
    [e[0].re, e[1].re, e[2].re]
}

/// Stable when the two eigenvalues other than the one nearest 0 have negative real parts.
fn is_stable(j: DMat3) -> bool {
    let mut e = eigen_real_parts(j);
    e.sort_by(|x, y| x.abs().total_cmp(&y.abs()));
    e[1] < 0.0 && e[2] < 0.0
}

/// Whether a viscous run from `q`, a small rotation away from the rest orientation `rest`, stays
/// near it: it comes to rest (|ω| < 1e-8) within `t_max` less than 0.05 rad from `rest`. A
/// neighbour on the (neutral) loop counts as near; an unstable point is left for good, either
/// rolling away or settling on a distant stable part of the loop.
fn stays_near(model: &SphereViscous, q: DQuat, rest: DQuat, t_max: f64) -> Result<bool> {
    let mut st = integrate::stepper(
        model,
        0.0,
        SphereViscous::initial_state(q),
        Method::dop853(1e-10),
    )?;
    while st.t() < t_max {
        st.step(t_max)?;
        let y = st.y();
        let now = DQuat::from_xyzw(y[1], y[2], y[3], y[0]).normalize();
        if 2.0 * now.dot(rest).abs().min(1.0).acos() > 0.05 {
            return Ok(false);
        }
        if model.observe(y).omega.length() < 1e-8 {
            return Ok(true);
        }
    }
    Ok(false)
}

/// Runs the figure: computes it, then writes OUT/sphere-halting/{data.csv, summary.json, figure.png}.
pub fn run(opts: &FigureOptions) -> Result<Summary> {
    let dir = opts.dir("sphere-halting")?;
    compute(opts)?.write_to(&dir, opts)
}

/// Computes the figure's rows, headline numbers and chart; writes nothing.
pub fn compute(opts: &FigureOptions) -> Result<FigureData<Summary>> {
    opts.no_alpha("sphere-halting", "α/α* over its levels")?;
    let fig = opts.sphere("sphere-halting")?;
    let (body, seed) = (fig.body.clone(), fig.seed);
    let ca = critical_angle(&Body::Sphere(body.clone()));
    super::refuse_perfect_sphere(
        "sphere-halting",
        ca.alpha_star,
        "it has no rest point on any tilted plane, so there are no halting loops Q = tan α; it \
         rolls from every orientation",
    )?;
    let (nt, np) = if opts.quick { (91, 181) } else { (181, 361) };
    let thetas: Vec<f64> = (0..nt)
        .map(|i| std::f64::consts::PI * i as f64 / (nt - 1) as f64)
        .collect();
    let phis: Vec<f64> = (0..np)
        .map(|j| -std::f64::consts::PI + std::f64::consts::TAU * j as f64 / (np - 1) as f64)
        .collect();
    let q: Vec<Vec<f64>> = thetas
        .iter()
        .map(|&t| {
            phis.iter()
                .map(|&p| body.surface(direction(t, p)).quality())
                .collect()
        })
        .collect();
    let mut levels = Vec::new();
    let mut series = Vec::new();
    let mut rows = Vec::new();
    for (li, f) in [0.5, 0.75, 0.9].into_iter().enumerate() {
        let alpha = f * ca.alpha_star;
        let ramp = Ramp::new(alpha, 0.0)?;
        let segs = level_set(&q, &thetas, &phis, alpha.tan());
        let bar = progress(segs.len(), "stability");
        let stab = par_map(segs.len(), &bar, |k| {
            let ((p0, t0), (p1, t1)) = segs[k];
            let u = direction(0.5 * (t0 + t1), 0.5 * (p0 + p1));
            let model = SphereViscous::new(&body, &ramp);
            is_stable(jacobian(&model, rest_orientation(&body, u)))
        });
        let (mut stable_pts, mut unstable_pts) = (Vec::new(), Vec::new());
        for (k, ((p0, t0), (p1, t1))) in segs.iter().enumerate() {
            let target = if stab[k] {
                &mut stable_pts
            } else {
                &mut unstable_pts
            };
            target.push((*p0, *t0));
            target.push((*p1, *t1));
            rows.push(vec![
                alpha,
                0.5 * (p0 + p1),
                0.5 * (t0 + t1),
                if stab[k] { 1.0 } else { 0.0 },
            ]);
        }
        // Check the classification by simulation on a few points of each kind.
        let model = SphereViscous::new(&body, &ramp);
        let check = |want: bool| -> Result<[usize; 2]> {
            let idx: Vec<usize> = (0..segs.len()).filter(|&k| stab[k] == want).collect();
            let picks: Vec<usize> = idx
                .iter()
                .step_by((idx.len() / 4).max(1))
                .take(4)
                .copied()
                .collect();
            let mut ok = 0;
            for &k in &picks {
                let ((p0, t0), (p1, t1)) = segs[k];
                let q = rest_orientation(&body, direction(0.5 * (t0 + t1), 0.5 * (p0 + p1)));
                let kicked = DQuat::from_scaled_axis(DVec3::new(1e-4, -2e-4, 1.5e-4)) * q;
                if stays_near(&model, kicked, q, 400.0)? == want {
                    ok += 1;
                }
            }
            Ok([ok, picks.len()])
        };
        let stable_confirmed = check(true)?;
        let unstable_confirmed = check(false)?;
        let total = segs.len().max(1) as f64;
        levels.push(LevelResult {
            alpha_over_alpha_star: f,
            alpha,
            segments: segs.len(),
            stable_fraction: stab.iter().filter(|s| **s).count() as f64 / total,
            stable_confirmed,
            unstable_confirmed,
        });
        let shade = 0.45 + 0.25 * li as f64;
        let tint = |c: (u8, u8, u8)| {
            (
                (c.0 as f64 * shade) as u8,
                (c.1 as f64 * shade) as u8,
                (c.2 as f64 * shade) as u8,
            )
        };
        series.push(Series {
            label: format!("stable, α = {f} α*"),
            points: stable_pts,
            color: tint(PALETTE[2]),
            style: Style::Segments,
        });
        series.push(Series {
            label: format!("unstable, α = {f} α*"),
            points: unstable_pts,
            color: tint(PALETTE[1]),
            style: Style::Segments,
        });
    }
    let (t_star, p_star) = angles(DVec3::from_array(ca.direction));
    series.push(Series {
        label: "max Q (rests only up to α*)".into(),
        points: vec![(p_star, t_star)],
        color: (0, 0, 0),
        style: Style::Markers,
    });
    let csv_header = "alpha,phi,theta,stable";
    let summary = Summary {
        body: fig.label,
        seed,
        alpha_star: ca.alpha_star,
        levels,
    };
    let panel = Panel {
        title: format!(
            "halting loops Q = tan α on the body (α* = {:.4}) and their stability",
            ca.alpha_star
        ),
        x_label: "contact azimuth φ (rad)".into(),
        y_label: "contact polar angle θ (rad)".into(),
        log_x: false,
        log_y: false,
        series,
        legend: SeriesLabelPosition::UpperRight,
        equal_aspect: false,
    };
    Ok(FigureData {
        panels: vec![panel],
        columns: 1,
        size: (1300, 760),
        header: csv_header,
        rows,
        summary,
    })
}
