//! From a scene's state to the renderer's plain draw data: the layout of the views, the
//! cameras, the colours (curvature on the body, age on the trails, |V| on the Poincaré field),
//! the text overlay and the legends. Window and headless build frames here, so they look the
//! same. Also the cache of Poincaré fields, computed off the render thread once per (body, α).
//!
//! Frames of reference: the physics lives in the ramp frame (x downhill, y across, z the ramp's
//! normal); the world is that frame turned by α about y, so the ramp is drawn tilted under a
//! vertical gravity. The default camera looks across the ramp (from −y), slightly from above and
//! uphill, 7 ⟨r⟩ from the body, 40° field of view, and follows the centre of mass: the body
//! rolls from left to right and down.

use std::collections::HashMap;
use std::f32::consts::PI;
use std::sync::{Arc, Mutex};

use glam::{DVec3, Mat4, Quat, Vec3};

use crate::analysis::sphere_orbits::{FieldArrow, poincare_field};
use crate::dynamics::Ramp;
use crate::geometry::Body;
use crate::geometry::mesh::{TriMesh, disk_mesh, icosphere, sphere_mesh};
use crate::render::overlay::{Anchor, Panel, PanelItem};
use crate::render::{
    Camera, Frame, Material, MeshData, MeshHandle, MeshInstance, Renderer, Segment, View,
};
use crate::scene::SceneSetup;
use crate::sim::{CYLINDER_LENGTH, Snapshot};

/// sRGB stops of the diverging map for curvature (blue below the sphere's K = 1, red above).
pub const DIVERGING: [[u8; 3]; 5] = [
    [59, 76, 192],
    [141, 176, 254],
    [221, 221, 221],
    [244, 154, 123],
    [180, 4, 38],
];

/// sRGB stops of the sequential map for |V| (viridis).
pub const SEQUENTIAL: [[u8; 3]; 5] = [
    [68, 1, 84],
    [59, 82, 139],
    [33, 145, 140],
    [94, 201, 98],
    [253, 231, 37],
];

/// sRGB (0–255) to linear RGBA.
pub fn linear(c: [u8; 3], alpha: f32) -> [f32; 4] {
    let f = |v: u8| {
        let s = v as f32 / 255.0;
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    };
    [f(c[0]), f(c[1]), f(c[2]), alpha]
}

/// Interpolates evenly spaced sRGB stops at t ∈ [0, 1].
pub fn colormap(stops: &[[u8; 3]], t: f32) -> [u8; 3] {
    crate::render::overlay::gradient(stops, t)
}

/// The curvature colour scale: symmetric about 1 (the perfect body's K or κ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvatureScale {
    /// Smallest value on the body.
    pub min: f32,
    /// Largest value on the body.
    pub max: f32,
    /// Half-width of the scale around 1.
    pub half_range: f32,
}

impl CurvatureScale {
    fn new((min, max): (f32, f32)) -> Self {
        let half_range = (max - 1.0).abs().max((1.0 - min).abs()).max(1e-3);
        Self {
            min,
            max,
            half_range,
        }
    }

    /// Position of value `v` on the colour bar, 0..1.
    pub fn position(&self, v: f32) -> f32 {
        (0.5 + 0.5 * (v - 1.0) / self.half_range).clamp(0.0, 1.0)
    }
}

/// Meshes uploaded for one scene, and how to frame them.
pub struct SceneView {
    body_mesh: MeshHandle,
    ramp_mesh: MeshHandle,
    marker_mesh: MeshHandle,
    ball_mesh: MeshHandle,
    boundary_mesh: MeshHandle,
    is_disk: bool,
    /// The curvature colour scale of the body.
    pub scale: CurvatureScale,
    name: String,
    show_body: bool,
    show_ball: bool,
    show_poincare: bool,
    show_overlay: bool,
}

