//! A tracked run's table as the trackers write it, read into (frame, across, down) rows in the
//! file's own units (the command line scales them to cm):
//!
//! - **plain**: a header row, then a row per frame (the paper authors' files: `frame`, `xn`
//!   across, `yn` down);
//! - **Tracker** (the physics-teaching video tool, its Export → Data File): a title line with
//!   the track's name (`mass A`) above a header of `t` (s), `x`, `y` (its calibration's units),
//!   in tab-, comma-, semicolon- or space-separated columns, with decimal commas where its locale
//!   writes them (`0,0333`). Tracker's incline tutorials turn the axes so that x runs down the
//!   ramp, hence x down and y across by default. Frames are t × fps, the frame rate read from
//!   the time steps unless given, and every t must then fall on a whole frame;
//! - **trackpy** (its `link` output saved by pandas): `frame`, `particle`, `x`, `y` (pixels) and
//!   more, a row per detection of every particle, perhaps after an unnamed index column. One
//!   particle is read (the only one, or the one named), sorted by frame.
//!
//! The format is told from the file (title lines above a header with `t`: Tracker; `frame` and
//! `particle` columns: trackpy; else plain) unless it is named. Hand-written rather than the
//! `csv` crate alone: that reads one known delimiter and one header row, where these files need
//! the delimiter and the header found below title lines, and decimal commas read.

use std::collections::BTreeMap;
use std::io::BufRead;

use serde::Serialize;
use thiserror::Error;

/// Which tracker wrote a table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum TableFormat {
    /// A header row and a row per frame (the paper authors' files).
    Plain,
    /// Tracker's data export: title lines, then `t`, `x`, `y`.
    Tracker,
    /// trackpy's linked table: `frame`, `particle`, `x`, `y`.
    Trackpy,
}

impl TableFormat {
    /// Every format, in the order `--format` lists them.
    pub const ALL: [TableFormat; 3] = [Self::Plain, Self::Tracker, Self::Trackpy];

    /// The format's name on the command line and in summaries.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::table::TableFormat;
    /// assert_eq!(TableFormat::Tracker.name(), "tracker");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Self::Plain => "plain",
            Self::Tracker => "tracker",
            Self::Trackpy => "trackpy",
        }
    }

    /// The format named `name`, if any.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::table::TableFormat;
    /// assert_eq!(TableFormat::named("trackpy"), Some(TableFormat::Trackpy));
    /// assert_eq!(TableFormat::named("excel"), None);
    /// ```
    pub fn named(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

    /// The columns read when none is named: (frame or time, across, down), and whether the
    /// first is a time in seconds.
    fn default_columns(self) -> (&'static str, bool, &'static str, &'static str) {
        match self {
            Self::Plain => ("frame", false, "xn", "yn"),
            Self::Tracker => ("t", true, "y", "x"),
            Self::Trackpy => ("frame", false, "y", "x"),
        }
    }

    /// Whether its coordinates are in units only the user knows (Tracker's calibration,
    /// trackpy's pixels), so that a scale to cm must be given.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::analysis::experiment::tracking::table::TableFormat;
    /// assert!(TableFormat::Tracker.needs_scale() && !TableFormat::Plain.needs_scale());
    /// ```
    pub fn needs_scale(self) -> bool {
        self != Self::Plain
    }
}

/// What to read from a table; `None` takes the format's default.
#[derive(Clone, Debug, Default)]
pub struct TableRequest {
    /// The format, or `None` to tell it from the file.
    pub format: Option<TableFormat>,
    /// The frame-number column.
    pub frame_column: Option<String>,
    /// A time column in seconds, read as frames at the frame rate (instead of a frame column).
    pub time_column: Option<String>,
    /// The across-the-ramp column.
    pub across_column: Option<String>,
    /// The down-the-ramp column.
    pub down_column: Option<String>,
    /// Frames per second, to turn times into frames; `None` reads it from the time steps.
    pub fps: Option<f64>,
    /// The time (s) of frame 0 where a time column is read; `None` takes the table's first
    /// time (markers take their track's, so that both count frames from one instant).
    pub time_origin: Option<f64>,
    /// trackpy: the particle to read.
    pub particle: Option<f64>,
    /// Read every particle's rows (markers: each detection is its own particle).
    pub every_particle: bool,
}

