//! A run's start as a person gives it (the fields of the command line's and Python's
//! `simulate`), checked once for both front-ends: which fields apply to which body and model,
//! finite numbers, a non-zero quaternion, and huge disk angles reduced modulo 2π. Each
//! front-end spells the fields its own way ([`Spelling`]: `--q0` or `q0`); the checks and the
//! messages are these.

use glam::{DQuat, DVec3};

use super::InitialState;
use crate::dynamics::sphere3d::orientation_touching;
use crate::geometry::Body;
use crate::geometry::sphere::direction;

/// Angles beyond this are reduced modulo 2π: at 1e17 an f64 has no digits left below 2π, so θ
/// could not move.
pub const MAX_PLAIN_ANGLE: f64 = 1e6;

/// A start as given, before checking. Absent fields take their defaults: a sphere touches the
/// ramp at its south pole, a disk at θ = 0, both at rest.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StartRequest {
    /// Sphere: the orientation (w, x, y, z), normalised when the run starts.
    pub q0: Option<[f64; 4]>,
    /// Sphere: the body-frame contact direction (θ, φ) to put on the ramp.
    pub contact: Option<[f64; 2]>,
    /// Sphere: a turn about the ramp's normal after touching (rad; 0 if absent).
    pub spin: Option<f64>,
    /// Sphere, inertial: the lab angular velocity.
    pub omega0: Option<[f64; 3]>,
    /// Disk: the contact angle θ.
    pub theta0: Option<f64>,
    /// Disk, inertial: θ̇.
    pub theta_dot0: Option<f64>,
}

/// A field of [`StartRequest`], for messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StartField {
    /// [`StartRequest::q0`].
    Q0,
    /// [`StartRequest::contact`].
    Contact,
    /// [`StartRequest::spin`].
    Spin,
    /// [`StartRequest::omega0`].
    Omega0,
    /// [`StartRequest::theta0`].
    Theta0,
    /// [`StartRequest::theta_dot0`].
    ThetaDot0,
}

impl StartField {
    /// The field's name as the library (and Python, whose arguments have these names) gives
    /// it; the command line and scenes name it their own way through [`Spelling`].
    ///
    /// # Example
    /// ```
    /// use rollphase_core::simulate::start::StartField;
    /// assert_eq!(StartField::ThetaDot0.name(), "theta_dot0");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            StartField::Q0 => "q0",
            StartField::Contact => "contact",
            StartField::Spin => "spin",
            StartField::Omega0 => "omega0",
            StartField::Theta0 => "theta0",
            StartField::ThetaDot0 => "theta_dot0",
        }
    }
}

impl std::fmt::Display for StartField {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a start was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StartError {
    /// An initial angular velocity given to the viscous model, where it follows from the state.
    #[error("{0} does not apply to the viscous model (m/m0 = 0)")]
    NotViscous(StartField),
    /// A sphere's field given for a disk.
    #[error("{0} does not apply to a 2D disk")]
    NotDisk(StartField),
    /// A disk's field given for a sphere.
    #[error("{0} does not apply to a 3D sphere")]
    NotSphere(StartField),
    /// Both ways of giving the orientation.
    #[error("q0 and contact both set the starting orientation")]
    Both,
    /// A spin with q0, which is already the whole orientation.
    #[error("spin turns the body after contact puts it on the ramp; q0 is already the orientation")]
    SpinWithQ0,
    /// A number that is not finite.
    #[error("{field} {value} is not a finite number")]
    NotFinite {
        /// Which field.
        field: StartField,
        /// The value.
        value: f64,
    },
    /// q0 = 0.
    #[error("q0 {0:?} has zero length")]
    ZeroQuaternion([f64; 4]),
}

/// How a front-end names the fields in its messages.
#[derive(Debug, Clone, Copy)]
pub struct Spelling<'a> {
    /// A field's name: `--q0` on the command line, `q0` in Python.
    pub field: fn(StartField) -> &'static str,
    /// The mass ratio's name (`--mass`, `mass_ratio`).
    pub mass: &'static str,
    /// The viscous model as set there (`--mass 0`, `mass_ratio=0`).
    pub viscous: &'static str,
    /// The body, as the user knows it (its file, or "this body").
    pub body: &'a str,
}

