//! The body on the ramp (meshes, trails, arrows), the SO(3) ball with the orientation's path,
//! and the Poincaré field on ∂Ω, as the renderer's plain draw data.

use std::f32::consts::PI;

use glam::{DVec3, Mat4, Quat, Vec3};

use crate::analysis::orbits::poincare_field::FieldArrow;
use crate::colormap::{VIRIDIS, linear, sample};
use crate::live::Snapshot;
use crate::render::types::{Camera, Material, MeshInstance, Segment, View};

use super::{CYLINDER_LENGTH, SceneView, ViewOptions};

/// The downhill arrow's three strokes on the ramp (ramp coordinates): the first placement, from
/// the preferred one (2.2 ⟨r⟩ in front of the body, 2.4 ⟨r⟩ long) towards smaller and nearer
/// ones, then the same behind the body, whose every point projects inside the frame with a 6%
/// margin and outside the body's silhouette (the body, a sphere of `body.1` around `body.0` in
/// world coordinates, would hide it or show a stick poking out); the smallest if none does (an
/// extreme aspect ratio or zoom). `covered` are boxes of the view, in clip space (x0, y0, x1,
/// y1), drawn over by something else (the ball and Poincaré insets): no point may fall in one.
fn downhill_arrow(
    camera: &Camera,
    aspect: f32,
    (centre_x, centre_y): (f64, f64),
    to_world: impl Fn(DVec3) -> Vec3,
    body: (Vec3, f32),
    covered: &[[f32; 4]],
) -> [(DVec3, DVec3); 3] {
    // Centred `ahead` downhill of the body and `y` across the ramp from it (a sphere drifts
    // across the ramp as it rolls), `half` its half length.
    let strokes = |y: f64, half: f64, ahead: f64| {
        let y = centre_y + y;
        let barb = (0.35 * half / 1.2, 0.25 * half / 1.2);
        let (x0, x1) = (centre_x + ahead - half, centre_x + ahead + half);
        let tip = DVec3::new(x1, y, 0.01);
        [
            (DVec3::new(x0, y, 0.01), tip),
            (tip, DVec3::new(x1 - barb.0, y - barb.1, 0.01)),
            (tip, DVec3::new(x1 - barb.0, y + barb.1, 0.01)),
        ]
    };
    let view_proj = camera.view_proj(aspect);
    let ndc = |p: Vec3| {
        let c = view_proj * p.extend(1.0);
        (c.w > 0.0).then(|| (c.x / c.w, c.y / c.w))
    };
    // The body's silhouette, as an ellipse in clip space, widened by 10 %.
    let forward = (camera.target - camera.eye).normalize();
    let right = forward.cross(camera.up).normalize();
    let up = right.cross(forward);
    let silhouette = ndc(body.0).and_then(|(cx, cy)| {
        let (rx, _) = ndc(body.0 + right * body.1)?;
        let (_, ry) = ndc(body.0 + up * body.1)?;
        Some((cx, cy, 1.1 * (rx - cx).abs(), 1.1 * (ry - cy).abs()))
    });
    let visible = |p: Vec3, need_clear: bool| {
        let Some((x, y)) = ndc(p) else {
            return false;
        };
        let in_frame = x.abs() <= 0.94
            && y.abs() <= 0.94
            && covered
                .iter()
                .all(|c| x < c[0] || x > c[2] || y < c[1] || y > c[3]);
        let clear = !need_clear
            || silhouette.is_none_or(|(cx, cy, rx, ry)| {
                ((x - cx) / rx.max(1e-6)).powi(2) + ((y - cy) / ry.max(1e-6)).powi(2) > 1.0
            });
        in_frame && clear
    };
    // Every point along each stroke, not only its ends: a shaft can cross the body.
    let stroke_visible = |(a, b): (DVec3, DVec3), need_clear: bool| {
        (0..=8).all(|i| visible(to_world(a.lerp(b, f64::from(i) / 8.0)), need_clear))
    };
    let mut last = strokes(-1.4, 0.5, 0.0);
    // In front of the body (towards the camera), from far and long to near and short; then
    // ahead of it downhill, beside it on the screen (a short, wide view under a caption band
    // has no room in front); then behind it. Clear of the body if any placement is; else
    // the first inside the frame.
    for need_clear in [true, false] {
        for (ahead, side) in [(0.0, 1.0), (2.6, 1.0), (0.0, -1.0)] {
            let ys: &[f64] = if ahead > 0.0 {
                &[0.0, -0.4, -0.8, -1.2]
            } else {
                &[-2.2, -2.0, -1.8, -1.6, -1.4]
            };
            for half in [1.2, 1.0, 0.8, 0.6, 0.5] {
                for &y in ys {
                    let s = strokes(side * y, half, ahead + half);
                    if s.iter().all(|&st| stroke_visible(st, need_clear)) {
                        return s;
                    }
                    if side > 0.0 && ahead == 0.0 {
                        last = s;
                    }
                }
            }
        }
    }
    last
}

