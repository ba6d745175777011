//! 2D rolling of a disk r(θ) on a ramp (SI §1A).
//!
//! Viscous model (SI eq. "viscous limit"), state [θ, x_c]:
//!   θ̇ = (F/γ) r (r sin α − r' cos α) / ((r² + r'²) κ),   ẋ_c = √(r² + r'²) θ̇,
//! with x_c the arc length rolled (the contact point's position on the ramp).
//!
//! Inertial model, state [θ, θ̇, x_c, W] (W = work done by drag). We derive it from the
//! Lagrangian rather than transcribe the paper's θ̈: rolling in 2D is holonomic, the body turns by
//! ψ̇ = −s(θ) θ̇ with s = √(r² + r'²) κ, the centre moves at speed |ψ̇| r, so
//!   T = ½ J(θ) θ̇²,  J = (I + m r²) s²,   V = −F sin α x_cm + F cos α h,
//!   dx_cm/dθ = κ r²,  h = r²/√(r² + r'²),  dh/dθ = κ r r',   drag force −γ s² θ̇,
//! and Lagrange's equation gives
//!   θ̈ = [F κ r (r sin α − r' cos α) − γ s² θ̇] / J − (m r r'/(I + m r²) + s'/s) θ̇².
//! The first term equals the paper's (SI eq. for θ̈: F r (r sin α − r' cos α)/(κ (r² + r'²)) over
//! I + m r²) exactly. The θ̇² coefficient is ½J'/J, which makes E = ½Jθ̇² + V + W constant along
//! solutions. `tests/paper_equations.rs` evaluates the paper's bracket as printed and finds it
//! equal to ½J'/J (to 1e-9, the accuracy of its finite-difference κ'): the paper's 2D equation is
//! right; we keep the shorter Lagrangian form because it needs no κ'. Dimensionless: F = γ = ⟨r⟩ = 1, I = m/2 (m = m/m0).
//!
//! Drawing: ψ = 3π/2 + Δθ − θ with tan Δθ = r'/r (continuous with an unwrapped θ), the centre at
//! x_cm = x_c − r r'/√(r² + r'²) downhill and height h above the ramp.

use std::f64::consts::PI;

use glam::{DQuat, DVec3};

use super::{ModelHealth, ModelKind, Observation, Observe, Ramp, RollingModel};
use crate::geometry::{Disk, RadiusJet};
use crate::integrate::OdeSystem;

/// Viscous 2D model; state [θ, x_c].
pub struct DiskViscous<'a> {
    disk: &'a Disk,
    sin_a: f64,
    cos_a: f64,
    drag: f64,
}

impl<'a> DiskViscous<'a> {
    /// The model for `disk` on `ramp` (mass ignored).
    pub fn new(disk: &'a Disk, ramp: &Ramp) -> Self {
        Self {
            disk,
            sin_a: ramp.alpha_rad.sin(),
            cos_a: ramp.alpha_rad.cos(),
            drag: if ramp.drag > 0.0 { ramp.drag } else { 1.0 },
        }
    }

    /// θ̇(θ) = r (r sin α − r' cos α) / ((r² + r'²) κ) / γ.
    pub fn theta_dot(&self, theta: f64) -> f64 {
        let j = self.disk.jet(theta);
        theta_dot_viscous(&j, self.sin_a, self.cos_a) / self.drag
    }
}

pub(crate) fn theta_dot_viscous(j: &RadiusJet, sin_a: f64, cos_a: f64) -> f64 {
    // (r² + r'²) κ = convexity / √(r² + r'²)
    j.r * (j.r * sin_a - j.r1 * cos_a) * j.arc_rate() / j.convexity()
}

impl OdeSystem<2> for DiskViscous<'_> {
    fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] {
        let j = self.disk.jet(y[0]);
        let td = theta_dot_viscous(&j, self.sin_a, self.cos_a) / self.drag;
        [td, j.arc_rate() * td]
    }
}

impl Observe<2> for DiskViscous<'_> {
    fn energy_balance(&self, _y: &[f64; 2]) -> Option<f64> {
        None
    }
}

/// Inertial 2D model; state [θ, θ̇, x_c, W].
pub struct DiskInertial<'a> {
    disk: &'a Disk,
    sin_a: f64,
    cos_a: f64,
    mass: f64,
    drag: f64,
}

impl<'a> DiskInertial<'a> {
    /// The model for `disk` on `ramp`; needs m/m0 > 0.
    pub fn new(disk: &'a Disk, ramp: &Ramp) -> Self {
        Self {
            disk,
            sin_a: ramp.alpha_rad.sin(),
            cos_a: ramp.alpha_rad.cos(),
            mass: ramp.mass_ratio,
            drag: ramp.drag,
        }
    }

    /// θ̈ from the Lagrangian form above.
    pub fn theta_ddot(&self, theta: f64, theta_dot: f64) -> f64 {
        let j = self.disk.jet(theta);
        self.theta_ddot_jet(&j, theta_dot)
    }

    fn theta_ddot_jet(&self, j: &RadiusJet, td: f64) -> f64 {
        let s = j.turn_rate();
        let inertia = self.mass * (0.5 + j.r * j.r); // I + m r², I = m/2
        let drive = j.curvature() * j.r * (j.r * self.sin_a - j.r1 * self.cos_a);
        let accel = (drive - self.drag * s * s * td) / (inertia * s * s);
        accel - (self.mass * j.r * j.r1 / inertia + j.turn_rate_d1() / s) * td * td
    }

