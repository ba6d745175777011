//! `rollphase track`: a tracked video of a rolling body read as a measurement, and compared with
//! the model's prediction for the same body.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use serde::Serialize;

use crate::analysis::experiment::prediction::{PredictOptions, PredictedOrbit};
use crate::analysis::experiment::tracking::markers::{MarkerReading, read_markers};
use crate::analysis::experiment::tracking::model::{
    Measured, ModelComparison, TrackAlignment, compare_with_model,
};
use crate::analysis::experiment::tracking::table::{
    TableFormat, TableRequest, TrackTable, read_table,
};
use crate::analysis::experiment::tracking::{
    CleanTrack, ErrorSource, Folded, PeriodFit, RepeatShown, Significance, fold_centre,
    fold_on_track, harmonic::BlockCheck, measure, repeat_shown,
};
use crate::geometry::ShapeFile;
use crate::output::{self, Inputs, OutputSet};

mod figures;
mod print;
use figures::{figure, refusal_figure};
use print::print_summary;

/// Read a tracked run: its period, advance per period and folded track, and the model's.
///
/// FILE is a table with one row per video frame: a frame number and the body's centre in two
/// coordinates of the ramp's plane (--frame-column, --down-column, --across-column; the
/// defaults read the paper authors' files, whose rectified `yn` runs down the ramp and `xn`
/// across it). Tracker's data export (a title line, then t, x, y: frames counted from the first
/// time at --fps, the rate read from the time steps unless given) and trackpy's linked table (frame, particle,
/// x, y; --particle picks the body) are read as they are written (--format). --scale SX,SY
/// gives cm per unit of the across and down columns, --fps the frame rate. The period is found automatically; it and its uncertainty come from a harmonic fit of
/// the whole track at its frames (`bench calibration`: the 95 % interval holds a synthetic
/// track's true period 92–97 % of the time from 6 to 300 frames a period), or, where blocks of
/// the track show that its turns take varying times, from the mean and spread of the whole
/// cycles' own periods. Where no period can be found with confidence the command says so and
/// exits with an error rather than guess. The release and the end of the ramp (where the speed
/// is not steady), gaps of up to 10 frames, tracker jumps and missing values are handled and
/// each is reported.
///
/// Writes to --out: data.csv (every centre and marker point with its period and local
/// coordinates), figure.png (the track folded into local coordinates, as the paper's Fig. 5c,
/// markers coloured by period in two alternating colours as Fig. 5e), summary.json (period_s,
/// advance_down_cm, advance_across_cm, speed, the evidence, …). With --markers it also says
/// whether the markers' pattern (each detection's offset from the centre) repeats after one
/// period or only after two (period doubling), with a score D1/D2 and its confidence against
/// 19 shuffles of the cycles and 19 unrelated phases, or that they are too sparse to tell
/// (summary.json: marker_reading). Under the period it says how closely it is shown
/// (summary.json: repeat_shown): where the centre leaves more unrepeated than 3 times its white
/// frame-to-frame noise explains, only roughly (a roll whose turns vary by chance), unless the
/// markers repeat. The period is stated only when every cycle repeats on its own, the track
/// repeats beyond chance (19 surrogate tracks with its smoothed spectrum and random phases) and
/// its turns neither follow from one another by a rule nor swing with a second period: over 20
/// turns or more, each turn's peak predicted from its nearest analogue in the peaks before
/// misses by under 0.25 of what a straight line misses in a chaotic motion (the Rössler
/// attractor: 0.002–0.1 at noise up to 2 %), while turns that vary by chance read about 2
/// (`bench calibration`), and sizes that swing every 7.3 turns are quasi-periodic.
/// Otherwise the command says why, writes refused.png (the track and its mismatch at every
/// shift) and exits 1.
/// With --body and --alpha: m/m0 and the time unit t0 solved together so that the model's
/// period in seconds is the measured one (the weight drives the body: m/m0 = ⟨r⟩/(g t0²)),
/// the SI's speed estimate v²/(g⟨r⟩ sin²α) (§2H) beside it as a check, and the predicted
/// orbit's period, advance, speed and path against the measured ones. For example:
///   rollphase track sphere-track-viscous.csv --markers sphere-markers-viscous.csv \
///       --fps 30 --scale 0.0404,0.0361 --body printed-sphere.json --alpha 0.2014 --out run
#[derive(Debug, Args)]
#[command(verbatim_doc_comment)]
pub struct TrackArgs {
    /// The centre's track (CSV with a header row).
    pub file: PathBuf,
    /// Frames per second of the video [default: read from a time column's steps, else 30, the
    /// authors' camera].
    #[arg(long, allow_negative_numbers = true)]
    pub fps: Option<f64>,
    /// cm per unit of the across and of the down column, as SX,SY (a negative factor flips that
    /// axis: the model's down is the direction the body rolls) [default: 0.0404,0.0361, the
    /// authors' camera, for plain tables; Tracker's and trackpy's need it: 100,100 for metres].
    #[arg(long, allow_hyphen_values = true)]
    pub scale: Option<String>,
    /// The table's layout: plain (a header row, a row per frame), tracker (Tracker's data
    /// export: a title line, then t, x, y; tabs, commas, semicolons or spaces; decimal commas
    /// read) or trackpy (frame, particle, x, y) [default: told from the file].
    #[arg(long, value_parser = ["plain", "tracker", "trackpy"])]
    pub format: Option<String>,
    /// Column of the frame number [default: frame].
    #[arg(long, conflicts_with = "time_column")]
    pub frame_column: Option<String>,
    /// Column of the time in seconds, read as frames at --fps (Tracker's t) [default for
    /// Tracker: t].
    #[arg(long)]
    pub time_column: Option<String>,
    /// Column of the position across the ramp, scaled by SX [default: xn; Tracker, trackpy: y].
    #[arg(long)]
    pub across_column: Option<String>,
    /// Column of the position down the ramp, scaled by SY [default: yn; Tracker, trackpy: x, as
    /// Tracker's incline tutorials turn the axes].
    #[arg(long)]
    pub down_column: Option<String>,
    /// trackpy: the particle that is the body's centre (needed when the table holds several).
    #[arg(long, allow_negative_numbers = true)]
    pub particle: Option<f64>,
    /// The frame rate used: --fps, or the one read from the times ([`run`] sets it).
    #[arg(skip)]
    pub rate: f64,
    /// Markers drawn on the body (CSV, the same column names), folded with the centre.
    #[arg(long, value_name = "FILE")]
    pub markers: Option<PathBuf>,
    /// Output folder for data.csv, figure.png and summary.json.
    #[arg(long, default_value = "track")]
    pub out: PathBuf,
    /// The body's shape file (with scale_mm, as `shape --from-mesh` writes), to compare with
    /// the model.
    #[arg(long, requires = "alpha")]
    pub body: Option<PathBuf>,
    /// The ramp's angle α (rad), with --body.
    #[arg(long, requires = "body", allow_negative_numbers = true)]
    pub alpha: Option<f64>,
    /// m/m0 for the prediction [default: solved with t0 so that the model's period in seconds
    /// is the measured one; below 0.1 the viscous model]. 0 runs the viscous model.
    #[arg(long, requires = "body", allow_negative_numbers = true)]
    pub mass: Option<f64>,
}

