//! The keyboard bindings (see the module map in [`super`]), class mode, presentation mode and
//! the `?` legend of the keys.

use egui::Key;

use crate::live::{SimCommand, SimStatus};
use crate::view::ViewOptions;

use super::{AppUi, SPEED_RANGE, UiAction};

impl AppUi {
    pub(super) fn keyboard(
        &mut self,
        ctx: &egui::Context,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let pressed = |k: Key| ctx.input(|i| i.key_pressed(k));
        // Keys that act once per press: two presses within one frame (a slow renderer, a
        // clicker) are two steps, not one.
        let presses = |k: Key| ctx.input(|i| i.num_presses(k));
        if pressed(Key::Space) {
            actions.push(UiAction::Sim(if status.paused {
                SimCommand::Play
            } else {
                SimCommand::Pause
            }));
        }
        for _ in 0..presses(Key::ArrowRight) {
            actions.push(UiAction::Sim(SimCommand::Step));
        }
        if pressed(Key::R) {
            actions.push(UiAction::Sim(SimCommand::Reset));
        }
        // A presenter's clicker sends Page Down / Page Up.
        if status.snapshot.lesson.is_some() {
            for _ in 0..presses(Key::N) + presses(Key::PageDown) {
                actions.push(UiAction::Sim(SimCommand::NextStep));
            }
            for _ in 0..presses(Key::B) + presses(Key::PageUp) {
                actions.push(UiAction::Sim(SimCommand::PreviousStep));
            }
        }
        let doublings =
            (presses(Key::Plus) + presses(Key::Equals)) as i32 - presses(Key::Minus) as i32;
        if presses(Key::Plus) + presses(Key::Equals) + presses(Key::Minus) > 0 {
            self.speed = (status.speed * 2f64.powi(doublings)).clamp(SPEED_RANGE.0, SPEED_RANGE.1);
            actions.push(UiAction::Sim(SimCommand::SetSpeed(self.speed)));
        }
        if pressed(Key::F) {
            self.view_options.follow = !self.view_options.follow;
            // Where the body is now: the camera stays there, not at the ramp's far origin.
            self.view_options.fixed_target = Some(status.snapshot.pose.centre);
        }
        if pressed(Key::F5) {
            self.set_presentation(ctx, !self.presenting, actions);
        }
        if pressed(Key::Questionmark) || pressed(Key::F1) {
            self.show_keys = !self.show_keys;
        }
        if pressed(Key::C) {
            self.set_class_mode(ctx, !self.class_mode, actions);
        }
        // Esc closes an open menu first (egui closes it when it draws it, after this): it must
        // not also leave class or presentation mode.
        if pressed(Key::Escape) && !egui::Popup::is_any_open(ctx) {
            if self.show_keys {
                self.show_keys = false;
            } else if self.presenting {
                self.set_presentation(ctx, false, actions);
            } else if self.class_mode {
                self.set_class_mode(ctx, false, actions);
            }
        }
        if pressed(Key::H) {
            self.show_controls = !self.show_controls;
        }
        if pressed(Key::P) {
            self.show_plots = !self.show_plots;
        }
        // Shift+Ctrl+Z first: Ctrl+Z alone would also match it (egui ignores an extra Shift).
        let shortcut = |m, k| egui::KeyboardShortcut::new(m, k);
        let redo = ctx.input_mut(|i| {
            i.consume_shortcut(&shortcut(
                egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
                Key::Z,
            )) || i.consume_shortcut(&shortcut(egui::Modifiers::COMMAND, Key::Y))
        });
        let undo = !redo
            && ctx.input_mut(|i| i.consume_shortcut(&shortcut(egui::Modifiers::COMMAND, Key::Z)));
        if undo || redo {
            self.step_history(undo, status, actions);
        }
    }

    pub(super) fn set_class_mode(
        &mut self,
        ctx: &egui::Context,
        on: bool,
        actions: &mut Vec<UiAction>,
    ) {
        self.class_mode = on;
        // The pointer rests where it was: no values under it on the large plot until it moves.
        self.pointer_resting = on;
        self.mode_entered_at = ctx.input(|i| i.time);
        ctx.set_zoom_factor(if on {
            class_zoom(ctx.content_rect().size() * ctx.zoom_factor())
        } else {
            1.0
        });
        self.view_options.text_scale = if on { 1.8 } else { 1.0 };
        self.view_options.room_text_px = if on { crate::view::ROOM_TEXT_PX } else { 0.0 };
        actions.push(UiAction::Fullscreen(on));
    }

