//! The overlay's text panels: the status numbers (or the red health warning), the colour-bar
//! legends and the view titles.

use crate::colormap::DIVERGING;
use crate::live::{PeriodSpan, Snapshot};
use crate::render::types::{Anchor, OverlayPanel, PanelItem};
use crate::view::MeasuredAhead;

use super::SceneView;

/// How large a panel's text is: its sizes (given for 1280×720) times `scale`, but none under
/// `min_px` (a room's floor: [`super::ROOM_TEXT_PX`] in presentation and class modes, 0
/// elsewhere).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct TextSize {
    /// Multiplies every size (and the panels' padding and bars).
    pub scale: f32,
    /// The least font size in pixels.
    pub min_px: f32,
}

impl TextSize {
    /// Text scaled by `scale`, with no floor.
    #[cfg(test)]
    pub fn plain(scale: f32) -> Self {
        Self { scale, min_px: 0.0 }
    }

    /// The font size in pixels for a size of `base` at 1280×720.
    pub fn px(self, base: f32) -> f32 {
        (base * self.scale).max(self.min_px)
    }

    /// Whether a room's floor applies (presentation and class modes): panels then leave out
    /// their small print.
    pub fn for_a_room(self) -> bool {
        self.min_px > 0.0
    }
}

impl SceneView {
    /// The numbers; `ahead` is what a lesson step's evidence measured ahead, its period and
    /// its 1/T (each said, marked so, while the live run has not found its own).
    pub(super) fn status_panel(
        &self,
        snap: &Snapshot,
        text: TextSize,
        ahead: MeasuredAhead,
    ) -> OverlayPanel {
        let room = text.for_a_room();
        let deg = snap.alpha_rad.to_degrees();
        let ratio = if snap.alpha_star > 0.0 {
            format!("α/α* = {:.4}", snap.alpha_rad / snap.alpha_star)
        } else {
            "perfect body".into()
        };
        let mass = if !snap.model.is_inertial() {
            format!("m/m0 = 0 ({} model)", snap.model)
        } else {
            format!(
                "m/m0 = {} ({} model)",
                short_number(snap.mass_ratio),
                snap.model
            )
        };
        let rate = if snap.halted {
            "halted: 1/T = 0".to_string()
        } else {
            // Before the live run decides its cycle, the time between its last two crossings
            // is not the period (on a doubled orbit it is half of it): where the step's
            // evidence measured ahead has the cycle's 1/T, that is said, marked, instead.
            let live = snap
                .stated_period()
                .filter(|&(_, span)| span != PeriodSpan::LastCrossings || ahead.rate.is_none());
            match live {
                // For a room, without the words on what T spans: a narrower panel at 24 px.
                Some((t, _)) if room => format!("1/T = {:.5}   (T = {:.3})", 1.0 / t, t),
                Some((t, span)) => format!(
                    "1/T = {:.5}   (T = {:.3}, {})",
                    1.0 / t,
                    t,
                    match span {
                        PeriodSpan::FullTurn => "one full turn",
                        PeriodSpan::Cycle { crossings: 1 } | PeriodSpan::LastCrossings => {
                            "∂Ω to ∂Ω"
                        }
                        PeriodSpan::Cycle { .. } => "the whole cycle",
                    },
                ),
                // The step's evidence, measured ahead on the same run: its point is on the
                // plot already, and "measuring…" beside it read as a contradiction.
                None => match ahead.rate {
                    Some(0.0) => "halted (measured ahead)".to_string(),
                    // A digit fewer for a room: the line stays as narrow as the live 1/T's.
                    Some(r) if room => format!("1/T = {r:.4} (measured ahead)"),
                    Some(r) => format!("1/T = {r:.5} (measured ahead)"),
                    None => "1/T: measuring…".to_string(),
                },
            }
        };
        let line = |s: String, px: f32| PanelItem::Text {
            text: s,
            size_px: text.px(px),
            color: [240; 3],
        };
        // For a room with other bodies on the ramp, each body's line gives its fate: the scene's
        // own rate lines are left out, so the panel leaves the bodies room.
        let listed = room && snap.views.lanes && !snap.lanes.is_empty();
        let mut items = if room {
            room_lines(snap, text)
        } else {
            vec![
                PanelItem::Text {
                    text: self.name.clone(),
                    size_px: text.px(19.0),
                    color: [255, 214, 10],
                },
                // Five decimals: the slider moves α by 1e-5 rad, and a lesson sets α = 0.99 α*.
                line(format!("α = {:.5} rad ({deg:.3}°)", snap.alpha_rad), 16.0),
                line(format!("α* = {:.5} rad   {ratio}", snap.alpha_star), 16.0),
                line(mass, 16.0),
                // The drag law is named with the model, on a line of its own (the panel keeps
                // its width beside the body's view): points taken under another law are
                // another experiment.
                line(snap.drag_law.label(), 16.0),
                line(format!("t = {:.2}", snap.t), 16.0),
            ]
        };
        let worst = snap
            .health
            .quat_norm_error
            .max(snap.health.contact_normal_error);
        let trustworthy = worst <= crate::simulate::FIXED_STEP_HEALTH_LIMIT;
        if let Some(stopped) = &snap.stopped {
            // The run stopped (a fixed step too coarse, say): the numbers above are the last
            // trustworthy ones, and the reason is what the viewer must read.
            items.push(PanelItem::Text {
                text: stopped.clone(),
                size_px: text.px(16.0),
                color: [255, 70, 60],
            });
        } else if !self.is_disk && !trustworthy {
            // The state has left the rolling constraint: its 1/T would be nonsense.
            items.push(PanelItem::Text {
                text: format!(
                    "NOT TRUSTWORTHY: ||q|−1| = {:.1e}, contact error = {:.1e} (limit 1e-3); use a \
                     smaller step",
                    snap.health.quat_norm_error, snap.health.contact_normal_error
                ),
                size_px: text.px(16.0),
                color: [255, 70, 60],
            });
        } else if let Some(validity) = &snap.validity {
            // The verdict's `left_model`: the motion computed past it is not a real body's, so
            // no 1/T or period is claimed for it.
            items.push(PanelItem::Text {
                text: format!("left the model: the body {validity}"),
                size_px: text.px(16.0),
                color: [255, 70, 60],
            });
        } else if !listed {
            items.push(line(rate, 16.0));
            // On a line of its own: appended to the 1/T line it widened the box over the body
            // at the period-doubling lesson's key moment.
            let live = snap.period_multiplicity.filter(|_| snap.period.is_some());
            if let Some(k) = live {
                items.push(line(period_line(k), 16.0));
            } else if let Some(k) = ahead.period.filter(|_| !snap.halted) {
                // The same run's evidence, measured ahead: the step's claim on the screen
                // when the step opens, marked as such until the live run settles too.
                // Short: for a room the line is 24 px, and the panel must stay clear of the
                // SO(3) inset at class mode's 1280×720.
                items.push(line(format!("period {k} (measured ahead)"), 16.0));
            }
        }
        items.extend(lane_lines(snap, text, self.lanes.placement(snap).aligned));
        if let Some((tips, lost)) = snap.hull_tips {
            // A dented cylinder rolls on its hull: say what the flats did.
            items.push(line(
                format!("on its convex hull: {tips} tip(s) across its flats, impacts took ΔE = {lost:.4}"),
                14.0,
            ));
        }
        if room {
            // The integrator and its health are small print for the operator, not the room;
            // an untrustworthy state is said above in red at full size.
        } else if !self.is_disk {
            // Before the first step nothing has been measured: "—", not a reassuring 0.0e0.
            let measured = |v: f64| {
                if snap.health.rhs_evals == 0 {
                    "—".to_string()
                } else {
                    format!("{v:.1e}")
                }
            };
            items.push(PanelItem::Text {
                text: format!(
                    "{}   ||q|−1| ≤ {}   contact error ≤ {}",
                    snap.integrator,
                    measured(snap.health.quat_norm_error),
                    measured(snap.health.contact_normal_error)
                ),
                size_px: text.px(13.0),
                color: [190; 3],
            });
        } else {
            items.push(PanelItem::Text {
                text: snap.integrator.to_string(),
                size_px: text.px(13.0),
                color: [190; 3],
            });
        }
        OverlayPanel {
            anchor: Anchor::TopLeft(10, 10),
            items,
            background: [16, 18, 24, 200],
            padding: (8.0 * text.scale) as u32,
        }
    }

