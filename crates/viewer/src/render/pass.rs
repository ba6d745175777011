//! Uploads and the render pass: [`Renderer::render`] draws a [`Frame`] into a texture view.

use glam::Vec3;
use wgpu::util::DeviceExt;

use super::pipelines::{
    CAMERA_SIZE, CameraUniform, DRAW_SIZE, DrawUniform, GpuMesh, QuadVertex, SegmentInstance,
    Targets, Vertex, srgba_texture, texture_group, uniform_group,
};
use super::{DEPTH_FORMAT, Frame, MeshData, MeshHandle, Renderer, overlay};

impl Renderer {
    /// The colour format this renderer draws into.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// Uploads a mesh once; frames refer to it by the handle.
    pub fn upload_mesh(&mut self, mesh: &MeshData) -> MeshHandle {
        self.upload(mesh)
    }

    /// Frees an uploaded mesh's GPU buffers; its handle then draws nothing, and a later upload
    /// may take its slot. A scene's meshes are freed when another scene replaces it.
    pub fn free_mesh(&mut self, mesh: MeshHandle) {
        if let Some(slot) = self.meshes.get_mut(mesh.0) {
            *slot = None;
        }
    }

    /// How many meshes are uploaded and not freed.
    pub fn mesh_count(&self) -> usize {
        self.meshes.iter().flatten().count()
    }