impl StartError {
    /// The message in a front-end's own words: which field, why, and what to give instead.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::simulate::start::{Spelling, StartError, StartField};
    /// let python = Spelling {
    ///     field: |f| match f {
    ///         StartField::Omega0 => "omega0",
    ///         _ => "another",
    ///     },
    ///     mass: "mass_ratio",
    ///     viscous: "mass_ratio=0",
    ///     body: "this body",
    /// };
    /// let text = StartError::NotViscous(StartField::Omega0).explain(&python);
    /// assert!(text.starts_with("omega0 does not apply to the viscous model (mass_ratio=0)"));
    /// assert!(text.contains("give mass_ratio > 0"));
    /// ```
    pub fn explain(&self, s: &Spelling) -> String {
        let name = s.field;
        let (q0, contact, spin) = (
            name(StartField::Q0),
            name(StartField::Contact),
            name(StartField::Spin),
        );
        let (theta0, theta_dot0) = (name(StartField::Theta0), name(StartField::ThetaDot0));
        match *self {
            StartError::NotViscous(f) => {
                let why = if f == StartField::ThetaDot0 {
                    "θ̇ follows from θ; give {mass} > 0 for an initial angular velocity"
                } else {
                    "its angular velocity follows from the orientation; give {mass} > 0 for an \
                     initial spin"
                };
                format!(
                    "{} does not apply to the viscous model ({}): {}",
                    name(f),
                    s.viscous,
                    why.replace("{mass}", s.mass)
                )
            }
            StartError::NotDisk(f) => format!(
                "{} is a 2D disk: give {theta0} (and {theta_dot0}), not {}",
                s.body,
                name(f)
            ),
            StartError::NotSphere(f) => format!(
                "{} is a 3D sphere: give {q0} or {contact} (θ, φ) (and {spin}), not {}",
                s.body,
                name(f)
            ),
            StartError::Both => {
                format!("give {q0} or {contact}, not both: each sets the starting orientation")
            }
            StartError::SpinWithQ0 => format!(
                "{spin} turns the body about the ramp's normal after {contact} (or the default \
                 contact) puts it on the ramp; {q0} is already the whole orientation, so give \
                 {spin} with {contact}, or fold the turn into {q0}"
            ),
            StartError::NotFinite { field, value } => {
                format!("{} {value} is not a finite number", name(field))
            }
            StartError::ZeroQuaternion([w, x, y, z]) => format!(
                "{q0} {w},{x},{y},{z} has zero length; give a rotation quaternion w, x, y, z"
            ),
        }
    }
}

/// A checked start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckedStart {
    /// The initial state.
    pub initial: InitialState,
    /// A disk's θ0 beyond ±[`MAX_PLAIN_ANGLE`] as given and as reduced modulo 2π, for the
    /// front-end to warn about.
    pub reduced_theta0: Option<(f64, f64)>,
}

fn finite(field: StartField, values: &[f64]) -> Result<(), StartError> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(&value) => Err(StartError::NotFinite { field, value }),
        None => Ok(()),
    }
}

