//! The 2D body: r(θ) = 1 + Σ_{l≥2} a_l/l² sin(l(θ − θ_l)) (SI §1C), with exact derivatives up to
//! r''', the curvature κ and the quantities the 2D models are written in. A body fitted to a
//! faceted print rolls on the print's outline instead ([`super::outline`]), its modes kept as
//! the smooth fit.

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
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Disk;
    /// // The perfect disk is a unit circle: κ = 1 everywhere.
    /// assert!((Disk::perfect().jet(0.4).curvature() - 1.0).abs() < 1e-15);
    /// ```
    pub fn curvature(&self) -> f64 {
        self.convexity() / (self.r * self.r + self.r1 * self.r1).powf(1.5)
    }

    /// The convexity numerator r² + 2r'² − r r'' (must be > 0 everywhere).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// // A strong l = 2 mode flattens the body: the numerator turns negative somewhere.
    /// let flat = Disk::new(vec![DiskMode { l: 2, a: 3.0, phase: 0.0 }]);
    /// assert!((0..360).any(|i| flat.jet(i as f64 * 0.0175).convexity() < 0.0));
    /// ```
    pub fn convexity(&self) -> f64 {
        self.r * self.r + 2.0 * self.r1 * self.r1 - self.r * self.r2
    }

    /// Quality factor Q = r'/r = d ln r / dθ (SI §1B).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// let disk = Disk::new(vec![DiskMode { l: 2, a: 0.4, phase: 0.3 }]);
    /// let (t, h) = (0.7, 1e-6);
    /// let d_ln_r = (disk.jet(t + h).r.ln() - disk.jet(t - h).r.ln()) / (2.0 * h);
    /// assert!((disk.jet(t).quality() - d_ln_r).abs() < 1e-9);
    /// ```
    pub fn quality(&self) -> f64 {
        self.r1 / self.r
    }

    /// dQ/dθ = r''/r − r'²/r².
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// let disk = Disk::new(vec![DiskMode { l: 3, a: 0.5, phase: 0.1 }]);
    /// let (t, h) = (0.7, 1e-5);
    /// let fd = (disk.jet(t + h).quality() - disk.jet(t - h).quality()) / (2.0 * h);
    /// assert!((disk.jet(t).quality_d1() - fd).abs() < 1e-8);
    /// ```
    pub fn quality_d1(&self) -> f64 {
        self.r2 / self.r - (self.r1 / self.r).powi(2)
    }

    /// d²Q/dθ² = r'''/r − 3 r' r''/r² + 2 r'³/r³.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// let disk = Disk::new(vec![DiskMode { l: 3, a: 0.5, phase: 0.1 }]);
    /// let (t, h) = (0.7, 1e-5);
    /// let fd = (disk.jet(t + h).quality_d1() - disk.jet(t - h).quality_d1()) / (2.0 * h);
    /// assert!((disk.jet(t).quality_d2() - fd).abs() < 1e-7);
    /// ```
    pub fn quality_d2(&self) -> f64 {
        let q = self.r1 / self.r;
        self.r3 / self.r - 3.0 * q * self.r2 / self.r + 2.0 * q * q * q
    }

    /// s(θ) = −dψ/dθ = √(r² + r'²) κ = (r² + 2r'² − r r'')/(r² + r'²): how fast the body turns per
    /// unit of contact angle.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// // The body turns once per turn of the contact angle: ∫ s dθ over a period is 2π.
    /// let disk = Disk::new(vec![DiskMode { l: 2, a: 0.5, phase: 0.0 }]);
    /// let n = 4000;
    /// let total: f64 = (0..n).map(|i| disk.jet(i as f64 * std::f64::consts::TAU / n as f64).turn_rate()).sum::<f64>()
    ///     * std::f64::consts::TAU / n as f64;
    /// assert!((total - std::f64::consts::TAU).abs() < 1e-9);
    /// ```
    pub fn turn_rate(&self) -> f64 {
        self.convexity() / (self.r * self.r + self.r1 * self.r1)
    }

    /// ds/dθ, exact.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// let disk = Disk::new(vec![DiskMode { l: 4, a: 0.6, phase: 0.2 }]);
    /// let (t, h) = (1.1, 1e-5);
    /// let fd = (disk.jet(t + h).turn_rate() - disk.jet(t - h).turn_rate()) / (2.0 * h);
    /// assert!((disk.jet(t).turn_rate_d1() - fd).abs() < 1e-8);
    /// ```
    pub fn turn_rate_d1(&self) -> f64 {
        let (r, r1, r2, r3) = (self.r, self.r1, self.r2, self.r3);
        let num = r * r + 2.0 * r1 * r1 - r * r2;
        let den = r * r + r1 * r1;
        let num_d = 2.0 * r * r1 + 4.0 * r1 * r2 - r1 * r2 - r * r3;
        let den_d = 2.0 * r * r1 + 2.0 * r1 * r2;
        (num_d * den - num * den_d) / (den * den)
    }

    /// Arc length per unit contact angle, √(r² + r'²).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// // On the unit circle a radian of contact angle is a unit of arc.
    /// let disk = Disk::perfect();
    /// assert_eq!(disk.jet(0.3).arc_rate(), 1.0);
    /// let bumpy = Disk::new(vec![DiskMode { l: 2, a: 0.5, phase: 0.0 }]);
    /// assert!(bumpy.jet(0.3).arc_rate() > bumpy.jet(0.3).r);
    /// ```
    pub fn arc_rate(&self) -> f64 {
        (self.r * self.r + self.r1 * self.r1).sqrt()
    }

    /// Height of the centre above the ramp when this point touches it: r²/√(r² + r'²).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Disk;
    /// assert_eq!(Disk::perfect().jet(2.0).height(), 1.0);
    /// ```
    pub fn height(&self) -> f64 {
        self.r * self.r / self.arc_rate()
    }

    /// Downhill offset of the centre from the contact point: −r r'/√(r² + r'²).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// assert_eq!(Disk::perfect().jet(2.0).centre_offset(), 0.0);
    /// // Where r grows with θ the centre sits uphill of the contact point.
    /// let disk = Disk::new(vec![DiskMode { l: 2, a: 0.5, phase: 0.0 }]);
    /// assert!(disk.jet(0.1).r1 > 0.0 && disk.jet(0.1).centre_offset() < 0.0);
    /// ```
    pub fn centre_offset(&self) -> f64 {
        -self.r * self.r1 / self.arc_rate()
    }

    /// Angle Δθ between contact vector and normal, tan Δθ = r'/r.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// let disk = Disk::new(vec![DiskMode { l: 2, a: 0.5, phase: 0.0 }]);
    /// let j = disk.jet(0.4);
    /// assert!((j.normal_offset().tan() - j.quality()).abs() < 1e-14);
    /// ```
    pub fn normal_offset(&self) -> f64 {
        self.r1.atan2(self.r)
    }
}

