//! Draws one app frame into any wgpu target: the 3D scene through the same [`Renderer`] as
//! headless frames, into the rectangle the UI leaves for it, then the egui panels on top
//! (egui-wgpu's renderer, patched so that its shader's options are pipeline constants: on
//! llvmpipe that halves a frame, `vendor/egui-wgpu/PATCH.md`). The window, the screenshot and
//! `rollphase bench app` all paint through here; only the target differs. Knows wgpu and egui,
//! not winit.
//!
//! The Poincaré field is computed off the UI thread ([`FieldCache::request`]) and only once α
//! has rested for [`FIELD_DEBOUNCE`]: every slider position would otherwise start a full field
//! computation on all cores and starve the simulation. Until the new one is ready the last field
//! stays on screen, and the UI says for which α it was computed.

use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::analysis::orbits::poincare_field::FieldArrow;
use crate::live::SimStatus;
use crate::live::{FieldCache, FieldWanted};
use crate::render::Renderer;
use crate::scene::ViewsSpec;
use crate::view::{CurvatureScale, SceneView, ViewOptions};

/// How long α must rest before the Poincaré field is recomputed for it.
pub const FIELD_DEBOUNCE: Duration = Duration::from_millis(400);

/// egui's output for one frame, tessellated.
pub struct EguiFrame {
    /// What to draw.
    pub primitives: Vec<egui::ClippedPrimitive>,
    /// Physical pixels per point.
    pub pixels_per_point: f32,
}

/// egui-wgpu's renderer (patched: vendor/egui-wgpu) with what its `render` needs again.
struct EguiRenderer {
    renderer: egui_wgpu::Renderer,
    primitives: Vec<egui::ClippedPrimitive>,
    screen: egui_wgpu::ScreenDescriptor,
}

impl EguiRenderer {
    fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let options = egui_wgpu::RendererOptions {
            msaa_samples: 1,
            depth_stencil_format: None,
            dithering: true,
            predictable_texture_filtering: false,
        };
        Self {
            renderer: egui_wgpu::Renderer::new(device, format, options),
            primitives: Vec::new(),
            screen: egui_wgpu::ScreenDescriptor {
                size_in_pixels: [1, 1],
                pixels_per_point: 1.0,
            },
        }
    }

    fn update_texture(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        id: egui::TextureId,
        delta: &egui::epaint::ImageDelta,
    ) {
        self.renderer.update_texture(device, queue, id, delta);
    }

    fn free_texture(&mut self, id: &egui::TextureId) {
        self.renderer.free_texture(id);
    }

    fn update_buffers(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        primitives: &[egui::ClippedPrimitive],
        size: (u32, u32),
        pixels_per_point: f32,
    ) {
        self.primitives = primitives.to_vec();
        self.screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [size.0, size.1],
            pixels_per_point,
        };
        let mut encoder = device.create_command_encoder(&Default::default());
        let extra = self.renderer.update_buffers(
            device,
            queue,
            &mut encoder,
            &self.primitives,
            &self.screen,
        );
        queue.submit(extra.into_iter().chain([encoder.finish()]));
    }

    fn render(&self, pass: &mut wgpu::RenderPass<'static>) {
        self.renderer.render(pass, &self.primitives, &self.screen);
    }
}

/// The 3D renderer and egui's renderer for one target format.
pub struct Painter {
    renderer: Renderer,
    egui: EguiRenderer,
    scene: Option<(u64, SceneView)>,
    fields: FieldCache,
    field: Option<(f64, Arc<Vec<FieldArrow>>)>,
    field_wanted: Option<(f64, Instant)>,
    field_error: Option<String>,
    /// The body's view as the window's scene last drew it: where a click lands on the body
    /// (sculpting).
    pick: Option<crate::view::pick::PickView>,
}

