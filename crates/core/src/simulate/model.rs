//! The body paired with its start ([`Start`]), and the running model ([`ModelState`]): one of the
//! registered models with its body and its integrated state, made from the registration
//! (`dynamics::models::with_registered_models`). A disk always carries an angle and a
//! sphere an orientation, so the code that steps them ([`super::run`] and the app's
//! `sim::Simulation`) matches one enum, with no impossible combinations to fall back from.

use glam::{DQuat, DVec3};

use super::{InitialState, RunError};
use crate::dynamics::{ModelKind, ModelVisitor, ModelVisitorMut, Pose, Ramp, RollingModel};
use crate::geometry::{Body, Disk, Sphere};

/// A body with the start of its run. Built (and checked) once from a body and an
/// [`InitialState`], where the two dimensions can still disagree.
#[derive(Debug, Clone)]
pub enum Start {
    /// A cylinder: contact angle θ₀ and its rate θ̇₀ (the rate is ignored by the viscous model).
    Disk {
        /// The cross-section.
        disk: Disk,
        /// θ₀.
        theta0: f64,
        /// θ̇₀.
        theta_dot0: f64,
    },
    /// A sphere: orientation q₀ (unit) and lab angular velocity ω₀ (ignored by the viscous
    /// model).
    Sphere {
        /// The body.
        sphere: Sphere,
        /// q₀, normalised.
        q0: DQuat,
        /// ω₀.
        omega0: DVec3,
    },
}

impl Start {
    /// Pairs `body` with `initial`: the dimensions must agree and the numbers be finite (a
    /// quaternion also non-zero; it is normalised here).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, Start};
    /// let disk = Body::paper_disk(84, 0.12, 5)?;
    /// assert!(Start::new(&disk, InitialState::Disk { theta0: 0.0, theta_dot0: 0.0 }).is_ok());
    /// // A 3D start on a 2D body, or a NaN, is refused.
    /// assert!(Start::new(&disk, InitialState::at_rest(&Body::random_sphere(1, 0.1, 3)?)).is_err());
    /// assert!(Start::new(&disk, InitialState::Disk { theta0: f64::NAN, theta_dot0: 0.0 }).is_err());
    /// # Ok::<(), rollphase_core::geometry::ShapeError>(())
    /// ```
    pub fn new(body: &Body, initial: InitialState) -> Result<Self, RunError> {
        match (body, initial) {
            (Body::Disk(d), InitialState::Disk { theta0, theta_dot0 }) => {
                for (name, v) in [("theta0", theta0), ("theta_dot0", theta_dot0)] {
                    if !v.is_finite() {
                        return Err(RunError::Mismatch(format!(
                            "{name} = {v} is not a finite number"
                        )));
                    }
                }
                Ok(Start::Disk {
                    disk: d.clone(),
                    theta0,
                    theta_dot0,
                })
            }
            (Body::Sphere(s), InitialState::Sphere { q0, omega0 }) => {
                if !(q0.is_finite() && q0.length() > 1e-12 && omega0.is_finite()) {
                    return Err(RunError::Mismatch(format!(
                        "initial orientation {q0:?} / ω {omega0:?} must be finite with |q| > 0"
                    )));
                }
                Ok(Start::Sphere {
                    sphere: s.clone(),
                    q0: q0.normalize(),
                    omega0,
                })
            }
            (Body::Disk(_), _) => Err(RunError::InitialStateDoesNotFit {
                body: "a 2D disk",
                wanted: "an angle θ0 (and θ̇0)",
                given: "a 3D orientation",
            }),
            (Body::Sphere(_), _) => Err(RunError::InitialStateDoesNotFit {
                body: "a 3D sphere",
                wanted: "an orientation q0 (and ω0)",
                given: "a 2D angle",
            }),
        }
    }
}