/// A star-shaped 2D body (a cylinder's cross-section) with ⟨r⟩ = 1.
#[derive(Debug, Clone)]
pub struct Disk {
    modes: Vec<DiskMode>,
    /// Its convex hull, found the first time it is asked for (a run of a dented body).
    hull: std::sync::OnceLock<super::hull::DiskHull>,
    /// The flat-sided section of the print it was fitted to, when its shape file keeps one.
    printed: Option<std::sync::Arc<super::facets::PrintedSection>>,
    /// That section's rounded outline, which the body then rolls on instead of the fit.
    outline: Option<std::sync::Arc<super::outline::PrintedOutline>>,
}

impl PartialEq for Disk {
    fn eq(&self, other: &Self) -> bool {
        self.modes == other.modes && self.printed == other.printed
    }
}

impl Disk {
    /// A disk from its modes (validated by [`crate::geometry::Body::from_shape`]).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// let disk = Disk::new(vec![DiskMode { l: 2, a: 0.4, phase: 0.0 }]);
    /// // r = 1 + 0.4/4 · sin 2θ.
    /// assert!((disk.jet(std::f64::consts::FRAC_PI_4).r - 1.1).abs() < 1e-15);
    /// ```
    pub fn new(modes: Vec<DiskMode>) -> Self {
        Self {
            modes,
            hull: std::sync::OnceLock::new(),
            printed: None,
            outline: None,
        }
    }

    /// This disk with the section of the print it was fitted to (or without one): it then
    /// rolls on that section's rounded outline ([`super::outline`]), its sides the flats of its
    /// hull, and keeps its modes as the smooth fit (for drawing, design and the shape file).
    /// A section that is not a polygon around the centroid is dropped (shape files are checked
    /// before: [`super::Body::from_shape`]).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Disk;
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// let square = PrintedSection { vertices: vec![[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]] };
    /// let disk = Disk::perfect().with_printed_section(Some(square.clone()));
    /// assert_eq!(disk.printed_section(), Some(&square));
    /// assert_ne!(disk, Disk::perfect());
    /// // It rolls on the square: four flat sides, at the apothem 1.
    /// assert_eq!(disk.hull().bridges().len(), 4);
    /// assert!((disk.jet(0.0).r - 1.0).abs() < 1e-15);
    /// ```
    pub fn with_printed_section(self, section: Option<super::facets::PrintedSection>) -> Self {
        let outline = section
            .as_ref()
            .and_then(super::outline::PrintedOutline::of)
            .map(std::sync::Arc::new);
        let section = section.filter(|_| outline.is_some());
        Self {
            modes: self.modes,
            hull: std::sync::OnceLock::new(),
            printed: section.map(std::sync::Arc::new),
            outline,
        }
    }