    /// The colour legend, at most `max_width` pixels wide (its view's width less margins).
    pub(super) fn legend_panel(&self, text: TextSize, max_width: f32) -> OverlayPanel {
        let s = &self.scale;
        let what = match (self.is_disk, text.for_a_room()) {
            (true, false) => "curvature κ of the section (1 = circle)",
            (false, false) => "Gaussian curvature K (1 = sphere)",
            // Shorter, to fit a narrow view at a room's size.
            (true, true) => "curvature κ (1 = circle)",
            (false, true) => "curvature K (1 = sphere)",
        };
        let padding = (8.0 * text.scale) as u32;
        // The bar leaves room for half a label at each end and the padding.
        let widest = (max_width - 2.0 * padding as f32 - 4.0 * text.px(13.0)).max(60.0);
        let mut labels = vec![(s.position(1.0), "1".to_string())];
        if s.max - s.min > 1e-3 {
            labels.push((s.position(s.min), format!("{:.2}", s.min)));
            labels.push((s.position(s.max), format!("{:.2}", s.max)));
        }
        OverlayPanel {
            anchor: Anchor::BottomLeft(10, 10),
            items: vec![
                PanelItem::Text {
                    text: what.into(),
                    size_px: text.px(15.0),
                    color: [240; 3],
                },
                PanelItem::ColorBar {
                    // As long as the title, so its numbers keep apart at a room's size.
                    width: if text.for_a_room() {
                        (240.0 * text.px(13.0) / 13.0).min(widest) as u32
                    } else {
                        (240.0 * text.scale) as u32
                    },
                    height: (12.0 * text.scale).max(4.0) as u32,
                    colors: DIVERGING.to_vec(),
                    labels,
                    size_px: text.px(13.0),
                },
            ],
            background: [16, 18, 24, 200],
            padding,
        }
    }
}