const FILES: [&str; 4] = ["data.csv", "figure.png", "summary.json", REFUSAL_FIGURE];
/// What a refused track writes instead ([`figures::refusal_figure`]).
const REFUSAL_FIGURE: &str = "refused.png";
/// Most rows read from a track file (a video of a day at 1000 frames/s is 8.6e7).
const MAX_ROWS: usize = 10_000_000;

/// The model's side of the comparison: the core's, with the shape file named.
#[derive(Debug, Serialize)]
pub struct Comparison {
    /// The shape file.
    pub body: String,
    /// Where the predicted path is drawn on the folded track: its phase, whether mirrored
    /// across the ramp (a body placed the other way round), and how much of the track each
    /// explains (`handedness_shown`: whether the track tells which way round it runs).
    #[serde(flatten)]
    pub alignment: TrackAlignment,
    /// The comparison.
    #[serde(flatten)]
    pub comparison: ModelComparison,
}

/// What `track` writes as summary.json.
#[derive(Debug, Serialize)]
pub struct TrackSummary {
    /// The track file.
    pub file: String,
    /// Frames per second.
    pub fps: f64,
    /// Frames read, and the frames used (the steady stretch).
    pub frames_read: usize,
    /// First and last frame used.
    pub frames_used: [f64; 2],
    /// The period (s).
    pub period_s: f64,
    /// Its standard error (s), always finite.
    pub period_error_s: f64,
    /// Where the standard error comes from: the cycles' spread, or the mismatch dip's width
    /// (fewer than three cycles).
    pub period_error_from: ErrorSource,
    /// The spread of the cycles' own periods (s); null with fewer than three cycles.
    pub period_spread_s: Option<f64>,
    /// Cycles that do not repeat on their own (at most a quarter are allowed).
    pub unrepeated_cycles: usize,
    /// The check against chance: surrogate tracks and the lowest dip they reached.
    pub significance: Option<Significance>,
    /// The harmonic regression's check over blocks of the track (whether its turns' times
    /// vary beyond the noise).
    pub block_check: Option<BlockCheck>,
    /// How closely the period is shown to be the motion's: the centre repeats as closely as its
    /// noise allows, or only roughly and the markers repeat, or only roughly (turns that vary
    /// without a rule between them, or too few to read one), with the mismatch over what the
    /// noise explains.
    pub repeat_shown: RepeatShown,
    /// The period in frames.
    pub period_frames: f64,
    /// Whole periods seen.
    pub periods_seen: usize,
    /// Unexplained fraction of the track's variation at the period (0 perfect, 1 none).
    pub mismatch: f64,
    /// Advance per period down the ramp (cm).
    pub advance_down_cm: f64,
    /// Advance per period across the ramp (cm).
    pub advance_across_cm: f64,
    /// Mean speed down the ramp (cm/s).
    pub speed_cm_s: f64,
    /// Standard errors of the advance per period (down, across; cm) and of the speed (cm/s),
    /// from the harmonic regression's slope and the period's error (`bench calibration`
    /// measures their coverage); null where the regression could not be fitted, and then no
    /// error is stated.
    pub advance_down_error_cm: Option<f64>,
    /// See `advance_down_error_cm`.
    pub advance_across_error_cm: Option<f64>,
    /// See `advance_down_error_cm`.
    pub speed_error_cm_s: Option<f64>,
    /// Each whole cycle's own period (s).
    pub cycle_periods_s: Vec<f64>,
    /// Markers read (0 without --markers).
    pub markers: usize,
    /// With --markers: whether their pattern repeats after one period or only after two
    /// (Fig. 5e), with the evidence, or that they are too sparse to tell.
    pub marker_reading: Option<MarkerReading>,
    /// How the file was read: its format, the columns, the frame rate read from its times and
    /// what was left out.
    pub table: TrackTable,
    /// What was cleaned or left out.
    pub warnings: Vec<String>,
    /// The model's prediction for the body, with --body.
    pub model: Option<Comparison>,
}