/// User-controlled camera and overlay settings (the app changes them; headless uses defaults).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewOptions {
    /// Extra turn of the main camera about the vertical, radians.
    pub yaw: f32,
    /// Extra elevation of the main camera, radians.
    pub pitch: f32,
    /// Distance multiplier of the main camera.
    pub zoom: f32,
    /// Follow the body (otherwise look at the ramp's origin).
    pub follow: bool,
    /// Multiplies every overlay font size (the app's "class" mode).
    pub text_scale: f32,
}

impl Default for ViewOptions {
    fn default() -> Self {
        Self {
            yaw: 0.0,
            pitch: 0.0,
            zoom: 1.0,
            follow: true,
            text_scale: 1.0,
        }
    }
}

fn to_mesh_data(mesh: &TriMesh, color: impl Fn(f32) -> [f32; 4]) -> MeshData {
    MeshData {
        positions: mesh.positions.clone(),
        normals: mesh.normals.clone(),
        colors: mesh.values.iter().map(|&v| color(v)).collect(),
        indices: mesh.indices.clone(),
    }
}

fn uniform_sphere(level: u32, color: [f32; 4]) -> MeshData {
    let (dirs, indices) = icosphere(level);
    let p: Vec<[f32; 3]> = dirs.iter().map(|d| d.as_vec3().to_array()).collect();
    MeshData {
        positions: p.clone(),
        normals: p,
        colors: vec![color; dirs.len()],
        indices,
    }
}

/// Mesh resolution of the body: icosphere level (3D) or segments around the section (2D).
const BODY_ICOSPHERE_LEVEL: u32 = 5;
const DISK_SEGMENTS: usize = 360;

impl SceneView {
    /// Builds and uploads the meshes the scene's views need.
    pub fn new(renderer: &mut Renderer, setup: &SceneSetup) -> Self {
        let mesh = match &setup.body {
            Body::Sphere(s) => sphere_mesh(s, BODY_ICOSPHERE_LEVEL),
            Body::Disk(d) => disk_mesh(d, DISK_SEGMENTS, CYLINDER_LENGTH),
        };
        let scale = CurvatureScale::new(mesh.value_range());
        let body_mesh = renderer.upload_mesh(&to_mesh_data(&mesh, |v| {
            // NaN: a cylinder cap's centre, drawn in the scale's neutral colour.
            linear(
                colormap(
                    &DIVERGING,
                    scale.position(if v.is_finite() { v } else { 1.0 }),
                ),
                1.0,
            )
        }));
        let half = 20.0f32;
        let ramp = MeshData {
            positions: vec![
                [-half, -half, 0.0],
                [half, -half, 0.0],
                [half, half, 0.0],
                [-half, half, 0.0],
            ],
            normals: vec![[0.0, 0.0, 1.0]; 4],
            colors: vec![linear([196, 188, 172], 1.0); 4],
            indices: vec![[0, 1, 2], [0, 2, 3]],
        };
        let ramp_mesh = renderer.upload_mesh(&ramp);
        let marker_mesh = renderer.upload_mesh(&uniform_sphere(2, [1.0; 4]));
        let ball_mesh = renderer.upload_mesh(&uniform_sphere(4, [1.0; 4]));
        let boundary_mesh = ball_mesh;
        let views = &setup.scene.views;
        Self {
            body_mesh,
            ramp_mesh,
            marker_mesh,
            ball_mesh,
            boundary_mesh,
            is_disk: matches!(setup.body, Body::Disk(_)),
            scale,
            name: setup.scene.name.clone(),
            show_body: views.body,
            show_ball: views.ball,
            show_poincare: views.poincare,
            show_overlay: views.overlay,
        }
    }

    /// Turns views on or off (the app's toggles); views a 2D body cannot show stay off.
    pub fn set_views(&mut self, body: bool, ball: bool, poincare: bool, overlay: bool) {
        self.show_body = body;
        self.show_ball = ball && !self.is_disk;
        self.show_poincare = poincare && !self.is_disk;
        self.show_overlay = overlay;
    }

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

