//! The 2D body: r(θ) = 1 + Σ_{l≥2} a_l/l² sin(l(θ − θ_l)) (SI §1C), with exact derivatives up to
//! r''', the curvature κ and the quantities the 2D models are written in.

use serde::{Deserialize, Serialize};

/// One Fourier mode of a disk: amplitude `a` (the paper's A_l) and phase θ_l = `phase`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiskMode {
    /// Mode number l ≥ 2.
    pub l: u32,
    /// Amplitude A_l; the radius carries A_l / l².
    pub a: f64,
    /// Phase θ_l in radians.
    pub phase: f64,
}

/// r and its first three θ-derivatives at one contact angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadiusJet {
    /// r(θ)
    pub r: f64,
    /// r'(θ)
    pub r1: f64,
    /// r''(θ)
    pub r2: f64,
    /// r'''(θ)
    pub r3: f64,
}

impl RadiusJet {
    /// Curvature κ = (r² + 2r'² − r r'') / (r² + r'²)^{3/2} (SI eq. after "dψ/dθ").
    pub fn curvature(&self) -> f64 {
        self.convexity() / (self.r * self.r + self.r1 * self.r1).powf(1.5)
    }

    /// The convexity numerator r² + 2r'² − r r'' (must be > 0 everywhere).
    pub fn convexity(&self) -> f64 {
        self.r * self.r + 2.0 * self.r1 * self.r1 - self.r * self.r2
    }

    /// Quality factor Q = r'/r = d ln r / dθ (SI §1B).
    pub fn quality(&self) -> f64 {
        self.r1 / self.r
    }

    /// dQ/dθ = r''/r − r'²/r².
    pub fn quality_d1(&self) -> f64 {
        self.r2 / self.r - (self.r1 / self.r).powi(2)
    }

    /// d²Q/dθ² = r'''/r − 3 r' r''/r² + 2 r'³/r³.
    pub fn quality_d2(&self) -> f64 {
        let q = self.r1 / self.r;
        self.r3 / self.r - 3.0 * q * self.r2 / self.r + 2.0 * q * q * q
    }

    /// s(θ) = −dψ/dθ = √(r² + r'²) κ = (r² + 2r'² − r r'')/(r² + r'²): how fast the body turns per
    /// unit of contact angle.
    pub fn turn_rate(&self) -> f64 {
        self.convexity() / (self.r * self.r + self.r1 * self.r1)
    }

    /// ds/dθ, exact.
    pub fn turn_rate_d1(&self) -> f64 {
        let (r, r1, r2, r3) = (self.r, self.r1, self.r2, self.r3);
        let num = r * r + 2.0 * r1 * r1 - r * r2;
        let den = r * r + r1 * r1;
        let num_d = 2.0 * r * r1 + 4.0 * r1 * r2 - r1 * r2 - r * r3;
        let den_d = 2.0 * r * r1 + 2.0 * r1 * r2;
        (num_d * den - num * den_d) / (den * den)
    }

    /// Arc length per unit contact angle, √(r² + r'²).
    pub fn arc_rate(&self) -> f64 {
        (self.r * self.r + self.r1 * self.r1).sqrt()
    }

    /// Height of the centre above the ramp when this point touches it: r²/√(r² + r'²).
    pub fn height(&self) -> f64 {
        self.r * self.r / self.arc_rate()
    }

    /// Downhill offset of the centre from the contact point: −r r'/√(r² + r'²).
    pub fn centre_offset(&self) -> f64 {
        -self.r * self.r1 / self.arc_rate()
    }

    /// Angle Δθ between contact vector and normal, tan Δθ = r'/r.
    pub fn normal_offset(&self) -> f64 {
        self.r1.atan2(self.r)
    }
}

/// A star-shaped 2D body (a cylinder's cross-section) with ⟨r⟩ = 1.
#[derive(Debug, Clone, PartialEq)]
pub struct Disk {
    modes: Vec<DiskMode>,
}

impl Disk {
    /// A disk from its modes (validated by [`crate::geometry::Body::from_shape`]).
    pub fn new(modes: Vec<DiskMode>) -> Self {
        Self { modes }
    }

    /// The perfect disk r ≡ 1.
    pub fn perfect() -> Self {
        Self { modes: Vec::new() }
    }

    /// The modes.
    pub fn modes(&self) -> &[DiskMode] {
        &self.modes
    }

    /// r, r', r'', r''' at contact angle θ, exact.
    pub fn jet(&self, theta: f64) -> RadiusJet {
        let mut j = RadiusJet {
            r: 1.0,
            r1: 0.0,
            r2: 0.0,
            r3: 0.0,
        };
        for m in &self.modes {
            let l = m.l as f64;
            let (s, c) = (l * (theta - m.phase)).sin_cos();
            j.r += m.a / (l * l) * s;
            j.r1 += m.a / l * c;
            j.r2 -= m.a * s;
            j.r3 -= m.a * l * c;
        }
        j
    }
}
