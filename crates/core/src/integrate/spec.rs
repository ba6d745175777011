//! The integrator as a person names it, read and written in one place: a kind (`dop853`,
//! `rk4`, `cf4`) with its settings given beside it (the command line's `--integrator` with
//! `--rtol`/`--dt`, a scene's `method` with `rtol`/`dt`, Python's `integrator=`), or one spec
//! string (`fast`, `balanced`, `precise`, `dop853:RTOL`, `rk4:DT`, `cf4:DT`: a sweep spec's
//! `integrators`). Every surface parses with these, so the names and messages are the same
//! everywhere.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::{Method, Preset};

/// An integrator's kind, without its settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", try_from = "String")]
pub enum MethodKind {
    /// Adaptive 8th-order Dormand–Prince with dense output (rtol, atol).
    Dop853,
    /// Classical fixed-step RK4 (dt).
    Rk4,
    /// Fixed-step Lie-group RK4: keeps |q| = 1 exactly (dt).
    Cf4,
}

/// The kinds and what each takes, for messages.
pub const KINDS_HELP: &str =
    "dop853 (adaptive, rtol), rk4 or cf4 (fixed step dt; cf4 keeps |q| = 1 exactly)";

/// The spec strings, for messages.
pub const SPECS_HELP: &str = "fast, balanced, precise, dop853:RTOL, rk4:DT or cf4:DT";

impl MethodKind {
    /// All kinds.
    pub const ALL: [MethodKind; 3] = [MethodKind::Dop853, MethodKind::Rk4, MethodKind::Cf4];

    /// The name as written.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::MethodKind;
    /// assert_eq!(MethodKind::Cf4.name(), "cf4");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            MethodKind::Dop853 => "dop853",
            MethodKind::Rk4 => "rk4",
            MethodKind::Cf4 => "cf4",
        }
    }

    /// This kind with its settings (`rtol` and `atol`, default `rtol`, for DOP853; `dt` for the
    /// fixed steps), checked ([`Method::validate`]).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::{Method, MethodKind};
    /// assert_eq!(MethodKind::Rk4.with(1e-8, None, 0.01)?, Method::Rk4 { dt: 0.01 });
    /// assert!(MethodKind::Cf4.with(1e-8, None, -1.0).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn with(
        self,
        rtol: f64,
        atol: Option<f64>,
        dt: f64,
    ) -> Result<Method, super::IntegrateError> {
        let m = match self {
            MethodKind::Dop853 => Method::Dop853 {
                rtol,
                atol: atol.unwrap_or(rtol),
            },
            MethodKind::Rk4 => Method::Rk4 { dt },
            MethodKind::Cf4 => Method::Cf4 { dt },
        };
        m.validate()?;
        Ok(m)
    }
}

impl fmt::Display for MethodKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why an integrator name or spec was refused: the text, and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct MethodParseError(String);

impl FromStr for MethodKind {
    type Err = MethodParseError;

    /// # Example
    /// ```
    /// use rollphase_core::integrate::MethodKind;
    /// assert_eq!("rk4".parse::<MethodKind>()?, MethodKind::Rk4);
    /// assert!("euler".parse::<MethodKind>().unwrap_err().to_string().contains("dop853"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        MethodKind::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| {
                MethodParseError(format!("{s:?} is not an integrator: one of {KINDS_HELP}"))
            })
    }
}

/// A scene's `method = "…"` is read by [`MethodKind::from_str`], with its message.
impl TryFrom<String> for MethodKind {
    type Error = MethodParseError;

    fn try_from(s: String) -> Result<Self, Self::Error> {
        s.parse()
    }
}

impl FromStr for Method {
    type Err = MethodParseError;

    /// A spec string: a preset's name, or a kind with its setting after a colon (DOP853's rtol,
    /// then optionally `:ATOL`; the fixed steps' dt), checked.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::Method;
    /// assert_eq!("balanced".parse::<Method>()?, Method::dop853(1e-8));
    /// assert_eq!("cf4:0.02".parse::<Method>()?, Method::Cf4 { dt: 0.02 });
    /// assert!("rk4:-1".parse::<Method>().is_err());
    /// // spec() writes it back.
    /// assert_eq!(Method::dop853(1e-9).spec().parse::<Method>()?, Method::dop853(1e-9));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if let Some(p) = Preset::ALL.into_iter().find(|p| p.name() == s) {
            return Ok(p.method());
        }
        let Some((kind, values)) = s.split_once(':') else {
            return Err(MethodParseError(format!(
                "{s:?} is not an integrator: one of {SPECS_HELP}"
            )));
        };
        let kind: MethodKind = kind.parse()?;
        let number = |v: &str| {
            v.trim().parse::<f64>().map_err(|_| {
                MethodParseError(format!("{v:?} in {s:?} is not a number ({SPECS_HELP})"))
            })
        };
        let (first, atol) = match (kind, values.split_once(':')) {
            (MethodKind::Dop853, Some((rtol, atol))) => (number(rtol)?, Some(number(atol)?)),
            (_, Some(_)) => {
                return Err(MethodParseError(format!(
                    "{s:?}: {kind} takes one number, its step dt"
                )));
            }
            (_, None) => (number(values)?, None),
        };
        kind.with(first, atol, first)
            .map_err(|e| MethodParseError(format!("{s:?}: {e}")))
    }
}

impl Method {
    /// The spec string [`Method::from_str`] reads back (`dop853:1e-8`, `dop853:1e-8:1e-10`,
    /// `rk4:0.01`); `Display` gives the readable name ("DOP853 rtol 1e-8").
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::Method;
    /// assert_eq!(Method::Rk4 { dt: 0.01 }.spec(), "rk4:0.01");
    /// ```
    pub fn spec(&self) -> String {
        match *self {
            Method::Dop853 { rtol, atol } if atol == rtol => format!("dop853:{rtol:e}"),
            Method::Dop853 { rtol, atol } => format!("dop853:{rtol:e}:{atol:e}"),
            Method::Rk4 { dt } => format!("rk4:{dt}"),
            Method::Cf4 { dt } => format!("cf4:{dt}"),
        }
    }

    /// The kind, without the settings.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::integrate::{Method, MethodKind};
    /// assert_eq!(Method::dop853(1e-8).kind(), MethodKind::Dop853);
    /// ```
    pub fn kind(&self) -> MethodKind {
        match self {
            Method::Dop853 { .. } => MethodKind::Dop853,
            Method::Rk4 { .. } => MethodKind::Rk4,
            Method::Cf4 { .. } => MethodKind::Cf4,
        }
    }
}