    fn upload(&mut self, mesh: &MeshData) -> MeshHandle {
        let vertices: Vec<Vertex> = (0..mesh.positions.len())
            .map(|i| Vertex {
                position: mesh.positions[i],
                normal: mesh.normals.get(i).copied().unwrap_or([0.0, 0.0, 1.0]),
                color: mesh.colors.get(i).copied().unwrap_or([1.0; 4]),
            })
            .collect();
        let vertices = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("mesh vertices"),
                contents: bytemuck::cast_slice(&vertices),
                usage: wgpu::BufferUsages::VERTEX,
            });
        let indices = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("mesh indices"),
                contents: bytemuck::cast_slice(&mesh.indices),
                usage: wgpu::BufferUsages::INDEX,
            });
        let uploaded = Some(GpuMesh {
            vertices,
            indices,
            index_count: mesh.indices.len() as u32 * 3,
        });
        match self.meshes.iter().position(Option::is_none) {
            Some(free) => {
                self.meshes[free] = uploaded;
                MeshHandle(free)
            }
            None => {
                self.meshes.push(uploaded);
                MeshHandle(self.meshes.len() - 1)
            }
        }
    }

    /// Makes sure depth (and MSAA) targets of `size` exist. Two sizes are kept, the most
    /// recently used last: a scaled 3D view draws at its own size and then the full target at
    /// the window's, every frame, and neither should be reallocated each time.
    pub(super) fn ensure_targets(&mut self, size: (u32, u32)) {
        if let Some(k) = self.targets.iter().position(|t| t.size == size) {
            let found = self.targets.remove(k);
            self.targets.push(found);
            return;
        }
        if self.targets.len() >= 2 {
            self.targets.remove(0);
        }
        let extent = wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        };
        let make = |format, label| {
            self.device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: extent,
                    mip_level_count: 1,
                    sample_count: self.sample_count,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let made = Targets {
            size,
            msaa: (self.sample_count > 1).then(|| make(self.format, "msaa colour")),
            depth: make(DEPTH_FORMAT, "depth"),
        };
        self.targets.push(made);
    }

    /// Draws `frame` into `target` (a `width`×`height` view of this renderer's format) and
    /// submits the work.
    pub fn render(&mut self, target: &wgpu::TextureView, size: (u32, u32), frame: &Frame) {
        self.render_in(target, size, [0, 0, size.0, size.1], frame);
    }

    /// Draws `frame`, laid out for a `rect[2]`×`rect[3]` picture, into the pixel rectangle `rect`
    /// (x, y, w, h) of `target` (`size` pixels): the app's 3D area beside its controls. The whole
    /// target is cleared to `frame.clear` first.
    pub fn render_in(
        &mut self,
        target: &wgpu::TextureView,
        size: (u32, u32),
        rect: [u32; 4],
        frame: &Frame,
    ) {
        self.draw(target, size, rect, frame, Layers::ALL);
    }

    /// [`Self::render_in`] with a choice of what is drawn: the views, the panels, and a
    /// picture drawn first over `rect` (the scaled 3D view, `render/scale.rs`).
    #[expect(
        clippy::too_many_lines,
        reason = "one frame's wgpu work in the order the GPU needs it (upload the frame's buffers, \
                  then one render pass over every view and panel); the steps share the buffers and \
                  the pass, and read in order"
    )]
    pub(super) fn draw(
        &mut self,
        target: &wgpu::TextureView,
        size: (u32, u32),
        rect: [u32; 4],
        frame: &Frame,
        layers: Layers<'_>,
    ) {
        self.ensure_targets(size);
        let (width, height) = size;
        let [ox, oy, _, _] = clamp_viewport(rect, size);
        let picture = (
            rect[2].min(width - ox).max(1),
            rect[3].min(height - oy).max(1),
        );
        // Uniforms: one camera per view, one draw per mesh instance, at aligned offsets.
        let cam_stride = CAMERA_SIZE.div_ceil(self.uniform_align) * self.uniform_align;
        let draw_stride = DRAW_SIZE.div_ceil(self.uniform_align) * self.uniform_align;
        let mut cam_bytes = Vec::new();
        let mut draw_bytes = Vec::new();
        let mut seg_data: Vec<SegmentInstance> = Vec::new();
        let mut quad_data: Vec<QuadVertex> = Vec::new();
        struct ViewPlan {
            viewport: [f32; 4],
            cam_offset: u32,
            background: Option<std::ops::Range<u32>>,
            opaque: Vec<(usize, u32)>,
            blended: Vec<(usize, u32)>,
            segments: std::ops::Range<u32>,
            segments_on_top: std::ops::Range<u32>,
        }
        let mut plans = Vec::new();
        let views: &[super::View] = if layers.views { &frame.views } else { &[] };
        for view in views {
            let [x, y, w, h] = clamp_viewport(view.viewport, picture);
            let (x, y) = (x + ox, y + oy);
            let aspect = w as f32 / h.max(1) as f32;
            let cam = CameraUniform {
                view_proj: view.camera.view_proj(aspect).to_cols_array_2d(),
                eye: view.camera.eye.extend(1.0).to_array(),
                light: view.light_dir.normalize_or(Vec3::Z).extend(0.22).to_array(),
                viewport: [w as f32, h as f32, 0.0, 0.0],
            };
            let cam_offset = cam_bytes.len() as u32;
            push_aligned(&mut cam_bytes, bytemuck::bytes_of(&cam), cam_stride);
            let background = view.background.map(|c| {
                let start = quad_data.len() as u32;
                // The viewport is the inset, so the quad covers its whole NDC square.
                quad_data.extend(quad([0, 0, w, h], (w, h), 1.0, [0.0, 0.0, 1.0, 1.0], c));
                start..quad_data.len() as u32
            });
            let mut opaque = Vec::new();
            let mut blended = Vec::new();
            for inst in &view.meshes {
                if self.meshes.get(inst.mesh.0).is_none_or(Option::is_none) {
                    continue;
                }
                let m = &inst.material;
                let draw = DrawUniform {
                    model: inst.model.to_cols_array_2d(),
                    tint: m.tint,
                    params: [
                        m.opacity,
                        m.grid_spacing,
                        m.specular,
                        if m.unlit { 1.0 } else { 0.0 },
                    ],
                };
                let offset = draw_bytes.len() as u32;
                push_aligned(&mut draw_bytes, bytemuck::bytes_of(&draw), draw_stride);
                if m.opacity < 1.0 {
                    blended.push((inst.mesh.0, offset));
                } else {
                    opaque.push((inst.mesh.0, offset));
                }
            }
            let instance = |s: &super::Segment| SegmentInstance {
                a: s.a.extend(s.width_px).to_array(),
                b: s.b.extend(0.0).to_array(),
                color: s.color,
            };
            let start = seg_data.len() as u32;
            seg_data.extend(view.segments.iter().map(instance));
            let on_top_start = seg_data.len() as u32;
            seg_data.extend(view.segments_on_top.iter().map(instance));
            plans.push(ViewPlan {
                viewport: [x as f32, y as f32, w as f32, h as f32],
                cam_offset,
                background,
                opaque,
                blended,
                segments: start..on_top_start,
                segments_on_top: on_top_start..seg_data.len() as u32,
            });
        }
        // Panels: rasterised on the CPU, one texture each; a panel the last frames showed
        // unchanged reuses its texture.
        let mut panel_draws = Vec::new();
        // A frame drawn without its panels leaves the cache as it was.
        let panels: &[super::OverlayPanel] = if layers.panels { &frame.panels } else { &[] };
        let mut cache = std::mem::take(&mut self.panel_cache);
        let mut kept = Vec::with_capacity(panels.len());
        for panel in panels {
            let cached = cache
                .iter()
                .position(|c| c.0 == *panel)
                .map(|i| cache.swap_remove(i));
            let (panel, (w, h), group) = match cached {
                Some(c) => c,
                None => {
                    let image = overlay::rasterise(panel, &self.font);
                    if image.width == 0 || image.height == 0 {
                        continue;
                    }
                    let texture = srgba_texture(
                        &self.device,
                        &self.queue,
                        "panel",
                        (image.width, image.height),
                        &image.rgba,
                    );
                    let group =
                        texture_group(&self.device, &self.texture_layout, &texture, &self.sampler);
                    (panel.clone(), (image.width, image.height), group)
                }
            };
            let (px, py) = panel.anchor.place(w, h, picture);
            let (px, py) = (px + ox, py + oy);
            let start = quad_data.len() as u32;
            quad_data.extend(quad(
                [px, py, w, h],
                size,
                0.0,
                [0.0, 0.0, 1.0, 1.0],
                [1.0; 4],
            ));
            panel_draws.push((group.clone(), start..quad_data.len() as u32));
            kept.push((panel, (w, h), group));
        }
        // Only this frame's panels stay: the cache never outgrows one frame's.
        self.panel_cache = if layers.panels { kept } else { cache };
        let underlay = layers.underlay.map(|group| {
            let [x, y, _, _] = clamp_viewport(rect, size);
            let start = quad_data.len() as u32;
            quad_data.extend(quad(
                [x, y, picture.0, picture.1],
                size,
                1.0,
                [0.0, 0.0, 1.0, 1.0],
                [1.0; 4],
            ));
            (group, start..quad_data.len() as u32)
        });
        if cam_bytes.is_empty() {
            cam_bytes.resize(cam_stride as usize, 0);
        }
        if draw_bytes.is_empty() {
            draw_bytes.resize(draw_stride as usize, 0);
        }
        if self.cameras.write(&self.device, &self.queue, &cam_bytes) {
            self.camera_group = uniform_group(
                &self.device,
                &self.camera_layout,
                &self.cameras.buffer,
                CAMERA_SIZE,
            );
        }
        if self.draws.write(&self.device, &self.queue, &draw_bytes) {
            self.draw_group = uniform_group(
                &self.device,
                &self.draw_layout,
                &self.draws.buffer,
                DRAW_SIZE,
            );
        }
        self.segments
            .write(&self.device, &self.queue, bytemuck::cast_slice(&seg_data));
        self.quads
            .write(&self.device, &self.queue, bytemuck::cast_slice(&quad_data));

        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        {
            let Some(targets) = self.targets.last() else {
                return;
            };
            let (view, resolve) = match &targets.msaa {
                Some(msaa) => (msaa, Some(target)),
                None => (target, None),
            };
            let [r, g, b, a] = clear_colour(frame.clear, self.format);
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("frame"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: resolve,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color { r, g, b, a }),
                        // With MSAA only the resolved image is needed; dropping the samples
                        // saves a full-size store per frame (a third of the frame time on
                        // llvmpipe at 1280×720).
                        store: if resolve.is_some() {
                            wgpu::StoreOp::Discard
                        } else {
                            wgpu::StoreOp::Store
                        },
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &targets.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if let Some((group, range)) = underlay {
                pass.set_pipeline(&self.blit);
                pass.set_bind_group(0, group, &[]);
                pass.set_vertex_buffer(0, self.quads.buffer.slice(..));
                pass.draw(range, 0..1);
            }
            for plan in &plans {
                let [x, y, w, h] = plan.viewport;
                pass.set_viewport(x, y, w, h, 0.0, 1.0);
                pass.set_scissor_rect(x as u32, y as u32, w as u32, h as u32);
                if let Some(range) = plan.background.clone() {
                    pass.set_pipeline(&self.overlay);
                    pass.set_bind_group(0, &self.white, &[]);
                    pass.set_vertex_buffer(0, self.quads.buffer.slice(..));
                    pass.draw(range, 0..1);
                }
                pass.set_bind_group(0, &self.camera_group, &[plan.cam_offset]);
                pass.set_pipeline(&self.mesh_opaque);
                for &(mesh, offset) in &plan.opaque {
                    self.draw_mesh(&mut pass, mesh, offset);
                }
                if !plan.segments.is_empty() {
                    pass.set_pipeline(&self.lines);
                    pass.set_vertex_buffer(0, self.segments.buffer.slice(..));
                    pass.draw(0..6, plan.segments.clone());
                }
                if !plan.blended.is_empty() {
                    pass.set_pipeline(&self.mesh_blended);
                    for &(mesh, offset) in &plan.blended {
                        self.draw_mesh(&mut pass, mesh, offset);
                    }
                }
                if !plan.segments_on_top.is_empty() {
                    pass.set_pipeline(&self.lines_on_top);
                    pass.set_vertex_buffer(0, self.segments.buffer.slice(..));
                    pass.draw(0..6, plan.segments_on_top.clone());
                }
            }
            pass.set_viewport(0.0, 0.0, width as f32, height as f32, 0.0, 1.0);
            pass.set_scissor_rect(0, 0, width, height);
            if !panel_draws.is_empty() {
                pass.set_pipeline(&self.overlay);
                pass.set_vertex_buffer(0, self.quads.buffer.slice(..));
                for (group, range) in &panel_draws {
                    pass.set_bind_group(0, group, &[]);
                    pass.draw(range.clone(), 0..1);
                }
            }
        }
        self.queue.submit([encoder.finish()]);
    }

    pub(super) fn draw_mesh(&self, pass: &mut wgpu::RenderPass<'_>, mesh: usize, offset: u32) {
        let Some(m) = self.meshes.get(mesh).and_then(Option::as_ref) else {
            return;
        };
        pass.set_bind_group(1, &self.draw_group, &[offset]);
        pass.set_vertex_buffer(0, m.vertices.slice(..));
        pass.set_index_buffer(m.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..m.index_count, 0, 0..1);
    }
}