/// For a room, the numbers a lesson talks about in three short lines at 24 px or more (the
/// 1/T line follows), so the panel keeps clear of the body beside a lesson's plot: α against
/// α*, m/m0 with the drag law, t. The scene's name, the model's name and α in degrees are the
/// operator's, in the window's other modes.
fn room_lines(snap: &Snapshot, text: TextSize) -> Vec<PanelItem> {
    let line = |s: String| PanelItem::Text {
        text: s,
        size_px: text.px(16.0),
        color: [240; 3],
    };
    let alpha = if snap.alpha_star > 0.0 {
        format!(
            "α = {:.5} rad = {:.4} α*",
            snap.alpha_rad,
            snap.alpha_rad / snap.alpha_star
        )
    } else {
        format!("α = {:.5} rad (perfect body)", snap.alpha_rad)
    };
    let mass = if snap.model.is_inertial() {
        short_number(snap.mass_ratio)
    } else {
        "0".to_string()
    };
    vec![
        line(alpha),
        line(format!("m/m0 = {mass}, {}", snap.drag_law.label())),
        line(format!("t = {:.2}", snap.t)),
    ]
}

/// Average advance of DejaVu Sans per pixel of font size, rounded up: enough to wrap a caption
/// to a width without the rasteriser's metrics (the view layer sees only `render::types`).
const CHARS_EM: f32 = 0.56;

/// The lesson's caption, wrapped to `max_width` pixels, centred at the bottom and lifted by
/// `lift` pixels (clear of the colour legend), with the step count above it.
pub(super) fn caption_panel(
    snap: &Snapshot,
    text: TextSize,
    max_width: f32,
    lift: u32,
) -> Option<OverlayPanel> {
    let caption = snap.caption.as_deref()?;
    let size_px = text.px(22.0);
    let per_line = ((max_width / (CHARS_EM * size_px)) as usize).max(12);
    let mut items = Vec::new();
    if let Some(l) = snap.lesson {
        items.push(PanelItem::Text {
            text: format!("step {} of {}", l.done, l.steps),
            size_px: text.px(14.0),
            color: [255, 214, 10],
        });
    }
    items.extend(
        wrap(caption, per_line)
            .into_iter()
            .map(|line| PanelItem::Text {
                text: line,
                size_px,
                color: [250; 3],
            }),
    );
    Some(OverlayPanel {
        anchor: Anchor::BottomCentre(lift),
        items,
        background: [10, 12, 18, 240],
        padding: (10.0 * text.scale) as u32,
    })
}

/// A panel's height in pixels as the overlay will draw it, from above: DejaVu Sans's line is
/// 1.164 of its size (ascent 0.928 + descent 0.236), taken as 1.2, plus the 2 px the overlay
/// puts under each item and the padding (the view layer has no font metrics; `render::overlay`
/// measures exactly, and tests/app/presentation.rs checks the band it sets against it).
pub(super) fn estimated_height(panel: &OverlayPanel) -> u32 {
    let items: f32 = panel
        .items
        .iter()
        .map(|item| match item {
            PanelItem::Text { size_px, .. } => (1.2 * size_px).ceil() + 2.0,
            PanelItem::ColorBar {
                height, size_px, ..
            } => *height as f32 + 4.0 + (1.2 * size_px).ceil() + 2.0,
        })
        .sum();
    items as u32 + 2 * panel.padding
}