    /// The frame showing `snap` at `size`; `field` is the Poincaré field if it is ready.
    pub fn frame(
        &self,
        snap: &Snapshot,
        field: Option<&[FieldArrow]>,
        size: (u32, u32),
        options: &ViewOptions,
    ) -> Frame {
        let [body_rect, ball_rect, poincare_rect] = self.layout(size);
        let inset_bg = Some(linear([24, 26, 34], 1.0));
        let mut views = Vec::new();
        let mut panels = Vec::new();
        let text = options.text_scale * (size.1 as f32 / 720.0).clamp(0.5, 3.0);
        if let Some(rect) = body_rect {
            views.push(self.body_view(snap, rect, options));
        }
        if let Some(rect) = ball_rect {
            views.push(self.ball_view(
                snap,
                rect,
                if body_rect.is_some() { inset_bg } else { None },
            ));
            panels.push(title_panel(
                rect,
                "SO(3) ball: vector part of q (q_w ≥ 0)",
                text,
            ));
        }
        if let Some(rect) = poincare_rect {
            views.push(self.poincare_view(
                field,
                rect,
                if body_rect.is_some() { inset_bg } else { None },
            ));
            let title = match field {
                Some(_) => "Poincaré map on ∂Ω (next crossing)",
                None => "Poincaré map on ∂Ω: computing…",
            };
            panels.push(title_panel(rect, title, text));
            if self.show_overlay
                && let Some(f) = field
            {
                let vmax = field_max(f);
                panels.push(Panel {
                    anchor: Anchor::TopLeft(rect[0] + 8, rect[1] + rect[3] - (70.0 * text) as u32),
                    items: vec![
                        PanelItem::Text {
                            text: "|V| = |P(p) − p|".into(),
                            size_px: 15.0 * text,
                            color: [235; 3],
                        },
                        PanelItem::ColorBar {
                            width: (160.0 * text) as u32,
                            height: (10.0 * text).max(4.0) as u32,
                            colors: SEQUENTIAL.to_vec(),
                            labels: vec![(0.0, "0".into()), (1.0, format!("{vmax:.2}"))],
                            size_px: 13.0 * text,
                        },
                    ],
                    background: [16, 18, 24, 200],
                    padding: (6.0 * text) as u32,
                });
            }
        }
        if self.show_overlay {
            let mut status = self.status_panel(snap, text);
            if body_rect.is_none() {
                // The views' titles hold the top edge; keep the numbers clear of them.
                status.anchor = Anchor::BottomLeft(10, 10);
            }
            panels.push(status);
            if body_rect.is_some() {
                panels.push(self.legend_panel(text));
            }
        }
        // Line widths are given for 720 rows; keep their look at other sizes.
        let line_scale = (size.1 as f32 / 720.0).clamp(0.75, 3.0);
        for view in &mut views {
            for s in &mut view.segments {
                s.width_px *= line_scale;
            }
        }
        Frame {
            clear: linear([40, 44, 54], 1.0),
            views,
            panels,
        }
    }