/// Pixel rectangles (x, y, w, h) of the frame as boxes (x0, y0, x1, y1) in the clip space of
/// a view drawn in `rect`.
fn clip_boxes(rect: [u32; 4], pixels: &[[u32; 4]]) -> Vec<[f32; 4]> {
    let [rx, ry, rw, rh] = rect.map(|v| v as f32);
    let ndc_x = |x: f32| 2.0 * (x - rx) / rw.max(1.0) - 1.0;
    let ndc_y = |y: f32| 1.0 - 2.0 * (y - ry) / rh.max(1.0);
    pixels
        .iter()
        .map(|c| {
            let [cx, cy, cw, ch] = c.map(|v| v as f32);
            [ndc_x(cx), ndc_y(cy + ch), ndc_x(cx + cw), ndc_y(cy)]
        })
        .collect()
}

/// Radius of the ring that marks a sphere's contact point through the body (ramp units, ⟨r⟩ = 1).
const CONTACT_RING_RADIUS: f64 = 0.12;

impl SceneView {
    /// The body on the ramp drawn in `rect`, at the pixel scale of a view `scale_height` pixels
    /// tall: a view shortened by a lesson's caption band shows the body as large as a full
    /// one (a narrower field of view, not a smaller body; drawing the ramp on behind the caption
    /// instead cost llvmpipe 5 % of the frame). `covered` are the frame's rectangles drawn over
    /// this view (the insets), which the downhill arrow keeps out of.
    pub(super) fn body_view(
        &self,
        snap: &Snapshot,
        rect: [u32; 4],
        scale_height: u32,
        covered: &[[u32; 4]],
        options: &ViewOptions,
    ) -> View {
        let alpha = snap.alpha_rad as f32;
        let world_from_ramp = Mat4::from_rotation_y(alpha);
        let to_world = |p: DVec3| world_from_ramp.transform_point3(p.as_vec3());
        // A cylinder's contact points are given on its mid-plane; draw them on the front face.
        let on_face = |p: DVec3| {
            if self.is_disk {
                DVec3::new(p.x, p.y - CYLINDER_LENGTH / 2.0, p.z)
            } else {
                p
            }
        };
        let centre = snap.pose.centre.as_vec3();
        // With other bodies on the ramp, the camera frames them all while it can.
        let placement = self.lanes.placement(snap);
        let (framed, lanes_zoom) = (placement.target, placement.zoom);
        let target = match (options.follow, options.fixed_target) {
            (false, Some(fixed)) => world_from_ramp.transform_point3(fixed.as_vec3()),
            _ => world_from_ramp.transform_point3(framed.as_vec3()),
        };
        // Parallel lanes are across the ramp, in depth to the usual camera: with other bodies
        // it looks down more steeply and from further uphill, so that they stand apart on the
        // screen.
        let (pitch, yaw) = (placement.pitch, placement.yaw);
        let options = &ViewOptions {
            zoom: options.zoom * lanes_zoom,
            pitch: options.pitch + pitch,
            yaw: options.yaw + yaw,
            ..*options
        };
        let full_height = scale_height.max(rect[3]).max(1) as f32;
        let shortened = rect[3].max(1) as f32 / full_height;
        // A view narrower than 16:9 of its full height (beside a lesson's large plot) shows
        // as much of the ramp across as a 16:9 one would: the body is drawn smaller rather
        // than reaching the numbers and the insets at the sides.
        let narrow = (16.0 / 9.0 * full_height / rect[2].max(1) as f32).max(1.0);
        let camera = self.body_camera(target, options, shortened * narrow);
        let snap_to = |v: f32| (v / 5.0).round() * 5.0;
        // Nearest first: the ramp, drawn last, is not shaded where the body and the marker
        // already cover it (the depth test drops those pixels before shading; on a CPU
        // renderer shading is most of a frame). Opaque and depth-tested, so the picture is
        // the same in any order.
        let mut meshes = vec![
            MeshInstance {
                mesh: self.body_mesh,
                model: world_from_ramp
                    * Mat4::from_rotation_translation(snap.pose.rotation.as_quat(), centre),
                material: Material::default(),
            },
            MeshInstance {
                mesh: self.marker_mesh,
                model: Mat4::from_scale_rotation_translation(
                    Vec3::splat(0.06),
                    Quat::IDENTITY,
                    to_world(on_face(snap.contact_on_ramp)),
                ),
                material: Material {
                    tint: linear([255, 214, 10], 1.0),
                    ..Material::default()
                },
            },
            MeshInstance {
                mesh: self.ramp_mesh,
                model: world_from_ramp
                    * Mat4::from_translation(Vec3::new(snap_to(centre.x), snap_to(centre.y), 0.0)),
                material: Material {
                    grid_spacing: 0.5,
                    specular: 0.05,
                    ..Material::default()
                },
            },
        ];
        let mut segments = Vec::new();
        // Contact path on the ramp, fading with age.
        let lift = DVec3::new(0.0, 0.0, 0.004);
        push_polyline(
            &mut segments,
            snap.ramp_trail.iter().map(|&p| to_world(on_face(p) + lift)),
            3.0,
            |age| linear(crate::colormap::body_colour(0), 0.25 + 0.75 * age),
        );
        // Contact trail on the body, carried with the body.
        let body_to_world =
            world_from_ramp * Mat4::from_rotation_translation(snap.pose.rotation.as_quat(), centre);
        let push_out = |p: DVec3| {
            if self.is_disk {
                // The front face: a hair in front of it, so the trail is not hidden by the cap.
                DVec3::new(p.x * 1.0, p.y - 0.004, p.z)
            } else {
                p * 1.006
            }
        };
        push_polyline(
            &mut segments,
            snap.body_trail
                .iter()
                .map(|&p| body_to_world.transform_point3(push_out(on_face(p)).as_vec3())),
            2.5,
            |age| linear([20, 20, 20], 0.35 + 0.65 * age),
        );
        // A dented cylinder's hull: the flats it rolls on across its dents, on the front face.
        let on_front = |p: DVec3| body_to_world.transform_point3(push_out(on_face(p)).as_vec3());
        segments.extend(self.hull_flat_segments(on_front));
        // Downhill arrow, painted on the ramp in front of the body, placed and sized so that
        // it lies inside the frame (at 1280×720 the old fixed place cut its lower barb).
        let aspect = rect[2].max(1) as f32 / rect[3].max(1) as f32;
        let orange = linear([255, 140, 0], 1.0);
        let body = (world_from_ramp.transform_point3(centre), self.body_radius);
        let at = (f64::from(centre.x), f64::from(centre.y));
        let covered = clip_boxes(rect, covered);
        for (a, b) in downhill_arrow(&camera, aspect, at, to_world, body, &covered) {
            segments.push(Segment {
                a: to_world(a),
                b: to_world(b),
                color: orange,
                width_px: 5.0,
            });
        }
        // Under a sphere the contact point is hidden from any camera above the ramp: a yellow
        // ring around it, drawn through the body, shows where it is (a cylinder's contact on
        // its front face is in plain sight).
        let mut segments_on_top = Vec::new();
        if !self.is_disk {
            let contact = snap.contact_on_ramp + DVec3::new(0.0, 0.0, 0.004);
            let ring: Vec<Vec3> = (0..=32)
                .map(|i| {
                    let a = std::f64::consts::TAU * f64::from(i) / 32.0;
                    to_world(contact + CONTACT_RING_RADIUS * DVec3::new(a.cos(), a.sin(), 0.0))
                })
                .collect();
            let yellow = linear([255, 214, 10], 0.9);
            segments_on_top.extend(ring.windows(2).map(|w| Segment {
                a: w[0],
                b: w[1],
                color: yellow,
                width_px: 3.0,
            }));
        }
        let (lane_meshes, lane_segments, lane_rings) =
            self.lanes
                .draw(snap, world_from_ramp, to_world, on_face, self.is_disk);
        // Before the ramp: the ramp, drawn last, is not shaded where a body covers it.
        meshes.splice(0..0, lane_meshes);
        segments.extend(lane_segments);
        segments_on_top.extend(lane_rings);
        View {
            viewport: rect,
            background: None,
            camera,
            light_dir: Vec3::new(-0.4, -0.6, 1.0),
            meshes,
            segments,
            segments_on_top,
        }
    }

