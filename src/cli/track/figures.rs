//! `track`'s pictures: figure.png (the track and its cycles, the folded coordinates with the
//! markers coloured by period, the model's path beside them) and, where no period is stated,
//! refused.png (the track less its drift and its mismatch at every shift, the evidence of why).

use anyhow::Result;

use super::{Drawn, REFUSAL_FIGURE, TrackArgs};
use crate::analysis::experiment::tracking::{CleanTrack, Folded, PeriodFit};
use crate::chart::{PALETTE, Panel, Series, SeriesLabelPosition, Style};
use crate::output::{self, Inputs, OutputSet};

/// Where a track is refused for want of a period (none with confidence, too fast, mostly
/// unsteady), the evidence the user needs to see why: OUT/refused.png with the track less its
/// mean drift and the normalised mismatch d′ at every shift against the level a repeat needs.
/// A file of its own name, so that it never sits beside a different run's summary.json as if
/// it were that run's. Returns the sentence that names it; `None` for other errors.
pub(super) fn refusal_figure(
    a: &TrackArgs,
    (frames, down, across): (&[f64], &[f64], &[f64]),
    error: &crate::analysis::experiment::tracking::TrackError,
    inputs: &Inputs,
) -> Result<Option<String>> {
    use crate::analysis::experiment::tracking::TrackError;
    if !matches!(
        error,
        TrackError::NoPeriod { .. }
            | TrackError::TooFast { .. }
            | TrackError::MostlyUnsteady { .. }
    ) {
        return Ok(None);
    }
    let Ok(track) = crate::analysis::experiment::tracking::clean(frames, down, across) else {
        return Ok(None);
    };
    // The middle 80 %, as the search first reads it (away from the release and the end).
    let len = track.frames.len();
    let middle = CleanTrack {
        frames: track.frames[len / 10..len - len / 10].to_vec(),
        down: track.down[len / 10..len - len / 10].to_vec(),
        across: track.across[len / 10..len - len / 10].to_vec(),
        warnings: Vec::new(),
    };
    let curve = crate::analysis::experiment::tracking::period::mismatch_curve(&middle);
    if curve.is_empty() {
        return Ok(None);
    }
    let n = track.frames.len();
    let (f0, f1) = (track.frames[0], track.frames[n - 1]);
    let drift = |v: &[f64]| (v[n - 1] - v[0]) / (f1 - f0).max(1.0);
    let (dd, da) = (drift(&track.down), drift(&track.across));
    let step = n.div_ceil(20_000).max(1);
    let less_drift = |v: &[f64], rate: f64| -> Vec<(f64, f64)> {
        (0..n)
            .step_by(step)
            .map(|i| (track.frames[i], v[i] - v[0] - rate * (track.frames[i] - f0)))
            .collect()
    };
    let series = |label: &str, points, color, style| Series {
        label: label.into(),
        points,
        color,
        style,
    };
    let track_panel = Panel {
        title: "the track, less its mean drift".into(),
        x_label: "frame".into(),
        y_label: "cm".into(),
        log_x: false,
        log_y: false,
        series: vec![
            series("down", less_drift(&track.down, dd), PALETTE[0], Style::Line),
            series(
                "across",
                less_drift(&track.across, da),
                PALETTE[1],
                Style::Line,
            ),
        ],
        legend: SeriesLabelPosition::UpperRight,
        equal_aspect: false,
    };
    let last = curve[curve.len() - 1][0];
    let level = crate::analysis::experiment::tracking::period::MAX_NORMALISED_DIP;
    let mismatch_panel = Panel {
        title: format!("refused: {}", first_words(&error.to_string(), 12)),
        x_label: "shift (frames), over the middle 80 % of the track, as the search first reads it"
            .into(),
        y_label: "normalised mismatch d′".into(),
        log_x: false,
        log_y: false,
        series: vec![
            series(
                "d′ at every shift",
                curve
                    .iter()
                    .step_by(curve.len().div_ceil(20_000).max(1))
                    .map(|c| (c[0], c[1]))
                    .collect(),
                PALETTE[0],
                Style::Line,
            ),
            series(
                "a repeat needs d′ below this",
                vec![(1.0, level), (last, level)],
                (0, 0, 0),
                Style::Line,
            ),
        ],
        legend: SeriesLabelPosition::UpperRight,
        equal_aspect: false,
    };
    let png = crate::chart::png_bytes(&[track_panel, mismatch_panel], 1, (1200, 1000))?;
    let path = a.out.join(REFUSAL_FIGURE);
    output::create_folder(&a.out)?;
    let mut set = OutputSet::new();
    set.write(&path, &png, inputs)?;
    set.commit()?;
    Ok(Some(format!(
        "wrote {} (the track and its mismatch at every shift) to show why no period is stated",
        path.display()
    )))
}

