//! A filmed run from Python: `read_track_table` (a tracker's table read as `rollphase track`
//! reads it), `measure_track` (the period search of `rollphase track`, with its evidence) and `compare_with_model` (the measurement beside the model's prediction, m/m0 and
//! t0 solved together). Each is the core's function of the same name
//! (`rollphase_core::analysis::experiment::tracking`), run with the GIL released.

use numpy::ndarray::{Array1, Array2};
use numpy::{AllowTypeChange, IntoPyArray, PyArrayLike1, PyArrayLike2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rollphase_core::analysis::experiment::prediction::PredictOptions;
use rollphase_core::analysis::experiment::tracking::model::{
    CompareError, Measured, compare_with_model_until,
};
use rollphase_core::analysis::experiment::tracking::table::{
    TableError, TableFormat, TableRequest, read_table,
};
use rollphase_core::analysis::experiment::tracking::{
    Folded, MAX_POSITION, RepeatShown, TrackError, fold_centre, measure, repeat_shown,
};

use crate::body::Body;
use crate::errors::{Classified, ErrorClass, input_error, internal_error, raise};
use crate::run::json_to_py;
use crate::{interruptible, whole};

impl Classified for TrackError {
    fn class(&self) -> ErrorClass {
        match self {
            // The data given show no period (or not one that can be stated): the input's.
            TrackError::TooShort { .. }
            | TrackError::Order { .. }
            | TrackError::Damaged(_)
            | TrackError::NoPeriod { .. }
            | TrackError::TooFast { .. }
            | TrackError::MostlyUnsteady { .. }
            | TrackError::BadArgument(_) => ErrorClass::Input,
        }
    }
}

impl Classified for TableError {
    fn class(&self) -> ErrorClass {
        ErrorClass::Input
    }
}

impl Classified for CompareError {
    fn class(&self) -> ErrorClass {
        match self {
            CompareError::BadArgument(_) => ErrorClass::Input,
            CompareError::Study(e) => e.class(),
            CompareError::NoOrbit { .. } | CompareError::NotSettled { .. } => ErrorClass::Run,
        }
    }
}

/// A serialisable value's fields into `d`, as `json.loads` would give them.
fn fields_into(
    d: &Bound<'_, PyDict>,
    value: &impl serde::Serialize,
    skip: &[&str],
) -> PyResult<()> {
    let value = serde_json::to_value(value).map_err(internal_error)?;
    if let serde_json::Value::Object(map) = value {
        for (k, v) in map {
            if !skip.contains(&k.as_str()) {
                d.set_item(k, json_to_py(d.py(), &v)?)?;
            }
        }
    }
    Ok(())
}

/// How closely a track's period is shown ({"shown": "closely" | "by_markers" | "roughly",
/// "beyond_noise": float or None, with "by_markers" "after": 1 or 2 periods, with "roughly"
/// "turn_rule": a TurnRule dict or None, "caveat": str,
/// empty where closely}), as summary.json's
/// `repeat_shown` with the line `track` prints.
fn repeat_dict(py: Python<'_>, shown: RepeatShown) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    fields_into(&d, &shown, &[])?;
    d.set_item("caveat", shown.caveat())?;
    Ok(d)
}

/// Most rows read from a table, as `rollphase track` reads.
const MAX_TABLE_ROWS: usize = 10_000_000;

/// A tracked run's table at `path` read as `rollphase track` reads it: the authors' plain CSV,
/// Tracker's data export (title lines, t, x, y; decimal commas; frames counted from the first time
/// at `fps`, the rate read from the time steps unless given) or trackpy's linked table (frame, particle, x, y;
/// `particle` picks the body, `every_particle` keeps all rows, for markers). Returns a dict
/// (TrackTable): format, columns (frame or time, across, down), frames, across and down (arrays,
/// in the file's units: multiply by cm per unit), fps_from_times (None where not read),
/// time_origin (the time of frame 0, None without a time column) and
/// notes. A file that cannot be read so raises InputError naming why.
#[pyfunction]
#[pyo3(signature = (
    path, *, format = None, frame_column = None, time_column = None, across_column = None,
    down_column = None, fps = None, particle = None, every_particle = false
))]
#[expect(
    clippy::too_many_arguments,
    reason = "Python keywords, one per command-line flag"
)]
pub fn read_track_table<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
    format: Option<String>,
    frame_column: Option<String>,
    time_column: Option<String>,
    across_column: Option<String>,
    down_column: Option<String>,
    fps: Option<f64>,
    particle: Option<f64>,
    every_particle: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let format = match format.as_deref() {
        None => None,
        Some(name) => Some(TableFormat::named(name).ok_or_else(|| {
            input_error(format!(
                "format {name:?} is not one of {}",
                TableFormat::ALL.map(TableFormat::name).join(", ")
            ))
        })?),
    };
    if frame_column.is_some() && time_column.is_some() {
        return Err(input_error(
            "give frame_column or time_column, not both".to_string(),
        ));
    }
    if let Some(f) = fps
        && !(f.is_finite() && (1e-5..=1e6).contains(&f))
    {
        return Err(input_error(format!(
            "fps {f:?} is not allowed (needs 1e-5 ≤ fps ≤ 1e6 frames per second)"
        )));
    }
    let meta = std::fs::metadata(&path)
        .map_err(|e| input_error(format!("cannot read {}: {e}", path.display())))?;
    if !meta.is_file() {
        return Err(input_error(format!(
            "{} is not a regular file (a device, FIFO or folder)",
            path.display()
        )));
    }
    let file = std::fs::File::open(&path)
        .map_err(|e| input_error(format!("cannot read {}: {e}", path.display())))?;
    let request = TableRequest {
        format,
        frame_column,
        time_column,
        across_column,
        down_column,
        fps,
        time_origin: None,
        particle,
        every_particle,
    };
    let table = read_table(std::io::BufReader::new(file), &request, MAX_TABLE_ROWS)
        .map_err(|e| input_error(format!("{}: {e}", path.display())))?;
    let d = PyDict::new(py);
    fields_into(&d, &table, &[])?;
    for (k, name) in ["frames", "across", "down"].into_iter().enumerate() {
        let column: Vec<f64> = table.rows.iter().map(|r| r[k]).collect();
        d.set_item(name, Array1::from_vec(column).into_pyarray(py))?;
    }
    Ok(d)
}