/// A table read: (frame, across, down) rows in the file's units.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrackTable {
    /// The format it was read as.
    pub format: TableFormat,
    /// (frame, across, down) per row; an empty cell or `nan` is NaN.
    #[serde(skip)]
    pub rows: Vec<[f64; 3]>,
    /// The columns read: frame (or time), across, down.
    pub columns: [String; 3],
    /// The frame rate read from the time column's steps, where it was not given.
    pub fps_from_times: Option<f64>,
    /// The time (s) of frame 0, where a time column was read.
    pub time_origin: Option<f64>,
    /// What was done that the user should know (rows of other particles left out, sorting).
    pub notes: Vec<String>,
}

/// Why a table cannot be read.
#[derive(Debug, Error, PartialEq)]
pub enum TableError {
    /// No header and numeric rows below it.
    #[error("{0}")]
    Layout(String),
    /// A column that is not there.
    #[error(
        "has no column {name:?} (its columns: {columns}); name the columns with \
         --frame-column (or --time-column), --across-column, --down-column{hint}"
    )]
    MissingColumn {
        /// The column asked for.
        name: String,
        /// The header's columns, quoted.
        columns: String,
        /// What else might be meant.
        hint: String,
    },
    /// A cell that is not a number.
    #[error("row {row}, column {column:?} (line {line}): {cell:?} is not a number")]
    NotNumber {
        /// The data row (1 = the first under the header).
        row: usize,
        /// The file's line.
        line: usize,
        /// The column.
        column: String,
        /// The cell.
        cell: String,
    },
    /// Anything else, said in full.
    #[error("{0}")]
    Other(String),
}

/// Lines read above the first numeric row before the table is called headerless.
const MAX_PREAMBLE_LINES: usize = 50;

/// The delimiters tried, in order of preference when they split a row alike (`None`: runs of
/// spaces and tabs).
const DELIMITERS: [Option<char>; 4] = [Some(','), Some('\t'), Some(';'), None];

/// A line's fields under `delimiter`, trimmed and unquoted.
fn fields(line: &str, delimiter: Option<char>) -> Vec<&str> {
    fn unquote(f: &str) -> &str {
        let f = f.trim();
        f.strip_prefix('"')
            .and_then(|g| g.strip_suffix('"'))
            .unwrap_or(f)
    }
    match delimiter {
        Some(d) => line.split(d).map(unquote).collect(),
        None => line.split_whitespace().map(unquote).collect(),
    }
}

/// A cell as a number: empty or `nan` is NaN; a decimal comma is read where commas do not
/// delimit. `None` if it is text.
fn number(cell: &str, delimiter: Option<char>) -> Option<f64> {
    if cell.is_empty() || cell.eq_ignore_ascii_case("nan") {
        return Some(f64::NAN);
    }
    if let Ok(v) = cell.parse::<f64>() {
        return Some(v);
    }
    if delimiter != Some(',') && cell.matches(',').count() == 1 && !cell.contains('.') {
        return cell.replace(',', ".").parse().ok();
    }
    None
}

/// Whether a cell holds a number (not an empty cell or `nan`).
fn holds_number(cell: &str, delimiter: Option<char>) -> bool {
    number(cell, delimiter).is_some_and(|v| !v.is_nan())
}

/// Whether a line's fields look like a data row: two or more, one of them a number (a cell of
/// text in a number's place is an error named when the row is read, not a second header).
fn is_data(cells: &[&str], delimiter: Option<char>) -> bool {
    cells.len() >= 2 && cells.iter().any(|c| holds_number(c, delimiter))
}

/// The layout found: the delimiter, the header's fields, the title lines above it and the line
/// number of the first data row.
struct Layout {
    delimiter: Option<char>,
    header: Vec<String>,
    titles: Vec<String>,
}