/// A frame a day (time-lapse) to a million a second; below, periods in seconds overflow.
fn check_rate(fps: f64, from: &str) -> Result<()> {
    if fps.is_finite() && (1e-5..=1e6).contains(&fps) {
        Ok(())
    } else {
        // `{:?}`: 1e308, not its 309 digits.
        bail!("{from} {fps:?} is not allowed (needs 1e-5 ≤ fps ≤ 1e6 frames per second)")
    }
}

/// The flags checked before any file is read: --fps, --particle, and --scale's factors (`None`
/// where not given).
fn checked_flags(a: &TrackArgs) -> Result<Option<(f64, f64)>> {
    if let Some(fps) = a.fps {
        check_rate(fps, "--fps")?;
    }
    if let Some(p) = a.particle
        && !(p.is_finite() && p.fract() == 0.0)
    {
        bail!("--particle {p} is not allowed (needs trackpy's particle number, a whole number)");
    }
    let Some(text) = &a.scale else {
        return Ok(None);
    };
    let scale = super::parse_list(text, 2, "--scale", "SX,SY (cm per unit across, down)")?;
    if scale.iter().any(|s| *s == 0.0 || s.abs() > 1e6) {
        bail!(
            "--scale {text} is not allowed (needs two non-zero cm-per-unit factors of at most \
             1e6)"
        );
    }
    Ok(Some((scale[0], scale[1])))
}

