//! The keyboard bindings (see the module map in [`super`]) and class mode.

use egui::Key;

use crate::sim::{SimCommand, SimStatus};
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
        if pressed(Key::Space) {
            actions.push(UiAction::Sim(if status.paused {
                SimCommand::Play
            } else {
                SimCommand::Pause
            }));
        }
        if pressed(Key::ArrowRight) {
            actions.push(UiAction::Sim(SimCommand::Step));
        }
        if pressed(Key::R) {
            actions.push(UiAction::Sim(SimCommand::Reset));
        }
        // A presenter's clicker sends Page Down / Page Up.
        if status.snapshot.lesson.is_some() {
            if pressed(Key::N) || pressed(Key::PageDown) {
                actions.push(UiAction::Sim(SimCommand::NextStep));
            }
            if pressed(Key::B) || pressed(Key::PageUp) {
                actions.push(UiAction::Sim(SimCommand::PreviousStep));
            }
        }
        let faster = pressed(Key::Plus) || pressed(Key::Equals);
        let slower = pressed(Key::Minus);
        if faster || slower {
            let factor = if faster { 2.0 } else { 0.5 };
            self.speed = (status.speed * factor).clamp(SPEED_RANGE.0, SPEED_RANGE.1);
            actions.push(UiAction::Sim(SimCommand::SetSpeed(self.speed)));
        }
        if pressed(Key::F) {
            self.view_options.follow = !self.view_options.follow;
        }
        if pressed(Key::C) {
            self.set_class_mode(ctx, !self.class_mode, actions);
        }
        if pressed(Key::Escape) && self.class_mode {
            self.set_class_mode(ctx, false, actions);
        }
        if pressed(Key::H) {
            self.show_controls = !self.show_controls;
        }
        if pressed(Key::P) {
            self.show_plots = !self.show_plots;
        }
    }

    pub(super) fn set_class_mode(
        &mut self,
        ctx: &egui::Context,
        on: bool,
        actions: &mut Vec<UiAction>,
    ) {
        self.class_mode = on;
        ctx.set_zoom_factor(if on { 1.6 } else { 1.0 });
        self.view_options.text_scale = if on { 1.8 } else { 1.0 };
        actions.push(UiAction::Fullscreen(on));
    }

    pub(super) fn reset_camera(&mut self) {
        self.view_options = ViewOptions {
            text_scale: self.view_options.text_scale,
            follow: self.view_options.follow,
            ..ViewOptions::default()
        };
    }
}
