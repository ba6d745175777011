//! Which body point lies under a pixel of the 3D view, for sculpting by hand: the body's surface
//! sampled densely in its own frame (6,000 nearly uniform directions on a 3D body; 720 angles
//! by 9 lengths on a cylinder's side), carried through the frame's own body transform and
//! camera; of the samples facing the eye (the body is convex: those are the ones drawn), the
//! one drawn nearest the pointer, within a few pixels.
//! The samples lie ~0.05 rad apart, finer than the narrowest stroke; and no mesh or depth buffer
//! is read back, so a pick costs about a millisecond and works the same headless.

use glam::{DVec3, Mat4, Vec3};

use crate::geometry::Body;
use crate::geometry::sculpt::StrokePoint;
use crate::geometry::sphere::fibonacci_sphere;
use crate::render::types::{Camera, Frame, MeshHandle};

use super::CYLINDER_LENGTH;

/// How far from the pointer (pixels) a surface sample may project and still be picked.
const PICK_RADIUS_PX: f32 = 8.0;

/// What a pick needs of a drawn frame: the body's view and where the body was drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PickView {
    /// The view's rectangle in the frame (x, y from the top left, width, height; pixels).
    pub viewport: [u32; 4],
    /// Its camera.
    pub camera: Camera,
    /// World from the body's own frame, as the body's mesh was drawn.
    pub world_from_body: Mat4,
}

impl PickView {
    /// The view of `frame` that draws the mesh `body` (the main view), if one does.
    pub fn of(frame: &Frame, body: MeshHandle) -> Option<Self> {
        frame.views.iter().find_map(|view| {
            let mesh = view.meshes.iter().find(|m| m.mesh == body)?;
            Some(Self {
                viewport: view.viewport,
                camera: view.camera,
                world_from_body: mesh.model,
            })
        })
    }

    /// Where body-frame point `p` is drawn (frame pixels) and its depth (0 near … 1 far), if in
    /// front of the camera.
    pub fn project(&self, p: DVec3) -> Option<(f32, f32, f32)> {
        let [vx, vy, vw, vh] = self.viewport.map(|v| v as f32);
        let clip = self.camera.view_proj(vw / vh.max(1.0))
            * self.world_from_body
            * p.as_vec3().extend(1.0);
        (clip.w > 0.0).then(|| {
            let ndc = clip.truncate() / clip.w;
            (
                vx + (ndc.x + 1.0) * 0.5 * vw,
                vy + (1.0 - ndc.y) * 0.5 * vh,
                ndc.z,
            )
        })
    }
}

/// The body point drawn at frame pixel (`x`, `y`), if the body is there: a direction on a 3D
/// body, a polar angle on a cylinder's side (its flat ends are no surface of the 2D body). The
/// body is convex, so the surface samples that face the eye are the ones drawn; of those, the
/// one drawn nearest the pixel.
pub fn body_point_at(view: &PickView, body: &Body, x: f32, y: f32) -> Option<StrokePoint> {
    let eye = eye_in_body(view);
    let drawn_at = |p: DVec3, normal: DVec3| {
        if normal.dot(eye - p) <= 0.0 {
            return None;
        }
        let (px, py, _) = view.project(p)?;
        let off = (px - x).hypot(py - y);
        (off <= PICK_RADIUS_PX).then_some(off)
    };
    let nearest = |best: Option<(f32, StrokePoint)>, candidate: Option<(f32, StrokePoint)>| match (
        best, candidate,
    ) {
        (Some(b), Some(c)) if c.0 < b.0 => Some(c),
        (None, c) => c,
        (b, _) => b,
    };
    match body {
        Body::Sphere(s) => fibonacci_sphere(6000)
            .into_iter()
            .map(|u| {
                let sp = s.surface(u);
                drawn_at(sp.p, sp.normal).map(|off| (off, StrokePoint::Sphere { u }))
            })
            .fold(None, nearest),
        Body::Disk(d) => {
            let half = 0.5 * CYLINDER_LENGTH;
            (0..720)
                .flat_map(|i| (0..9).map(move |k| (i, k)))
                .map(|(i, k)| {
                    let theta = std::f64::consts::TAU * i as f64 / 720.0;
                    let along = -half + CYLINDER_LENGTH * k as f64 / 8.0;
                    let j = d.jet(theta);
                    let (sn, c) = theta.sin_cos();
                    let p = DVec3::new(j.r * c, along, j.r * sn);
                    // The outward normal of the curve (r cos θ, r sin θ), as the mesh has it.
                    let tangent = DVec3::new(j.r1 * c - j.r * sn, 0.0, j.r1 * sn + j.r * c);
                    let normal = DVec3::new(tangent.z, 0.0, -tangent.x);
                    drawn_at(p, normal).map(|off| (off, StrokePoint::Disk { theta }))
                })
                .fold(None, nearest)
        }
    }
    .map(|(_, point)| point)
}

/// The camera's eye in the body's frame (for tests: which side of the body faces the viewer).
pub fn eye_in_body(view: &PickView) -> DVec3 {
    let eye: Vec3 = view.camera.eye;
    view.world_from_body
        .inverse()
        .transform_point3(eye)
        .as_dvec3()
}