/// The centre's table read, with the frame rate (given, read from its times, or the authors'
/// 30) set in `a.rate` and the scale (given, or the authors' for a plain table) returned.
fn read_centre(a: &mut TrackArgs, scale: Option<(f64, f64)>) -> Result<(TrackTable, f64, f64)> {
    let table = read_track_table(&a.file, &table_request(a, a.fps))?;
    a.rate = match (a.fps, table.fps_from_times) {
        (Some(given), _) => given,
        (None, Some(read)) => {
            check_rate(read, "the frame rate read from the times,")?;
            read
        }
        (None, None) => 30.0,
    };
    let (sx, sy) = match scale {
        Some(s) => s,
        None if table.format.needs_scale() => bail!(
            "{} is a {} table, whose x and y are in units only you know (Tracker's calibration, \
             often m; trackpy's pixels): give --scale SX,SY in cm per unit (100,100 for metres)",
            a.file.display(),
            table.format.name()
        ),
        None => (0.0404, 0.0361),
    };
    for note in &table.notes {
        eprintln!("note: {}: {note}", a.file.display());
    }
    Ok((table, sx, sy))
}

/// Runs `track`.
pub fn run(mut a: TrackArgs) -> Result<()> {
    let scale = checked_flags(&a)?;
    let body = match (&a.body, a.alpha) {
        (Some(path), Some(alpha)) => {
            let (body, scale_mm) = ShapeFile::load_scaled(path)?;
            body.check_convex()?;
            crate::dynamics::Ramp::new(alpha, a.mass.unwrap_or(0.0))?;
            let Some(scale_mm) = scale_mm else {
                bail!(
                    "{} has no scale_mm: a comparison in cm needs the body's size (fit it from \
                     its mesh with `rollphase shape --from-mesh`, or add \"scale_mm\" to the file)",
                    path.display()
                );
            };
            Some((path.clone(), body, scale_mm, alpha))
        }
        _ => None,
    };
    let mut inputs = Inputs::of([&a.file]);
    if let Some(m) = &a.markers {
        inputs.add(m);
    }
    if let Some(b) = &a.body {
        inputs.add(b);
    }
    output::check_folder(&a.out, &FILES, &inputs)?;
    let (table, sx, sy) = read_centre(&mut a, scale)?;
    let rows = &table.rows;
    let frames_read = rows.len();
    let frames: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    let down: Vec<f64> = rows.iter().map(|r| r[2] * sy).collect();
    let across: Vec<f64> = rows.iter().map(|r| r[1] * sx).collect();
    let (track, fit) = measure_or_show_why(&a, (&frames, &down, &across), &inputs)?;
    let measured_rows: Vec<(f64, f64, f64)> = (0..frames.len())
        .map(|i| (frames[i], down[i], across[i]))
        .collect();
    for w in &track.warnings {
        eprintln!("warning: {w}");
    }
    let markers: Vec<(f64, f64, f64)> = match &a.markers {
        Some(path) => {
            let request = TableRequest {
                every_particle: true,
                time_origin: table.time_origin,
                ..table_request(&a, Some(a.rate))
            };
            let markers = read_track_table(path, &request)?;
            // One scale and one set of columns for both files: a layout of its own would be read
            // in the track's units (a plain file's pixels as Tracker's metres).
            if markers.format != table.format {
                bail!(
                    "{} is a {} table but the track {} a {} one: give the markers in the track's \
                     layout (--scale and the columns apply to both)",
                    path.display(),
                    markers.format.name(),
                    a.file.display(),
                    table.format.name()
                );
            }
            markers
                .rows
                .into_iter()
                .map(|r| (r[0], r[2] * sy, r[1] * sx))
                .collect()
        }
        None => Vec::new(),
    };
    let start = track.frames[0];
    let folded_centre = fold_centre(&track, &fit);
    let end = track.frames[track.frames.len() - 1];
    let (markers, in_range) = markers_on_track(a.markers.as_deref(), markers, start, end)?;
    let folded_markers = fold_on_track(&track, &fit, &in_range);
    let period_s = fit.period_frames / a.rate;
    let speed = fit.advance_down / period_s;
    let marker_reading = a
        .markers
        .is_some()
        .then(|| read_markers(&track, &markers, start, fit.period_frames));
    let mut summary = TrackSummary {
        file: a.file.display().to_string(),
        fps: a.rate,
        table: table.clone(),
        frames_read,
        frames_used: [start, end],
        period_s,
        period_error_s: fit.period_error_frames / a.rate,
        period_error_from: fit.period_error_from,
        period_spread_s: fit.period_spread_frames.map(|s| s / a.rate),
        unrepeated_cycles: fit.unrepeated_cycles,
        significance: fit.significance.clone(),
        block_check: fit.block_check,
        period_frames: fit.period_frames,
        periods_seen: fit.periods_seen,
        mismatch: fit.mismatch,
        advance_down_cm: fit.advance_down,
        advance_across_cm: fit.advance_across,
        speed_cm_s: speed,
        advance_down_error_cm: fit.advance_error.map(|e| e[0]),
        advance_across_error_cm: fit.advance_error.map(|e| e[1]),
        speed_error_cm_s: fit.velocity.map(|(_, e)| e[0] * a.rate),
        cycle_periods_s: fit.cycle_periods.iter().map(|p| p / a.rate).collect(),
        markers: in_range.len(),
        repeat_shown: repeat_shown(&measured_rows, &track, &fit, marker_reading.as_ref()),
        marker_reading,
        warnings: track.warnings.clone(),
        model: None,
    };
    let mut predicted_path = None;
    if let Some((path, body, scale_mm, alpha)) = &body {
        let (comparison, drawn) = compare(
            path,
            body,
            (*scale_mm, *alpha),
            a.mass,
            &fit,
            &folded_centre,
            a.rate,
        )?;
        summary.model = Some(comparison);
        predicted_path = Some(drawn);
    }
    let figure = figure(
        &fit,
        &folded_centre,
        &folded_markers,
        &a,
        predicted_path.as_ref(),
    );
    let png = crate::chart::png_bytes(&figure, 2, (1400, 1000))?;
    let csv = data_csv(&folded_centre, &track, &folded_markers, &in_range, a.rate)?;
    output::create_folder(&a.out)?;
    let mut set = OutputSet::new();
    set.write(&a.out.join("data.csv"), csv.as_bytes(), &inputs)?;
    set.write(&a.out.join("figure.png"), &png, &inputs)?;
    set.write(
        &a.out.join("summary.json"),
        (serde_json::to_string_pretty(&summary)? + "\n").as_bytes(),
        &inputs,
    )?;
    set.commit()?;
    print_summary(&a, &summary)
}

