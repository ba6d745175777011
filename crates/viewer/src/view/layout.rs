//! Where each view goes in the frame, and the fixed camera of the SO(3) ball.

use glam::Vec3;

use crate::render::types::Camera;

use super::SceneView;

impl SceneView {
    /// Rectangles (x, y, w, h) of the body view, the ball and the Poincaré view.
    pub fn layout(&self, size: (u32, u32)) -> [Option<[u32; 4]>; 3] {
        layout_for(size, self.show_body, self.show_ball, self.show_poincare)
    }

    pub(super) fn ball_camera() -> Camera {
        ball_camera()
    }
}

/// The point of ∂Ω (a unit vector, on the side facing the viewer) drawn at pixel (x, y) of a
/// ball or Poincaré view occupying `rect` (x, y, w, h), or `None` off the ball: the inverse of
/// the views' fixed camera, for a click that picks an orientation.
pub fn pick_boundary_point(rect: [u32; 4], x: f32, y: f32) -> Option<glam::DVec3> {
    let [rx, ry, rw, rh] = rect.map(|v| v as f32);
    if rw < 1.0 || rh < 1.0 {
        return None;
    }
    let ndc_x = 2.0 * (x - rx) / rw - 1.0;
    let ndc_y = 1.0 - 2.0 * (y - ry) / rh;
    let inverse = ball_camera().view_proj(rw / rh).inverse();
    let near = inverse.project_point3(Vec3::new(ndc_x, ndc_y, 0.0));
    let far = inverse.project_point3(Vec3::new(ndc_x, ndc_y, 1.0));
    let (o, d) = (near.as_dvec3(), (far - near).as_dvec3().normalize());
    // |o + t d| = 1, nearest root.
    let b = o.dot(d);
    let disc = b * b - (o.length_squared() - 1.0);
    (disc >= 0.0).then(|| (o + d * (-b - disc.sqrt())).normalize())
}

/// Where boundary point `p` is drawn in a ball or Poincaré view occupying `rect` (pixels),
/// if it is on the side facing the viewer.
pub fn boundary_point_position(rect: [u32; 4], p: glam::DVec3) -> Option<(f32, f32)> {
    let [rx, ry, rw, rh] = rect.map(|v| v as f32);
    let camera = ball_camera();
    if p.dot((camera.eye - camera.target).as_dvec3()) <= 0.0 {
        return None;
    }
    let c = camera.view_proj(rw / rh).project_point3(p.as_vec3());
    Some((rx + (c.x + 1.0) * 0.5 * rw, ry + (1.0 - c.y) * 0.5 * rh))
}

/// Rectangles (x, y, w, h) of the body view, the ball and the Poincaré view in a frame of
/// `size` with these views shown.
pub fn layout_for(
    size: (u32, u32),
    show_body: bool,
    show_ball: bool,
    show_poincare: bool,
) -> [Option<[u32; 4]>; 3] {
    let (w, h) = size;
    let insets = [show_ball, show_poincare];
    let n_insets = insets.iter().filter(|&&x| x).count() as u32;
    if show_body {
        let margin = (h / 60).max(4);
        let side = if n_insets == 2 {
            (h - 3 * margin) / 2
        } else {
            (h as f32 * 0.42) as u32
        }
        .min(w / 3);
        let mut y = margin;
        let mut place = |on: bool| {
            on.then(|| {
                let r = [w - side - margin, y, side, side];
                y += side + margin;
                r
            })
        };
        let ball = place(show_ball);
        let poincare = place(show_poincare);
        [Some([0, 0, w, h]), ball, poincare]
    } else {
        let cols = n_insets.max(1);
        let cw = w / cols;
        let mut x = 0;
        let mut place = |on: bool| {
            on.then(|| {
                let r = [x, 0, cw, h];
                x += cw;
                r
            })
        };
        let ball = place(show_ball);
        let poincare = place(show_poincare);
        [None, ball, poincare]
    }
}

/// The fixed camera of the ball and Poincaré views.
pub fn ball_camera() -> Camera {
    Camera {
        eye: Vec3::new(1.3, -2.2, 1.2).normalize() * 3.3,
        target: Vec3::ZERO,
        up: Vec3::Z,
        fov_y_rad: 40f32.to_radians(),
        near: 0.1,
        far: 20.0,
    }
}