/// `rollphase track`'s measurement of a centre track: `frames` (increasing frame numbers),
/// `down` and `across` (cm, one value a frame; NaN for a missing one) cleaned (gaps of up to 10
/// frames bridged, tracker jumps replaced, the release and the end of the ramp cut off, each in
/// `warnings`), and its period found at every shift by FFT. Returns a dict (TrackMeasurement):
/// period_frames with period_error_frames (always finite) and period_error_from ("harmonics",
/// the regression's; "cycles" where the turns' times vary or it cannot be fitted; "dip_width"),
/// block_check (whether blocks of the track show the turns' times vary),
/// period_spread_frames (None under three cycles), cycle_periods (array),
/// unrepeated_cycles, periods_seen, mismatch, advance_down and advance_across (cm per period),
/// advance_error ([down, across] standard errors in cm, from the regression's slope and the
/// period's error; None where the regression could not be fitted), velocity ([[down, across]
/// in cm a frame, [their standard errors]], None likewise), significance (the surrogates' check against chance), mismatch_curve ((N, 2) array of shift
/// and normalised mismatch), frames_used ([first, last]), folded ((N, 4) array: the cleaned
/// track folded on its period as `track` draws it: period index, frames into the period, down
/// and across in cm since the period began less the earlier periods' advance; give it to
/// `compare_with_model(folded=…)`) and warnings. A track that does not
/// show a period with that evidence raises InputError saying why. Multiply by 1/fps for
/// seconds; the same numbers as the command line's summary.json. With `markers` (an (N, 3)
/// array of frame, down, across in cm: the markers drawn on the body), also marker_reading:
/// whether their pattern repeats after one period or only after two (MarkerReading: verdict
/// "every_period", "every_other_period", "no_repeat" or "too_sparse", the score D1/D2, its
/// shuffles and a reason), as `track --markers`. repeat_shown says how closely the period is
/// shown to be the motion's ({"shown": "closely", "by_markers" or "roughly", "beyond_noise": the
/// mismatch over the share the frame-to-frame noise explains, "caveat": what `track` prints):
/// a centre that varies from turn to turn beyond its noise repeats only roughly, unless the
/// markers repeat, with "turn_rule" (TurnRule) saying whether its turns show a rule. A track
/// whose turns follow from one another by a rule (a chaotic motion: over 20 turns, the
/// analogues' error under 0.25 of a straight line's) or swing with a second period that is not a
/// whole number of turns (a quasi-periodic one) raises InputError: it has no period.
#[pyfunction]
#[pyo3(signature = (frames, down, across, *, markers = None))]
pub fn measure_track<'py>(
    py: Python<'py>,
    frames: PyArrayLike1<'py, f64, AllowTypeChange>,
    down: PyArrayLike1<'py, f64, AllowTypeChange>,
    across: PyArrayLike1<'py, f64, AllowTypeChange>,
    markers: Option<PyArrayLike2<'py, f64, AllowTypeChange>>,
) -> PyResult<Bound<'py, PyDict>> {
    let markers: Option<Vec<(f64, f64, f64)>> = match markers {
        Some(m) => {
            let m = m.as_array();
            if m.ncols() != 3 {
                return Err(input_error(format!(
                    "markers has {} columns (needs 3: frame, down, across in cm)",
                    m.ncols()
                )));
            }
            Some(m.rows().into_iter().map(|r| (r[0], r[1], r[2])).collect())
        }
        None => None,
    };
    let (frames, down, across) = (
        frames.as_array().to_vec(),
        down.as_array().to_vec(),
        across.as_array().to_vec(),
    );
    let (track, fit) =
        interruptible(py, |_| measure(&frames, &down, &across, &|_, _| {}))?.map_err(raise)?;
    let rows: Vec<(f64, f64, f64)> = (0..frames.len().min(down.len()).min(across.len()))
        .map(|i| (frames[i], down[i], across[i]))
        .collect();
    let d = PyDict::new(py);
    fields_into(&d, &fit, &["mismatch_curve", "cycle_periods"])?;
    d.set_item(
        "cycle_periods",
        Array1::from_vec(fit.cycle_periods.clone()).into_pyarray(py),
    )?;
    let flat: Vec<f64> = fit.mismatch_curve.iter().flatten().copied().collect();
    let curve =
        Array2::from_shape_vec((fit.mismatch_curve.len(), 2), flat).map_err(internal_error)?;
    d.set_item("mismatch_curve", curve.into_pyarray(py))?;
    d.set_item(
        "frames_used",
        vec![track.frames[0], track.frames[track.frames.len() - 1]],
    )?;
    let folded: Vec<f64> = fold_centre(&track, &fit)
        .iter()
        .flat_map(|f| [f.period as f64, f.t_local, f.down_local, f.across_local])
        .collect();
    let folded = Array2::from_shape_vec((folded.len() / 4, 4), folded).map_err(internal_error)?;
    d.set_item("folded", folded.into_pyarray(py))?;
    if let Some(m) = markers {
        let reading = rollphase_core::analysis::experiment::tracking::markers::read_markers(
            &track,
            &m,
            track.frames[0],
            fit.period_frames,
        );
        let r = PyDict::new(py);
        fields_into(&r, &reading, &[])?;
        d.set_item("marker_reading", r)?;
        d.set_item(
            "repeat_shown",
            repeat_dict(py, repeat_shown(&rows, &track, &fit, Some(&reading)))?,
        )?;
    } else {
        d.set_item(
            "repeat_shown",
            repeat_dict(py, repeat_shown(&rows, &track, &fit, None))?,
        )?;
    }
    d.set_item("warnings", track.warnings)?;
    Ok(d)
}