/// The first `n` words of `text`, with "…" if it had more.
fn first_words(text: &str, n: usize) -> String {
    let words: Vec<&str> = text.split_whitespace().collect();
    if words.len() <= n {
        text.to_string()
    } else {
        words[..n].join(" ") + " …"
    }
}

/// Most periods drawn over each other in the folded panels.
const MAX_DRAWN_PERIODS: usize = 200;
/// Most points a line of the figure is drawn with (the picture is 1400 pixels wide).
const MAX_DRAWN_POINTS: usize = 20_000;

/// Every k-th point, so that at most [`MAX_DRAWN_POINTS`] are drawn.
fn thinned<T>(points: &[T]) -> impl Iterator<Item = &T> {
    points
        .iter()
        .step_by(points.len().div_ceil(MAX_DRAWN_POINTS).max(1))
}

/// The curve in at most [`MAX_DRAWN_POINTS`] points: each run of points by its lowest and its
/// highest, in order, so that no dip (the evidence) is thinned away.
fn lowest_and_highest(curve: &[[f64; 2]]) -> impl Iterator<Item = &[f64; 2]> {
    let run = curve.len().div_ceil(MAX_DRAWN_POINTS / 2).max(1);
    curve.chunks(run).flat_map(|c| {
        let low = c.iter().min_by(|a, b| a[1].total_cmp(&b[1]));
        let high = c.iter().max_by(|a, b| a[1].total_cmp(&b[1]));
        match (low, high) {
            (Some(l), Some(h)) if l[0] <= h[0] => vec![l, h],
            (Some(l), Some(h)) => vec![h, l],
            _ => vec![],
        }
    })
}

