//! Presentation on a projector: on every bundled lesson, at every step, at 1280×720, 1600×900
//! and 3840×2160 (and 768×720, 1152×1080: the 3D view beside a lesson's large plot), in plain
//! and class text sizes, nothing covers the body: the body's screen box
//! (its bounding sphere projected through the frame's own camera and viewport) meets neither
//! the caption's box nor any other panel's (the numbers, the colour legend, the insets' titles;
//! each as the overlay rasterises it, placed by its anchor) nor an inset view. The body keeps
//! the size it has without a caption (over 35 % of the height of a 16:9 frame as wide), and the downhill arrow
//! stays inside the body's view, clear of every panel and inset.
#![cfg(feature = "render")]

use rollphase::geometry::Body;
use rollphase::headless::HeadlessRenderer;
use rollphase::render::overlay::{Font, rasterise};
use rollphase::render::types::{Anchor, Frame};
use rollphase::scene::{PRESETS, Scene};
use rollphase::view::{MeasuredAhead, ROOM_TEXT_PX, ViewOptions};

/// A radius that contains the body (its largest r over a fine set of directions, plus 2 %; a
/// cylinder's half length counts too).
fn bounding_radius(body: &Body) -> f32 {
    let r_max = match body {
        Body::Sphere(s) => {
            let n = 4000;
            (0..n)
                .map(|i| {
                    let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
                    let phi = i as f64 * std::f64::consts::PI * (3.0 - 5f64.sqrt());
                    let rho = (1.0 - z * z).sqrt();
                    s.radius(glam::DVec3::new(rho * phi.cos(), rho * phi.sin(), z))
                })
                .fold(0.0, f64::max)
        }
        Body::Disk(d) => (0..3600)
            .map(|i| d.jet(i as f64 * std::f64::consts::TAU / 3600.0).r)
            .fold(0.0, f64::max),
    };
    let half_length = if matches!(body, Body::Disk(_)) {
        0.5 * rollphase::view::CYLINDER_LENGTH
    } else {
        0.0
    };
    (1.02 * (r_max * r_max + half_length * half_length).sqrt()) as f32
}

/// The body's box on screen (x0, y0, x1, y1 in frame pixels): the main view's camera looks at
/// the body's centre, so the box is centred on the target's projection, and its half size is
/// the projected radius, enlarged for the perspective silhouette.
fn body_box(frame: &Frame, radius: f32) -> [f32; 4] {
    boxes_of(frame, radius, true)
}

/// A body's box at the point the camera looks at: the picture's scale, with one body or more.
fn scale_box(frame: &Frame, radius: f32) -> [f32; 4] {
    boxes_of(frame, radius, false)
}

/// How many bodies the main view draws (meshes at full scale without the ramp's grid).
fn bodies_drawn(frame: &Frame) -> usize {
    frame.views[0]
        .meshes
        .iter()
        .filter(|m| m.material.grid_spacing == 0.0 && m.model.x_axis.truncate().length() > 0.5)
        .count()
}

fn boxes_of(frame: &Frame, radius: f32, every_body: bool) -> [f32; 4] {
    let view = &frame.views[0];
    let [vx, vy, vw, vh] = view.viewport.map(|v| v as f32);
    let cam = &view.camera;
    let view_proj = cam.view_proj(vw / vh);
    let to_pixel = |p: glam::Vec3| {
        let c = view_proj.project_point3(p);
        (vx + (c.x + 1.0) * 0.5 * vw, vy + (1.0 - c.y) * 0.5 * vh)
    };
    let forward = (cam.target - cam.eye).normalize();
    let right = forward.cross(cam.up).normalize();
    let up = right.cross(forward);
    let one = |centre: glam::Vec3| {
        let (cx, cy) = to_pixel(centre);
        let distance = (centre - cam.eye).length();
        let silhouette = 1.0 / (1.0 - (radius / distance).powi(2)).sqrt();
        let rx = (to_pixel(centre + right * radius).0 - cx).abs() * silhouette;
        let ry = (to_pixel(centre + up * radius).1 - cy).abs() * silhouette;
        [cx - rx, cy - ry, cx + rx, cy + ry]
    };
    // Several bodies on the ramp (`[[bodies]]`): each body's mesh, at full scale and without
    // the ramp's grid (not the contact marker, not the ramp), counts.
    let bodies: Vec<glam::Vec3> = view
        .meshes
        .iter()
        .filter(|m| m.material.grid_spacing == 0.0 && m.model.x_axis.truncate().length() > 0.5)
        .map(|m| m.model.w_axis.truncate())
        .collect();
    if bodies.len() < 2 || !every_body {
        return one(cam.target);
    }
    bodies.into_iter().map(one).fold(
        [
            f32::INFINITY,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NEG_INFINITY,
        ],
        |a, b| {
            [
                a[0].min(b[0]),
                a[1].min(b[1]),
                a[2].max(b[2]),
                a[3].max(b[3]),
            ]
        },
    )
}