/// One marker detection: (frame, down, across).
type Marker = (f64, f64, f64);

/// The markers read (every row, `(frame, down, across)`) split into the finite ones and those
/// of them within the track's frames `start..=end`. A markers file none of whose rows is a
/// marker on the track is an error that says why, not a reading of nothing.
fn markers_on_track(
    path: Option<&std::path::Path>,
    rows: Vec<Marker>,
    start: f64,
    end: f64,
) -> Result<(Vec<Marker>, Vec<Marker>)> {
    let read = rows.len();
    let finite: Vec<(f64, f64, f64)> = rows
        .into_iter()
        .filter(|m| m.0.is_finite() && m.1.is_finite() && m.2.is_finite())
        .collect();
    let in_range: Vec<(f64, f64, f64)> = finite
        .iter()
        .copied()
        .filter(|m| m.0 >= start && m.0 <= end)
        .collect();
    if let Some(path) = path
        && in_range.is_empty()
    {
        bail!(
            "{}: none of its {read} rows is a marker on the track: {} have a value that is not \
             a finite number, and the other {} lie outside the track's frames {} to {} (is it \
             the markers file of this run, with the same --frame-column?)",
            path.display(),
            read - finite.len(),
            finite.len(),
            super::short(start),
            super::short(end)
        );
    }
    Ok((finite, in_range))
}

/// [`measure`] with a progress bar on long tracks; a track refused for want of a period
/// leaves [`figures::refusal_figure`] behind.
fn measure_or_show_why(
    a: &TrackArgs,
    (frames, down, across): (&[f64], &[f64], &[f64]),
    inputs: &Inputs,
) -> Result<(CleanTrack, PeriodFit)> {
    let bar = if frames.len() > 100_000 && std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        indicatif::ProgressBar::new(
            crate::analysis::experiment::tracking::period::SURROGATES as u64,
        )
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_message("surrogate tracks (the chance level)");
    let measured = measure(frames, down, across, &|done, _| {
        bar.set_position(done as u64);
    });
    bar.finish_and_clear();
    match measured {
        Ok(m) => Ok(m),
        Err(e) => {
            if let Some(shown) = refusal_figure(a, (frames, down, across), &e, inputs)? {
                eprintln!("note: {shown}");
            }
            Err(anyhow::Error::new(e).context(format!("track {}", a.file.display())))
        }
    }
}