    fn body_view(&self, snap: &Snapshot, rect: [u32; 4], options: &ViewOptions) -> View {
        let alpha = snap.alpha_rad as f32;
        let world_from_ramp = Mat4::from_rotation_y(alpha);
        let to_world = |p: DVec3| world_from_ramp.transform_point3(p.as_vec3());
        let centre = snap.pose.centre.as_vec3();
        let target = if options.follow {
            world_from_ramp.transform_point3(centre)
        } else {
            Vec3::ZERO
        };
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
        let camera = Camera {
            eye: target + dir * distance,
            target,
            up: Vec3::Z,
            fov_y_rad: 40f32.to_radians(),
            near: 0.05,
            far: 200.0,
        };
        let snap_to = |v: f32| (v / 5.0).round() * 5.0;
        let meshes = vec![
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
                    to_world(snap.contact_on_ramp),
                ),
                material: Material {
                    tint: linear([255, 214, 10], 1.0),
                    ..Material::default()
                },
            },
        ];
        let mut segments = Vec::new();
        // Contact path on the ramp, fading with age.
        let lift = DVec3::new(0.0, 0.0, 0.004);
        push_polyline(
            &mut segments,
            snap.ramp_trail.iter().map(|&p| to_world(p + lift)),
            3.0,
            |age| linear([230, 90, 20], 0.25 + 0.75 * age),
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
                .map(|&p| body_to_world.transform_point3(push_out(p).as_vec3())),
            2.5,
            |age| linear([20, 20, 20], 0.35 + 0.65 * age),
        );
        // Downhill arrow, painted on the ramp in front of the body.
        let y_arrow = -2.2;
        let x0 = centre.x as f64 - 1.2;
        let x1 = centre.x as f64 + 1.2;
        let orange = linear([255, 140, 0], 1.0);
        let tip = DVec3::new(x1, y_arrow, 0.01);
        for (a, b) in [
            (DVec3::new(x0, y_arrow, 0.01), tip),
            (tip, DVec3::new(x1 - 0.35, y_arrow - 0.25, 0.01)),
            (tip, DVec3::new(x1 - 0.35, y_arrow + 0.25, 0.01)),
        ] {
            segments.push(Segment {
                a: to_world(a),
                b: to_world(b),
                color: orange,
                width_px: 5.0,
            });
        }
        View {
            viewport: rect,
            background: None,
            camera,
            light_dir: Vec3::new(-0.4, -0.6, 1.0),
            meshes,
            segments,
        }
    }

    fn ball_camera() -> Camera {
        Camera {
            eye: Vec3::new(1.3, -2.2, 1.2).normalize() * 3.3,
            target: Vec3::ZERO,
            up: Vec3::Z,
            fov_y_rad: 40f32.to_radians(),
            near: 0.1,
            far: 20.0,
        }
    }

    fn ball_view(&self, snap: &Snapshot, rect: [u32; 4], background: Option<[f32; 4]>) -> View {
        let mut segments = Vec::new();
        axes_and_circles(&mut segments);
        let pieces = &snap.ball_trail;
        let total: usize = pieces.iter().map(|p| p.len()).sum();
        let mut seen = 0usize;
        for piece in pieces {
            let start = seen;
            push_polyline_indexed(&mut segments, piece, 3.0, |i| {
                let age = (start + i) as f32 / total.max(1) as f32;
                linear(
                    colormap(&[[70, 110, 190], [255, 140, 30]], age),
                    0.3 + 0.7 * age,
                )
            });
            seen += piece.len();
        }
        let mut meshes = Vec::new();
        if let Some(p) = snap.ball_point {
            meshes.push(MeshInstance {
                mesh: self.marker_mesh,
                model: Mat4::from_scale_rotation_translation(
                    Vec3::splat(0.055),
                    Quat::IDENTITY,
                    p.as_vec3(),
                ),
                material: Material {
                    tint: linear([240, 40, 40], 1.0),
                    ..Material::default()
                },
            });
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
        }
    }

    fn poincare_view(
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
                let color = linear(colormap(&SEQUENTIAL, v / vmax), 1.0);
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
        }
    }

    fn status_panel(&self, snap: &Snapshot, text: f32) -> Panel {
        let deg = snap.alpha_rad.to_degrees();
        let ratio = if snap.alpha_star > 0.0 {
            format!("α/α* = {:.3}", snap.alpha_rad / snap.alpha_star)
        } else {
            "perfect body".into()
        };
        let mass = if snap.mass_ratio == 0.0 {
            format!("m/m0 = 0 ({} model)", snap.model)
        } else {
            format!("m/m0 = {} ({} model)", trim(snap.mass_ratio), snap.model)
        };
        let rate = if snap.halted {
            "halted: 1/T = 0".to_string()
        } else {
            match snap.period {
                Some(t) => format!(
                    "1/T = {:.5}   (T = {:.3}, {}){}",
                    1.0 / t,
                    t,
                    if self.is_disk {
                        "one full turn"
                    } else {
                        "∂Ω to ∂Ω"
                    },
                    multiplicity_text(snap.period_multiplicity)
                ),
                None => "1/T: measuring…".to_string(),
            }
        };
        let line = |s: String, px: f32| PanelItem::Text {
            text: s,
            size_px: px * text,
            color: [240; 3],
        };
        let mut items = vec![
            PanelItem::Text {
                text: self.name.clone(),
                size_px: 19.0 * text,
                color: [255, 214, 10],
            },
            line(
                format!(
                    "α = {:.4} rad ({deg:.2}°)   α* = {:.4} rad   {ratio}",
                    snap.alpha_rad, snap.alpha_star
                ),
                16.0,
            ),
            line(mass, 16.0),
            line(format!("t = {:.2}", snap.t), 16.0),
        ];
        let worst = snap
            .health
            .quat_norm_error
            .max(snap.health.contact_normal_error);
        let trustworthy = worst <= crate::simulate::FIXED_STEP_HEALTH_LIMIT;
        if !self.is_disk && !trustworthy {
            // The state has left the rolling constraint: its 1/T would be nonsense.
            items.push(PanelItem::Text {
                text: format!(
                    "NOT TRUSTWORTHY: ||q|−1| = {:.1e}, contact error = {:.1e} (limit 1e-3); use a \
                     smaller step",
                    snap.health.quat_norm_error, snap.health.contact_normal_error
                ),
                size_px: 16.0 * text,
                color: [255, 70, 60],
            });
        } else {
            items.push(line(rate, 16.0));
        }
        if !self.is_disk {
            items.push(PanelItem::Text {
                text: format!(
                    "{}   ||q|−1| ≤ {:.1e}   contact error ≤ {:.1e}",
                    snap.integrator, snap.health.quat_norm_error, snap.health.contact_normal_error
                ),
                size_px: 13.0 * text,
                color: [190; 3],
            });
        } else {
            items.push(PanelItem::Text {
                text: snap.integrator.to_string(),
                size_px: 13.0 * text,
                color: [190; 3],
            });
        }
        Panel {
            anchor: Anchor::TopLeft(10, 10),
            items,
            background: [16, 18, 24, 200],
            padding: (8.0 * text) as u32,
        }
    }

    fn legend_panel(&self, text: f32) -> Panel {
        let s = &self.scale;
        let what = if self.is_disk {
            "curvature κ of the section (1 = circle)"
        } else {
            "Gaussian curvature K (1 = sphere)"
        };
        let mut labels = vec![(s.position(1.0), "1".to_string())];
        if s.max - s.min > 1e-3 {
            labels.push((s.position(s.min), format!("{:.2}", s.min)));
            labels.push((s.position(s.max), format!("{:.2}", s.max)));
        }
        Panel {
            anchor: Anchor::BottomLeft(10, 10),
            items: vec![
                PanelItem::Text {
                    text: what.into(),
                    size_px: 15.0 * text,
                    color: [240; 3],
                },
                PanelItem::ColorBar {
                    width: (240.0 * text) as u32,
                    height: (12.0 * text).max(4.0) as u32,
                    colors: DIVERGING.to_vec(),
                    labels,
                    size_px: 13.0 * text,
                },
            ],
            background: [16, 18, 24, 200],
            padding: (8.0 * text) as u32,
        }
    }
}

