//! The plots' axes: numbers on a 1-2-5 ladder at every size, far enough apart to read, and
//! the finer grid between them (egui_plot's own spacer labelled rounding noise and crowded a
//! small plot).

use egui_plot::{GridInput, GridMark};

/// How far apart the numbers of an x axis are at least, in points: a number such as
/// "0.04425" is about 45 points wide; with the gap neighbours never read as one, and a plot
/// 130 points wide still gets two.
pub(super) const X_LABEL_POINTS: f64 = 55.0;
/// How far apart the numbers of a y axis are at least, in points (a line of text is 14).
pub(super) const Y_LABEL_POINTS: f64 = 32.0;
/// egui_plot's default finest grid spacing, in points: `GridInput::base_step_size` is this
/// many points' worth of data.
const GRID_MIN_POINTS: f64 = 8.0;

/// The step of rung `k` of the 1-2-5 ladder: …, 0.1, 0.2, 0.5, 1, 2, 5, 10, … (k = 0 is 1).
fn rung(k: i32) -> f64 {
    [1.0, 2.0, 5.0][k.rem_euclid(3) as usize] * 10f64.powi(k.div_euclid(3))
}

/// Grid marks with exactly one labelled level: numbers every `label` (the finest 1-2-5 step
/// at least `label_points` apart), grid lines every fifth (a quarter of a 2) of it between
/// them. egui_plot labels every mark whose step is further apart than the axis's label
/// spacing, so marks of two coarser steps were both labelled ("0.0440.0450.046", or t at 0,
/// 200, 400, 500, 600): here a mark has the label step or the fine one, and the axes' label
/// spacing ([`label_spacing`]) lies between the two. A number within `edge_points` of the
/// upper end, where the widget's edge would cut it, or `low_edge_points` of the lower end,
/// where it would meet the other axis's numbers, is left off.
fn axis_marks(
    input: GridInput,
    label_points: f64,
    (low_edge_points, edge_points): (f64, f64),
) -> Vec<GridMark> {
    let (lo, hi) = input.bounds;
    if !(lo.is_finite() && hi.is_finite() && hi > lo && input.base_step_size > 0.0) {
        return Vec::new();
    }
    let points_per_unit = GRID_MIN_POINTS / input.base_step_size;
    let wanted = label_points / points_per_unit;
    let mut k = wanted.log10().floor() as i32 * 3 - 3;
    while rung(k) < wanted {
        k += 1;
    }
    // A 2× or 2.5× step of the ladder can leave one number on a narrow plot: then the step
    // under it, if its numbers are still 3/4 of the spacing apart.
    let labels_in = |step: f64| ((hi / step).floor() - (lo / step).ceil() + 1.0).max(0.0);
    if labels_in(rung(k)) < 2.0 && rung(k - 1) >= 0.75 * wanted {
        k -= 1;
    }
    let label = rung(k);
    let per_label: i64 = if k.rem_euclid(3) == 1 { 4 } else { 5 };
    let fine = label / per_label as f64;
    let first = (lo / fine).ceil() as i64;
    let last = (hi / fine).floor() as i64;
    if last - first > 10_000 {
        return Vec::new();
    }
    (first..=last)
        .map(|i| {
            let value = i as f64 * fine;
            let near_edge = (value - lo) * points_per_unit < low_edge_points
                || (hi - value) * points_per_unit < edge_points;
            let step_size = if i.rem_euclid(per_label) == 0 && !near_edge {
                label
            } else {
                fine
            };
            GridMark { value, step_size }
        })
        .collect()
}

/// The x axis's marks ([`axis_marks`]).
pub fn x_marks(input: GridInput) -> Vec<GridMark> {
    axis_marks(input, X_LABEL_POINTS, (0.0, 0.4 * X_LABEL_POINTS))
}

/// The y axis's marks ([`axis_marks`]).
pub fn y_marks(input: GridInput) -> Vec<GridMark> {
    // A y number at an end overhangs the frame by half a line, which the axis has room for.
    axis_marks(input, Y_LABEL_POINTS, (0.0, 0.0))
}

/// The label spacing to give egui_plot for an axis whose numbers are `label_points` apart:
/// above the fine marks' spacing (at most 2.5/5 of it) and below the labelled ones' (at least
/// 3/4 of it).
pub(super) fn label_spacing(label_points: f64) -> std::ops::RangeInclusive<f32> {
    let min = (0.7 * label_points) as f32;
    min..=min + 1.0
}

/// A tick's number with as many decimals as its step needs (a step of 0.0005 shows 0.0495, not
/// egui_plot's rounded 0.050); an axis's numbers share one step ([`axis_marks`]), so they all
/// have the same decimals (0.0490 beside 0.0495, not 0.049).
pub fn tick_label(mark: GridMark, _range: &std::ops::RangeInclusive<f64>) -> String {
    let decimals = (-mark.step_size.log10() - 1e-9).ceil().max(0.0) as usize;
    format!("{:.*}", decimals.min(12), mark.value)
}