    /// The smooth body of its modes alone, without the print's section it may roll on: the
    /// fit `design` works on and a mesh fit's residuals are measured against.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Disk;
    /// use rollphase_core::geometry::facets::PrintedSection;
    /// let square = PrintedSection { vertices: vec![[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0]] };
    /// let print = Disk::perfect().with_printed_section(Some(square));
    /// assert_eq!(print.smooth_fit(), Disk::perfect());
    /// ```
    pub fn smooth_fit(&self) -> Disk {
        Disk::new(self.modes.clone())
    }

    /// The outline it rolls on when it was fitted to a faceted print
    /// ([`Disk::with_printed_section`]); `None` for a body of the model.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Disk;
    /// assert!(Disk::perfect().printed_outline().is_none());
    /// ```
    pub fn printed_outline(&self) -> Option<&super::outline::PrintedOutline> {
        self.outline.as_deref()
    }

    /// The section of the print it was fitted to, if its shape file keeps one
    /// ([`super::facets::PrintedSection`]).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Disk;
    /// assert!(Disk::perfect().printed_section().is_none());
    /// ```
    pub fn printed_section(&self) -> Option<&super::facets::PrintedSection> {
        self.printed.as_deref()
    }

    /// The perfect disk r ≡ 1.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Disk;
    /// let disk = Disk::perfect();
    /// assert!(disk.modes().is_empty() && disk.jet(1.0).r == 1.0);
    /// ```
    pub fn perfect() -> Self {
        Self::new(Vec::new())
    }

    /// Its convex hull: the bridges over its dents, none for a convex body (computed once).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// assert!(Disk::perfect().hull().bridges().is_empty());
    /// let dented = Disk::new(vec![DiskMode { l: 3, a: 2.0, phase: 0.0 }]);
    /// assert_eq!(dented.hull().bridges().len(), 3);
    /// ```
    pub fn hull(&self) -> &super::hull::DiskHull {
        self.hull.get_or_init(|| match &self.outline {
            Some(o) => super::hull::DiskHull::from_bridges(o.bridges().to_vec()),
            None => super::hull::DiskHull::of(self),
        })
    }

    /// The modes.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// let mode = DiskMode { l: 3, a: 0.2, phase: 1.0 };
    /// assert_eq!(Disk::new(vec![mode]).modes(), &[mode]);
    /// ```
    pub fn modes(&self) -> &[DiskMode] {
        &self.modes
    }

    /// The same cylinder turned end for end: its section seen from the other side, r(−θ)
    /// (each mode a_l, θ_l becomes −a_l, −θ_l). A cylinder can be set on the ramp either way
    /// round, and rolls down it with its section mirrored the other way, so its critical angle
    /// that way is the mirror's.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// let d = Disk::new(vec![DiskMode { l: 3, a: 0.2, phase: 0.4 }, DiskMode { l: 2, a: 0.1, phase: 1.0 }]);
    /// let m = d.turned();
    /// for t in [0.0, 0.7, 2.0] {
    ///     assert!((m.jet(t).r - d.jet(-t).r).abs() < 1e-15);
    /// }
    /// ```
    pub fn turned(&self) -> Disk {
        Disk::new(
            self.modes
                .iter()
                .map(|m| DiskMode {
                    l: m.l,
                    a: -m.a,
                    phase: -m.phase,
                })
                .collect(),
        )
        .with_printed_section(self.printed.as_deref().map(|p| p.turned()))
    }

    /// r, r', r'', r''' at contact angle θ, exact.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, DiskMode};
    /// let disk = Disk::new(vec![DiskMode { l: 2, a: 0.4, phase: 0.3 }]);
    /// let (t, h) = (0.9, 1e-5);
    /// let j = disk.jet(t);
    /// assert!((j.r1 - (disk.jet(t + h).r - disk.jet(t - h).r) / (2.0 * h)).abs() < 1e-9);
    /// assert!((j.r3 - (disk.jet(t + h).r2 - disk.jet(t - h).r2) / (2.0 * h)).abs() < 1e-8);
    /// ```
    pub fn jet(&self, theta: f64) -> RadiusJet {
        if let Some(o) = &self.outline {
            let [r, r1, r2, r3] = o.jet(theta);
            return RadiusJet { r, r1, r2, r3 };
        }
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