impl Start {
    /// The body's dimension: 2 for a cylinder, 3 for a sphere.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, Start};
    /// let disk = Body::paper_disk(84, 0.12, 5)?;
    /// assert_eq!(Start::new(&disk, InitialState::at_rest(&disk))?.dimension(), 2);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn dimension(&self) -> u32 {
        match self {
            Start::Disk { .. } => 2,
            Start::Sphere { .. } => 3,
        }
    }

    /// The body.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, Start};
    /// let disk = Body::paper_disk(84, 0.12, 5)?;
    /// assert_eq!(Start::new(&disk, InitialState::at_rest(&disk))?.body().dimension(), 2);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn body(&self) -> Body {
        match self {
            Start::Disk { disk, .. } => Body::Disk(disk.clone()),
            Start::Sphere { sphere, .. } => Body::Sphere(sphere.clone()),
        }
    }

    /// Where it starts, at the origin of the ramp: what every model of its dimension begins
    /// from.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::Pose;
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, Start};
    /// let disk = Body::paper_disk(84, 0.12, 5)?;
    /// let start = Start::new(&disk, InitialState::Disk { theta0: 0.5, theta_dot0: 2.0 })?;
    /// assert_eq!(start.pose(), Pose::Disk { theta: 0.5, theta_dot: 2.0, x_c: 0.0 });
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn pose(&self) -> Pose {
        match *self {
            Start::Disk {
                theta0, theta_dot0, ..
            } => Pose::Disk {
                theta: theta0,
                theta_dot: theta_dot0,
                x_c: 0.0,
            },
            Start::Sphere { q0, omega0, .. } => Pose::Sphere {
                q: q0,
                omega: omega0,
                position: [0.0, 0.0],
            },
        }
    }
}

/// [`ModelState`] and the matches over it, from the registration
/// (`dynamics::models::with_registered_models`): one variant per model, holding its body and
/// its state.
macro_rules! define_model_states {
    ($($kind:ident {
        model: $model:ty,
        state_len: $n:literal,
        body: $body:ident,
        $($entry:ident: $value:literal,)*
    },)*) => {
        /// One of the registered models with its body and integrated state: the state vector
        /// is the one the model's [`crate::integrate::OdeSystem`] integrates (its layout is the
        /// registry's `state`).
        #[derive(Debug, Clone)]
        pub enum ModelState {
            $(
                #[doc = concat!("The ", stringify!($kind), " model.")]
                $kind {
                    /// The body.
                    body: $body,
                    /// The state.
                    y: [f64; $n],
                },
            )*
        }

        impl ModelState {
            /// `kind`'s state for `body` at `pose`; `None` when they do not fit it.
            fn of_kind(kind: ModelKind, body: &Body, pose: &Pose) -> Option<Self> {
                match kind {
                    $(
                        ModelKind::$kind => {
                            let Body::$body(body) = body else {
                                return None;
                            };
                            Some(ModelState::$kind {
                                body: body.clone(),
                                y: <$model as RollingModel<$n>>::state_at(pose)?,
                            })
                        }
                    )*
                }
            }

            fn dispatch<V: ModelVisitor>(&self, ramp: &Ramp, visitor: V) -> V::Output {
                match self {
                    $(ModelState::$kind { body, y } => visitor.visit(&<$model>::new(body, ramp), y),)*
                }
            }

            fn dispatch_mut<V: ModelVisitorMut>(&mut self, ramp: &Ramp, visitor: V) -> V::Output {
                match self {
                    $(ModelState::$kind { body, y } => visitor.visit(&<$model>::new(body, ramp), y),)*
                }
            }

            fn kind_of(&self) -> ModelKind {
                match self {
                    $(ModelState::$kind { .. } => ModelKind::$kind,)*
                }
            }

            fn pose_of(&self) -> Pose {
                match self {
                    $(ModelState::$kind { y, .. } => <$model as RollingModel<$n>>::pose(y),)*
                }
            }

            fn vector_of(&self) -> &[f64] {
                match self {
                    $(ModelState::$kind { y, .. } => y,)*
                }
            }

            /// Sets the state to `v` (of the state's length, finite), checked by the model.
            fn set_vector(&mut self, v: &[f64]) -> Result<(), String> {
                match self {
                    $(
                        ModelState::$kind { y, .. } => {
                            let v: [f64; $n] = v.try_into().map_err(|_| {
                                format!("{} numbers, not {}", $n, v.len())
                            })?;
                            *y = <$model as RollingModel<$n>>::checked_state(v)?;
                        }
                    )*
                }
                Ok(())
            }

            fn body_of(&self) -> Body {
                match self {
                    $(ModelState::$kind { body, .. } => Body::$body(body.clone()),)*
                }
            }
        }
    };
}
crate::dynamics::models::with_registered_models!(define_model_states);