/// Each panel's box as the overlay draws it, the caption's marked.
fn panel_boxes(frame: &Frame, size: (u32, u32), font: &Font) -> Vec<([f32; 4], bool)> {
    frame
        .panels
        .iter()
        .map(|panel| {
            let image = rasterise(panel, font);
            let (x, y) = panel.anchor.place(image.width, image.height, size);
            let b = [
                x as f32,
                y as f32,
                (x + image.width) as f32,
                (y + image.height) as f32,
            ];
            (b, matches!(panel.anchor, Anchor::BottomCentre(_)))
        })
        .collect()
}

fn apart(a: [f32; 4], b: [f32; 4]) -> bool {
    a[3] <= b[1] || b[3] <= a[1] || a[2] <= b[0] || b[2] <= a[0]
}

#[test]
fn the_caption_never_covers_the_body_on_any_lesson_step() {
    let font = Font::bundled();
    let mut measured = 0;
    for (name, _) in PRESETS.iter().filter(|(n, _)| n.starts_with("lesson-")) {
        let setup = Scene::preset(name).unwrap().setup(None).unwrap();
        let radius = bounding_radius(&setup.body);
        let steps: Vec<f64> = setup.timeline.iter().map(|s| s.at).collect();
        // 768×720 and 1152×1080: the 3D view presentation mode leaves beside the lesson's plot.
        for size in [
            (1280, 720),
            (1600, 900),
            (1920, 1080),
            (3840, 2160),
            (768, 720),
            (1152, 1080),
            // Class mode's 3D view at 1280×720, beside the controls and the lesson's plot.
            (540, 656),
        ] {
            for text_scale in [1.0, 1.8] {
                let mut r = HeadlessRenderer::new(setup.clone(), size, 1).unwrap();
                // Class text is the app's presentation and class modes: a room's 24 px floor.
                let room_text_px = if text_scale > 1.0 { ROOM_TEXT_PX } else { 0.0 };
                // The widest numbers a step can show: a period and a 1/T measured ahead as
                // well.
                r.set_view_options(ViewOptions {
                    text_scale,
                    room_text_px,
                    lesson_ahead: MeasuredAhead {
                        period: Some(2),
                        rate: Some(0.012_345),
                    },
                    ..ViewOptions::default()
                });
                let mut k = 0;
                for (i, &at) in steps.iter().enumerate() {
                    // The first frame of the step (its caption showing), one 2 s later, and
                    // the last before the next step: the key moment, when the overlay has
                    // its longest lines ("period 2: doubled" once the orbit has settled).
                    while setup.frame_time(k) <= at {
                        k += 1;
                    }
                    let mut last = k + 60;
                    if let Some(&next) = steps.get(i + 1) {
                        while setup.frame_time(last + 1) < next {
                            last += 1;
                        }
                    }
                    for frame_k in [k, k + 60, last] {
                        let frame = r.frame_data(frame_k).unwrap();
                        let body = body_box(&frame, radius);
                        let boxes = panel_boxes(&frame, size, &font);
                        let caption = boxes
                            .iter()
                            .find(|b| b.1)
                            .unwrap_or_else(|| panic!("{name} at t = {at}: no caption"))
                            .0;
                        if room_text_px > 0.0 {
                            room_checks(&frame, &boxes, size, &format!("{name} at t = {at}"));
                        }
                        for (b, is_caption) in &boxes {
                            assert!(
                                apart(body, *b),
                                "{name}, step at t = {at}, {size:?}, text ×{text_scale}: body \
                                 box {body:?} meets the {} box {b:?}",
                                if *is_caption { "caption" } else { "panel" }
                            );
                        }
                        // The body is as large as without a caption: the caption's band lifts
                        // the picture instead of shrinking it (it was ~20 % of the height). A
                        // frame narrower than 16:9 (beside a lesson's plot) draws the ramp as
                        // a 16:9 frame as wide would: the body's share is of that height.
                        let height_16_9 = (size.1 as f32).min(size.0 as f32 * 9.0 / 16.0);
                        let scale = scale_box(&frame, radius);
                        let body_share = (scale[3] - scale[1]) / height_16_9;
                        // With other bodies on the ramp (the doubling lesson's last step) the
                        // camera stands back to frame them and the group is fitted between
                        // the numbers and the caption: each body is to stay readable, at least
                        // 0.1 of the height (72 px at 720p), rather than as large as one body
                        // alone.
                        let least = if bodies_drawn(&frame) > 1 { 0.1 } else { 0.35 };
                        assert!(
                            body_share > least,
                            "{name} at t = {at}, {size:?}, text ×{text_scale}: the body is \
                             {body_share:.2} of the frame's (16:9) height"
                        );
                        // The downhill arrow (orange strokes) is drawn, inside the body's view
                        // and clear of every panel and inset (its head hid behind the
                        // Poincaré inset).
                        let mut covers: Vec<[f32; 4]> = boxes.iter().map(|b| b.0).collect();
                        covers.extend(frame.views[1..].iter().map(|inset| {
                            let [x, y, w, h] = inset.viewport.map(|v| v as f32);
                            [x, y, x + w, y + h]
                        }));
                        let view = &frame.views[0];
                        let orange = rollphase::colormap::linear([255, 140, 0], 1.0);
                        let [vx, vy, vw, vh] = view.viewport.map(|v| v as f32);
                        let vp = view.camera.view_proj(vw / vh);
                        let arrow: Vec<_> =
                            view.segments.iter().filter(|s| s.color == orange).collect();
                        assert_eq!(arrow.len(), 3, "{name} at t = {at}: the downhill arrow");
                        for seg in arrow {
                            for p in [seg.a, seg.b] {
                                let c = vp.project_point3(p);
                                let (x, y) =
                                    (vx + (c.x + 1.0) * 0.5 * vw, vy + (1.0 - c.y) * 0.5 * vh);
                                assert!(
                                    covers.iter().all(|c| apart([x, y, x, y], *c)),
                                    "{name} at t = {at}, {size:?}, frame {frame_k}, text \
                                     ×{text_scale}: the arrow's point ({x}, {y}) is under a \
                                     panel or inset: {covers:?}"
                                );
                                assert!(
                                    x >= vx && x <= vx + vw && y >= vy && y <= vy + vh,
                                    "{name} at t = {at}, {size:?}, frame {frame_k}, text ×{text_scale}: the arrow leaves the view at ({x}, {y}) of {:?}: {p:?} → {c:?} cam {:?}",
                                    view.viewport,
                                    view.camera
                                );
                            }
                        }
                        for inset in &frame.views[1..] {
                            let [x, y, w, h] = inset.viewport.map(|v| v as f32);
                            assert!(
                                apart(body, [x, y, x + w, y + h]),
                                "{name} at t = {at}, {size:?}: the body is under an inset"
                            );
                        }
                        if frame_k == k && text_scale == 1.8 {
                            eprintln!(
                                "{name} t = {at:>6} {}x{} class: body y {:.0}–{:.0}, caption y \
                                 {:.0}–{:.0} (gap {:.0} px)",
                                size.0,
                                size.1,
                                body[1],
                                body[3],
                                caption[1],
                                caption[3],
                                caption[1] - body[3]
                            );
                        }
                        measured += 1;
                    }
                }
            }
        }
    }
    assert!(measured >= 3 * 4 * 3 * 4, "{measured} frames measured");
}