/// Finds the header (the last line above the first data row) and the delimiter that splits it
/// and the data row alike into the most fields.
fn layout(preamble: &[String], first_data: &str) -> Option<Layout> {
    let header_line = preamble.iter().rposition(|l| !l.trim().is_empty())?;
    let best = DELIMITERS
        .into_iter()
        .filter(|&d| {
            let data = fields(first_data, d);
            let header = fields(&preamble[header_line], d);
            // A header names its columns: a row with numbers above is data, not a header.
            is_data(&data, d)
                && header.len() == data.len()
                && !header.iter().any(|h| holds_number(h, d))
        })
        .max_by_key(|&d| {
            // The first listed wins a tie: max_by_key keeps the last maximum, so rank by order.
            let rank = DELIMITERS.iter().position(|&x| x == d).unwrap_or(0);
            (fields(first_data, d).len(), usize::MAX - rank)
        })?;
    Some(Layout {
        delimiter: best,
        header: fields(&preamble[header_line], best)
            .into_iter()
            .map(str::to_string)
            .collect(),
        titles: preamble[..header_line]
            .iter()
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.trim().to_string())
            .collect(),
    })
}

/// The columns a request reads from a table: their indices (frame or time, across, down), the
/// particle column's in trackpy's, their names, and whether the first is a time.
struct Columns {
    wanted: [usize; 3],
    particle: Option<usize>,
    names: [String; 3],
    is_time: bool,
}

/// The request's columns found in `header` (a table of `format`), each named once, and its
/// particle a particle number that the format has.
fn columns(
    format: TableFormat,
    header: &[String],
    request: &TableRequest,
) -> Result<Columns, TableError> {
    let has = |name: &str| header.iter().any(|h| h == name);
    let (default_first, default_is_time, default_across, default_down) = format.default_columns();
    let (first, is_time) = match (&request.time_column, &request.frame_column) {
        (Some(t), _) => (t.clone(), true),
        (None, Some(f)) => (f.clone(), false),
        (None, None) => (default_first.to_string(), default_is_time),
    };
    let across = request
        .across_column
        .clone()
        .unwrap_or(default_across.into());
    let down = request.down_column.clone().unwrap_or(default_down.into());
    let column = |name: &str| {
        let times = header.iter().filter(|h| *h == name).count();
        if times > 1 {
            return Err(TableError::Other(format!(
                "has {times} columns named {name:?}: a table of several tracks (Tracker's \
                 #multi export) or objects; export the body's track alone, or name another \
                 column"
            )));
        }
        header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| TableError::MissingColumn {
                name: name.to_string(),
                columns: header
                    .iter()
                    .map(|h| format!("{h:?}"))
                    .collect::<Vec<_>>()
                    .join(", "),
                hint: if !is_time && name == first && has("t") && has("x") && has("y") {
                    "; a table of t, x, y is Tracker's export (read as such with --format \
                     tracker, or its title line kept)"
                        .into()
                } else if !is_time && name == first && has("t") {
                    "; its \"t\" column (seconds) can stand for the frames: --time-column t".into()
                } else {
                    String::new()
                },
            })
    };
    for (a, b) in [(&first, &across), (&first, &down), (&across, &down)] {
        if a == b {
            return Err(TableError::Other(format!(
                "would read column {a:?} twice (frame or time, across and down are three \
                 different columns)"
            )));
        }
    }
    if let Some(p) = request.particle
        && !(p.is_finite() && p.fract() == 0.0 && p.abs() < 1e15)
    {
        return Err(TableError::Other(format!(
            "particle {} is not a particle number (trackpy numbers them 0, 1, 2, …)",
            if p.abs() < 1e15 {
                p.to_string()
            } else {
                format!("{p:e}")
            }
        )));
    }
    let wanted = [column(&first)?, column(&across)?, column(&down)?];
    let particle = if format == TableFormat::Trackpy {
        Some(column("particle")?)
    } else if request.particle.is_some() {
        return Err(TableError::Other(format!(
            "is a {} table: a particle is picked only in trackpy's (--format trackpy)",
            format.name()
        )));
    } else {
        None
    };
    Ok(Columns {
        wanted,
        particle,
        names: [first, across, down],
        is_time,
    })
}

