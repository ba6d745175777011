//! `rollphase simulate`: one run written as CSV, with an optional JSON health summary.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, anyhow};
use clap::{Args, ValueEnum};

use crate::dynamics::Ramp;
use crate::geometry::Body;
use crate::integrate::{Method, MethodKind, MethodParseError};
use crate::output::{self, Inputs};
use crate::simulate::start::{Spelling, StartField, StartRequest, check_start};
use crate::simulate::{
    ContactLimits, DISK_HEADER, FORCE_HEADER, InitialState, OnViolation, RunError, RunSpec,
    SPHERE_HEADER, SummaryReport,
};

/// Simulate one run and write the trajectory as CSV.
///
/// The model follows from the body and --mass: a disk file gives the 2D model, a sphere file the
/// 3D model; m/m0 = 0 is viscous, m/m0 > 0 inertial.
///
/// CSV columns, 2D: t,theta,theta_dot,psi,x,y (θ contact angle in the body, ψ body rotation,
/// (x, y) centre of mass: x downhill along the ramp, y height above it).
/// 3D: t,qw,qx,qy,qz,ux,uy,uz,wx,wy,wz,x,y,z (q body-to-lab unit quaternion, Hamilton; u the
/// contact point as a body-frame unit vector; w the lab angular velocity; x, y, z the centre of
/// mass: x downhill, z above the ramp).
///
/// 3D start: --q0 w,x,y,z, or --contact θ,φ (the body point at polar angle θ, azimuth φ put on the
/// ramp by the shortest rotation) then --spin s (a turn by s radians about the ramp's normal +z).
/// With neither, the body's south pole (θ = π, the point at body-frame −z) touches the ramp,
/// turned by --spin (default 0); released from rest (--omega0 0,0,0). --q0 is the whole
/// orientation, so --spin does not go with it. A flag of the other kind of body, or an initial
/// velocity (--omega0, --thetadot0) with --mass 0, is an error, never ignored.
///
/// Where the model holds: every model assumes the body stays on the ramp and rolls without
/// slipping. The run follows the exact contact force (f = m a − F, in units of the weight F:
/// the normal force N and the friction needed |f_t|/N), and the summary gives their extremes,
/// the first time N ≤ 0 (the body leaves the ramp) and, with --friction μ, the first time the
/// friction needed exceeds μ (it slips). --on-invalid says what happens then: `warn` (the
/// default) goes on and says so on standard error and in the summary; `stop` ends the run
/// there with an error naming the time and the force. --forces adds the force to the CSV
/// (normal_force, friction_x, friction_y, friction_needed; inf where N ≤ 0). The viscous
/// model (m/m0 = 0) presses with N = cos α and needs μ = tan α throughout.
///
/// Rows go to standard output unless -o FILE is given; a file is written whole or not at all.
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct SimulateArgs {
    /// Shape file (JSON).
    pub file: PathBuf,
    /// Ramp angle α in radians, 1e-9 ≤ α < π/2.
    #[arg(long, allow_negative_numbers = true)]
    pub alpha: f64,
    /// Mass ratio m/m0 ≥ 0 (0: viscous model).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub mass: f64,
    /// Rotational drag γ in units of γ0 (0 allowed for inertial runs: energy is then conserved).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub drag: f64,
    /// The drag law's parameters (one flag per registered law).
    #[command(flatten)]
    pub drag_law: super::drag_law::DragLawArgs,
    /// End time.
    #[arg(long)]
    pub t_end: f64,
    /// Output CSV file ("-" for standard output).
    #[arg(short, long, default_value = "-")]
    pub output: PathBuf,
    /// 3D: initial orientation quaternion w,x,y,z (normalised).
    #[arg(long, conflicts_with = "contact", allow_hyphen_values = true)]
    pub q0: Option<String>,
    /// 3D: initial contact point θ,φ in the body frame (polar, azimuth).
    #[arg(long, allow_hyphen_values = true)]
    pub contact: Option<String>,
    /// 3D: spin about the ramp normal after --contact, radians [default: 0].
    #[arg(long, allow_negative_numbers = true)]
    pub spin: Option<f64>,
    /// 3D inertial: initial lab angular velocity x,y,z.
    #[arg(long, allow_hyphen_values = true)]
    pub omega0: Option<String>,
    /// 2D: initial contact angle θ₀.
    #[arg(long, allow_negative_numbers = true)]
    pub theta0: Option<f64>,
    /// 2D inertial: initial θ̇₀.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub thetadot0: f64,
    /// Integrator: dop853 (adaptive 8th-order Dormand–Prince with dense output; --rtol,
    /// --atol), rk4 (classical fixed step; --dt) or cf4 (fixed-step Lie-group RK4, keeps
    /// |q| = 1 exactly; --dt).
    #[arg(long, default_value = "dop853", value_parser = parse_kind)]
    pub integrator: MethodKind,
    /// DOP853 relative tolerance.
    #[arg(long, default_value = "1e-10", allow_negative_numbers = true)]
    pub rtol: f64,
    /// DOP853 absolute tolerance [default: rtol].
    #[arg(long, allow_negative_numbers = true)]
    pub atol: Option<f64>,
    /// RK4/CF4 time step (at most t_end). The run checks it by step doubling and stops, naming a
    /// step that would pass, when one step's error estimate exceeds 1e-3.
    #[arg(long, default_value_t = 0.01)]
    pub dt: f64,
    /// Number of CSV rows, equally spaced from t = 0 to t-end (from the dense output).
    #[arg(long, default_value_t = 1001)]
    pub samples: usize,
    /// Step budget; the run stops with an error beyond it.
    #[arg(long, default_value_t = 100_000_000)]
    pub max_steps: u64,
    /// Write a JSON summary: rhs_evals, steps, max_quat_norm_error, max_contact_normal_error,
    /// energy_drift, wall_seconds, min_normal_force, max_normal_force, max_friction_needed,
    /// lift_off_t, slip_t, friction, and the run's fate in the words every command uses:
    /// "left_model" (with the first `violation`), "halted" (at rest from `t` on), or
    /// "undecided" (`why`: a fixed-time run does not look for a cycle; `period` and `predict`
    /// do).
    #[arg(long)]
    pub summary: Option<PathBuf>,
    /// Add the contact force's columns to the CSV: normal_force, friction_x, friction_y (units
    /// of the weight F; friction_x < 0 points uphill) and friction_needed (|f_t|/N).
    #[arg(long)]
    pub forces: bool,
    /// The surface's coefficient of static friction μ ≥ 0: the run reports the first time
    /// rolling needs more (it slips) [default: slip not checked].
    #[arg(long, allow_negative_numbers = true)]
    pub friction: Option<f64>,
    /// What a lift-off (N ≤ 0) or a slip (friction needed > --friction) does: `warn` goes on
    /// and says so; `stop` ends the run there with an error and writes no CSV.
    #[arg(long, value_enum, default_value_t = OnInvalid::Warn)]
    pub on_invalid: OnInvalid,
}