impl ModelState {
    /// The model `start` runs on `ramp` (viscous when m/m0 = 0), at its initial state.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelKind, Ramp};
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, ModelState, Start};
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let start = Start::new(&body, InitialState::at_rest(&body))?;
    /// let state = ModelState::new(&start, &Ramp::new(0.15, 6.0)?);
    /// assert_eq!(state.kind(), ModelKind::SphereInertial);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn new(start: &Start, ramp: &Ramp) -> Self {
        let kind = ModelKind::for_dimension(start.dimension(), ramp);
        Self::of_kind(kind, &start.body(), &start.pose())
            .expect("the model chosen for a start's dimension rolls its body")
    }

    /// The one place that reaches the run's model: runs `visitor` with this state's model on
    /// `ramp` and its state. Everything that steps or observes a run (`run`, the app's
    /// simulation) goes through here, and asks the model
    /// ([`crate::dynamics::RollingModel`]) for the rest.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelVisitor, Ramp, RollingModel};
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, ModelState, Start};
    /// // A visitor reads what any registered model offers, here its CSV columns.
    /// struct Columns;
    /// impl ModelVisitor for Columns {
    ///     type Output = &'static str;
    ///     fn visit<const N: usize, M: RollingModel<N>>(self, _model: &M, _y: &[f64; N]) -> &'static str {
    ///         M::COLUMNS
    ///     }
    /// }
    /// let disk = Body::paper_disk(84, 0.12, 5)?;
    /// let ramp = Ramp::new(0.1, 0.0)?;
    /// let state = ModelState::new(&Start::new(&disk, InitialState::at_rest(&disk))?, &ramp);
    /// assert_eq!(state.visit(&ramp, Columns), "t,theta,theta_dot,psi,x,y");
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn visit<V: ModelVisitor>(&self, ramp: &Ramp, visitor: V) -> V::Output {
        self.dispatch(ramp, visitor)
    }

    /// [`Self::visit`] that may change the state (stepping it).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelVisitorMut, Ramp, RollingModel};
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, ModelState, Start};
    /// // A visitor that moves the body's first state component (θ for a disk) and says where
    /// // it is now.
    /// struct Nudge;
    /// impl ModelVisitorMut for Nudge {
    ///     type Output = f64;
    ///     fn visit<const N: usize, M: RollingModel<N>>(self, _model: &M, y: &mut [f64; N]) -> f64 {
    ///         y[0] += 0.5;
    ///         y[0]
    ///     }
    /// }
    /// let disk = Body::paper_disk(84, 0.12, 5)?;
    /// let ramp = Ramp::new(0.1, 0.0)?;
    /// let start = Start::new(&disk, InitialState::Disk { theta0: 1.0, theta_dot0: 0.0 })?;
    /// let mut state = ModelState::new(&start, &ramp);
    /// assert_eq!(state.visit_mut(&ramp, Nudge), 1.5);
    /// assert_eq!(state.visit_mut(&ramp, Nudge), 2.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn visit_mut<V: ModelVisitorMut>(&mut self, ramp: &Ramp, visitor: V) -> V::Output {
        self.dispatch_mut(ramp, visitor)
    }

    /// Which registered model this is.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelKind, Ramp};
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, ModelState, Start};
    /// let disk = Body::paper_disk(84, 0.12, 5)?;
    /// let start = Start::new(&disk, InitialState::at_rest(&disk))?;
    /// assert_eq!(ModelState::new(&start, &Ramp::new(0.1, 0.0)?).kind(), ModelKind::DiskViscous);
    /// assert_eq!(ModelState::new(&start, &Ramp::new(0.1, 2.0)?).kind(), ModelKind::DiskInertial);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn kind(&self) -> ModelKind {
        self.kind_of()
    }

    /// The same body in the same pose under `ramp`: between inertial settings the angular
    /// velocity is kept; inertial → viscous drops it; viscous → inertial starts from rest.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::{ModelKind, Ramp};
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, ModelState, Start};
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let start = Start::new(&body, InitialState::at_rest(&body))?;
    /// let viscous = ModelState::new(&start, &Ramp::new(0.15, 0.0)?);
    /// // Turning on inertia mid-lesson: the same pose, now with m/m0 = 6, from rest.
    /// let heavy = viscous.for_ramp(&Ramp::new(0.15, 6.0)?);
    /// assert_eq!(heavy.kind(), ModelKind::SphereInertial);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn for_ramp(self, ramp: &Ramp) -> Self {
        let kind = ModelKind::for_dimension(self.kind().entry().dimension, ramp);
        if kind == self.kind() {
            return self;
        }
        Self::of_kind(kind, &self.body(), &self.pose_of())
            .expect("a model of the same dimension rolls the same body")
    }

    /// The integrated state vector (what [`Self::kind`]'s model integrates: the layouts above).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::Ramp;
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, ModelState, Start};
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let state = ModelState::new(&Start::new(&body, InitialState::at_rest(&body))?, &Ramp::new(0.15, 6.0)?);
    /// assert_eq!(state.vector().len(), 10); // q, ω, x, y, W
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn vector(&self) -> &[f64] {
        self.vector_of()
    }

    /// The same model at the state vector `v` (a saved state resumed): refused, with the reason,
    /// when `v` has another length than this model's state or a value that is not finite, or
    /// (3D) when its quaternion is not of unit length to 1e-6 (it is renormalised within that).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::Ramp;
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, ModelState, Start};
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let state = ModelState::new(&Start::new(&body, InitialState::at_rest(&body))?, &Ramp::new(0.15, 0.0)?);
    /// let moved = state.clone().with_vector(&[0.0, 1.0, 0.0, 0.0, 3.5, -0.2])?;
    /// assert_eq!(moved.vector()[4], 3.5);
    /// assert!(state.with_vector(&[1.0, 0.0]).is_err()); // a cylinder's length
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with_vector(mut self, v: &[f64]) -> Result<Self, String> {
        let len = self.vector().len();
        if v.len() != len {
            return Err(format!(
                "the {} model's state has {len} numbers, not {}",
                self.kind(),
                v.len()
            ));
        }
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(format!("state number {i} is {}, not a finite number", v[i]));
        }
        self.set_vector(v)?;
        Ok(self)
    }

    /// The body, as a [`Body`].
    ///
    /// # Example
    /// ```
    /// use rollphase_core::dynamics::Ramp;
    /// use rollphase_core::geometry::Body;
    /// use rollphase_core::simulate::{InitialState, ModelState, Start};
    /// let body = Body::paper_sphere(219, 0.25, 5)?;
    /// let state = ModelState::new(&Start::new(&body, InitialState::at_rest(&body))?, &Ramp::new(0.15, 0.0)?);
    /// assert_eq!(state.body().alpha_star(), body.alpha_star());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn body(&self) -> Body {
        self.body_of()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_start_of_the_other_dimension_is_refused_and_the_model_follows_the_mass() {
        let disk = Body::Disk(Disk::perfect());
        let sphere_start = InitialState::Sphere {
            q0: DQuat::IDENTITY,
            omega0: DVec3::ZERO,
        };
        assert!(matches!(
            Start::new(&disk, sphere_start),
            Err(RunError::InitialStateDoesNotFit { .. })
        ));
        let start = Start::new(
            &disk,
            InitialState::Disk {
                theta0: 0.5,
                theta_dot0: 2.0,
            },
        )
        .unwrap();
        let viscous = Ramp::new(0.3, 0.0).unwrap();
        let inertial = Ramp::new(0.3, 2.0).unwrap();
        let m = ModelState::new(&start, &inertial);
        assert_eq!(m.kind(), ModelKind::DiskInertial);
        assert!(matches!(m, ModelState::DiskInertial { y, .. } if y == [0.5, 2.0, 0.0, 0.0]));
        // Inertial → viscous keeps θ and x_c, drops θ̇ and W; and back starts from rest.
        let v = ModelState::new(&start, &inertial).for_ramp(&viscous);
        assert!(matches!(v, ModelState::DiskViscous { y, .. } if y == [0.5, 0.0]));
        let back = v.for_ramp(&inertial);
        assert!(matches!(back, ModelState::DiskInertial { y, .. } if y == [0.5, 0.0, 0.0, 0.0]));
        assert_eq!(
            ModelState::new(&start, &viscous).kind(),
            ModelKind::DiskViscous
        );
    }

    /// Every registered model is made from its one entry: a start of its dimension runs it at
    /// the mass that asks for it, with the state its entry describes, and a change of mass
    /// carries the pose to the other model of its dimension and back.
    #[test]
    fn every_registered_model_runs_from_its_entry_and_hands_its_pose_on() {
        use crate::dynamics::models::REGISTERED;
        for entry in REGISTERED {
            let (body, initial) = if entry.dimension == 2 {
                let initial = InitialState::Disk {
                    theta0: 0.7,
                    theta_dot0: 0.3,
                };
                (Body::paper_disk(84, 0.12, 5).unwrap(), initial)
            } else {
                let initial = InitialState::Sphere {
                    q0: DQuat::from_rotation_x(0.4),
                    omega0: DVec3::new(0.1, 0.0, 0.2),
                };
                (Body::paper_sphere(219, 0.25, 5).unwrap(), initial)
            };
            let ramp = Ramp::new(0.2, if entry.inertial { 3.0 } else { 0.0 }).unwrap();
            let other = Ramp::new(0.2, if entry.inertial { 0.0 } else { 3.0 }).unwrap();
            let start = Start::new(&body, initial).unwrap();
            let state = ModelState::new(&start, &ramp);
            assert_eq!(state.kind(), entry.kind);
            assert_eq!(
                state.vector().len(),
                entry.state.split(", ").count(),
                "{}",
                entry.name
            );
            assert_eq!(state.body().dimension(), entry.dimension);
            let (kind, _, _, finite) = state.visit(&ramp, Describe);
            assert!(kind == entry.kind && finite, "{}", entry.name);
            // The pose survives a change of model and back; the rate only if it had one.
            let there = state.clone().for_ramp(&other);
            assert_ne!(there.kind(), entry.kind);
            let back = there.for_ramp(&ramp);
            assert_eq!(back.pose_of(), {
                let mut p = state.pose_of();
                if entry.inertial {
                    match &mut p {
                        Pose::Disk { theta_dot, .. } => *theta_dot = 0.0,
                        Pose::Sphere { omega, .. } => *omega = DVec3::ZERO,
                    }
                }
                p
            });
            // A resumed vector of its own length is taken; another length refused.
            assert!(state.clone().with_vector(state.vector()).is_ok());
            assert!(state.with_vector(&[0.0; 3]).is_err());
        }
    }

    /// What `visit` hands over: the model's name, its columns and one sample row.
    struct Describe;

    impl ModelVisitor for Describe {
        type Output = (ModelKind, &'static str, usize, bool);
        fn visit<const N: usize, M: crate::dynamics::RollingModel<N>>(
            self,
            model: &M,
            y: &[f64; N],
        ) -> Self::Output {
            let mut row = Vec::new();
            model.row(0.0, y, &mut row);
            let o = model.observation(y);
            (
                M::KIND,
                M::COLUMNS,
                row.len(),
                model.section(y).is_finite() && o.centre.is_finite(),
            )
        }
    }

    #[test]
    fn visit_hands_each_state_its_own_model_with_matching_columns() {
        let disk = Body::Disk(Disk::perfect());
        let sphere = Body::Sphere(Sphere::perfect());
        let starts = [
            Start::new(
                &disk,
                InitialState::Disk {
                    theta0: 0.5,
                    theta_dot0: 0.0,
                },
            )
            .unwrap(),
            Start::new(
                &sphere,
                InitialState::Sphere {
                    q0: DQuat::IDENTITY,
                    omega0: DVec3::ZERO,
                },
            )
            .unwrap(),
        ];
        let mut seen = Vec::new();
        for start in &starts {
            for mass in [0.0, 2.0] {
                let ramp = Ramp::new(0.3, mass).unwrap();
                let state = ModelState::new(start, &ramp);
                let (kind, columns, width, finite) = state.visit(&ramp, Describe);
                assert_eq!(kind, state.kind());
                assert_eq!(columns.split(',').count(), width, "{kind}");
                let header = if matches!(start, Start::Disk { .. }) {
                    super::super::DISK_HEADER
                } else {
                    super::super::SPHERE_HEADER
                };
                assert_eq!(columns, header);
                assert!(finite);
                seen.push(kind);
            }
        }
        let registered: Vec<ModelKind> = crate::dynamics::models::REGISTERED
            .iter()
            .map(|m| m.kind)
            .collect();
        assert_eq!(seen, registered);
    }
}