/// Checks `request` for `body` with m/m0 = `mass_ratio` (0: viscous) and builds the initial
/// state. Every field that does not apply to this body or model is an error, never ignored.
///
/// # Example
/// ```
/// use rollphase_core::geometry::Body;
/// use rollphase_core::simulate::InitialState;
/// use rollphase_core::simulate::start::{StartError, StartField, StartRequest, check_start};
/// let disk = Body::paper_disk(84, 0.12, 5)?;
/// let start = check_start(&disk, 1.0, &StartRequest { theta0: Some(0.5), ..Default::default() })?;
/// assert_eq!(start.initial, InitialState::Disk { theta0: 0.5, theta_dot0: 0.0 });
/// // A sphere's spin given for a disk is refused, not ignored.
/// let spun = StartRequest { spin: Some(1.0), ..Default::default() };
/// assert_eq!(check_start(&disk, 1.0, &spun), Err(StartError::NotDisk(StartField::Spin)));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn check_start(
    body: &Body,
    mass_ratio: f64,
    r: &StartRequest,
) -> Result<CheckedStart, StartError> {
    if !crate::dynamics::models::asks_for_inertia(mass_ratio) {
        if r.omega0.is_some() {
            return Err(StartError::NotViscous(StartField::Omega0));
        }
        if r.theta_dot0.is_some_and(|v| v != 0.0) {
            return Err(StartError::NotViscous(StartField::ThetaDot0));
        }
    }
    match body {
        Body::Disk(_) => {
            let sphere_fields = [
                (r.q0.is_some(), StartField::Q0),
                (r.contact.is_some(), StartField::Contact),
                (r.omega0.is_some(), StartField::Omega0),
                (r.spin.is_some(), StartField::Spin),
            ];
            if let Some(&(_, f)) = sphere_fields.iter().find(|(given, _)| *given) {
                return Err(StartError::NotDisk(f));
            }
            let theta_dot0 = r.theta_dot0.unwrap_or(0.0);
            let mut theta0 = r.theta0.unwrap_or(0.0);
            finite(StartField::Theta0, &[theta0])?;
            finite(StartField::ThetaDot0, &[theta_dot0])?;
            let mut reduced_theta0 = None;
            if theta0.abs() > MAX_PLAIN_ANGLE {
                let reduced = theta0.rem_euclid(std::f64::consts::TAU);
                reduced_theta0 = Some((theta0, reduced));
                theta0 = reduced;
            }
            Ok(CheckedStart {
                initial: InitialState::Disk { theta0, theta_dot0 },
                reduced_theta0,
            })
        }
        Body::Sphere(s) => {
            if r.theta0.is_some() {
                return Err(StartError::NotSphere(StartField::Theta0));
            }
            if r.theta_dot0.is_some() {
                return Err(StartError::NotSphere(StartField::ThetaDot0));
            }
            if r.q0.is_some() && r.contact.is_some() {
                return Err(StartError::Both);
            }
            let spin = r.spin.unwrap_or(0.0);
            finite(StartField::Spin, &[spin])?;
            let q0 = match (r.q0, r.contact) {
                (Some(v), _) => {
                    // Given is given, 0 included: `--spin 0 --q0 …` names two orientations.
                    if r.spin.is_some() {
                        return Err(StartError::SpinWithQ0);
                    }
                    finite(StartField::Q0, &v)?;
                    let q = DQuat::from_xyzw(v[1], v[2], v[3], v[0]);
                    let scale = v.iter().fold(0.0f64, |m, c| m.max(c.abs()));
                    if scale == 0.0 {
                        return Err(StartError::ZeroQuaternion(v));
                    }
                    // Normalised once, where the run starts (`Start`), as for every caller.
                    // Only the direction matters: where |q| over- or underflows (components
                    // of 1e154, or 1e-160) it is scaled by its largest component first; other
                    // quaternions are kept as given, so their numbers stay bit for bit.
                    let length = q.length();
                    if length.is_finite() && length > 1e-150 {
                        q
                    } else {
                        q / scale
                    }
                }
                (None, Some(c)) => {
                    finite(StartField::Contact, &c)?;
                    orientation_touching(s, direction(c[0], c[1]), spin)
                }
                (None, None) => orientation_touching(s, DVec3::NEG_Z, spin),
            };
            let omega0 = match r.omega0 {
                Some(w) => {
                    finite(StartField::Omega0, &w)?;
                    DVec3::from_array(w)
                }
                None => DVec3::ZERO,
            };
            Ok(CheckedStart {
                initial: InitialState::Sphere { q0, omega0 },
                reduced_theta0: None,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bodies() -> (Body, Body) {
        (
            Body::paper_disk(84, 0.12, 5).unwrap(),
            Body::paper_sphere(219, 0.25, 5).unwrap(),
        )
    }

    #[test]
    fn every_field_that_does_not_apply_is_refused() {
        let (disk, sphere) = bodies();
        let r = StartRequest::default;
        let cases = [
            (
                &sphere,
                0.0,
                StartRequest {
                    omega0: Some([0.0, 1.0, 0.0]),
                    ..r()
                },
                StartError::NotViscous(StartField::Omega0),
            ),
            (
                &disk,
                0.0,
                StartRequest {
                    theta_dot0: Some(0.2),
                    ..r()
                },
                StartError::NotViscous(StartField::ThetaDot0),
            ),
            (
                &disk,
                1.0,
                StartRequest {
                    q0: Some([1.0, 0.0, 0.0, 0.0]),
                    ..r()
                },
                StartError::NotDisk(StartField::Q0),
            ),
            (
                &disk,
                1.0,
                StartRequest {
                    contact: Some([1.0, 2.0]),
                    ..r()
                },
                StartError::NotDisk(StartField::Contact),
            ),
            (
                &disk,
                1.0,
                StartRequest {
                    omega0: Some([0.0; 3]),
                    ..r()
                },
                StartError::NotDisk(StartField::Omega0),
            ),
            (
                &disk,
                1.0,
                StartRequest {
                    spin: Some(0.3),
                    ..r()
                },
                StartError::NotDisk(StartField::Spin),
            ),
            (
                &sphere,
                1.0,
                StartRequest {
                    theta0: Some(1.0),
                    ..r()
                },
                StartError::NotSphere(StartField::Theta0),
            ),
            (
                &sphere,
                1.0,
                StartRequest {
                    theta_dot0: Some(0.0),
                    ..r()
                },
                StartError::NotSphere(StartField::ThetaDot0),
            ),
            (
                &sphere,
                0.0,
                StartRequest {
                    q0: Some([1.0, 0.0, 0.0, 0.0]),
                    contact: Some([1.0, 2.0]),
                    ..r()
                },
                StartError::Both,
            ),
            (
                &sphere,
                0.0,
                StartRequest {
                    q0: Some([1.0, 0.0, 0.0, 0.0]),
                    spin: Some(0.5),
                    ..r()
                },
                StartError::SpinWithQ0,
            ),
            (
                &sphere,
                0.0,
                StartRequest {
                    q0: Some([0.0; 4]),
                    ..r()
                },
                StartError::ZeroQuaternion([0.0; 4]),
            ),
            (
                &sphere,
                0.0,
                StartRequest {
                    spin: Some(f64::INFINITY),
                    ..r()
                },
                StartError::NotFinite {
                    field: StartField::Spin,
                    value: f64::INFINITY,
                },
            ),
            (
                &sphere,
                1.0,
                StartRequest {
                    omega0: Some([0.0, f64::INFINITY, 0.0]),
                    ..r()
                },
                StartError::NotFinite {
                    field: StartField::Omega0,
                    value: f64::INFINITY,
                },
            ),
        ];
        for (body, mass, request, want) in cases {
            assert_eq!(
                check_start(body, mass, &request),
                Err(want.clone()),
                "{request:?}"
            );
        }
        // NaN compares unequal: matched by kind.
        let nan = StartRequest {
            contact: Some([f64::NAN, 0.0]),
            ..r()
        };
        assert!(matches!(
            check_start(&sphere, 0.0, &nan),
            Err(StartError::NotFinite {
                field: StartField::Contact,
                ..
            })
        ));
    }

    #[test]
    fn a_given_spin_is_given_even_when_zero_and_huge_angles_are_accepted() {
        let (disk, sphere) = bodies();
        // Issue 37: a spin of 0 was taken as "not given", so `--spin 0 --q0 …` passed. Given
        // is given: with q0 it names a second orientation, and a disk has no spin.
        let q = StartRequest {
            q0: Some([2.0, 0.0, 0.0, 0.0]),
            spin: Some(0.0),
            ..Default::default()
        };
        assert_eq!(check_start(&sphere, 1.0, &q), Err(StartError::SpinWithQ0));
        let spun_disk = StartRequest {
            spin: Some(0.0),
            ..Default::default()
        };
        assert_eq!(
            check_start(&disk, 0.0, &spun_disk),
            Err(StartError::NotDisk(StartField::Spin))
        );
        // Without the spin, q0 is left as given: `Start` normalises it, for every caller.
        let s = check_start(
            &sphere,
            1.0,
            &StartRequest {
                q0: Some([2.0, 0.0, 0.0, 0.0]),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(
            s.initial,
            InitialState::Sphere {
                q0: DQuat::from_xyzw(0.0, 0.0, 0.0, 2.0),
                omega0: DVec3::ZERO
            }
        );
        let huge = StartRequest {
            theta0: Some(1e17),
            ..Default::default()
        };
        let h = check_start(&disk, 1.0, &huge).unwrap();
        let (given, reduced) = h.reduced_theta0.unwrap();
        assert_eq!(given, 1e17);
        assert!((0.0..std::f64::consts::TAU).contains(&reduced));
        assert_eq!(
            h.initial,
            InitialState::Disk {
                theta0: reduced,
                theta_dot0: 0.0
            }
        );
    }

    #[test]
    fn messages_use_the_front_ends_names() {
        let cli = Spelling {
            field: |f| match f {
                StartField::Q0 => "--q0",
                StartField::Spin => "--spin",
                StartField::ThetaDot0 => "--thetadot0",
                _ => "--theta0",
            },
            mass: "--mass",
            viscous: "--mass 0",
            body: "disk.json",
        };
        assert_eq!(
            StartError::NotDisk(StartField::Spin).explain(&cli),
            "disk.json is a 2D disk: give --theta0 (and --thetadot0), not --spin"
        );
        assert!(
            StartError::ZeroQuaternion([0.0; 4])
                .explain(&cli)
                .starts_with("--q0 0,0,0,0 has zero length")
        );
        assert!(
            StartError::SpinWithQ0
                .explain(&cli)
                .contains("--q0 is already the whole orientation")
        );
    }
}