#[expect(
    clippy::too_many_lines,
    reason = "four panels (the track and its cycles, the two folded coordinates with the markers \
              and the prediction, the period's evidence), each a handful of series"
)]
pub(super) fn figure(
    fit: &PeriodFit,
    centre: &[Folded],
    markers: &[Folded],
    a: &TrackArgs,
    predicted: Option<&Drawn>,
) -> Vec<Panel> {
    let fps = a.rate;
    let grey = (150, 150, 150);
    let (blue, red) = ((31, 119, 180), (214, 39, 40));
    let periods = centre.iter().map(|f| f.period).max().unwrap_or(0) + 1;
    // Each period's points in one pass (a long track has tens of thousands of periods), and at
    // most MAX_DRAWN_PERIODS of them drawn, evenly chosen: more only darken the same band.
    let mut by_period: Vec<Vec<&Folded>> = vec![Vec::new(); periods];
    for f in centre {
        by_period[f.period].push(f);
    }
    let drawn: Vec<usize> = if periods <= MAX_DRAWN_PERIODS {
        (0..periods).collect()
    } else {
        (0..MAX_DRAWN_PERIODS)
            .map(|i| i * periods / MAX_DRAWN_PERIODS)
            .collect()
    };
    let centre_label = if drawn.len() == periods {
        "centre, each period".to_string()
    } else {
        format!("centre, {} of {periods} periods", drawn.len())
    };
    let per_period = |k: usize, coord: fn(&Folded) -> f64| Series {
        label: if k == drawn[0] {
            centre_label.clone()
        } else {
            String::new()
        },
        points: by_period[k]
            .iter()
            .map(|f| (f.t_local / fps, coord(f)))
            .collect(),
        color: grey,
        style: Style::Line,
    };
    let marker_series = |even: bool, coord: fn(&Folded) -> f64| Series {
        label: if even {
            "markers, even periods".into()
        } else {
            "markers, odd periods".into()
        },
        points: markers
            .iter()
            .filter(|f| (f.period % 2 == 0) == even)
            .map(|f| (f.t_local / fps, coord(f)))
            .collect(),
        color: if even { blue } else { red },
        style: Style::Markers,
    };
    let model_series = |k: usize| -> Option<Series> {
        let (orbit, cm, frames_per_t0, phase, mirrored) = predicted?;
        let per = (orbit.path.len() - 1) / 3;
        let sign = if k == 1 && *mirrored { -1.0 } else { 1.0 };
        let dt = orbit.period * frames_per_t0 / per as f64 / fps;
        let points = (0..=per + per / 10)
            .filter(|j| phase + j < orbit.path.len())
            .map(|j| {
                (
                    j as f64 * dt,
                    sign * cm * (orbit.path[phase + j][k] - orbit.path[*phase][k]),
                )
            })
            .collect();
        Some(Series {
            label: "model (offset free)".into(),
            points,
            color: (0, 0, 0),
            style: Style::Line,
        })
    };
    let folded_panel = |title: &str, y: &str, coord: fn(&Folded) -> f64, k: usize| {
        let mut series: Vec<Series> = drawn.iter().map(|&p| per_period(p, coord)).collect();
        if !markers.is_empty() {
            series.push(marker_series(true, coord));
            series.push(marker_series(false, coord));
        }
        series.extend(model_series(k));
        Panel {
            title: title.into(),
            x_label: "t local (s)".into(),
            y_label: y.into(),
            log_x: false,
            log_y: false,
            series,
            legend: SeriesLabelPosition::UpperLeft,
            equal_aspect: false,
        }
    };
    let starts: Vec<(f64, f64)> = centre
        .windows(2)
        .filter(|w| w[1].period != w[0].period)
        .map(|w| {
            (
                w[1].t_local / fps + (w[1].period as f64 * fit.period_frames) / fps,
                w[1].down_local + w[1].period as f64 * fit.advance_down,
            )
        })
        .collect();
    // A marker a period, at most a thousand of them.
    let starts: Vec<(f64, f64)> = starts
        .iter()
        .step_by(starts.len().div_ceil(1000).max(1))
        .copied()
        .collect();
    let global = Panel {
        title: format!(
            "the track: {} periods of {:.3} s",
            fit.periods_seen,
            fit.period_frames / fps
        ),
        x_label: "t from the first frame used (s)".into(),
        y_label: "down the ramp (cm)".into(),
        log_x: false,
        log_y: false,
        series: vec![
            Series {
                label: "centre".into(),
                points: thinned(centre)
                    .map(|f| {
                        (
                            (f.t_local + f.period as f64 * fit.period_frames) / fps,
                            f.down_local + f.period as f64 * fit.advance_down,
                        )
                    })
                    .collect(),
                color: grey,
                style: Style::Line,
            },
            Series {
                label: "start of each period".into(),
                points: starts,
                color: red,
                style: Style::Markers,
            },
        ],
        legend: SeriesLabelPosition::UpperLeft,
        equal_aspect: false,
    };
    let evidence = Panel {
        title: "how well the track repeats after a shift".into(),
        x_label: "shift (s)".into(),
        y_label: "unexplained fraction".into(),
        log_x: false,
        log_y: false,
        series: vec![
            Series {
                label: "mismatch".into(),
                points: lowest_and_highest(&fit.mismatch_curve)
                    .map(|c| (c[0] / fps, c[1]))
                    .collect(),
                color: blue,
                style: Style::Line,
            },
            Series {
                label: format!("period {:.3} s", fit.period_frames / fps),
                points: vec![(fit.period_frames / fps, fit.mismatch)],
                color: red,
                style: Style::Markers,
            },
        ],
        legend: SeriesLabelPosition::UpperRight,
        equal_aspect: false,
    };
    vec![
        global,
        evidence,
        folded_panel(
            "folded: down the ramp (Fig. 5c)",
            "x local, down the ramp (cm)",
            |f| f.down_local,
            0,
        ),
        folded_panel(
            "folded: across the ramp",
            "y local, across the ramp (cm)",
            |f| f.across_local,
            1,
        ),
    ]
}