/// Reads a tracked run's table (see the module doc) from `source`, at most `max_rows` rows.
///
/// # Example
/// ```
/// use rollphase_core::analysis::experiment::tracking::table::{
///     TableFormat, TableRequest, read_table,
/// };
/// // Tracker's export in a German locale: a title line, tabs, decimal commas, t in seconds.
/// let text = "mass A\nt\tx\ty\n0,0\t0,10\t0,02\n0,04\t0,11\t0,02\n0,08\t0,12\t0,03\n";
/// let table = read_table(text.as_bytes(), &TableRequest::default(), 1000)?;
/// assert_eq!(table.format, TableFormat::Tracker);
/// assert_eq!(table.fps_from_times, Some(25.0));
/// // (frame, across = y, down = x)
/// assert_eq!(table.rows[2], [2.0, 0.03, 0.12]);
/// # Ok::<(), rollphase_core::analysis::experiment::tracking::table::TableError>(())
/// ```
pub fn read_table(
    mut source: impl BufRead,
    request: &TableRequest,
    max_rows: usize,
) -> Result<TrackTable, TableError> {
    let start = source
        .fill_buf()
        .map_err(|e| TableError::Other(format!("cannot be read: {e}")))?;
    if start.starts_with(&[0xFF, 0xFE]) || start.starts_with(&[0xFE, 0xFF]) {
        return Err(TableError::Other(
            "is UTF-16 text (as a spreadsheet's \"Unicode text\" saves it): save it as CSV in \
             UTF-8"
                .into(),
        ));
    }
    let unreadable = |line: usize, e: std::io::Error| {
        TableError::Other(if e.kind() == std::io::ErrorKind::InvalidData {
            format!(
                "line {line} is not UTF-8 text (Latin-1 or Windows-1252, perhaps): save the file \
                 as UTF-8"
            )
        } else {
            format!("cannot be read at line {line}: {e}")
        })
    };
    let mut lines = source.lines().enumerate();
    let mut preamble = Vec::new();
    let (found, first_line) = loop {
        let Some((i, line)) = lines.next() else {
            return Err(TableError::Layout(
                "holds no row of numbers under a header row".into(),
            ));
        };
        let mut line = line.map_err(|e| unreadable(i + 1, e))?;
        if line.trim_end_matches('\r').contains('\r') {
            return Err(TableError::Other(format!(
                "line {} holds carriage returns inside it: old Mac line ends (CR alone); save the \
                 file with LF or CRLF line ends",
                i + 1
            )));
        }
        if i == 0 {
            // The byte-order mark spreadsheets write first is not part of the first column's name.
            line = line.trim_start_matches('\u{feff}').to_string();
        }
        if let Some(found) = layout(&preamble, &line) {
            break (found, (i + 1, line));
        }
        if preamble.len() >= MAX_PREAMBLE_LINES {
            return Err(TableError::Layout(format!(
                "has no header row followed by rows of numbers in its first {MAX_PREAMBLE_LINES} \
                 lines (a track is a header row, such as frame,xn,yn, then a row per frame)"
            )));
        }
        preamble.push(line);
    };
    let Layout {
        delimiter,
        header,
        titles,
    } = found;
    let has = |name: &str| header.iter().any(|h| h == name);
    let format = request
        .format
        .unwrap_or(if has("frame") && has("particle") {
            TableFormat::Trackpy
        } else if !titles.is_empty() && has("t") {
            TableFormat::Tracker
        } else {
            TableFormat::Plain
        });
    let Columns {
        wanted,
        particle,
        names: [first, across, down],
        is_time,
    } = columns(format, &header, request)?;
    let names = [first.as_str(), across.as_str(), down.as_str()];
    let mut rows = Vec::new();
    let mut particles = Vec::new();
    let mut read_row = |line_no: usize, line: &str| -> Result<(), TableError> {
        if line.trim().is_empty() {
            return Ok(());
        }
        if rows.len() >= max_rows {
            return Err(TableError::Other(format!("has more than {max_rows} rows")));
        }
        let cells = fields(line, delimiter);
        if cells.len() > header.len() {
            return Err(TableError::Other(format!(
                "line {line_no} has {} cells where the header has {} columns",
                cells.len(),
                header.len()
            )));
        }
        let cell = |i: usize| cells.get(i).copied().unwrap_or("");
        let value = |i: usize, name: &str| {
            number(cell(i), delimiter).ok_or_else(|| TableError::NotNumber {
                row: rows.len() + 1,
                line: line_no,
                column: name.to_string(),
                cell: cell(i).to_string(),
            })
        };
        let mut row = [0.0; 3];
        for k in 0..3 {
            row[k] = value(wanted[k], names[k])?;
        }
        if let Some(p) = particle {
            particles.push(value(p, "particle")?);
        }
        rows.push(row);
        Ok(())
    };
    read_row(first_line.0, &first_line.1)?;
    for (i, line) in lines {
        let line = line.map_err(|e| unreadable(i + 1, e))?;
        read_row(i + 1, &line)?;
    }
    let mut notes = Vec::new();
    if particle.is_some() {
        rows = one_particle(rows, &particles, request, &mut notes)?;
    }
    let (fps_from_times, time_origin) = if is_time {
        let (rate, origin) = times_as_frames(&mut rows, request.fps, request.time_origin, &first)?;
        (rate, Some(origin))
    } else {
        (None, None)
    };
    Ok(TrackTable {
        format,
        rows,
        columns: [first, across, down],
        fps_from_times,
        time_origin,
        notes,
    })
}

