//! From a scene's state to the renderer's plain draw data: the layout of the views, the
//! cameras, the colours (curvature on the body, age on the trails, |V| on the Poincaré field),
//! the text overlay and the legends. Window and headless build frames here, so they look the
//! same.
//!
//! Frames of reference: the physics lives in the ramp frame (x downhill, y across, z the ramp's
//! normal); the world is that frame turned by α about y, so the ramp is drawn tilted under a
//! vertical gravity. The default camera looks across the ramp (from −y), slightly from above and
//! uphill, 7 ⟨r⟩ from the body, 40° field of view, and follows the centre of mass: the body
//! rolls from left to right and down.
//!
//! | file | owns |
//! |---|---|
//! | `mod` | [`SceneView`] (the uploaded meshes) and [`SceneView::frame`], [`ViewOptions`] |
//! | `layout` | where each view goes in the frame, the SO(3) ball's camera |
//! | `body` | the body on the ramp, the SO(3) ball and the Poincaré field as draw data |
//! | `panels` | the status text, the legends and the titles |
//!
//! Colours come from [`crate::colormap`]; the Poincaré field from [`crate::live::FieldCache`].

use crate::analysis::orbits::poincare_field::FieldArrow;
use crate::colormap::{DIVERGING, VIRIDIS, linear, sample};
use crate::geometry::Body;
use crate::geometry::mesh::{TriMesh, disk_mesh, icosphere, sphere_mesh};
use crate::live::Snapshot;
use crate::render::types::{
    Anchor, Frame, MeshData, MeshHandle, MeshStore, OverlayPanel, PanelItem,
};
use crate::scene::SceneSetup;
use glam::DVec3;

mod body;
mod lanes;
pub mod layout;
mod panels;
pub mod pick;

use body::field_max;
use panels::{TextSize, title_panel, titled_panel};
pub use panels::{multiplicity_text, short_number};

/// The SO(3) ball's key: what a point is, and its axes by colour (x downhill, y across the
/// ramp, z its normal: the lab frame the orientation turns the body into).
pub const SO3_KEY: &str = "a point: rotation axis × sin(angle/2)\nx downhill (red), y across (green),\nz the ramp's normal (blue)";

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
    /// A dented cylinder's hull flats (P_a, P_b in the body frame, mid-plane): the straight
    /// sides it rolls on across its dents, drawn over the body as it is.
    hull_flats: Vec<(DVec3, DVec3)>,
    /// The body's bounding radius in ⟨r⟩.
    body_radius: f32,
    /// The curvature colour scale of the body.
    pub scale: CurvatureScale,
    name: String,
    show_body: bool,
    show_ball: bool,
    show_poincare: bool,
    show_overlay: bool,
    /// The scene's other bodies (`[[bodies]]`).
    lanes: lanes::LaneMeshes,
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
    /// Follow the body; otherwise look at `fixed_target`.
    pub follow: bool,
    /// Where the camera looks when it does not follow (ramp coordinates); `None`: the body's
    /// centre now. The app moves it to the body when the body leaves the frame, so the view
    /// never loses the body.
    pub fixed_target: Option<glam::DVec3>,
    /// Multiplies every overlay font size (the app's "class" mode).
    pub text_scale: f32,
    /// The least font size in pixels of any text on the view, 0 for none: [`ROOM_TEXT_PX`] in
    /// the app's presentation and class modes, where the view is read from the back of a room.
    /// Panels then leave out their small print (the integrator's health line, the SO(3) ball's
    /// key) rather than show it too small to read.
    pub room_text_px: f32,
    /// What a lesson step's evidence, measured ahead on the same run, shows at the step's end:
    /// said on the overlay, marked "measured ahead", until the live run finds its own.
    pub lesson_ahead: MeasuredAhead,
}

/// What a lesson step's evidence, measured ahead on the same run, shows at the step's end
/// ([`ViewOptions::lesson_ahead`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MeasuredAhead {
    /// Its period, 1 or 2 (`LessonEvidence::period_shown`).
    pub period: Option<usize>,
    /// Its 1/T at the step's α, 0 where it halts (`LessonEvidence::rate_shown`).
    pub rate: Option<f64>,
}

