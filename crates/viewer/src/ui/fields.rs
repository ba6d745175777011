//! The typed number fields (α, m/m0): what is typed is applied on Enter or when focus leaves,
//! never per keystroke, and a value outside the app's range is refused with the range named;
//! and [`FineAlpha`], the α rail's scale, finest at α*.

use super::{ALPHA_MAX, ALPHA_MIN};

/// What a typed number may be, for the field's messages.
pub(super) struct NumberLimits {
    pub(super) name: &'static str,
    pub(super) unit: &'static str,
    pub(super) range: (f64, f64),
}

/// What a number field did this frame.
#[derive(Debug, PartialEq)]
pub(super) enum FieldOutcome {
    /// Nothing to apply: not edited, still being typed, or Esc.
    Unchanged,
    /// A valid new value, on Enter or when the field lost focus.
    Committed(f64),
    /// Text that is not an allowed value; the field shows the running value again.
    Refused(String),
}

/// A number field that applies what is typed only on Enter or when focus leaves it, never on
/// each keystroke (typing "0.09" over 0.3 would otherwise run at 0.0, then 0.09 after a halt),
/// and never writes back the value it shows: focusing and leaving it, or Esc, changes nothing.
/// `edit` holds the text while the field has focus.
pub(super) fn number_field(
    ui: &mut egui::Ui,
    id: &str,
    value: f64,
    edit: &mut Option<String>,
    limits: &NumberLimits,
) -> FieldOutcome {
    let shown = shown_number(value);
    let mut text = edit.take().unwrap_or_else(|| shown.clone());
    let response = ui
        .add(
            egui::TextEdit::singleline(&mut text)
                .id(egui::Id::unique(id))
                .desired_width(96.0)
                // A long value (α = 0.13924012345678) widens the field rather than being cut.
                .clip_text(false),
        )
        .on_hover_text(format!(
            "{shown}: type a value{} and press Enter (Esc: keep the running value)",
            limits.unit
        ));
    if response.has_focus() {
        *edit = Some(text);
        return FieldOutcome::Unchanged;
    }
    if !response.lost_focus() || ui.input(|i| i.key_pressed(egui::Key::Escape)) {
        return FieldOutcome::Unchanged;
    }
    parse_number(&text, &shown, limits)
}

/// The value as the field shows it: the shortest text that reads back as exactly this value.
fn shown_number(value: f64) -> String {
    format!("{value}")
}

/// The typed `text` as a value within `limits`; the same text as `shown` is no change.
fn parse_number(text: &str, shown: &str, limits: &NumberLimits) -> FieldOutcome {
    let text = text.trim();
    if text == shown.trim() {
        return FieldOutcome::Unchanged;
    }
    let (lo, hi) = limits.range;
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && (lo..=hi).contains(&v) => FieldOutcome::Committed(v),
        Ok(v) if v.is_finite() => FieldOutcome::Refused(format!(
            "{} = {text}{} is outside what the app allows ({lo} … {hi}{}); kept {shown}",
            limits.name, limits.unit, limits.unit
        )),
        _ => FieldOutcome::Refused(format!(
            "{} {text:?} is not a number (type e.g. {shown}); kept {shown}",
            limits.name
        )),
    }
}

/// The α slider's scale: a handle position p ∈ [−1, 1] with α* at 0 and the ends at
/// [`ALPHA_MIN`] and [`ALPHA_MAX`], and |α − α*| = F ((1 + R/F)^|p| − 1) with F =
/// [`FineAlpha::FINEST`] and R the reach to that side's end: linear in p below F, one step of
/// the handle a fixed ratio of |α − α*| above it. On a linear rail of ~300 px the region around α* that matters
/// (the √(α − α*) law lives within a few per cent of α*) was a few pixels wide.
#[derive(Debug, Clone, Copy)]
pub struct FineAlpha {
    alpha_star: f64,
}

impl FineAlpha {
    /// The |α − α*| below which the rail is linear: a pixel of a 300 px rail there is about
    /// 8e-6 rad, and 1.05 α* sits near the middle of each half.
    pub const FINEST: f64 = 1e-4;

    /// The scale around `alpha_star` (clamped into the rail; 0 or NaN centres it).
    pub fn new(alpha_star: f64) -> Self {
        let centre = 0.5 * (ALPHA_MIN + ALPHA_MAX);
        let alpha_star = if alpha_star.is_finite() && alpha_star > 0.0 {
            alpha_star.clamp(2.0 * ALPHA_MIN, ALPHA_MAX - ALPHA_MIN)
        } else {
            centre
        };
        Self { alpha_star }
    }

    /// The largest |α − α*| on the side of `sign`.
    fn reach(&self, sign: f64) -> f64 {
        if sign > 0.0 {
            ALPHA_MAX - self.alpha_star
        } else {
            self.alpha_star - ALPHA_MIN
        }
    }

    /// The handle position of α.
    pub fn position(&self, alpha: f64) -> f64 {
        let d = alpha - self.alpha_star;
        if d == 0.0 || !d.is_finite() {
            return 0.0;
        }
        let sign = d.signum();
        let reach = self.reach(sign);
        let ratio = 1.0 + reach / Self::FINEST;
        let p = (1.0 + d.abs().min(reach) / Self::FINEST).ln() / ratio.ln();
        sign * p.clamp(0.0, 1.0)
    }