/// The clear colour as `format` stores it: a non-sRGB target gets it sRGB-encoded, as the
/// shaders' `output_colour` encodes what they draw.
fn clear_colour(linear: [f32; 4], format: wgpu::TextureFormat) -> [f64; 4] {
    let [r, g, b, a] = linear.map(f64::from);
    if format.is_srgb() {
        return [r, g, b, a];
    }
    let encode = |c: f64| {
        let c = c.clamp(0.0, 1.0);
        if c <= 0.003_130_8 {
            c * 12.92
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        }
    };
    [encode(r), encode(g), encode(b), a]
}

/// What [`Renderer::draw`] draws of a frame.
#[derive(Clone, Copy)]
pub(super) struct Layers<'a> {
    /// The 3D views.
    pub(super) views: bool,
    /// The 2D panels.
    pub(super) panels: bool,
    /// A texture stretched over the picture's rectangle before anything else.
    pub(super) underlay: Option<&'a wgpu::BindGroup>,
}

impl Layers<'_> {
    /// The whole frame.
    pub(super) const ALL: Layers<'static> = Layers {
        views: true,
        panels: true,
        underlay: None,
    };
}

pub(super) fn push_aligned(out: &mut Vec<u8>, bytes: &[u8], stride: u64) {
    out.extend_from_slice(bytes);
    out.resize(out.len() + (stride as usize - bytes.len()), 0);
}

