//! `track`'s report for people: the period with its error and where the error comes from, how
//! the table was read, the evidence against chance, the advance and speed with their errors,
//! the markers' reading and the model beside it.

use anyhow::Result;

use super::{TrackArgs, TrackSummary};
use crate::analysis::experiment::tracking::ErrorSource;
use crate::analysis::experiment::tracking::table::TableFormat;

/// `value ± error` with two significant digits of the error and the value to the same place
/// (3 to 9 decimals), or the value to 3 decimals where no error is stated.
fn with_error(value: f64, error: Option<f64>) -> String {
    match error.filter(|e| e.is_finite() && *e > 0.0) {
        Some(e) => {
            // Two significant digits of the error need this many decimals; past 9 fixed
            // notation prints the error as zeros, so both go to scientific notation.
            let digits = 1 - e.log10().floor() as i32;
            if digits > 9 {
                format!("{value:.4e} ± {e:.1e}")
            } else {
                let digits = digits.max(3) as usize;
                format!("{value:.digits$} ± {e:.digits$}")
            }
        }
        None => format!("{value:.3}"),
    }
}

/// The measurement (and the model's) for people.
pub(super) fn print_summary(a: &TrackArgs, summary: &TrackSummary) -> Result<()> {
    let error_from = match summary.period_error_from {
        ErrorSource::Cycles if summary.block_check.is_some_and(|b| b.turns_vary) => {
            "from the cycles' spread: blocks of the track show its turns' times vary, so the \
             period is their mean"
        }
        ErrorSource::Cycles => "from the cycles' spread",
        ErrorSource::Harmonics => {
            "from a harmonic fit of the whole track, correlated residuals included"
        }
        ErrorSource::DipWidth => "from the dip's width: too few cycles for a spread",
    };
    // Two significant digits of the error, and the period to the same place.
    let digits = (1 - summary.period_error_s.log10().floor() as i32).clamp(3, 9) as usize;
    outln!(
        "{}: period {:.digits$} ± {:.digits$} s ({:.2} frames; {} whole periods seen; error \
         {error_from})",
        a.file.display(),
        summary.period_s,
        summary.period_error_s,
        summary.period_frames,
        summary.periods_seen,
    )?;
    let table = &summary.table;
    if table.format != TableFormat::Plain || table.fps_from_times.is_some() {
        let rate = match table.fps_from_times {
            Some(fps) => format!("at {fps} frames/s, read from its time steps"),
            None => format!("at {} frames/s", summary.fps),
        };
        outln!(
            "  read as a {} table: frames from column {:?} {rate}, across {:?}, down {:?}",
            table.format.name(),
            table.columns[0],
            table.columns[1],
            table.columns[2],
        )?;
    }
    if let Some(s) = &summary.significance {
        outln!(
            "  evidence: repeats with normalised mismatch {:.3}; {} surrogate tracks (same \
             smoothed spectrum, random phases) reach {:.3} at best (p < {:.2})",
            s.normalised_dip,
            s.surrogates,
            s.surrogate_floor,
            s.p_bound
        )?;
    }
    let caveat = summary.repeat_shown.caveat();
    if !caveat.is_empty() {
        outln!("  {caveat}")?;
    }
    outln!(
        "  per period: {} cm down the ramp, {} cm across; speed {} cm/s",
        with_error(summary.advance_down_cm, summary.advance_down_error_cm),
        with_error(summary.advance_across_cm, summary.advance_across_error_cm),
        with_error(summary.speed_cm_s, summary.speed_error_cm_s)
    )?;
    if let Some(m) = &summary.marker_reading {
        outln!("  markers: {}", m.reason)?;
    }
    if let Some(m) = &summary.model {
        let c = &m.comparison;
        let model = if c.mass_ratio_model == 0.0 {
            "viscous model".to_string()
        } else {
            format!("inertial model at m/m0 = {:.3}", c.mass_ratio_model)
        };
        use crate::analysis::experiment::tracking::model::MassSource;
        let (m_text, t0_text) = (
            with_error(c.mass_ratio, c.mass_ratio_error),
            with_error(c.t0_s, c.t0_error_s),
        );
        let how = match (c.mass_ratio_from, c.mass_ratio_error.is_some()) {
            (MassSource::Period, true) => format!(
                "m/m0 = {m_text} and t0 = {t0_text} s found together from the period (errors \
                 from the period's alone, not ⟨r⟩'s or α's)"
            ),
            (MassSource::Period, false) => {
                format!("m/m0 = {m_text} and t0 = {t0_text} s found together from the period")
            }
            (MassSource::ViscousPeriod, true) => format!(
                "t0 = {t0_text} s from the period, as --mass 0 asks, so m/m0 = {m_text} (errors \
                 from the period's alone)"
            ),
            (MassSource::ViscousPeriod, false) => {
                format!("t0 = {t0_text} s from the period, as --mass 0 asks, so m/m0 = {m_text}")
            }
            (MassSource::Given, _) => {
                format!("m/m0 = {m_text} as given, so t0 = {t0_text} s")
            }
        };
        outln!(
            "  model ({}, {model}): {how}; the SI's speed estimate v²/(g⟨r⟩ sin²α) gives m/m0 = \
             {:.3}, t0 = {:.4} s, a period of {:.3} s",
            m.body,
            c.mass_ratio_from_speed,
            c.t0_from_speed_s,
            c.period_from_speed_s
        )?;
        outln!(
            "  predicted per period: {:.3} cm down, {:.3} cm across, {:.3} s, {:.3} cm/s \
             (measured against predicted: advance {:+.1} %, period {:+.1} %, speed {:+.1} %)",
            c.predicted_advance_down_cm,
            c.predicted_advance_across_cm,
            c.predicted_period_s,
            c.predicted_speed_cm_s,
            100.0 * c.advance_down_difference,
            100.0 * c.period_difference,
            100.0 * c.speed_difference
        )?;
        let a = &m.alignment;
        let way = if a.mirrored_across {
            "mirrored across the ramp"
        } else {
            "as predicted across the ramp"
        };
        let shares = format!(
            "{:.0} % of the folded track's across motion against {:.0} % the other way round; \
             {:.0} % of its down motion",
            100.0 * a.across_explained[0],
            100.0 * a.across_explained[1],
            100.0 * a.down_explained
        );
        if a.handedness_shown {
            outln!("  the orbit fits the track {way} ({shares})")?;
        } else {
            outln!(
                "  which way round the track runs across the ramp is not shown ({shares}): the \
                 figure draws the orbit {way}, the closer of the two"
            )?;
        }
    }
    outln!(
        "  wrote {}/{{data.csv, figure.png, summary.json}}",
        a.out.display()
    )?;
    Ok(())
}