    /// The camera of the body's view looking at `target`, turned and zoomed by `options`; its
    /// field of view narrowed by `shortened` (the view's height over the height it is scaled
    /// for), so the body keeps its size in a view cut short by a caption.
    fn body_camera(&self, target: Vec3, options: &ViewOptions, shortened: f32) -> Camera {
        let base_dir = if self.is_disk {
            Vec3::new(-0.12, -1.0, 0.3)
        } else {
            Vec3::new(-0.3, -1.0, 0.5)
        }
        .normalize();
        let dir = Quat::from_rotation_z(options.yaw)
            * Quat::from_axis_angle(
                Vec3::Y.cross(base_dir).normalize_or(Vec3::X),
                -options.pitch,
            )
            * base_dir;
        let distance = 7.0 * options.zoom.clamp(0.1, 20.0);
        Camera {
            eye: target + dir * distance,
            target,
            up: Vec3::Z,
            fov_y_rad: 2.0 * (20f32.to_radians().tan() * shortened).atan(),
            near: 0.05,
            far: 200.0,
        }
    }

    /// A dented cylinder's hull flats (none for a convex body) as blue segments, each end put
    /// where `to` draws a body point.
    fn hull_flat_segments(&self, to: impl Fn(DVec3) -> Vec3) -> Vec<Segment> {
        self.hull_flats
            .iter()
            .map(|&(a, b)| Segment {
                a: to(a),
                b: to(b),
                color: linear([0, 170, 220], 1.0),
                width_px: 4.0,
            })
            .collect()
    }