impl Painter {
    /// Painter for targets of `format`; the 3D scene uses `sample_count` (1 or 4) MSAA samples.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        format: wgpu::TextureFormat,
        sample_count: u32,
    ) -> Self {
        Self {
            renderer: Renderer::new(device, queue, format, sample_count),
            egui: EguiRenderer::new(device, format),
            scene: None,
            fields: FieldCache::default(),
            field: None,
            field_wanted: None,
            field_error: None,
            pick: None,
        }
    }

    /// How many meshes the 3D renderer holds (the running scene's: four).
    pub fn mesh_count(&self) -> usize {
        self.renderer.mesh_count()
    }

    /// Follows the status: new meshes when the scene changed, the field when it is wanted.
    /// Returns the curvature scale of the body (for the plots) and a note on the field.
    pub fn sync(
        &mut self,
        status: &SimStatus,
        views: &ViewsSpec,
    ) -> (Option<CurvatureScale>, Option<String>) {
        if self.scene.as_ref().map(|s| s.0) != Some(status.scene_id) {
            // The old scene's meshes go first: every load would otherwise keep ~0.7 MB of GPU
            // buffers for the rest of the session.
            if let Some((_, old)) = self.scene.take() {
                old.release(&mut self.renderer);
            }
            let view = SceneView::new(&mut self.renderer, &status.setup);
            self.scene = Some((status.scene_id, view));
            self.field = None;
            self.field_wanted = None;
            self.field_error = None;
        }
        let note = if views.poincare {
            self.want_field(status)
        } else {
            None
        };
        let scale = self.scene.as_ref().map(|(_, v)| v.scale);
        (scale, note)
    }

    /// Fetches the field the simulation wants ([`FieldWanted`], decided there), once α has
    /// rested for [`FIELD_DEBOUNCE`]; returns a note for the status line.
    fn want_field(&mut self, status: &SimStatus) -> Option<String> {
        let ramp = match status.snapshot.poincare_field {
            FieldWanted::Off => return None,
            FieldWanted::NeedsViscous => {
                return Some(
                    "Poincaré field: needs the viscous model (the map on ∂Ω is of orientations \
                     alone); switch inertia off"
                        .into(),
                );
            }
            FieldWanted::Ramp(ramp) => ramp,
        };
        let alpha = ramp.alpha_rad;
        if self.field.as_ref().is_some_and(|f| f.0 == alpha) {
            return None;
        }
        let now = Instant::now();
        match self.field_wanted {
            Some((a, since)) if a == alpha => {
                if now - since >= FIELD_DEBOUNCE {
                    match self.fields.request(&status.setup, &ramp) {
                        Ok(Some(field)) => {
                            self.field = Some((alpha, field));
                            self.field_error = None;
                            return None;
                        }
                        Ok(None) => {}
                        Err(e) => self.field_error = Some(e),
                    }
                }
            }
            _ => self.field_wanted = Some((alpha, now)),
        }
        if let Some(e) = &self.field_error {
            return Some(format!("Poincaré field failed: {e}"));
        }
        Some(match &self.field {
            Some((a, _)) => format!("Poincaré field of α = {a:.4}; computing α = {alpha:.4}…"),
            None => format!("computing the Poincaré field for α = {alpha:.4}…"),
        })
    }

    /// Uploads egui's pending texture changes (`textures.set`) and this frame's buffers; call
    /// once before [`Self::paint`].
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        size: (u32, u32),
        egui_frame: &EguiFrame,
        textures: &mut egui::TexturesDelta,
    ) {
        for (id, deltas) in std::mem::take(&mut textures.set) {
            for delta in deltas {
                self.egui.update_texture(device, queue, id, &delta);
            }
        }
        self.egui.update_buffers(
            device,
            queue,
            &egui_frame.primitives,
            size,
            egui_frame.pixels_per_point,
        );
    }

    /// Frees the textures egui is done with; call once after the frame's last paint.
    pub fn finish(&mut self, textures: &mut egui::TexturesDelta) {
        for id in std::mem::take(&mut textures.free) {
            self.egui.free_texture(&id);
        }
    }

    /// The 3D scene alone, `size` pixels, into `target` (recording).
    pub fn paint_scene(
        &mut self,
        target: &wgpu::TextureView,
        size: (u32, u32),
        status: &SimStatus,
        views: &ViewsSpec,
        options: &ViewOptions,
    ) {
        let rect = [0, 0, size.0, size.1];
        self.paint_scene_in(target, size, rect, status, views, options, 1.0);
    }

    /// Paints the scene into `rect`; returns the body's view as drawn, for picking.
    #[allow(clippy::too_many_arguments)]
    fn paint_scene_in(
        &mut self,
        target: &wgpu::TextureView,
        size: (u32, u32),
        rect: [u32; 4],
        status: &SimStatus,
        views: &ViewsSpec,
        options: &ViewOptions,
        scale: f32,
    ) -> Option<crate::view::pick::PickView> {
        let (_, view) = self.scene.as_mut()?;
        view.set_views(views.body, views.ball, views.poincare, views.overlay);
        let field = self
            .field
            .as_ref()
            .filter(|_| views.poincare)
            .map(|f| f.1.as_slice());
        let frame = view.frame(&status.snapshot, field, (rect[2], rect[3]), options);
        let pick = view.pick_view(&frame);
        self.renderer
            .render_scaled_in(target, size, rect, &frame, scale);
        pick
    }

    /// The body's view as the window's scene was last painted (frame pixels from the scene
    /// area's top left), if a body was drawn.
    pub fn pick_view(&self) -> Option<crate::view::pick::PickView> {
        self.pick
    }

    /// The whole frame: the 3D scene in `scene_rect` (pixels, its views drawn at `scale` of
    /// that: `ui::render_scale`), egui's panels (uploaded by [`Self::prepare`]) over it.
    #[allow(clippy::too_many_arguments)]
    pub fn paint(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &wgpu::TextureView,
        size: (u32, u32),
        scene_rect: [u32; 4],
        status: &SimStatus,
        views: &ViewsSpec,
        options: &ViewOptions,
        scale: f32,
    ) {
        let has_scene = scene_rect[2] >= 16 && scene_rect[3] >= 16;
        if has_scene {
            self.pick =
                self.paint_scene_in(target, size, scene_rect, status, views, options, scale);
        }
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            // With no 3D area this pass also clears, so the panels never draw over stale pixels.
            let load = if has_scene {
                wgpu::LoadOp::Load
            } else {
                wgpu::LoadOp::Clear(wgpu::Color::BLACK)
            };
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            // egui-wgpu's render takes a pass without the encoder's lifetime.
            let mut pass = pass.forget_lifetime();
            self.egui.render(&mut pass);
        }
        queue.submit([encoder.finish()]);
    }
}

/// The UI's 3D rectangle (points) in whole pixels inside a `size` target.
pub fn rect_to_pixels(rect: egui::Rect, pixels_per_point: f32, size: (u32, u32)) -> [u32; 4] {
    let x0 = (rect.left() * pixels_per_point)
        .round()
        .clamp(0.0, size.0 as f32) as u32;
    let y0 = (rect.top() * pixels_per_point)
        .round()
        .clamp(0.0, size.1 as f32) as u32;
    let x1 = (rect.right() * pixels_per_point)
        .round()
        .clamp(0.0, size.0 as f32) as u32;
    let y1 = (rect.bottom() * pixels_per_point)
        .round()
        .clamp(0.0, size.1 as f32) as u32;
    [x0, y0, x1.saturating_sub(x0), y1.saturating_sub(y0)]
}