/// trackpy's rows of the one particle asked for (or the only one), sorted by frame; every row
/// when `every_particle`.
fn one_particle(
    rows: Vec<[f64; 3]>,
    particles: &[f64],
    request: &TableRequest,
    notes: &mut Vec<String>,
) -> Result<Vec<[f64; 3]>, TableError> {
    let mut counts: BTreeMap<i64, usize> = BTreeMap::new();
    for p in particles {
        if !(p.is_finite() && p.fract() == 0.0 && p.abs() < 1e15) {
            return Err(TableError::Other(format!(
                "its particle column holds {p}, which is not a particle number"
            )));
        }
        *counts.entry(*p as i64).or_default() += 1;
    }
    let listed = || {
        let mut by_rows: Vec<(i64, usize)> = counts.iter().map(|(&p, &n)| (p, n)).collect();
        by_rows.sort_by_key(|&(p, n)| (std::cmp::Reverse(n), p));
        let shown: Vec<String> = by_rows
            .iter()
            .take(8)
            .map(|(p, n)| format!("{p}: {n} rows"))
            .collect();
        let more = by_rows.len().saturating_sub(8);
        format!(
            "{}{}",
            shown.join(", "),
            if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            }
        )
    };
    let chosen = if request.every_particle {
        None
    } else if let Some(p) = request.particle {
        if !counts.contains_key(&(p as i64)) || p.fract() != 0.0 {
            return Err(TableError::Other(format!(
                "has no particle {p} (its particles: {})",
                listed()
            )));
        }
        Some(p)
    } else if counts.len() > 1 {
        return Err(TableError::Other(format!(
            "holds {} particles ({}): pick the body's centre with --particle",
            counts.len(),
            listed()
        )));
    } else {
        None
    };
    let mut kept: Vec<[f64; 3]> = rows
        .into_iter()
        .zip(particles)
        .filter(|(_, p)| chosen.is_none_or(|c| **p == c))
        .map(|(r, _)| r)
        .collect();
    if let Some(c) = chosen
        && counts.len() > 1
    {
        notes.push(format!(
            "particle {c} read ({} rows); the other {} particles' rows left out",
            kept.len(),
            counts.len() - 1
        ));
    }
    if !kept.is_sorted_by(|a, b| a[0] <= b[0]) {
        kept.sort_by(|a, b| a[0].total_cmp(&b[0]));
        notes.push("rows sorted by frame".into());
    }
    Ok(kept)
}

/// How far from a whole frame a time may fall (in frames) and still be that frame.
const FRAME_TOLERANCE: f64 = 0.05;