pub(super) fn clamp_viewport(v: [u32; 4], size: (u32, u32)) -> [u32; 4] {
    let x = v[0].min(size.0.saturating_sub(1));
    let y = v[1].min(size.1.saturating_sub(1));
    let w = v[2].clamp(1, size.0 - x);
    let h = v[3].clamp(1, size.1 - y);
    [x, y, w, h]
}

/// Two triangles covering a pixel rectangle, at `depth`.
pub(super) fn quad(
    rect: [u32; 4],
    size: (u32, u32),
    depth: f32,
    uv: [f32; 4],
    color: [f32; 4],
) -> [QuadVertex; 6] {
    let to_ndc = |px: f32, py: f32| {
        [
            px / size.0 as f32 * 2.0 - 1.0,
            1.0 - py / size.1 as f32 * 2.0,
        ]
    };
    let [x, y, w, h] = rect.map(|v| v as f32);
    let [x0, y0] = to_ndc(x, y);
    let [x1, y1] = to_ndc(x + w, y + h);
    let v = |px: f32, py: f32, u: f32, vv: f32| QuadVertex {
        position: [px, py, depth],
        uv: [u, vv],
        color,
    };
    let [u0, v0, u1, v1] = uv;
    [
        v(x0, y0, u0, v0),
        v(x0, y1, u0, v1),
        v(x1, y0, u1, v0),
        v(x1, y0, u1, v0),
        v(x0, y1, u0, v1),
        v(x1, y1, u1, v1),
    ]
}

impl super::types::MeshStore for Renderer {
    fn upload_mesh(&mut self, mesh: &MeshData) -> MeshHandle {
        self.upload(mesh)
    }

    fn free_mesh(&mut self, mesh: MeshHandle) {
        Renderer::free_mesh(self, mesh);
    }
}