/// For a room: every text at least [`ROOM_TEXT_PX`], every panel inside the frame, and no two
/// panels (nor a panel and an inset it does not title) over each other.
fn room_checks(frame: &Frame, boxes: &[([f32; 4], bool)], size: (u32, u32), what: &str) {
    use rollphase::render::types::PanelItem;
    for panel in &frame.panels {
        for item in &panel.items {
            let (text, px) = match item {
                PanelItem::Text { text, size_px, .. } => (text.clone(), *size_px),
                PanelItem::ColorBar {
                    labels, size_px, ..
                } => (format!("{labels:?}"), *size_px),
            };
            assert!(
                px >= ROOM_TEXT_PX,
                "{what}, {size:?}: \"{text}\" at {px:.1} px, under {ROOM_TEXT_PX}"
            );
        }
    }
    let (w, h) = (size.0 as f32, size.1 as f32);
    let insets: Vec<[f32; 4]> = frame.views[1..]
        .iter()
        .map(|v| {
            let [x, y, vw, vh] = v.viewport.map(|u| u as f32);
            [x, y, x + vw, y + vh]
        })
        .collect();
    let inside =
        |b: [f32; 4], r: [f32; 4]| b[0] >= r[0] && b[1] >= r[1] && b[2] <= r[2] && b[3] <= r[3];
    for (i, (a, _)) in boxes.iter().enumerate() {
        assert!(
            inside(*a, [0.0, 0.0, w, h]),
            "{what}, {size:?}: panel {i} {a:?} leaves the frame"
        );
        for (j, (b, _)) in boxes.iter().enumerate().skip(i + 1) {
            assert!(
                apart(*a, *b),
                "{what}, {size:?}: panels {i} {a:?} and {j} {b:?} overlap"
            );
        }
        // A panel inside an inset is its title (over the inset's own views); any other keeps
        // off every inset.
        if insets.iter().any(|inset| inside(*a, *inset)) {
            continue;
        }
        for inset in &insets {
            assert!(
                apart(*a, *inset),
                "{what}, {size:?}: panel {i} {a:?} reaches over the inset {inset:?}"
            );
        }
    }
}