/// The first column's times (s) turned into frame numbers counted from `origin` (by default
/// the first time: a clip's start time is no frame), at `fps` or, where it is `None`, at the
/// rate read from the steps. Every time must fall on a whole frame. Returns the rate read and
/// the origin.
fn times_as_frames(
    rows: &mut [[f64; 3]],
    fps: Option<f64>,
    origin: Option<f64>,
    column: &str,
) -> Result<(Option<f64>, f64), TableError> {
    let times: Vec<f64> = rows
        .iter()
        .map(|r| r[0])
        .filter(|t| t.is_finite())
        .collect();
    let (rate, read) = match fps {
        Some(f) => (f, None),
        None => {
            let steps: Vec<f64> = times
                .windows(2)
                .map(|w| w[1] - w[0])
                .filter(|d| *d > 0.0)
                .collect();
            if steps.is_empty() {
                return Err(TableError::Other(format!(
                    "its time column {column:?} has no two increasing times to read the frame \
                     rate from (give --fps)"
                )));
            }
            let mut sorted = steps.clone();
            sorted.sort_by(f64::total_cmp);
            let median = sorted[sorted.len() / 2];
            // Each step as a whole number of median steps, the rate from their sum: times
            // written to 3 decimals (0.033, 0.067, …) give 30 frames/s, not 1/0.033.
            let (mut span, mut count) = (0.0, 0.0);
            for d in steps {
                let k = (d / median).round();
                if k >= 1.0 {
                    span += d;
                    count += k;
                }
            }
            let step = span / count;
            // The rate to 6 digits: 29.97 frames/s stays 29.97, not 29.970029970.
            let rate = format!("{:.6e}", 1.0 / step)
                .parse::<f64>()
                .unwrap_or(1.0 / step);
            (rate, Some(rate))
        }
    };
    let start = origin.unwrap_or_else(|| times.first().copied().unwrap_or(0.0));
    for (i, row) in rows.iter_mut().enumerate() {
        let f = (row[0] - start) * rate;
        if f.is_finite() && (f - f.round()).abs() > FRAME_TOLERANCE {
            return Err(TableError::Other(format!(
                "row {}: {column} = {} s is {f:.3} frames after {start} s at {rate} \
                 frames/s, not a whole frame (give the rate the times were taken at with --fps: \
                 the video's, or its own divided by the tracker's step size)",
                i + 1,
                row[0]
            )));
        }
        row[0] = f.round();
    }
    Ok((read, start))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str, request: &TableRequest) -> Result<TrackTable, TableError> {
        read_table(text.as_bytes(), request, 1000)
    }

    #[test]
    fn the_authors_plain_table_reads_frame_xn_yn() {
        // A spreadsheet's byte-order mark and quoted names are read past.
        let t = read(
            "\u{feff}\"frame\",xn,yn\n1,2,3\n2,,nan\n",
            &TableRequest::default(),
        )
        .unwrap();
        assert_eq!(t.format, TableFormat::Plain);
        assert_eq!(t.rows[0], [1.0, 2.0, 3.0]);
        assert!(t.rows[1][1].is_nan() && t.rows[1][2].is_nan());
    }

    #[test]
    fn trackers_export_reads_with_any_delimiter_and_decimal_commas() {
        for (d, decimal) in [
            (",", "."),
            ("\t", "."),
            ("\t", ","),
            (";", ","),
            ("  ", "."),
        ] {
            let n = |v: &str| v.replace('.', decimal);
            let text = format!(
                "mass A\nt{d}x{d}y\n{}{d}{}{d}{}\n{}{d}{}{d}{}\n",
                n("0.000"),
                n("1.5E-1"),
                n("0.02"),
                n("0.0333667"),
                n("1.6E-1"),
                n("0.02"),
            );
            let t = read(&text, &TableRequest::default()).unwrap();
            assert_eq!(t.format, TableFormat::Tracker, "{d:?} {decimal}");
            assert_eq!(t.fps_from_times, Some(29.97));
            assert_eq!(t.rows[1], [1.0, 0.02, 0.16], "{d:?} {decimal}");
        }
    }

    #[test]
    fn rounded_times_and_a_start_time_read_as_whole_frames() {
        // Tracker's formatted export: 3 decimals at 30 frames/s, from a clip start of 0.01 s.
        let mut text = String::from("mass A\nt,x,y\n");
        for k in 0..100 {
            text += &format!("{:.3},{k},0\n", 0.01 + f64::from(k) / 30.0);
        }
        let t = read(&text, &TableRequest::default()).unwrap();
        assert_eq!(t.fps_from_times, Some(30.0));
        assert!(t.rows.iter().enumerate().all(|(k, r)| r[0] == k as f64));
        let same = TableRequest {
            across_column: Some("x".into()),
            down_column: Some("x".into()),
            ..TableRequest::default()
        };
        assert!(
            read(&text, &same)
                .unwrap_err()
                .to_string()
                .contains("twice")
        );
        let odd = TableRequest {
            particle: Some(f64::NAN),
            ..TableRequest::default()
        };
        let e = read(&text, &odd).unwrap_err().to_string();
        assert!(e.contains("not a particle number"), "{e}");
    }

    #[test]
    fn a_time_off_the_frames_is_refused_with_the_rate() {
        let text = "mass A\nt,x,y\n0,0,0\n0.04,1,0\n0.1,2,0\n";
        let e = read(text, &TableRequest::default()).unwrap_err();
        assert!(e.to_string().contains("not a whole frame"), "{e}");
        let given = TableRequest {
            fps: Some(50.0),
            ..TableRequest::default()
        };
        assert_eq!(read(text, &given).unwrap().rows[2][0], 5.0);
    }

    #[test]
    fn trackpy_needs_one_particle_and_is_sorted_by_frame() {
        let text = ",y,x,mass,frame,particle\n0,5,1,9,1,7\n1,6,2,9,0,7\n2,0,0,1,0,3\n";
        let e = read(text, &TableRequest::default()).unwrap_err();
        assert!(e.to_string().contains("7: 2 rows, 3: 1 rows"), "{e}");
        let seven = TableRequest {
            particle: Some(7.0),
            ..TableRequest::default()
        };
        let t = read(text, &seven).unwrap();
        assert_eq!(t.format, TableFormat::Trackpy);
        assert_eq!(t.rows, vec![[0.0, 6.0, 2.0], [1.0, 5.0, 1.0]]);
        assert_eq!(t.notes.len(), 2);
        let missing = TableRequest {
            particle: Some(4.0),
            ..TableRequest::default()
        };
        assert!(read(text, &missing).is_err());
        let plain = read("frame,xn,yn\n1,2,3\n", &seven).unwrap_err();
        assert!(plain.to_string().contains("only in trackpy's"), "{plain}");
        let all = TableRequest {
            every_particle: true,
            ..TableRequest::default()
        };
        assert_eq!(read(text, &all).unwrap().rows.len(), 3);
    }

    #[test]
    fn hostile_tables_are_refused_by_name() {
        let r = TableRequest::default();
        for (text, needle) in [
            ("", "no row of numbers"),
            ("frame,xn,yn\n", "no row of numbers"),
            ("1,2,3\n4,5,6\n", "no row of numbers"),
            ("frame,xn,yn\n1,2,zero\n", "row 1, column \"yn\" (line 2)"),
            ("frame,xn,yn\n1,2,3\n1,2,3,4\n", "line 3 has 4 cells"),
            ("t,x,y\n1,0,0\n", "--format tracker"),
            ("t,x,z\n1,0,0\n", "--time-column t"),
            ("mass A\nt,x,y\n0,0,0\n0,1,0\n", "no two increasing times"),
            (
                "#multi:\nA,,B,\nt,x,y,x,y\n0,1,2,3,4\n",
                "2 columns named \"y\"",
            ),
        ] {
            let e = read(text, &r).unwrap_err().to_string();
            assert!(e.contains(needle), "{text:?}: {e}");
        }
        for (bytes, needle) in [
            (&b"\xff\xfef\x00r\x00"[..], "UTF-16"),
            (
                &b"frame,xn,yn\n1,2,3\n\xe9,2,3\n"[..],
                "line 3 is not UTF-8",
            ),
            (&b"frame,xn,yn\r1,2,3\r2,3,4\r"[..], "old Mac line ends"),
        ] {
            let e = read_table(bytes, &r, 1000).unwrap_err().to_string();
            assert!(e.contains(needle), "{e}");
        }
        let long = "frame,xn,yn\n".to_string() + &"1,2,3\n".repeat(1001);
        assert!(
            read(&long, &r)
                .unwrap_err()
                .to_string()
                .contains("more than 1000")
        );
    }
}