/// [`tick_label`] for an axis of a quantity that is never negative (1/T): no number below 0.
/// The plot's margin draws a little of the axis below 0 so that a halted body's point (1/T = 0)
/// shows whole; its tick read "-0.001" on a projected lesson, a rate no body has.
pub fn rate_tick_label(mark: GridMark, range: &std::ops::RangeInclusive<f64>) -> String {
    // A tick at 0 computed as -1e-18 is 0, not "-0.000".
    let tiny = 1e-9 * mark.step_size.abs();
    if mark.value < -tiny {
        String::new()
    } else {
        let value = if mark.value.abs() <= tiny {
            0.0
        } else {
            mark.value
        };
        tick_label(GridMark { value, ..mark }, range)
    }
}

#[cfg(test)]
mod axis_tests {
    use super::{X_LABEL_POINTS, label_spacing, rate_tick_label, tick_label, x_marks, y_marks};

    #[test]
    fn a_rate_axis_shows_no_number_below_zero() {
        let range = -0.0012..=0.011;
        let mark = |value: f64| GridMark {
            value,
            step_size: 0.001,
        };
        assert_eq!(rate_tick_label(mark(-0.001), &range), "");
        assert_eq!(rate_tick_label(mark(-1e-19), &range), "0.000");
        assert_eq!(rate_tick_label(mark(0.0), &range), "0.000");
        assert_eq!(rate_tick_label(mark(0.004), &range), "0.004");
    }
    use egui_plot::{GridInput, GridMark};

    /// The labelled ticks of an axis `pixels` long over `bounds`, as egui_plot labels them: a
    /// mark whose step spans more than the axis's label spacing.
    fn labelled(
        marks: fn(GridInput) -> Vec<GridMark>,
        spacing: f64,
        bounds: (f64, f64),
        pixels: f64,
    ) -> Vec<(f64, String)> {
        let per_point = (bounds.1 - bounds.0) / pixels;
        // egui_plot asks for steps of at least 8 points.
        marks(GridInput {
            bounds,
            base_step_size: 8.0 * per_point,
        })
        .iter()
        .filter(|m| m.step_size / per_point > f64::from(*label_spacing(spacing).start()))
        .map(|m| (m.value, tick_label(*m, &(bounds.0..=bounds.1))))
        .collect()
    }

    #[test]
    fn every_axis_gets_evenly_spaced_numbers_at_one_level_at_any_range_and_size() {
        for bounds in [
            (0.0489, 0.0499),
            (0.0, 1.0),
            (-16.0, -15.2),
            (0.0, 2000.0),
            (0.0, 830.0),
            (0.1, 6.3),
            (0.0440, 0.0462),
        ] {
            for pixels in [180.0, 320.0, 900.0] {
                for (marks, spacing) in [(x_marks as fn(_) -> _, X_LABEL_POINTS), (y_marks, 32.0)] {
                    let ticks = labelled(marks, spacing, bounds, pixels);
                    let what = format!("{bounds:?} over {pixels} px: {ticks:?}");
                    assert!(ticks.len() >= 2, "{what}");
                    // Distinct numbers with the same decimals, evenly spaced, far enough
                    // apart to read (t: 0, 200, 400, 500, 600 had two steps).
                    let steps: Vec<f64> = ticks.windows(2).map(|w| w[1].0 - w[0].0).collect();
                    let step = steps[0];
                    assert!(
                        steps.iter().all(|s| (s - step).abs() < 1e-9 * step),
                        "{what}"
                    );
                    assert!(
                        step / (bounds.1 - bounds.0) * pixels >= 0.75 * spacing - 1e-9,
                        "{what}"
                    );
                    let decimals: Vec<usize> = ticks
                        .iter()
                        .map(|(_, t)| t.split('.').nth(1).map_or(0, str::len))
                        .collect();
                    assert!(decimals.iter().all(|&d| d == decimals[0]), "{what}");
                    let mut unique: Vec<&String> = ticks.iter().map(|(_, t)| t).collect();
                    unique.dedup();
                    assert_eq!(unique.len(), ticks.len(), "{what}");
                }
            }
        }
        // The case of issue 25: α from α* = 0.0489 to 0.0499 on a 300 px plot.
        let ticks = labelled(x_marks, X_LABEL_POINTS, (0.0489, 0.0499), 300.0);
        assert!(ticks.iter().any(|(_, t)| t == "0.0490"), "{ticks:?}");
        // No number at the very end of an axis, where the frame cuts it.
        let ticks = labelled(x_marks, X_LABEL_POINTS, (0.0, 1000.0), 320.0);
        assert!(ticks.iter().all(|(v, _)| *v != 1000.0), "{ticks:?}");
        // Nothing for a broken range.
        assert!(
            x_marks(GridInput {
                bounds: (1.0, f64::NAN),
                base_step_size: 0.1
            })
            .is_empty()
        );
    }
}