/// With inertia on, the Poincaré inset has no field to wait for: its title says what it needs
/// (it read "computing…" for ever, the reason only in small text under Views).
#[test]
fn the_poincare_inset_says_it_needs_the_viscous_model_when_inertia_is_on() {
    let titles = |mass_ratio: f64| -> Vec<String> {
        let mut setup = Scene::preset("poincare-field")
            .unwrap()
            .setup(None)
            .unwrap();
        // The scene file refuses this pairing; the app reaches it when inertia is switched on.
        setup.ramp = rollphase::dynamics::Ramp::new(setup.ramp.alpha_rad, mass_ratio).unwrap();
        let mut r = HeadlessRenderer::new(setup, (1280, 720), 1).unwrap();
        panel_texts(&r.frame_data(0).unwrap())
            .into_iter()
            .filter(|t| t.starts_with("Poincaré map"))
            .collect()
    };
    let inertial = titles(1.0);
    assert!(
        inertial
            .iter()
            .any(|t| t.contains("needs the viscous model")),
        "{inertial:?}"
    );
    let viscous = titles(0.0);
    assert!(
        viscous
            .iter()
            .all(|t| !t.contains("needs the viscous model")),
        "{viscous:?}"
    );
}

/// The SO(3) ball says in words what a point is and which axis is which (its title was
/// programmer notation, "q (q_w ≥ 0)", and its axes had no labels), in text the room can read.
#[test]
fn the_so3_ball_names_its_point_and_its_axes() {
    use rollphase::render::types::PanelItem;
    for size in [(1280, 720), (1920, 1080)] {
        let setup = Scene::preset("sphere-cruising")
            .unwrap()
            .setup(None)
            .unwrap();
        let mut r = HeadlessRenderer::new(setup, size, 1).unwrap();
        let frame = r.frame_data(0).unwrap();
        let texts: Vec<(String, f32)> = frame
            .panels
            .iter()
            .flat_map(|p| p.items.iter())
            .filter_map(|item| match item {
                PanelItem::Text { text, size_px, .. } => Some((text.clone(), *size_px)),
                _ => None,
            })
            .collect();
        let all: String = texts
            .iter()
            .map(|t| t.0.as_str())
            .collect::<Vec<_>>()
            .join(" ");
        for words in [
            "Orientation (SO(3) ball)",
            "rotation axis × sin(angle/2)",
            "x downhill (red)",
            "y across (green)",
            "z the ramp's normal (blue)",
        ] {
            assert!(all.contains(words), "{size:?}: {words:?} not in {all:?}");
        }
        let key_size = texts
            .iter()
            .find(|t| t.0.contains("downhill (red)"))
            .map(|t| t.1)
            .unwrap();
        assert!(key_size >= 10.0, "{size:?}: the key is {key_size} px");
    }
}