    /// Presentation mode: the 3D view fills the (full) screen with class mode's large text; the
    /// menu, controls, plots and status bar are hidden until it is left (F5 or Esc), when the
    /// panels come back as they were.
    pub fn set_presentation(&mut self, ctx: &egui::Context, on: bool, actions: &mut Vec<UiAction>) {
        if on == self.presenting {
            return;
        }
        if on {
            self.panels_before = (self.show_controls, self.show_plots);
            self.show_controls = false;
            self.show_plots = false;
            self.view_options.follow = true;
            self.notice = Some((
                "presentation: F5 or Esc to leave, ? for the keys".into(),
                false,
            ));
        } else {
            (self.show_controls, self.show_plots) = self.panels_before;
            // Its hint is about a mode that has ended.
            if self
                .notice
                .as_ref()
                .is_some_and(|(n, _)| n.starts_with("presentation: "))
            {
                self.notice = None;
            }
        }
        self.presenting = on;
        self.set_class_mode(ctx, on, actions);
    }

    /// The keys, as the `?` legend lists them.
    pub const KEYS: [(&'static str, &'static str); 15] = [
        ("Space", "play / pause"),
        ("→", "one step"),
        ("R", "restart the scene"),
        ("+ / −", "speed ×2 / ÷2"),
        ("N, Page Down", "next lesson step"),
        ("B, Page Up", "previous lesson step"),
        ("F", "follow the body / hold the camera"),
        ("F5", "presentation mode"),
        ("C", "class mode (large text, full screen)"),
        ("H", "hide / show the controls"),
        ("P", "hide / show the plots"),
        ("Ctrl+Z", "undo a sculpting stroke"),
        ("Ctrl+Y, Ctrl+Shift+Z", "redo it"),
        ("Esc", "close this list; leave presentation or class mode"),
        ("?", "this list"),
    ];

    pub(super) fn keys_legend_ui(&self, ctx: &egui::Context) {
        if !self.show_keys {
            return;
        }
        let Some(rect) = self.scene_rect else {
            return;
        };
        egui::Area::new(egui::Id::unique("rollphase-keys"))
            .fixed_pos(egui::pos2(rect.left() + 12.0, rect.top() + 12.0))
            .interactable(false)
            .show(ctx, |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    egui::Grid::new("keys").num_columns(2).show(ui, |ui| {
                        for (key, what) in Self::KEYS {
                            ui.label(egui::RichText::new(key).strong());
                            ui.label(what);
                            ui.end_row();
                        }
                    });
                });
            });
    }

    /// In class mode, follows the window's size with the zoom (it goes full screen after the
    /// mode is set, and a window can be resized).
    pub(super) fn keep_class_zoom(&self, ctx: &egui::Context) {
        if !self.class_mode {
            return;
        }
        let zoom = class_zoom(ctx.content_rect().size() * ctx.zoom_factor());
        if (ctx.zoom_factor() - zoom).abs() > 0.01 {
            ctx.set_zoom_factor(zoom);
        }
    }

    pub(super) fn reset_camera(&mut self) {
        self.view_options = ViewOptions {
            text_scale: self.view_options.text_scale,
            room_text_px: self.view_options.room_text_px,
            follow: self.view_options.follow,
            lesson_ahead: self.view_options.lesson_ahead,
            fixed_target: None,
            ..ViewOptions::default()
        };
    }
}

/// Class mode's egui zoom for a window of `size` points at zoom 1: 1.6 at 1600×900 and above,
/// less on a smaller window so that the controls and the plots leave the 3D view most of it
/// (at 1280×720 the zoom 1.6 left it 660×215 px and pushed the last plot off the window).
pub(super) fn class_zoom(size: egui::Vec2) -> f32 {
    (1.6 * (size.x / 1600.0).min(size.y / 900.0)).clamp(1.1, 1.6)
}
