//! Starts picked in the views: a click on the curvature map restarts the run with that body
//! point on the ramp, a click in the SO(3) ball's inset or on the Poincaré field restarts it
//! at that orientation, and the views' rectangles those clicks are read in.

use super::{AppUi, UiAction};
use crate::live::{SimCommand, SimStatus};

impl AppUi {
    /// Restarts the run with body point (θ, φ) on the ramp (a click on the curvature map): the
    /// current α, m/m0, integrator and speed, released from rest with no spin, so the trails
    /// clear; the notice says where it restarted.
    pub(super) fn restart_from_contact(
        &mut self,
        theta: f64,
        phi: f64,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let initial = crate::scene::InitialSpec {
            contact: Some([theta, phi]),
            ..crate::scene::InitialSpec::default()
        };
        let said = format!("with body point θ = {theta:.3}, φ = {phi:.3} on the ramp");
        self.restart_from(initial, &said, status, actions);
    }

    /// Restarts the run of the current scene (live α, m/m0, integrator, speed) from `initial`,
    /// as a new run of the same scene; the notice says "restarted at t = 0 {said}", or why the
    /// start was refused.
    pub(super) fn restart_from(
        &mut self,
        initial: crate::scene::InitialSpec,
        said: &str,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let mut scene = self.current_scene(status);
        scene.initial = initial;
        match scene.setup(self.base.as_deref()) {
            Ok(setup) => {
                self.notice = Some((format!("restarted at t = 0 {said}"), false));
                actions.push(UiAction::Sim(SimCommand::Restart(Box::new(setup))));
            }
            Err(e) => self.notice = Some((e.to_string(), true)),
        }
    }

    /// The point of ∂Ω under `pos` (points) if it falls on the Poincaré sphere of the scene
    /// area `rect`.
    pub(super) fn poincare_pick(
        &self,
        rect: egui::Rect,
        pos: egui::Pos2,
        status: &SimStatus,
    ) -> Option<glam::DVec3> {
        let inset = self.poincare_rect(rect.size(), status)?;
        let ppp = self.pixels_per_point;
        let (x, y) = ((pos.x - rect.min.x) * ppp, (pos.y - rect.min.y) * ppp);
        let [rx, ry, rw, rh] = inset.map(|v| v as f32);
        let inside = x >= rx && x < rx + rw && y >= ry && y < ry + rh;
        inside
            .then(|| crate::view::layout::pick_boundary_point(inset, x, y))
            .flatten()
    }

    /// Whether `pos` (points) falls on the SO(3) ball's inset of the scene area `rect`.
    pub(super) fn in_ball_inset(
        &self,
        rect: egui::Rect,
        pos: egui::Pos2,
        status: &SimStatus,
    ) -> bool {
        let ppp = self.pixels_per_point;
        let ball = self.view_rects(rect.size(), status)[1];
        let (x, y) = ((pos.x - rect.min.x) * ppp, (pos.y - rect.min.y) * ppp);
        ball.is_some_and(|[rx, ry, rw, rh]| {
            let [rx, ry, rw, rh] = [rx, ry, rw, rh].map(|v| v as f32);
            x >= rx && x < rx + rw && y >= ry && y < ry + rh
        })
    }

    /// The Poincaré view's rectangle (pixels, relative to the scene area), if it is shown.
    pub(super) fn poincare_rect(&self, scene: egui::Vec2, status: &SimStatus) -> Option<[u32; 4]> {
        self.view_rects(scene, status)[2]
    }

    /// The rectangles (pixels, relative to the scene area of `scene` points) of the body view,
    /// the SO(3) ball and the Poincaré view, as the frame lays them out (a cylinder has no
    /// insets).
    pub(super) fn view_rects(
        &self,
        scene: egui::Vec2,
        status: &SimStatus,
    ) -> [Option<[u32; 4]>; 3] {
        let disk = status.snapshot.theta.is_some();
        let ppp = self.pixels_per_point;
        crate::view::layout::layout_for(
            ((scene.x * ppp) as u32, (scene.y * ppp) as u32),
            self.views.body,
            self.views.ball && !disk,
            self.views.poincare && !disk,
        )
    }

    /// Where boundary point `p` is drawn on the Poincaré sphere (screen points), if shown and
    /// facing the viewer: for tests and scripted demos, which click there.
    pub fn poincare_position(&self, p: glam::DVec3, status: &SimStatus) -> Option<egui::Pos2> {
        let rect = self.scene_rect?;
        let inset = self.poincare_rect(rect.size(), status)?;
        let (x, y) = crate::view::layout::boundary_point_position(inset, p)?;
        let ppp = self.pixels_per_point;
        Some(rect.min + egui::vec2(x / ppp, y / ppp))
    }

    /// Restarts the run from orientation q = (0, p) on ∂Ω (a rotation by π about `p`), released
    /// from rest with the current α, m/m0, integrator and speed.
    pub(super) fn restart_from_boundary(
        &mut self,
        p: glam::DVec3,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let initial = crate::scene::InitialSpec {
            q0: Some([0.0, p.x, p.y, p.z]),
            ..crate::scene::InitialSpec::default()
        };
        let said = format!("from q = (0, {:.3}, {:.3}, {:.3}) on ∂Ω", p.x, p.y, p.z);
        self.restart_from(initial, &said, status, actions);
    }

    /// Restarts the run with the body as it is now turned by `angle` about the ramp normal
    /// (shift-drag in the 3D view): the contact point stays, and the body is released from
    /// rest with the current α, m/m0, integrator and speed.
    pub(super) fn restart_turned(
        &mut self,
        angle: f64,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let q = glam::DQuat::from_rotation_z(angle) * status.snapshot.pose.rotation;
        let initial = crate::scene::InitialSpec {
            q0: Some([q.w, q.x, q.y, q.z]),
            ..crate::scene::InitialSpec::default()
        };
        let said = format!("turned by {:.0}° about the ramp normal", angle.to_degrees());
        self.restart_from(initial, &said, status, actions);
    }

    /// Where body point (θ, φ) is drawn on the contact map (screen points), if the map is shown:
    /// for tests and scripted demos, which click there.
    pub fn map_position(&self, theta: f64, phi: f64) -> Option<egui::Pos2> {
        self.map_transform
            .map(|t| t.position_from_point(&egui_plot::PlotPoint::new(phi, theta)))
    }
}