/// Every text line of a frame's panels, in order.
fn panel_texts(frame: &rollphase::render::types::Frame) -> Vec<String> {
    use rollphase::render::types::PanelItem;
    frame
        .panels
        .iter()
        .flat_map(|p| p.items.iter())
        .filter_map(|item| match item {
            PanelItem::Text { text, .. } => Some(text.clone()),
            _ => None,
        })
        .collect()
}

/// The overlay speaks the verdict: once the body would leave the ramp, it says so in place of
/// the rate, and claims no 1/T or period for the motion the model computes past it.
#[test]
fn the_overlay_claims_no_rate_for_a_body_that_left_the_ramp() {
    let mut setup = Scene::preset("sphere-cruising")
        .unwrap()
        .setup(None)
        .unwrap();
    setup.ramp = rollphase::dynamics::Ramp::new(1.0, 10.0).unwrap();
    let mut r = HeadlessRenderer::new(setup, (1280, 720), 1).unwrap();
    let mut lines = |frame: u64| panel_texts(&r.frame_data(frame).unwrap());
    let start = lines(0);
    assert!(
        !start.iter().any(|t| t.contains("left the model")),
        "{start:?}"
    );
    let later = lines(90);
    assert!(
        later
            .iter()
            .any(|t| t.starts_with("left the model: the body leaves the ramp at t = ")),
        "{later:?}"
    );
    assert!(!later.iter().any(|t| t.starts_with("1/T")), "{later:?}");
}

/// Presentation and class modes on every preset that is not a lesson (F5 works on any scene):
/// the room's checks ([`room_checks`]: text, overlaps, the frame) and the body clear of every
/// panel and inset, at the 3D view sizes those modes give.
#[test]
fn every_preset_reads_from_the_back_of_a_room() {
    let font = Font::bundled();
    let mut measured = 0;
    for (name, _) in PRESETS.iter().filter(|(n, _)| !n.starts_with("lesson-")) {
        let setup = Scene::preset(name).unwrap().setup(None).unwrap();
        let radius = bounding_radius(&setup.body);
        // Presentation's whole screen, class mode's view beside a lesson's plot (540×656) and
        // above the row of plots at 1280×720 and 1920×1080 (896×420, 1344×584).
        for size in [
            (1280, 720),
            (1920, 1080),
            (540, 656),
            (896, 420),
            (1344, 584),
        ] {
            let mut r = HeadlessRenderer::new(setup.clone(), size, 1).unwrap();
            r.set_view_options(ViewOptions {
                text_scale: 1.8,
                room_text_px: ROOM_TEXT_PX,
                ..ViewOptions::default()
            });
            for k in [0, 90] {
                let frame = r.frame_data(k).unwrap();
                let boxes = panel_boxes(&frame, size, &font);
                let what = format!("{name}, frame {k}");
                room_checks(&frame, &boxes, size, &what);
                if setup.scene.views.body {
                    let body = body_box(&frame, radius);
                    for (b, _) in &boxes {
                        assert!(
                            apart(body, *b),
                            "{what}, {size:?}: the body {body:?} meets the panel {b:?}"
                        );
                    }
                }
                measured += 1;
            }
        }
    }
    assert!(measured >= 20, "{measured} frames measured");
}