/// What a run does when the motion stops being rollable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OnInvalid {
    /// Go on; a warning on standard error and in the summary.
    Warn,
    /// Stop with an error naming the time and the force.
    Stop,
}

impl OnInvalid {
    /// The core's name for it.
    pub(super) fn policy(self) -> OnViolation {
        match self {
            OnInvalid::Warn => OnViolation::Warn,
            OnInvalid::Stop => OnViolation::Stop,
        }
    }
}

/// The command line's names of the start's fields, for the core's messages.
pub(super) fn flag(f: StartField) -> &'static str {
    match f {
        StartField::Q0 => "--q0",
        StartField::Contact => "--contact",
        StartField::Spin => "--spin",
        StartField::Omega0 => "--omega0",
        StartField::Theta0 => "--theta0",
        StartField::ThetaDot0 => "--thetadot0",
    }
}

/// The start from the flags, checked by the core ([`check_start`], as Python's `simulate`):
/// a flag that does not apply to this body or model is an error, never ignored.
fn initial_state(a: &SimulateArgs, body: &Body) -> Result<InitialState> {
    let list = |text: &Option<String>, n: usize, f: StartField, names: &str| {
        text.as_deref()
            .map(|t| super::parse_list(t, n, flag(f), names))
            .transpose()
    };
    let q0 = list(&a.q0, 4, StartField::Q0, "w,x,y,z")?;
    let contact = list(&a.contact, 2, StartField::Contact, "θ,φ")?;
    let omega0 = list(&a.omega0, 3, StartField::Omega0, "x,y,z")?;
    let request = StartRequest {
        q0: q0.map(|v| [v[0], v[1], v[2], v[3]]),
        contact: contact.map(|v| [v[0], v[1]]),
        spin: a.spin,
        omega0: omega0.map(|v| [v[0], v[1], v[2]]),
        theta0: a.theta0,
        // The flag defaults to 0, so only a non-zero value says it was given.
        theta_dot0: Some(a.thetadot0).filter(|v| *v != 0.0),
    };
    checked_start(body, &a.file, a.mass, &request)
}