/// The predicted orbit drawn over the folded track: the orbit, cm per ⟨r⟩, frames per t0, the
/// phase (path sample) it starts at, and whether it is mirrored across the ramp.
type Drawn = (PredictedOrbit, f64, f64, usize, bool);

/// The model's prediction for `body` against the measured `fit` (the core's
/// [`compare_with_model`]), and the path aligned with the folded track.
fn compare(
    path: &Path,
    body: &crate::geometry::Body,
    (scale_mm, alpha): (f64, f64),
    mass: Option<f64>,
    fit: &PeriodFit,
    folded: &[Folded],
    fps: f64,
) -> Result<(Comparison, Drawn)> {
    let measured = Measured {
        period_s: fit.period_frames / fps,
        advance_down_cm: fit.advance_down,
        advance_across_cm: fit.advance_across,
    };
    let c = compare_with_model(
        body,
        scale_mm,
        alpha,
        &measured,
        mass,
        &PredictOptions::default(),
    )
    .with_context(|| format!("the model for {}", path.display()))?
    .with_period_error(measured.period_s, fit.period_error_frames / fps);
    let cm = scale_mm / 10.0;
    let alignment = c.aligned_with(folded, fps);
    let drawn = (
        c.orbit.clone(),
        cm,
        c.t0_s * fps,
        alignment.phase,
        alignment.mirrored_across,
    );
    Ok((
        Comparison {
            body: path.display().to_string(),
            alignment,
            comparison: c,
        },
        drawn,
    ))
}

/// The request for a table from the flags; `fps` turns a time column into frames (the markers
/// take the centre's rate).
fn table_request(a: &TrackArgs, fps: Option<f64>) -> TableRequest {
    TableRequest {
        format: a.format.as_deref().and_then(TableFormat::named),
        frame_column: a.frame_column.clone(),
        time_column: a.time_column.clone(),
        across_column: a.across_column.clone(),
        down_column: a.down_column.clone(),
        fps,
        time_origin: None,
        particle: a.particle,
        every_particle: false,
    }
}

/// The table at `path` ([`read_table`]): a regular file, its errors named by it.
fn read_track_table(path: &Path, request: &TableRequest) -> Result<TrackTable> {
    let meta =
        std::fs::metadata(path).with_context(|| format!("cannot read {}", path.display()))?;
    if !meta.is_file() {
        bail!(
            "{} is not a regular file (a device, FIFO or folder): give the track's CSV file",
            path.display()
        );
    }
    let file =
        std::fs::File::open(path).with_context(|| format!("cannot read {}", path.display()))?;
    read_table(std::io::BufReader::new(file), request, MAX_ROWS)
        .with_context(|| format!("{}", path.display()))
}

/// data.csv: every centre and marker point with its period and local coordinates.
fn data_csv(
    centre: &[Folded],
    track: &CleanTrack,
    markers: &[Folded],
    marker_points: &[(f64, f64, f64)],
    fps: f64,
) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "kind",
        "frame",
        "t_s",
        "down_cm",
        "across_cm",
        "period",
        "t_local_s",
        "down_local_cm",
        "across_local_cm",
    ])?;
    let mut row = |kind: &str, (f, d, a): (f64, f64, f64), x: &Folded| {
        w.write_record([
            kind.to_string(),
            f.to_string(),
            (f / fps).to_string(),
            d.to_string(),
            a.to_string(),
            x.period.to_string(),
            (x.t_local / fps).to_string(),
            x.down_local.to_string(),
            x.across_local.to_string(),
        ])
    };
    for (i, x) in centre.iter().enumerate() {
        row(
            "centre",
            (track.frames[i], track.down[i], track.across[i]),
            x,
        )?;
    }
    for (m, x) in marker_points.iter().zip(markers) {
        row("marker", *m, x)?;
    }
    Ok(String::from_utf8(w.into_inner()?)?)
}