fn trim(x: f64) -> String {
    let s = format!("{x:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

fn title_panel(rect: [u32; 4], title: &str, text: f32) -> Panel {
    Panel {
        anchor: Anchor::TopLeft(rect[0] + 6, rect[1] + 6),
        items: vec![PanelItem::Text {
            text: title.into(),
            size_px: 14.0 * text,
            color: [225; 3],
        }],
        background: [0, 0, 0, 0],
        padding: 2,
    }
}

/// Largest arrow length of a field (at least a small positive number).
fn field_max(field: &[FieldArrow]) -> f32 {
    field
        .iter()
        .filter_map(|a| a.end.map(|e| (e - a.start).length() as f32))
        .fold(1e-6, f32::max)
}

fn slerp_unit(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    (a * (1.0 - t) + b * t).normalize_or(a)
}

fn axes_and_circles(out: &mut Vec<Segment>) {
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

fn push_polyline(
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

fn push_polyline_indexed(
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

/// Key of a cached field: the body's shape file text, α's bits, the arrow count and rtol's bits.
type FieldKey = (String, u64, usize, u64);

/// Poincaré fields computed once per (body, α, resolution), on a worker thread.
#[derive(Default, Clone)]
pub struct FieldCache {
    entries: Arc<Mutex<HashMap<FieldKey, FieldEntry>>>,
}

#[derive(Clone)]
enum FieldEntry {
    Computing,
    Ready(Arc<Vec<FieldArrow>>),
    Failed(String),
}

impl FieldCache {
    fn key(setup: &SceneSetup, ramp: &Ramp) -> FieldKey {
        let p = &setup.scene.poincare;
        (
            setup.body.to_file().to_json(),
            ramp.alpha_rad.to_bits(),
            p.arrows,
            p.rtol.to_bits(),
        )
    }

    /// The field if it is ready; otherwise starts computing it on a worker thread (once) and
    /// returns `Ok(None)`. A failed computation is reported once per key.
    pub fn request(
        &self,
        setup: &SceneSetup,
        ramp: &Ramp,
    ) -> Result<Option<Arc<Vec<FieldArrow>>>, String> {
        let key = Self::key(setup, ramp);
        let mut entries = self.entries.lock().map_err(|e| e.to_string())?;
        match entries.get(&key) {
            Some(FieldEntry::Ready(f)) => return Ok(Some(f.clone())),
            Some(FieldEntry::Computing) => return Ok(None),
            Some(FieldEntry::Failed(e)) => return Err(e.clone()),
            None => {}
        }
        entries.insert(key.clone(), FieldEntry::Computing);
        drop(entries);
        let cache = self.entries.clone();
        let (setup, ramp) = (setup.clone(), *ramp);
        std::thread::spawn(move || {
            let result = compute_field(&setup, &ramp);
            if let Ok(mut entries) = cache.lock() {
                entries.insert(
                    key,
                    match result {
                        Ok(f) => FieldEntry::Ready(Arc::new(f)),
                        Err(e) => FieldEntry::Failed(e),
                    },
                );
            }
        });
        Ok(None)
    }

    /// The field, computed now if it is not cached (headless: frames must not depend on timing).
    pub fn get_blocking(
        &self,
        setup: &SceneSetup,
        ramp: &Ramp,
    ) -> Result<Arc<Vec<FieldArrow>>, String> {
        let key = Self::key(setup, ramp);
        if let Ok(entries) = self.entries.lock()
            && let Some(FieldEntry::Ready(f)) = entries.get(&key)
        {
            return Ok(f.clone());
        }
        let f = Arc::new(compute_field(setup, ramp)?);
        if let Ok(mut entries) = self.entries.lock() {
            entries.insert(key, FieldEntry::Ready(f.clone()));
        }
        Ok(f)
    }
}

fn compute_field(setup: &SceneSetup, ramp: &Ramp) -> Result<Vec<FieldArrow>, String> {
    let Body::Sphere(s) = &setup.body else {
        return Err("the Poincaré field needs a 3D body".into());
    };
    let p = &setup.scene.poincare;
    poincare_field(s, ramp, p.arrows, p.t_max, p.rtol, &|| {}).map_err(|e| e.to_string())
}

/// "; period k" once the crossings of ∂Ω repeat (3D), else nothing.
pub fn multiplicity_text(k: Option<usize>) -> String {
    match k {
        Some(2) => "; period 2, doubled".into(),
        Some(k) => format!("; period {k}"),
        None => String::new(),
    }
}