    /// α at handle position `p` (clamped to [−1, 1]).
    pub fn alpha(&self, p: f64) -> f64 {
        let p = if p.is_finite() {
            p.clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let sign = if p < 0.0 { -1.0 } else { 1.0 };
        if p.abs() == 1.0 {
            // The ends exactly, not within a rounding of them.
            return if p < 0.0 { ALPHA_MIN } else { ALPHA_MAX };
        }
        let reach = self.reach(sign);
        let d = Self::FINEST * ((1.0 + reach / Self::FINEST).powf(p.abs()) - 1.0);
        (self.alpha_star + sign * d.min(reach)).clamp(ALPHA_MIN, ALPHA_MAX)
    }
}

#[cfg(test)]
mod fine_alpha_tests {
    use super::{ALPHA_MAX, ALPHA_MIN, FineAlpha};

    #[test]
    fn the_rail_runs_from_end_to_end_through_alpha_star_and_back() {
        for alpha_star in [0.0572, 0.1394, 0.6, 1.4] {
            let s = FineAlpha::new(alpha_star);
            assert_eq!(s.alpha(-1.0), ALPHA_MIN);
            assert_eq!(s.alpha(1.0), ALPHA_MAX);
            assert_eq!(s.alpha(0.0), alpha_star);
            assert_eq!(s.position(alpha_star), 0.0);
            let mut last = f64::NEG_INFINITY;
            for i in 0..=2000 {
                let p = -1.0 + i as f64 / 1000.0;
                let a = s.alpha(p);
                assert!(a >= last, "monotone at p = {p}");
                last = a;
                assert!((s.position(a) - p).abs() < 1e-9, "round trip at p = {p}");
            }
        }
    }

    #[test]
    fn it_is_fine_near_alpha_star_and_coarse_far_away() {
        let s = FineAlpha::new(0.1394);
        // One thousandth of the rail moves α by about 1e-6 next to α*, by 1e-2 at the end.
        let near = s.alpha(0.001) - s.alpha(0.0);
        let far = s.alpha(1.0) - s.alpha(0.999);
        assert!(near < 2e-6 && far / near > 1000.0, "{near} {far}");
        // …while 1.05 α* (5 % above) sits well inside the rail, not at its edge.
        let p = s.position(1.05 * 0.1394);
        assert!(p > 0.3 && p < 0.7, "{p}");
        // Bad values do not panic.
        assert_eq!(FineAlpha::new(f64::NAN).position(f64::NAN), 0.0);
        assert!(s.alpha(f64::NAN).is_finite());
    }
}

#[cfg(test)]
mod number_field_tests {
    use super::{FieldOutcome, NumberLimits, parse_number, shown_number};

    const ALPHA: NumberLimits = NumberLimits {
        name: "α",
        unit: " rad",
        range: (0.001, 1.5),
    };

    #[test]
    fn the_shown_text_reads_back_exactly_and_is_no_change() {
        for v in [0.17662345, 0.1 + 0.2, 1.5, 0.001, 0.3] {
            let shown = shown_number(v);
            assert_eq!(shown.parse::<f64>().unwrap(), v);
            assert_eq!(
                parse_number(&shown, &shown, &ALPHA),
                FieldOutcome::Unchanged
            );
            assert_eq!(
                parse_number(&format!(" {shown} "), &shown, &ALPHA),
                FieldOutcome::Unchanged
            );
        }
    }

    #[test]
    fn typed_values_commit_whole_and_bad_ones_are_refused_with_the_limits() {
        assert_eq!(
            parse_number("0.09", "0.3", &ALPHA),
            FieldOutcome::Committed(0.09)
        );
        let FieldOutcome::Refused(why) = parse_number("5", "0.3", &ALPHA) else {
            panic!("5 rad accepted");
        };
        assert!(why.contains("0.001") && why.contains("1.5") && why.contains("kept 0.3"));
        for bad in ["abc", "", "nan", "inf", "0.0.1"] {
            let FieldOutcome::Refused(why) = parse_number(bad, "0.3", &ALPHA) else {
                panic!("{bad:?} accepted");
            };
            assert!(why.contains("α"), "{why}");
        }
    }
}

#[cfg(test)]
mod number_field_width_tests {
    use super::*;
    use egui::Color32;

    /// The field's width beside the width of its text, for `value`.
    fn widths(value: f64) -> (f32, f32) {
        let ctx = egui::Context::default();
        let mut out = (0.0, 0.0);
        let mut output = ctx.run_ui(egui::RawInput::default(), |ui| {
            let limits = NumberLimits {
                name: "alpha",
                unit: " rad",
                range: (0.0, 1.5),
            };
            let before = ui.cursor().min.x;
            let _ = number_field(ui, "test-field", value, &mut None, &limits);
            let field = ui.min_rect().max.x - before;
            let text = ui.fonts_mut(|f| {
                f.layout_no_wrap(
                    shown_number(value),
                    egui::TextStyle::Body.resolve(ui.style()),
                    Color32::WHITE,
                )
                .size()
                .x
            });
            out = (field, text);
        });
        output.textures_delta.clear();
        out
    }

    #[test]
    fn a_long_value_widens_the_field_rather_than_being_cut() {
        let (short_field, _) = widths(0.3);
        let (long_field, long_text) = widths(0.139_240_123_456_789_01);
        assert!(
            long_field > long_text,
            "field {long_field} < text {long_text}"
        );
        assert!(long_field > short_field, "{long_field} ≤ {short_field}");
    }
}