    /// Moment J(θ) = (I + m r²) s² of the reduced one-degree-of-freedom system.
    pub fn reduced_inertia(&self, theta: f64) -> f64 {
        let j = self.disk.jet(theta);
        let s = j.turn_rate();
        self.mass * (0.5 + j.r * j.r) * s * s
    }

    /// Potential V = −F sin α x_cm + F cos α h for contact angle θ and rolled arc x_c.
    pub fn potential(&self, theta: f64, x_c: f64) -> f64 {
        let j = self.disk.jet(theta);
        -self.sin_a * (x_c + j.centre_offset()) + self.cos_a * j.height()
    }
}

impl OdeSystem<4> for DiskInertial<'_> {
    fn rhs(&self, _t: f64, y: &[f64; 4]) -> [f64; 4] {
        let j = self.disk.jet(y[0]);
        let td = y[1];
        let s = j.turn_rate();
        [
            td,
            self.theta_ddot_jet(&j, td),
            j.arc_rate() * td,
            self.drag * s * s * td * td,
        ]
    }
}

impl Observe<4> for DiskInertial<'_> {
    fn energy_balance(&self, y: &[f64; 4]) -> Option<f64> {
        let kinetic = 0.5 * self.reduced_inertia(y[0]) * y[1] * y[1];
        Some(kinetic + self.potential(y[0], y[2]) + y[3])
    }
}

/// What a 2D state looks like in the lab: rotation angle and centre of mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiskPose {
    /// Body-to-lab rotation ψ (radians, continuous when θ is unwrapped).
    pub psi: f64,
    /// Centre of mass downhill along the ramp.
    pub x: f64,
    /// Height of the centre of mass above the ramp.
    pub y: f64,
}

/// ψ and the centre of mass for contact angle θ and rolled arc x_c.
pub fn pose(disk: &Disk, theta: f64, x_c: f64) -> DiskPose {
    let j = disk.jet(theta);
    DiskPose {
        psi: 1.5 * PI + j.normal_offset() - theta,
        x: x_c + j.centre_offset(),
        y: j.height(),
    }
}

impl RollingModel<2> for DiskViscous<'_> {
    const KIND: ModelKind = ModelKind::DiskViscous;
    const COLUMNS: &'static str = "t,theta,theta_dot,psi,x,y";

    fn row(&self, t: f64, y: &[f64; 2], out: &mut Vec<f64>) {
        let p = pose(self.disk, y[0], y[1]);
        out.clear();
        out.extend([t, y[0], self.theta_dot(y[0]), p.psi, p.x, p.y]);
    }

    fn health(&self, _y: &[f64; 2]) -> ModelHealth {
        ModelHealth::default()
    }

    fn observation(&self, y: &[f64; 2]) -> Observation {
        disk_observation(self.disk, y[0], self.theta_dot(y[0]), y[1], None)
    }

    fn section(&self, y: &[f64; 2]) -> f64 {
        (y[0] / 2.0).sin()
    }

    fn section_point(&self, _y: &[f64; 2]) -> Option<DVec3> {
        None
    }
}

impl RollingModel<4> for DiskInertial<'_> {
    const KIND: ModelKind = ModelKind::DiskInertial;
    const COLUMNS: &'static str = "t,theta,theta_dot,psi,x,y";

    fn row(&self, t: f64, y: &[f64; 4], out: &mut Vec<f64>) {
        let p = pose(self.disk, y[0], y[2]);
        out.clear();
        out.extend([t, y[0], y[1], p.psi, p.x, p.y]);
    }

    fn health(&self, y: &[f64; 4]) -> ModelHealth {
        ModelHealth {
            energy: self.energy_balance(y),
            ..ModelHealth::default()
        }
    }

    fn observation(&self, y: &[f64; 4]) -> Observation {
        disk_observation(self.disk, y[0], y[1], y[2], self.energy_balance(y))
    }

    fn section(&self, y: &[f64; 4]) -> f64 {
        (y[0] / 2.0).sin()
    }

    fn section_point(&self, _y: &[f64; 4]) -> Option<DVec3> {
        None
    }
}

/// 2D: the cross-section lies in the ramp's (x, z) plane; ψ turns it about the y axis (the
/// body point at angle θ sits at r(θ)(cos θ, 0, sin θ) in the body frame, as in
/// [`crate::geometry::mesh::disk_mesh`]). Contact points are on the mid-plane y = 0; where a
/// cylinder of some length is drawn is the view's business.
fn disk_observation(
    d: &Disk,
    theta: f64,
    theta_dot: f64,
    x_c: f64,
    energy: Option<f64>,
) -> Observation {
    let p = pose(d, theta, x_c);
    let r = d.jet(theta).r;
    // Lab 2D (x downhill, y up) maps to ramp 3D (x, z); a counter-clockwise turn ψ in that plane
    // is a rotation by −ψ about +y.
    Observation {
        rotation: DQuat::from_rotation_y(-p.psi),
        centre: DVec3::new(p.x, 0.0, p.y),
        contact_on_ramp: DVec3::new(x_c, 0.0, 0.0),
        contact_in_body: DVec3::new(r * theta.cos(), 0.0, r * theta.sin()),
        orientation: None,
        angular_speed: theta_dot.abs(),
        theta: Some(theta),
        theta_dot: Some(theta_dot),
        health: ModelHealth {
            energy,
            ..ModelHealth::default()
        },
    }
}