    /// The SO(3) ball: the path of the body's orientation, and with the other bodies shown
    /// (`lanes`), each body's path in its own colour, newest brightest, with its current
    /// orientation as a marker in that colour; alone, the path fades from blue (old) to orange.
    pub(super) fn ball_view(
        &self,
        snap: &Snapshot,
        lanes: bool,
        rect: [u32; 4],
        background: Option<[f32; 4]>,
    ) -> View {
        let mut segments = Vec::new();
        axes_and_circles(&mut segments);
        let mut meshes = Vec::new();
        let bodies: Vec<&Snapshot> = if lanes {
            std::iter::once(snap).chain(&snap.lanes).collect()
        } else {
            vec![snap]
        };
        for (n, body) in bodies.iter().enumerate() {
            let colour = lanes.then(|| crate::colormap::body_colour(n));
            let pieces = &body.ball_trail;
            let total: usize = pieces.iter().map(|p| p.len()).sum();
            let mut seen = 0usize;
            for piece in pieces {
                let start = seen;
                push_polyline_indexed(&mut segments, piece, 3.0, |i| {
                    let age = (start + i) as f32 / total.max(1) as f32;
                    match colour {
                        // Opaque enough that each body's colour reads as itself over the
                        // translucent ball (at 25 % the orange read as the x axis's red).
                        Some(c) => linear(c, 0.55 + 0.45 * age),
                        None => linear(
                            sample(&[[70, 110, 190], [255, 140, 30]], age),
                            0.3 + 0.7 * age,
                        ),
                    }
                });
                seen += piece.len();
            }
            if let Some(p) = body.ball_point {
                meshes.push(MeshInstance {
                    mesh: self.marker_mesh,
                    model: Mat4::from_scale_rotation_translation(
                        Vec3::splat(0.055),
                        Quat::IDENTITY,
                        p.as_vec3(),
                    ),
                    material: Material {
                        tint: linear(colour.unwrap_or([240, 40, 40]), 1.0),
                        ..Material::default()
                    },
                });
            }
        }
        meshes.push(MeshInstance {
            mesh: self.ball_mesh,
            model: Mat4::IDENTITY,
            material: Material {
                tint: linear([150, 190, 255], 1.0),
                opacity: 0.16,
                specular: 0.5,
                ..Material::default()
            },
        });
        View {
            viewport: rect,
            background,
            camera: Self::ball_camera(),
            light_dir: Vec3::new(0.3, -0.5, 1.0),
            meshes,
            segments,
            segments_on_top: Vec::new(),
        }
    }