/// The measured motion of `body` on a ramp at `alpha` (rad) beside the model's prediction, as
/// `rollphase track --body` gives it: `period_s` (s) and the advance per period
/// (`advance_down_cm`, `advance_across_cm`) from `measure_track` and the frame rate. The body's
/// size is its scale_mm (from Body.from_mesh or a shape file), or `scale_mm=`. m/m0 and the
/// time unit t0 are solved together so that the model's period in seconds is the measured one
/// (m/m0 = ⟨r⟩/(g t0²), g = 9.81), unless `mass_ratio` is given (0: the viscous model, t0 from
/// the period). Returns a dict (ModelComparison): mass_ratio, mass_ratio_from ("period";
/// "given" for a mass_ratio > 0; "viscous_period" for mass_ratio = 0, where t0 and so m/m0 come
/// from the period in the viscous model), mass_ratio_model (what the model ran at: 0 is viscous, used below 0.1), t0_s, the
/// SI's speed estimate mass_ratio_from_speed = v²/(g⟨r⟩ sin²α) with the t0_from_speed_s and
/// period_from_speed_s it implies, the predicted orbit nearest in advance (predicted_period_t0,
/// predicted_period_s, predicted_advance_down_cm, predicted_advance_across_cm,
/// predicted_speed_cm_s, repeat, orbit_fraction), the differences measured against predicted
/// (advance_down_difference, period_difference, speed_difference), all orbits
/// ([advance_down_cm, period_t0] pairs), iterations, period_sensitivity (d ln(m/m0)/d ln
/// period), mass_ratio_error and t0_error_s (from `period_error_s`, the period's standard error,
/// alone: None without it or where m/m0 was given), and path ((N, 2) array: the orbit's centre,
/// down and across in cm, over three repeats). With `folded` (`measure_track`'s) and `fps`
/// (the track's frames a second, 1e-5 to 1e6, as `track --fps`), also where the orbit sits on
/// the folded track, as `track --body` draws it and its summary.json says: phase (the path
/// sample at which the track's periods begin, where the down path fits best), mirrored_across
/// (whether the orbit is drawn mirrored across the ramp: the sign that fits better),
/// handedness_shown (whether that is a finding: the drawn sign explains at least half of the
/// track's across variance and a quarter more than the other), down_explained and
/// across_explained (the shares of the track's variance explained, drawn sign then the other).
#[pyfunction]
#[pyo3(signature = (
    body, alpha, *, period_s, advance_down_cm, advance_across_cm, mass_ratio = None,
    scale_mm = None, starts = 32, seed = 1, period_error_s = None, folded = None, fps = None
))]
pub fn compare_with_model<'py>(
    py: Python<'py>,
    body: &Body,
    alpha: f64,
    period_s: f64,
    advance_down_cm: f64,
    advance_across_cm: f64,
    mass_ratio: Option<f64>,
    scale_mm: Option<f64>,
    starts: i128,
    seed: i128,
    period_error_s: Option<f64>,
    folded: Option<Bound<'py, PyAny>>,
    fps: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (starts, seed): (usize, u64) = (whole("starts", starts)?, whole("seed", seed)?);
    let folded = folded_track(folded, fps, period_s)?;
    if let Some(e) = period_error_s
        && !(e.is_finite() && e > 0.0 && e <= 0.25 * period_s)
    {
        return Err(input_error(format!(
            "period_error_s = {e} is not allowed (the period's standard error: a positive \
             number of seconds up to a quarter of period_s = {period_s}, where carrying it \
             through the solve linearly still means something; or None)"
        )));
    }
    let core = body.convex()?;
    let Some(scale_mm) = scale_mm.or(body.scale_mm) else {
        return Err(input_error(
            "the body has no scale_mm: a comparison in cm needs its size (fit it with \
             Body.from_mesh, load a shape file with scale_mm, or pass scale_mm=)",
        ));
    };
    if let Some(m) = mass_ratio {
        rollphase_core::dynamics::Ramp::new(alpha, m).map_err(raise)?;
    }
    let measured = Measured {
        period_s,
        advance_down_cm,
        advance_across_cm,
    };
    let options = PredictOptions {
        starts,
        seed,
        ..PredictOptions::default()
    };
    let (c, alignment) = interruptible(py, |stop| {
        let c =
            compare_with_model_until(core, scale_mm, alpha, &measured, mass_ratio, &options, stop)?;
        let alignment = folded.as_ref().map(|(f, fps)| c.aligned_with(f, *fps));
        Ok::<_, rollphase_core::analysis::experiment::tracking::model::CompareError>((c, alignment))
    })?
    .map_err(raise)?;
    let c = match period_error_s {
        Some(e) => c.with_period_error(period_s, e),
        None => c,
    };
    let d = PyDict::new(py);
    fields_into(&d, &c, &[])?;
    if let Some(alignment) = alignment {
        fields_into(&d, &alignment, &[])?;
    }
    let cm = scale_mm / 10.0;
    let flat: Vec<f64> = c.orbit.path.iter().flatten().map(|v| v * cm).collect();
    let path = Array2::from_shape_vec((c.orbit.path.len(), 2), flat).map_err(internal_error)?;
    d.set_item("path", path.into_pyarray(py))?;
    Ok(d)
}