/// [`check_start`] with the command line's flag names and its warning for a reduced θ0
/// (`simulate` and `period`).
pub(super) fn checked_start(
    body: &Body,
    file: &std::path::Path,
    mass: f64,
    request: &StartRequest,
) -> Result<InitialState> {
    let body_name = file.display().to_string();
    let spelling = Spelling {
        field: flag,
        mass: "--mass",
        viscous: "--mass 0",
        body: &body_name,
    };
    let start = check_start(body, mass, request).map_err(|e| anyhow!(e.explain(&spelling)))?;
    if let Some((given, reduced)) = start.reduced_theta0 {
        eprintln!(
            "warning: --theta0 {} reduced modulo 2π to {reduced} (beyond ±1e6 rad an angle has \
             too few digits left to advance)",
            super::short(given)
        );
    }
    Ok(start.initial)
}

/// Runs `simulate`.
pub fn run(a: SimulateArgs) -> Result<()> {
    let body = super::load_body(&a.file)?;
    let ramp = Ramp::with_drag(a.alpha, a.mass, a.drag)?.with_drag_law(a.drag_law.law()?);
    let method = a.integrator.with(a.rtol, a.atol, a.dt)?;
    let limits = ContactLimits {
        friction: a.friction,
        on_violation: a.on_invalid.policy(),
    };
    limits.validate().map_err(|e| anyhow!("--friction: {e}"))?;
    let initial = initial_state(&a, &body)?;
    // The model the run will use (the viscous limit below rtol), then the cost of a stiff one.
    // (A fixed step is refused there when too long for the stiffness; that error comes from the
    // run, with the flags it ran with.)
    if matches!(method, Method::Dop853 { .. })
        && let Ok(chosen) = crate::simulate::choose_model(&body, ramp, method)
    {
        super::warn_if_stiff(&body, &chosen.ramp, a.t_end, "--t-end");
    }
    let spec = RunSpec {
        ramp,
        initial,
        method,
        t_end: a.t_end,
        samples: a.samples,
        max_steps: a.max_steps,
        limits,
    };
    let model_header = if body.dimension() == 2 {
        DISK_HEADER
    } else {
        SPHERE_HEADER
    };
    let header = if a.forces {
        format!("{model_header},{FORCE_HEADER}")
    } else {
        model_header.to_string()
    };
    let columns = header.split(',').count();
    // Staged beside the destination and moved into place at the end, with the summary, so a
    // failed run leaves no half file (see `crate::output`: devices and links are kept).
    let inputs = Inputs::of([&a.file]);
    if let Some(s) = &a.summary {
        output::check_distinct(&[("-o", &a.output), ("--summary", s)])?;
        output::check_file(s, &inputs)?;
    }
    let mut file = output::OutputFile::create(&a.output, &inputs)?;
    // The header goes out with the first row, so a run refused before it starts writes nothing
    // (also on standard output).
    let mut header = Some(header.as_str());
    let mut out = csv::WriterBuilder::new().from_writer(&mut file);
    let bar = indicatif::ProgressBar::new(a.samples as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} rows, t = {msg} {elapsed}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let mut io_error: Option<std::io::Error> = None;
    // Numbers go out through ryu (shortest round-trip digits, as serde_json writes them): a
    // short run's time was mostly the standard library's float formatting. Only finite values
    // reach here (`simulate::run` checks every row).
    let mut number = ryu::Buffer::new();
    let mut write_row = |out: &mut csv::Writer<_>, row: &[f64]| -> Result<(), csv::Error> {
        for &v in row {
            out.write_field(number.format(v))?;
        }
        out.write_record(None::<&[u8]>)
    };
    let result = crate::simulate::run(&body, &spec, |row| {
        if io_error.is_some() {
            return;
        }
        let written = header
            .take()
            .map_or(Ok(()), |h| out.write_record(h.split(',')))
            .and_then(|()| write_row(&mut out, &row[..columns]));
        if let Err(e) = written {
            io_error = Some(csv_io_error(e));
        }
        bar.inc(1);
        if !bar.is_hidden() {
            bar.set_message(format!("{:.1}", row[0]));
        }
    });
    bar.finish_and_clear();
    if io_error.is_none()
        && let Err(e) = out.flush()
    {
        io_error = Some(e);
    }
    drop(out);
    let summary = match result {
        Ok(s) => s,
        Err(e) => {
            file.abort();
            let settings = settings_text(method);
            if let RunError::LeftModel { report, .. } = &e {
                eprintln!(
                    "contact force up to there: N/F from {:.4} to {:.4}, friction needed up to \
                     {:.4}",
                    report.min_normal_force, report.max_normal_force, report.max_friction_needed
                );
            }
            // Rows already sent to standard output cannot be taken back; a file is untouched.
            // (The header goes out with the first row: none sent, none to take back.)
            let left = if header.is_some() {
                "no rows were written"
            } else if output::is_standard_output(&a.output) {
                "the rows on standard output stop there and are incomplete"
            } else {
                "no CSV was written"
            };
            return Err(e).context(format!(
                "simulation failed with --alpha {} --mass {} and {settings}; {left}",
                super::short(a.alpha),
                super::short(a.mass)
            ));
        }
    };
    if let Some(e) = io_error {
        file.abort();
        return Err(e).context(format!("cannot write {}", a.output.display()));
    }
    let mut outputs = output::OutputSet::new();
    outputs.add(file)?;
    let wall = start.elapsed().as_secs_f64();
    if let Some(note) = &summary.model_note {
        eprintln!("note: {note}");
    }
    for warning in summary.validity_warnings() {
        eprintln!("warning: the body {warning}");
    }
    if let Some(path) = &a.summary {
        let file = SummaryReport::new(summary, wall, a.alpha, a.mass, ramp.drag_law);
        let text = serde_json::to_string_pretty(&file)? + "\n";
        outputs.write(path, text.as_bytes(), &inputs)?;
    }
    outputs.commit()?;
    Ok(())
}

/// `--integrator`, read by the core's one parser (the same names and message as scenes, sweep
/// specs and Python).
fn parse_kind(s: &str) -> Result<MethodKind, String> {
    s.parse().map_err(|e: MethodParseError| e.to_string())
}

/// The integrator's flags as the user gave them, for a failed run's message.
fn settings_text(method: Method) -> String {
    match method {
        Method::Dop853 { rtol, atol } => format!(
            "dop853 --rtol {} --atol {}",
            super::short(rtol),
            super::short(atol)
        ),
        Method::Rk4 { dt } | Method::Cf4 { dt } => {
            format!("{} --dt {}", method.name(), super::short(dt))
        }
    }
}

/// The I/O error inside a CSV error (a closed pipe must stay recognisable as one).
fn csv_io_error(e: csv::Error) -> std::io::Error {
    match e.into_kind() {
        csv::ErrorKind::Io(io) => io,
        other => std::io::Error::other(format!("{other:?}")),
    }
}