/// The least text size on the view and the lesson's plot in presentation and class modes, in
/// pixels: read from the back of a room.
pub const ROOM_TEXT_PX: f32 = 24.0;

impl Default for ViewOptions {
    fn default() -> Self {
        Self {
            yaw: 0.0,
            pitch: 0.0,
            zoom: 1.0,
            follow: true,
            fixed_target: None,
            text_scale: 1.0,
            room_text_px: 0.0,
            lesson_ahead: MeasuredAhead::default(),
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

/// Length of the 2D cylinder drawn, in ⟨r⟩ (the physics is per unit length).
pub const CYLINDER_LENGTH: f64 = 1.2;

/// Mesh resolution of the body: icosphere level (3D) or segments around the section (2D).
const BODY_ICOSPHERE_LEVEL: u32 = 5;
const DISK_SEGMENTS: usize = 360;

impl SceneView {
    /// Frees the meshes [`Self::new`] uploaded, when another scene replaces this one.
    pub fn release(self, store: &mut impl MeshStore) {
        self.lanes.release(store);
        // The boundary sphere may be the ball's mesh; freeing a freed mesh again does nothing.
        for handle in [
            self.body_mesh,
            self.ramp_mesh,
            self.marker_mesh,
            self.ball_mesh,
            self.boundary_mesh,
        ] {
            store.free_mesh(handle);
        }
    }

    /// Builds and uploads the meshes the scene's views need.
    pub fn new(renderer: &mut impl MeshStore, setup: &SceneSetup) -> Self {
        let mesh = match &setup.body {
            Body::Sphere(s) => sphere_mesh(s, BODY_ICOSPHERE_LEVEL),
            Body::Disk(d) => disk_mesh(d, DISK_SEGMENTS, CYLINDER_LENGTH),
        };
        let scale = CurvatureScale::new(mesh.value_range());
        // The body's bounding radius (a cylinder's half length included), for keeping the
        // downhill arrow clear of it.
        let body_radius = mesh
            .positions
            .iter()
            .map(|p| glam::Vec3::from_array(*p).length())
            .fold(0.0f32, f32::max);
        let body_mesh = renderer.upload_mesh(&to_mesh_data(&mesh, |v| {
            // NaN: a cylinder cap's centre, drawn in the scale's neutral colour.
            linear(
                sample(
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
            hull_flats: match &setup.body {
                Body::Disk(d) => d
                    .hull()
                    .bridges()
                    .iter()
                    .map(|b| {
                        let at = |t: f64| {
                            let r = d.jet(t).r;
                            DVec3::new(r * t.cos(), 0.0, r * t.sin())
                        };
                        (at(b.theta_a), at(b.theta_b))
                    })
                    .collect(),
                Body::Sphere(_) => Vec::new(),
            },
            body_radius,
            scale,
            name: setup.scene.name.clone(),
            show_body: views.body,
            show_ball: views.ball,
            show_poincare: views.poincare,
            show_overlay: views.overlay,
            lanes: lanes::LaneMeshes::new(renderer, setup),
        }
    }

    /// Turns views on or off (the app's toggles); views a 2D body cannot show stay off.
    pub fn set_views(&mut self, body: bool, ball: bool, poincare: bool, overlay: bool) {
        self.show_body = body;
        self.show_ball = ball && !self.is_disk;
        self.show_poincare = poincare && !self.is_disk;
        self.show_overlay = overlay;
    }

    /// The body's view where a room's large numbers (top left) and colour legend (bottom left,
    /// `legend`, where no caption's band holds it) would reach the body: it moves clear of them
    /// at the same scale (a band above it moves it down by half the band, one below moves it
    /// up), or where it cannot fit between them, is drawn smaller.
    #[allow(clippy::too_many_arguments)]
    fn body_view_for_a_room(
        &self,
        snap: &Snapshot,
        rect: [u32; 4],
        full_height: u32,
        covered: &[[u32; 4]],
        options: &ViewOptions,
        status: &OverlayPanel,
        legend: Option<&OverlayPanel>,
        size: (u32, u32),
    ) -> crate::render::View {
        let mut view = self.body_view(snap, rect, full_height, covered, options);
        // Every body on the ramp is kept clear of the panels, not only the scene's own.
        let centres = self.lanes.world_centres(snap);
        // (Their meshes differ a little in size: 5 % more than the scene's own body's.)
        let radius = if centres.is_empty() {
            self.body_radius
        } else {
            1.05 * self.body_radius
        };
        let [left, top, _, bottom] = body::screen_box(&view, radius, &centres);
        // A panel at the left edge is in the way only where it reaches the body's box.
        let group = !centres.is_empty();
        // A group of bodies keeps a margin from the panel's estimated width.
        let margin = if group { 24.0 } else { 0.0 };
        let reaches_from = |panel: &OverlayPanel, left: f32| {
            (10 + panels::estimated_width(panel)) as f32 + margin > left
        };
        let reaches = |panel: &OverlayPanel| reaches_from(panel, left);
        let below_numbers = if reaches(status) {
            (10 + panels::estimated_height(status) + 4) as f32
        } else {
            rect[1] as f32
        };
        let view_bottom = (rect[1] + rect[3]) as f32;
        let above_legend = if let Some(legend) = legend.filter(|l| reaches(l)) {
            size.1 as f32 - (10 + panels::estimated_height(legend) + 4) as f32
        } else {
            view_bottom
        }
        .min(view_bottom);
        let (mut rect, mut scale_height) = (rect, full_height);
        let (height, room) = (bottom - top, above_legend - below_numbers);
        if height > room && room > 0.0 {
            scale_height = ((scale_height as f32) * room / height).floor() as u32;
        }
        // Where the body's centre goes: as it is, within what the panels leave.
        let centre = 0.5 * (top + bottom);
        let half = 0.5 * height.min(room.max(0.0));
        let wanted = centre.clamp(
            below_numbers + half,
            (above_legend - half).max(below_numbers + half),
        );
        let shift = wanted - centre;
        let band = (2.0 * shift.abs()).ceil() as u32;
        if band > 0 && band < rect[3] / 2 {
            if shift > 0.0 {
                rect[1] += band;
            }
            rect[3] -= band;
        }
        if band > 0 || scale_height != full_height {
            view = self.body_view(snap, rect, scale_height, covered, options);
        }
        // A group is not centred on what the camera looks at, and shrinks about that point,
        // not its own centre: moved again, or drawn smaller, until it clears both.
        let mut options = *options;
        for _ in 0..6 {
            if !group {
                break;
            }
            let [left, top, right, bottom] = body::screen_box(&view, radius, &centres);
            // The insets (the SO(3) ball, the Poincaré field) over the view are kept clear too:
            // one in the upper half as the numbers are, one in the lower as the legend is.
            let (mut below, mut above) = (rect[1] as f32, (rect[1] + rect[3]) as f32);
            if reaches_from(status, left) {
                below = below.max((10 + panels::estimated_height(status) + 4) as f32);
            }
            if let Some(legend) = legend.filter(|l| reaches(l)) {
                above =
                    above.min(size.1 as f32 - (10 + panels::estimated_height(legend) + 4) as f32);
            }
            for &[x, y, w, h] in covered {
                let (x0, x1, y0, y1) = (x as f32, (x + w) as f32, y as f32, (y + h) as f32);
                if x1 > left && x0 < right {
                    if y0 + y1 < size.1 as f32 {
                        below = below.max(y1 + 4.0);
                    } else {
                        above = above.min(y0 - 4.0);
                    }
                }
            }
            let (down, up) = (below - top, bottom - above);
            let band = (2.0 * down.max(up)).ceil() as u32;
            if down <= 0.0 && up <= 0.0 {
                break;
            } else if bottom - top > above - below || band >= rect[3] / 2 {
                // Farther back: the group smaller about the same point.
                options.zoom *= 1.12;
            } else {
                if down > 0.0 {
                    rect[1] += band;
                }
                rect[3] -= band;
            }
            view = self.body_view(snap, rect, scale_height, covered, &options);
        }
        view
    }

    /// What picking a body point under the pointer needs of `frame` (drawn by this view):
    /// [`pick::body_point_at`].
    pub fn pick_view(&self, frame: &Frame) -> Option<pick::PickView> {
        pick::PickView::of(frame, self.body_mesh)
    }

    /// The frame showing `snap` at `size`; `field` is the Poincaré field if it is ready.
    pub fn frame(
        &self,
        snap: &Snapshot,
        field: Option<&[FieldArrow]>,
        size: (u32, u32),
        options: &ViewOptions,
    ) -> Frame {
        let [body_rect, mut ball_rect, mut poincare_rect] = self.layout(size);
        let inset_bg = Some(linear([24, 26, 34], 1.0));
        let mut views = Vec::new();
        let mut panels = Vec::new();
        // Text is sized for 1280×720 and scaled with the frame's tighter side, so a portrait or
        // square frame keeps its panels inside the frame and clear of the insets.
        let fit = (size.0 as f32 / 1280.0).min(size.1 as f32 / 720.0);
        let text = options.text_scale * fit.clamp(0.3, 3.0);
        let sized = |scale: f32| TextSize {
            scale,
            min_px: options.room_text_px.max(0.0),
        };
        // A lesson's caption is part of what it shows, so it stays when the overlay is off.
        // It sits above the colour legend (about 70 px tall at text scale 1), in a band of its
        // own: the body's view ends above the band and keeps the scale it has without a caption,
        // so the caption never covers the body and the body stays as large as elsewhere
        // (tests/app/presentation.rs measures it on every lesson step).
        // Under a caption the colour legend keeps the plain size: the caption is what the room
        // reads, and a large legend would lift it into the body's view.
        let legend_text = if snap.caption.is_some() {
            text.min(fit.clamp(0.3, 3.0))
        } else {
            text
        };
        let legend = self.legend_panel(sized(legend_text), size.0.saturating_sub(20) as f32);
        let lift = if self.show_overlay && body_rect.is_some() {
            // 72 px a unit of text holds the legend; a room's floor can make it taller.
            if options.room_text_px > 0.0 {
                10 + panels::estimated_height(&legend).max((72.0 * legend_text) as u32)
            } else {
                10 + (72.0 * legend_text) as u32
            }
        } else {
            10
        };
        let caption = panels::caption_panel(snap, sized(text), 0.86 * size.0 as f32, lift);
        // The caption's band, under the body's view (at most half of the frame).
        let band = match (&body_rect, &caption) {
            (Some(rect), Some(c)) => {
                (lift + panels::estimated_height(c) + (6.0 * text) as u32).min(rect[3] / 2)
            }
            _ => 0,
        };
        // The numbers, built before the body's view: for a room their 24 px lines take a band
        // at the top, which the body's view starts below (as it ends above the caption's).
        let status = self.show_overlay.then(|| {
            // Under a caption the body's view is shorter, and class mode's largest numbers would
            // reach the body: they are a little smaller than elsewhere, still large enough for
            // the back of the room (α and α/α* are what a lesson talks about).
            let status_text = if caption.is_some() {
                text.min(1.4 * fit.clamp(0.3, 3.0))
            } else {
                text
            };
            let mut status = self.status_panel(snap, sized(status_text), options.lesson_ahead);
            if body_rect.is_none() {
                // The views' titles hold the top edge; keep the numbers clear of them.
                status.anchor = Anchor::BottomLeft(10, 10);
            }
            status
        });
        // Without the body's view the numbers sit at the bottom left, over the insets; for a
        // room they are too large for that, and the insets end above them.
        if let (None, Some(status)) = (body_rect, &status)
            && options.room_text_px > 0.0
        {
            let band = panels::estimated_height(status) + 20;
            for rect in [&mut ball_rect, &mut poincare_rect].into_iter().flatten() {
                rect[3] = rect[3].saturating_sub(band).max(rect[3] / 2);
            }
        }
        if let Some(mut rect) = body_rect {
            let covered: Vec<[u32; 4]> = [ball_rect, poincare_rect].into_iter().flatten().collect();
            let full_height = rect[3];
            rect[3] -= band;
            // For a room, and with other bodies on the ramp (whose group reaches the corners),
            // the picture moves or shrinks clear of the numbers and the legend.
            let room = status
                .as_ref()
                .filter(|_| options.room_text_px > 0.0 || self.lanes.shown(snap));
            let legend = (caption.is_none() && self.show_overlay).then_some(&legend);
            let view = match room {
                Some(status) => self.body_view_for_a_room(
                    snap,
                    rect,
                    full_height,
                    &covered,
                    options,
                    status,
                    legend,
                    size,
                ),
                None => self.body_view(snap, rect, full_height, &covered, options),
            };
            views.push(view);
        }
        if let Some(rect) = ball_rect {
            // The ball below its title and key, not under them (at 720p the key's lines sat
            // over the top of the ball): the inset's background behind both, the ball's view
            // in what the text leaves.
            let key = titled_panel(rect, "Orientation (SO(3) ball)", Some(SO3_KEY), sized(text));
            let below = (panels::estimated_height(&key)).min(rect[3] / 3);
            let ball = self.ball_view(
                snap,
                self.lanes.shown(snap),
                [rect[0], rect[1] + below, rect[2], rect[3] - below],
                if body_rect.is_some() { inset_bg } else { None },
            );
            if body_rect.is_some() {
                // The whole inset's background, drawn first: nothing in it but the fill.
                views.push(crate::render::View {
                    viewport: rect,
                    meshes: Vec::new(),
                    segments: Vec::new(),
                    segments_on_top: Vec::new(),
                    ..ball.clone()
                });
            }
            views.push(ball);
            // Short enough not to wrap in the inset, in words rather than q_w, with what a
            // point means and which axis is which (the axes are drawn in these colours).
            panels.push(key);
        }
        if let Some(rect) = poincare_rect {
            views.push(self.poincare_view(
                field,
                rect,
                if body_rect.is_some() { inset_bg } else { None },
            ));
            // With inertia there is no field to wait for: say so where the eye is, not only in
            // small text under Views (it read "computing…" for ever).
            let title = match (field, &snap.poincare_field) {
                (Some(_), _) => "Poincaré map on ∂Ω (next crossing)",
                (None, crate::live::FieldWanted::NeedsViscous) => {
                    "Poincaré map on ∂Ω: needs the viscous model (inertia off)"
                }
                (None, _) => "Poincaré map on ∂Ω: computing…",
            };
            panels.push(title_panel(rect, title, sized(text)));
            if self.show_overlay
                && let Some(f) = field
            {
                panels.push(field_legend(rect, field_max(f), text, sized(text)));
            }
        }
        if let Some(status) = status {
            panels.push(status);
            if body_rect.is_some() {
                panels.push(legend);
            }
        }
        if let Some(caption) = caption {
            panels.push(caption);
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
}

/// The Poincaré field's colour legend at the bottom left of its inset `rect`: 70 px a unit of
/// text up, or higher if a room's text makes it taller.
fn field_legend(rect: [u32; 4], vmax: f32, scale: f32, t: TextSize) -> OverlayPanel {
    let mut legend = OverlayPanel {
        anchor: Anchor::TopLeft(rect[0], rect[1]),
        items: vec![
            PanelItem::Text {
                text: "|V| = |P(p) − p|".into(),
                size_px: t.px(15.0),
                color: [235; 3],
            },
            PanelItem::ColorBar {
                // For a room, as long as its labels need, within the inset.
                width: if t.for_a_room() {
                    let padding = (6.0 * scale) as u32;
                    let widest = rect[2] as f32 - 16.0 - 2.0 * padding as f32 - 3.0 * t.px(13.0);
                    (160.0 * t.px(13.0) / 13.0).min(widest.max(40.0)) as u32
                } else {
                    (160.0 * scale) as u32
                },
                height: (10.0 * scale).max(4.0) as u32,
                colors: VIRIDIS.to_vec(),
                labels: vec![(0.0, "0".into()), (1.0, format!("{vmax:.2}"))],
                size_px: t.px(13.0),
            },
        ],
        background: [16, 18, 24, 200],
        padding: (6.0 * scale) as u32,
    };
    let mut up = (70.0 * scale) as u32;
    if t.for_a_room() {
        up = up.max(panels::estimated_height(&legend) + 8);
    }
    legend.anchor = Anchor::TopLeft(
        rect[0] + 8,
        (rect[1] + rect[3]).saturating_sub(up).max(rect[1]),
    );
    legend
}