/// A panel's width in pixels as the overlay will draw it, from above (by [`CHARS_EM`], which
/// overestimates DejaVu Sans's advance: never narrower than drawn).
pub(super) fn estimated_width(panel: &OverlayPanel) -> u32 {
    let items = panel
        .items
        .iter()
        .map(|item| match item {
            PanelItem::Text { text, size_px, .. } => {
                text.chars().count() as f32 * CHARS_EM * size_px
            }
            PanelItem::ColorBar {
                width,
                labels,
                size_px,
                ..
            } => {
                let widest = labels
                    .iter()
                    .map(|l| l.1.chars().count())
                    .max()
                    .unwrap_or(0);
                *width as f32 + widest as f32 * CHARS_EM * size_px
            }
        })
        .fold(0.0f32, f32::max);
    items.ceil() as u32 + 2 * panel.padding
}

/// Greedy word wrap to at most `width` characters a line (a longer word gets a line of its own).
pub(super) fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let len = line.chars().count();
        if len > 0 && len + 1 + word.chars().count() > width {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// The overlay's period line for a cycle of multiplicity `k`.
/// Each body's line when the scene has others on the ramp (`[[bodies]]`) and they are shown:
/// its name, m/m0 and fate in the verdict's words, in its colour, and how far along the ramp
/// it is from the scene's own body.
fn lane_lines(snap: &Snapshot, text: TextSize, aligned: bool) -> Vec<PanelItem> {
    if !snap.views.lanes || snap.lanes.is_empty() {
        return Vec::new();
    }
    let room = text.for_a_room();
    let line = |n: usize, body: &Snapshot, relative: String| {
        // A label that names its m/m0 ("m/m0 = 4.5") is not followed by it again; for a room,
        // the label and the fate's first words only, on a panel narrow enough for 24 px.
        let mass = if body.label.contains("m/m0") || room {
            String::new()
        } else {
            format!(" (m/m0 = {})", short_number(body.mass_ratio))
        };
        let fate = if room { room_fate(body) } else { body.fate() };
        PanelItem::Text {
            text: format!("● {}{mass}: {fate}{relative}", body.label),
            size_px: text.px(15.0),
            color: crate::colormap::body_colour(n),
        }
    };
    let mut items = vec![line(0, snap, String::new())];
    for (i, lane) in snap.lanes.iter().enumerate() {
        let dx = lane.pose.centre.x - snap.pose.centre.x;
        let relative = if dx.abs() >= 1.0 && !room {
            format!(
                ", {:.1} radii {}",
                dx.abs(),
                if dx > 0.0 { "ahead" } else { "behind" }
            )
        } else {
            String::new()
        };
        items.push(line(i + 1, lane, relative));
    }
    if aligned {
        items.push(PanelItem::Text {
            text: if room {
                "drawn beside body 1".to_string()
            } else {
                "too far apart: drawn side by side, not to scale".to_string()
            },
            size_px: text.px(13.0),
            color: [190; 3],
        });
    }
    items
}

/// A body's fate in its first words, for a room: "period 2", "periodic", "halted", "left the
/// model", "undecided", "stopped".
fn room_fate(body: &Snapshot) -> String {
    let fate = body.fate();
    match (
        fate.split(':').next().unwrap_or(""),
        body.period_multiplicity,
    ) {
        ("periodic", Some(k)) if body.theta.is_none() => format!("period {k}"),
        (word, _) => word.to_string(),
    }
}

fn period_line(k: usize) -> String {
    if k == 2 {
        "period 2: doubled".to_string()
    } else {
        format!("period {k}")
    }
}

/// A number for people: four decimals, trailing zeros dropped (m/m0 = 3.2100635417193555
/// shows as 3.2101, 2.5 as 2.5).
pub fn short_number(x: f64) -> String {
    let s = format!("{x:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

pub(super) fn title_panel(rect: [u32; 4], title: &str, text: TextSize) -> OverlayPanel {
    titled_panel(rect, title, None, text)
}

/// [`title_panel`] with a key under the title in smaller grey lines (what a point means, which
/// axis is which), each of its `\n`-separated lines wrapped to the inset's width.
pub(super) fn titled_panel(
    rect: [u32; 4],
    title: &str,
    key: Option<&str>,
    text: TextSize,
) -> OverlayPanel {
    // The title keeps the text size of the other panels (a projector's room reads it too) and
    // wraps to its inset's width; only a word longer than the inset shrinks it. (Shrunk to one
    // line it was 11 px at 720p in class text.) CHARS_EM overestimates DejaVu's advance, so
    // the lines fit.
    let width = rect[2].saturating_sub(16) as f32;
    let lines_at = |words: &str, size_px: f32| {
        let lines = wrap(words, ((width / (CHARS_EM * size_px)) as usize).max(1));
        let longest = lines.iter().map(|l| l.chars().count()).max().unwrap_or(1);
        let size_px = size_px.min(width / (CHARS_EM * longest as f32));
        (lines, size_px)
    };
    // For a room the key is small print: the title alone, at the room's size.
    let key = key.filter(|_| !text.for_a_room());
    let (lines, size_px) = lines_at(title, text.px(14.0));
    let mut items: Vec<PanelItem> = lines
        .into_iter()
        .map(|line| PanelItem::Text {
            text: line,
            size_px,
            color: [225; 3],
        })
        .collect();
    // Each of the key's lines wraps on its own.
    for part in key.into_iter().flat_map(|k| k.split('\n')) {
        let (lines, size_px) = lines_at(part, text.px(12.0));
        items.extend(lines.into_iter().map(|line| PanelItem::Text {
            text: line,
            size_px,
            color: [185; 3],
        }));
    }
    // A key's small grey lines cross the trail: they get the other panels' backing.
    let background = if key.is_some() {
        [16, 18, 24, 190]
    } else {
        [0, 0, 0, 0]
    };
    OverlayPanel {
        anchor: Anchor::TopLeft(rect[0] + 6, rect[1] + 6),
        items,
        background,
        padding: 2,
    }
}

/// "; period k" once the crossings of ∂Ω repeat (3D), else nothing.
pub fn multiplicity_text(k: Option<usize>) -> String {
    match k {
        Some(2) => "; period 2, doubled".into(),
        Some(k) => format!("; period {k}"),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn captions_wrap_at_words_within_the_width() {
        let lines = wrap("the quick brown fox jumps over the lazy dog", 10);
        assert_eq!(
            lines,
            ["the quick", "brown fox", "jumps over", "the lazy", "dog"]
        );
        assert!(lines.iter().all(|l| l.chars().count() <= 10));
        // A word longer than the width gets a line of its own rather than being cut.
        assert_eq!(
            wrap("averyveryverylongword and", 5),
            ["averyveryverylongword", "and"]
        );
        assert!(wrap("   ", 10).is_empty());
        // Characters, not bytes: Greek letters count once.
        assert_eq!(wrap("α α α α", 3), ["α α", "α α"]);
    }

    fn texts(panel: &OverlayPanel) -> Vec<(String, f32)> {
        panel
            .items
            .iter()
            .filter_map(|item| match item {
                PanelItem::Text { text, size_px, .. } => Some((text.clone(), *size_px)),
                PanelItem::ColorBar { .. } => None,
            })
            .collect()
    }

    #[test]
    fn a_lessons_caption_is_wrapped_under_its_step_and_grows_in_class_mode() {
        let setup = crate::scene::Scene::preset("lesson-critical-angle")
            .unwrap()
            .setup(None)
            .unwrap();
        let caption = setup.timeline[0].caption.clone().unwrap();
        let snap = crate::live::LiveRun::new(setup).snapshot();
        let normal = caption_panel(&snap, TextSize::plain(1.0), 700.0, 10).unwrap();
        assert_eq!(normal.anchor, Anchor::BottomCentre(10));
        let lines = texts(&normal);
        assert_eq!(lines[0].0, "step 1 of 7");
        let body: Vec<&str> = lines[1..].iter().map(|(t, _)| t.as_str()).collect();
        assert_eq!(body.join(" "), caption);
        assert!(body.len() >= 2, "wrapped to 700 px: {body:?}");
        assert!(lines[1..].iter().all(|(_, size)| *size == 22.0));
        // Class mode's text scale 1.8: the same caption, larger, on more lines.
        let class = texts(&caption_panel(&snap, TextSize::plain(1.8), 700.0, 10).unwrap());
        assert!(
            class[1..]
                .iter()
                .all(|(_, size)| (*size - 22.0 * 1.8).abs() < 1e-4)
        );
        assert!(class.len() > lines.len());
        // No caption, no panel.
        let plain = crate::scene::Scene::preset("sphere-cruising")
            .unwrap()
            .setup(None)
            .unwrap();
        let snap = crate::live::LiveRun::new(plain).snapshot();
        assert!(caption_panel(&snap, TextSize::plain(1.0), 700.0, 10).is_none());
    }
}