/// `compare_with_model`'s folded track and frame rate, checked before the model runs: both or
/// neither; `fps` a number of frames a second from 1e-5 to 1e6 (`track --fps`'s range; not a
/// bool); `folded` an (N, 4) array of finite numbers as `measure_track` gives it (N ≥ 1, the
/// period index a whole number from 0 to 1e15, the frames into the period from 0 to a period,
/// `period_s`·fps, and down and across within ±1e100 cm, as a track's own positions).
fn folded_track(
    folded: Option<Bound<'_, PyAny>>,
    fps: Option<Bound<'_, PyAny>>,
    period_s: f64,
) -> PyResult<Option<(Vec<Folded>, f64)>> {
    if !(period_s.is_finite() && period_s > 0.0) {
        // The model refuses the period itself, naming it, before any alignment: a folded
        // track judged against it would be refused for the period's fault.
        return Ok(None);
    }
    let (folded, fps) = match (folded, fps) {
        (None, None) => return Ok(None),
        (Some(f), Some(fps)) => (f, fps),
        _ => {
            return Err(input_error(
                "folded and fps go together: the folded track (measure_track's \"folded\") \
                 and its frames a second, to place the orbit on it; or neither",
            ));
        }
    };
    let fps = if fps.is_instance_of::<pyo3::types::PyBool>() {
        None
    } else {
        fps.extract::<f64>().ok()
    }
    .filter(|f| f.is_finite() && (1e-5..=1e6).contains(f))
    .ok_or_else(|| {
        input_error(format!(
            "fps = {} is not allowed (the track's frames a second: a number from 1e-5 to 1e6, \
             as track --fps)",
            fps.repr().map_or_else(|_| "?".into(), |r| r.to_string())
        ))
    })?;
    let shape_error = |what: String| {
        input_error(format!(
            "folded is {what} (needs an N × 4 array of numbers, N ≥ 1: period index, frames into \
             the period, down and across in cm, as measure_track's \"folded\")"
        ))
    };
    let folded = folded
        .extract::<PyArrayLike2<'_, f64, AllowTypeChange>>()
        .map_err(|e| shape_error(format!("not a 2-D array of numbers ({e})")))?;
    let folded = folded.as_array();
    if folded.ncols() != 4 || folded.nrows() == 0 {
        return Err(shape_error(format!(
            "{}×{}",
            folded.nrows(),
            folded.ncols()
        )));
    }
    let period_frames = period_s * fps;
    folded
        .rows()
        .into_iter()
        .enumerate()
        .map(|(i, r)| {
            let whole_period = r[0] >= 0.0 && r[0].fract() == 0.0 && r[0] <= 1e15;
            let in_period = r[1] >= 0.0 && r[1] <= period_frames * (1.0 + 1e-9);
            let positions = r[2].abs() <= MAX_POSITION && r[3].abs() <= MAX_POSITION;
            if !(r.iter().all(|v| v.is_finite()) && whole_period && in_period && positions) {
                return Err(input_error(format!(
                    "folded row {i} is {:?}: every value must be finite, the period index a \
                     whole number from 0 to 1e15, the frames into the period from 0 to a period \
                     ({period_frames} frames: period_s {period_s} × fps {fps}; a track folded on \
                     another period or frame rate does not belong here), and down and across \
                     within ±1e100 cm",
                    r.to_vec()
                )));
            }
            Ok(Folded {
                period: r[0] as usize,
                t_local: r[1],
                down_local: r[2],
                across_local: r[3],
            })
        })
        .collect::<PyResult<Vec<Folded>>>()
        .and_then(|f| {
            // A folded track of a whole period or more spans it (the cleaned track has every
            // frame); one folded at twice the frame rate spans half of it.
            let reach = f.iter().map(|p| p.t_local).fold(0.0, f64::max);
            if reach < 0.9 * period_frames {
                return Err(input_error(format!(
                    "folded reaches {reach} frames into a period of {period_frames} frames \
                     (period_s {period_s} × fps {fps}): a folded track spans its whole period, \
                     so it was folded on another period or frame rate, or holds less than one \
                     period"
                )));
            }
            Ok(Some((f, fps)))
        })
}