    pub(super) fn poincare_view(
        &self,
        field: Option<&[FieldArrow]>,
        rect: [u32; 4],
        background: Option<[f32; 4]>,
    ) -> View {
        let mut segments = Vec::new();
        if let Some(field) = field {
            let vmax = field_max(field);
            // Arrow length on screen: the true V where it is short, capped where a start runs
            // far around the sphere, so the picture stays readable.
            for a in field {
                let p = a.start.as_vec3();
                let Some(end) = a.end else {
                    continue;
                };
                let e = end.as_vec3();
                let v = (e - p).length();
                let color = linear(sample(&VIRIDIS, v / vmax), 1.0);
                let cap = 0.18;
                let shown = if v > cap {
                    slerp_unit(p, e, cap / v)
                } else {
                    e
                };
                let r = 1.012;
                let mut prev = p * r;
                for k in 1..=4 {
                    let q = slerp_unit(p, shown, k as f32 / 4.0) * r;
                    segments.push(Segment {
                        a: prev,
                        b: q,
                        color,
                        width_px: 1.8,
                    });
                    prev = q;
                }
                let dir = (shown - p).normalize_or_zero();
                let side = p.cross(dir).normalize_or_zero();
                let head = 0.035_f32.min(0.5 * (shown - p).length() + 0.01);
                for s in [-1.0, 1.0] {
                    segments.push(Segment {
                        a: prev,
                        b: prev - dir * head + side * head * 0.6 * s,
                        color,
                        width_px: 1.8,
                    });
                }
            }
        }
        View {
            viewport: rect,
            background,
            camera: Self::ball_camera(),
            light_dir: Vec3::new(0.3, -0.5, 1.0),
            meshes: vec![MeshInstance {
                mesh: self.boundary_mesh,
                model: Mat4::IDENTITY,
                material: Material {
                    tint: linear([120, 124, 136], 1.0),
                    specular: 0.2,
                    ..Material::default()
                },
            }],
            segments,
            segments_on_top: Vec::new(),
        }
    }
}