/// A lesson step's period and 1/T, measured ahead on the same run
/// (`LessonEvidence::period_shown`, `rate_shown`), are on the overlay as the step opens, marked
/// so; without them the overlay claims no period before the live run has found one.
#[test]
fn the_overlay_says_the_steps_period_measured_ahead_until_the_live_run_finds_it() {
    let setup = Scene::preset("lesson-period-doubling")
        .unwrap()
        .setup(None)
        .unwrap();
    let mut r = HeadlessRenderer::new(setup, (1280, 720), 1).unwrap();
    let live = panel_texts(&r.frame_data(0).unwrap());
    assert!(!live.iter().any(|t| t.starts_with("period")), "{live:?}");
    assert!(live.iter().any(|t| t == "1/T: measuring…"), "{live:?}");
    for room in [0.0, ROOM_TEXT_PX] {
        r.set_view_options(ViewOptions {
            lesson_ahead: MeasuredAhead {
                period: Some(2),
                rate: Some(0.011_19),
            },
            room_text_px: room,
            ..ViewOptions::default()
        });
        let ahead = panel_texts(&r.frame_data(0).unwrap());
        assert!(
            ahead.iter().any(|t| t == "period 2 (measured ahead)"),
            "{ahead:?}"
        );
        // Its 1/T too, where the plot shows the point already.
        let rate = if room > 0.0 {
            "1/T = 0.0112 (measured ahead)"
        } else {
            "1/T = 0.01119 (measured ahead)"
        };
        assert!(ahead.iter().any(|t| t == rate), "{ahead:?}");
        r.set_view_options(ViewOptions {
            lesson_ahead: MeasuredAhead {
                period: None,
                rate: Some(0.0),
            },
            room_text_px: room,
            ..ViewOptions::default()
        });
        let halted = panel_texts(&r.frame_data(0).unwrap());
        assert!(
            halted.iter().any(|t| t == "halted (measured ahead)"),
            "{halted:?}"
        );
    }
    // Crossings under way but no cycle decided yet (the first settles at t ≈ 256): the live
    // spacing of the last two crossings is no period of the cycle (half of it on a doubled
    // orbit), so the 1/T measured ahead is said in its place; with none ahead the spacing is
    // said for what it is.
    let setup = r.simulation().setup().clone();
    let k = (0u64..).find(|&k| setup.frame_time(k) >= 170.0).unwrap();
    r.set_view_options(ViewOptions::default());
    let spacing = panel_texts(&r.frame_data(k).unwrap());
    assert!(
        spacing
            .iter()
            .any(|t| t.starts_with("1/T = ") && t.ends_with("∂Ω to ∂Ω)")),
        "{spacing:?}"
    );
    assert!(
        !spacing.iter().any(|t| t.starts_with("period")),
        "{spacing:?}"
    );
    r.set_view_options(ViewOptions {
        lesson_ahead: MeasuredAhead {
            period: Some(1),
            rate: Some(0.019_38),
        },
        ..ViewOptions::default()
    });
    let ahead = panel_texts(&r.frame_data(k).unwrap());
    assert!(
        ahead.iter().any(|t| t == "1/T = 0.01938 (measured ahead)"),
        "{ahead:?}"
    );
    assert!(!ahead.iter().any(|t| t.contains("∂Ω to ∂Ω")), "{ahead:?}");
}
