//! Where each view goes in the frame, and the fixed camera of the SO(3) ball.

use glam::Vec3;

use crate::render::types::Camera;

use super::SceneView;

impl SceneView {
    /// Rectangles (x, y, w, h) of the body view, the ball and the Poincaré view.
    pub fn layout(&self, size: (u32, u32)) -> [Option<[u32; 4]>; 3] {
        let (w, h) = size;
        let insets = [self.show_ball, self.show_poincare];
        let n_insets = insets.iter().filter(|&&x| x).count() as u32;
        if self.show_body {
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
            let ball = place(self.show_ball);
            let poincare = place(self.show_poincare);
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
            let ball = place(self.show_ball);
            let poincare = place(self.show_poincare);
            [None, ball, poincare]
        }
    }

    pub(super) fn ball_camera() -> Camera {
        Camera {
            eye: Vec3::new(1.3, -2.2, 1.2).normalize() * 3.3,
            target: Vec3::ZERO,
            up: Vec3::Z,
            fov_y_rad: 40f32.to_radians(),
            near: 0.1,
            far: 20.0,
        }
    }
}