/// Largest arrow length of a field (at least a small positive number).
pub(super) fn field_max(field: &[FieldArrow]) -> f32 {
    field
        .iter()
        .filter_map(|a| a.end.map(|e| (e - a.start).length() as f32))
        .fold(1e-6, f32::max)
}

pub(super) fn slerp_unit(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    (a * (1.0 - t) + b * t).normalize_or(a)
}

pub(super) fn axes_and_circles(out: &mut Vec<Segment>) {
    let grey = linear([150, 150, 160], 0.6);
    let n = 96;
    for axis in 0..3 {
        let pt = |k: usize| {
            let t = k as f32 / n as f32 * 2.0 * PI;
            let (s, c) = t.sin_cos();
            match axis {
                0 => Vec3::new(c, s, 0.0),
                1 => Vec3::new(c, 0.0, s),
                _ => Vec3::new(0.0, c, s),
            }
        };
        for k in 0..n {
            out.push(Segment {
                a: pt(k),
                b: pt(k + 1),
                color: grey,
                width_px: 1.0,
            });
        }
    }
    for (dir, c) in [
        (Vec3::X, [230, 80, 80]),
        (Vec3::Y, [90, 200, 90]),
        (Vec3::Z, [90, 140, 240]),
    ] {
        out.push(Segment {
            a: Vec3::ZERO,
            b: dir,
            color: linear(c, 0.9),
            width_px: 1.5,
        });
    }
}

pub(super) fn push_polyline(
    out: &mut Vec<Segment>,
    points: impl Iterator<Item = Vec3>,
    width_px: f32,
    color_of_age: impl Fn(f32) -> [f32; 4],
) {
    let pts: Vec<Vec3> = points.collect();
    let n = pts.len();
    for (i, w) in pts.windows(2).enumerate() {
        out.push(Segment {
            a: w[0],
            b: w[1],
            color: color_of_age(i as f32 / n.max(1) as f32),
            width_px,
        });
    }
}

pub(super) fn push_polyline_indexed(
    out: &mut Vec<Segment>,
    points: &[DVec3],
    width_px: f32,
    color_of_index: impl Fn(usize) -> [f32; 4],
) {
    for (i, w) in points.windows(2).enumerate() {
        out.push(Segment {
            a: w[0].as_vec3(),
            b: w[1].as_vec3(),
            color: color_of_index(i),
            width_px,
        });
    }
}

/// The box (x0, y0, x1, y1, frame pixels) the bodies' bounding spheres of `radius` cover on
/// screen in the body's `view`, each centred on one of `centres` (world coordinates; none:
/// what the camera looks at, the body when the camera follows it), widened for the
/// perspective silhouette.
pub(super) fn screen_box(view: &View, radius: f32, centres: &[Vec3]) -> [f32; 4] {
    let [vx, vy, vw, vh] = view.viewport.map(|v| v as f32);
    let cam = &view.camera;
    let view_proj = cam.view_proj(vw / vh.max(1.0));
    let to_pixel = |p: Vec3| {
        let c = view_proj.project_point3(p);
        (vx + (c.x + 1.0) * 0.5 * vw, vy + (1.0 - c.y) * 0.5 * vh)
    };
    let forward = (cam.target - cam.eye).normalize_or(Vec3::X);
    let right = forward.cross(cam.up).normalize_or(Vec3::Y);
    let up = right.cross(forward);
    let one = |centre: Vec3| {
        let (cx, cy) = to_pixel(centre);
        let distance = (centre - cam.eye).length().max(1e-6);
        let silhouette = 1.0 / (1.0 - (radius / distance).powi(2)).max(1e-6).sqrt();
        let rx = (to_pixel(centre + right * radius).0 - cx).abs() * silhouette;
        let ry = (to_pixel(centre + up * radius).1 - cy).abs() * silhouette;
        [cx - rx, cy - ry, cx + rx, cy + ry]
    };
    if centres.is_empty() {
        return one(cam.target);
    }
    centres.iter().map(|&c| one(c)).fold(
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The default camera of a 3D scene following a body of radius 1 on a ramp at α = 0.3.
    fn default_camera() -> Camera {
        let dir = Vec3::new(-0.3, -1.0, 0.5).normalize();
        let target = Mat4::from_rotation_y(0.3).transform_point3(Vec3::Z);
        Camera {
            eye: target + dir * 7.0,
            target,
            up: Vec3::Z,
            fov_y_rad: 40f32.to_radians(),
            near: 0.05,
            far: 200.0,
        }
    }

    #[test]
    fn the_downhill_arrow_stays_inside_the_frame_at_every_aspect() {
        let camera = default_camera();
        let tilt = Mat4::from_rotation_y(0.3);
        let to_world = |p: DVec3| tilt.transform_point3(p.as_vec3());
        for (w, h) in [
            (1280, 720),
            (640, 360),
            (1920, 1080),
            (720, 1280),
            (400, 400),
            (320, 180),
        ] {
            let aspect = w as f32 / h as f32;
            let strokes = downhill_arrow(
                &camera,
                aspect,
                (0.0, 0.0),
                to_world,
                (camera.target, 1.2),
                &[],
            );
            let view_proj = camera.view_proj(aspect);
            for (a, b) in strokes {
                for p in [a, b] {
                    let c = view_proj * to_world(p).extend(1.0);
                    let (x, y) = (c.x / c.w, c.y / c.w);
                    assert!(
                        x.abs() <= 0.94 && y.abs() <= 0.94,
                        "{w}x{h}: arrow point at ({x:.3}, {y:.3}) in clip space"
                    );
                }
            }
            // It still points downhill (+x), from left to right.
            assert!(strokes[0].1.x > strokes[0].0.x + 0.9);
        }
        // Seen from any side the arrow is clear of the body's silhouette (it moves behind the
        // body when the body would hide it).
        let target = camera.target;
        for yaw_deg in (-180..180).step_by(15) {
            let dir = Quat::from_rotation_z((yaw_deg as f32).to_radians())
                * (camera.eye - target).normalize();
            let turned = Camera {
                eye: target + dir * 7.0,
                ..camera
            };
            let strokes = downhill_arrow(
                &turned,
                16.0 / 9.0,
                (0.0, 0.0),
                to_world,
                (target, 1.2),
                &[],
            );
            let vp = turned.view_proj(16.0 / 9.0);
            let c = vp.project_point3(target);
            let right = (target - turned.eye).normalize().cross(Vec3::Z).normalize();
            let rx = (vp.project_point3(target + right * 1.2).x - c.x).abs() * 1.1;
            let up = right.cross((target - turned.eye).normalize());
            let ry = (vp.project_point3(target + up * 1.2).y - c.y).abs() * 1.1;
            for (a, b) in strokes {
                for i in 0..=8 {
                    let p = vp.project_point3(to_world(a.lerp(b, f64::from(i) / 8.0)));
                    let e = ((p.x - c.x) / rx).powi(2) + ((p.y - c.y) / ry).powi(2);
                    assert!(
                        e > 1.0,
                        "yaw {yaw_deg}°: arrow point inside the body ({e:.2})"
                    );
                }
            }
        }
        // At 1280×720 the old fixed place (2.2 in front, 2.4 long) had its lower barb at
        // y = −1.03 in clip space: outside the frame.
        let old_barb = DVec3::new(1.2 - 0.35, -2.2 - 0.25, 0.01);
        let c = camera.view_proj(1280.0 / 720.0) * to_world(old_barb).extend(1.0);
        assert!((c.y / c.w) < -1.0, "{}", c.y / c.w);
    }
}
