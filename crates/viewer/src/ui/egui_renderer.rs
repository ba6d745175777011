//! Draws egui's tessellated output (its meshes, clip rectangles and textures) with wgpu.
//!
//! Our own instead of egui-wgpu's renderer, for speed on CPU renderers: egui-wgpu 0.37's
//! fragment shader branches on a uniform between hardware sampling and four manual texel
//! loads with wrap arithmetic, and llvmpipe (the renderer of machines without a GPU: many
//! classroom PCs and remote desktops) runs both sides for every pixel. At 1280×720 with the
//! plots the panels took 31 ms a frame that way and 9 ms with one sample (`bench app`, this
//! machine, 2026-11-24), which is what lifts the app from 22 to over 30 frames/s there. On a
//! GPU the two cost the same.
//!
//! What the app needs of egui-wgpu is small, and this is all of it: the textures egui asks for
//! (full and partial updates, its sampler options), one pipeline with egui's blending
//! (premultiplied alpha), and each mesh under its clip rectangle. No paint callbacks: the 3D
//! view is drawn by [`crate::render::Renderer`] before the panels.
//!
//! Kept honest three ways. What it cannot draw (a paint callback, a mesh whose texture egui never
//! sent, a patch of a texture it does not have) is skipped with a warning on stderr, once per
//! kind, and listed by [`EguiRenderer::skipped`]. Each mesh's indices are rebased on the CPU, so
//! it never needs `base_vertex` (which WebGL2 and GLES 3.0 lack). And `tests/app/egui_renderer.rs`
//! draws the same egui frames through egui-wgpu (a dev-dependency) and compares the pixels, so
//! an egui release that changes what it sends shows there; the upgrade checklist is next to
//! `egui` in `Cargo.toml`.

use std::collections::HashMap;

use egui::epaint::{self, ClippedPrimitive, ImageData, Primitive, TextureId};

use crate::render::{Scratch, texture_group, texture_sampler_layout};

/// The shader (`shaders/egui.wgsl`), validated by `tests/app/shaders.rs` with the renderer's own.
pub const SHADER: (&str, &str) = ("egui.wgsl", include_str!("../../../../shaders/egui.wgsl"));

/// One egui vertex as the shader reads it. Built field by field rather than cast from
/// [`epaint::Vertex`], whose field order depends on egui's `unity` feature.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuVertex {
    position: [f32; 2],
    uv: [f32; 2],
    color: u32,
}

/// One mesh to draw: its pixel clip rectangle, texture and range in the frame's index buffer
/// (whose indices already point at the frame's vertex buffer).
struct Draw {
    scissor: [u32; 4],
    texture: TextureId,
    indices: std::ops::Range<u32>,
}

/// What egui asked for that this renderer skipped (each reported on stderr once).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Skipped {
    /// A paint callback (custom wgpu drawing inside the UI): this app's UI makes none.
    PaintCallback,
    /// A mesh whose texture egui never sent (drawn by egui-wgpu as nothing, too).
    MissingTexture,
    /// A partial update of a texture this renderer does not have.
    PatchOfUnknownTexture,
}

impl Skipped {
    fn describe(self) -> &'static str {
        match self {
            Skipped::PaintCallback => {
                "a paint callback (custom drawing inside the UI) is not drawn"
            }
            Skipped::MissingTexture => "a mesh whose texture egui never sent is not drawn",
            Skipped::PatchOfUnknownTexture => {
                "a partial update of a texture egui never sent whole is ignored"
            }
        }
    }
}

/// egui's renderer for targets of one format.
pub struct EguiRenderer {
    pipeline: wgpu::RenderPipeline,
    screen: wgpu::Buffer,
    screen_group: wgpu::BindGroup,
    texture_layout: wgpu::BindGroupLayout,
    textures: HashMap<TextureId, EguiTexture>,
    samplers: HashMap<epaint::textures::TextureOptions, wgpu::Sampler>,
    vertices: Scratch,
    indices: Scratch,
    draws: Vec<Draw>,
    skipped: std::collections::BTreeSet<Skipped>,
}

/// A texture egui sent, with the sampler options its bind group was made with.
struct EguiTexture {
    texture: wgpu::Texture,
    group: wgpu::BindGroup,
    options: epaint::textures::TextureOptions,
}

impl EguiRenderer {
    /// A renderer drawing into targets of `format`: gamma formats get egui's colours as they
    /// are, sRGB formats the linear values that encode back to them.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(SHADER.0),
            source: wgpu::ShaderSource::Wgsl(SHADER.1.into()),
        });
        let screen_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("egui screen"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let texture_layout = texture_sampler_layout(device, "egui texture");
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("egui"),
            bind_group_layouts: &[Some(&screen_layout), Some(&texture_layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("egui"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<GpuVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x2, 1 => Float32x2, 2 => Uint32],
                })],
                compilation_options: Default::default(),
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(if format.is_srgb() {
                    "fs_main_linear"
                } else {
                    "fs_main"
                }),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    // egui's colours are premultiplied by alpha (as in egui-wgpu).
                    blend: Some(wgpu::BlendState {
                        color: wgpu::BlendComponent {
                            src_factor: wgpu::BlendFactor::One,
                            dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                            operation: wgpu::BlendOperation::Add,
                        },
                        alpha: wgpu::BlendComponent {
                            src_factor: wgpu::BlendFactor::OneMinusDstAlpha,
                            dst_factor: wgpu::BlendFactor::One,
                            operation: wgpu::BlendOperation::Add,
                        },
                    }),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
                compilation_options: Default::default(),
            }),
            multiview_mask: None,
            cache: None,
        });
        let screen = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("egui screen"),
            size: 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let screen_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("egui screen"),
            layout: &screen_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: screen.as_entire_binding(),
            }],
        });
        Self {
            pipeline,
            screen,
            screen_group,
            texture_layout,
            textures: HashMap::new(),
            samplers: HashMap::new(),
            vertices: Scratch::new(device, "egui vertices", wgpu::BufferUsages::VERTEX),
            indices: Scratch::new(device, "egui indices", wgpu::BufferUsages::INDEX),
            draws: Vec::new(),
            skipped: std::collections::BTreeSet::new(),
        }
    }

    /// The kinds of egui output skipped so far, each reported once on stderr.
    pub fn skipped(&self) -> Vec<Skipped> {
        self.skipped.iter().copied().collect()
    }

    fn skip(&mut self, what: Skipped) {
        if self.skipped.insert(what) {
            eprintln!(
                "warning: the egui renderer skips what it cannot draw: {} (shown once)",
                what.describe()
            );
        }
    }

    /// The bind group of texture `texture` with a sampler for `options`.
    fn bind(
        &mut self,
        device: &wgpu::Device,
        texture: &wgpu::Texture,
        options: epaint::textures::TextureOptions,
    ) -> wgpu::BindGroup {
        let sampler = self
            .samplers
            .entry(options)
            .or_insert_with(|| sampler(device, options));
        texture_group(device, &self.texture_layout, texture, sampler)
    }

    /// Creates or updates (a sub-rectangle of) texture `id` from egui's `delta`.
    pub fn update_texture(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        id: TextureId,
        delta: &epaint::ImageDelta,
    ) {
        let ImageData::Color(image) = &delta.image;
        let [width, height] = image.size.map(|s| s as u32);
        if width == 0 || height == 0 {
            return;
        }
        let origin = match delta.pos {
            Some([x, y]) => {
                let Some(known) = self.textures.get(&id) else {
                    // egui only patches textures it created; nothing to patch means a bug
                    // upstream, and a missing glyph is better than a crash in a lesson.
                    self.skip(Skipped::PatchOfUnknownTexture);
                    return;
                };
                if known.options != delta.options {
                    // A patch may change how the whole texture is sampled (egui-wgpu rebinds
                    // then too).
                    let texture = known.texture.clone();
                    let group = self.bind(device, &texture, delta.options);
                    let known = self.textures.get_mut(&id).expect("looked up above");
                    known.group = group;
                    known.options = delta.options;
                }
                wgpu::Origin3d {
                    x: x as u32,
                    y: y as u32,
                    z: 0,
                }
            }
            None => {
                let texture = device.create_texture(&wgpu::TextureDescriptor {
                    label: Some("egui texture"),
                    size: wgpu::Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    // Gamma values, filtered as they are (as egui-wgpu does).
                    format: wgpu::TextureFormat::Rgba8Unorm,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                    view_formats: &[],
                });
                let group = self.bind(device, &texture, delta.options);
                let made = EguiTexture {
                    texture,
                    group,
                    options: delta.options,
                };
                if let Some(old) = self.textures.insert(id, made) {
                    old.texture.destroy();
                }
                wgpu::Origin3d::ZERO
            }
        };
        let texture = &self.textures[&id].texture;
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin,
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(image.pixels.as_slice()),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * width),
                rows_per_image: Some(height),
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Frees texture `id` (egui is done with it).
    pub fn free_texture(&mut self, id: &TextureId) {
        if let Some(old) = self.textures.remove(id) {
            old.texture.destroy();
        }
    }

    /// Uploads this frame's meshes for a target of `size` pixels at `pixels_per_point`.
    pub fn update_buffers(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        primitives: &[ClippedPrimitive],
        size: (u32, u32),
        pixels_per_point: f32,
    ) {
        let points = [
            size.0 as f32 / pixels_per_point,
            size.1 as f32 / pixels_per_point,
        ];
        queue.write_buffer(
            &self.screen,
            0,
            bytemuck::cast_slice(&[points[0], points[1], 0.0, 0.0]),
        );
        let mut vertices: Vec<GpuVertex> = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        self.draws.clear();
        for ClippedPrimitive {
            clip_rect,
            primitive,
        } in primitives
        {
            let Primitive::Mesh(mesh) = primitive else {
                self.skip(Skipped::PaintCallback);
                continue;
            };
            let scissor = scissor(clip_rect, pixels_per_point, size);
            if scissor[2] == 0 || scissor[3] == 0 || mesh.indices.is_empty() {
                continue;
            }
            if !self.textures.contains_key(&mesh.texture_id) {
                self.skip(Skipped::MissingTexture);
                continue;
            }
            let start = indices.len() as u32;
            self.draws.push(Draw {
                scissor,
                texture: mesh.texture_id,
                indices: start..start + mesh.indices.len() as u32,
            });
            // Rebased here rather than by draw_indexed's base_vertex, which WebGL2 and
            // GLES 3.0 lack (wgpu's DownlevelFlags::BASE_VERTEX).
            let base = vertices.len() as u32;
            indices.extend(mesh.indices.iter().map(|i| i + base));
            vertices.extend(mesh.vertices.iter().map(|v| GpuVertex {
                position: [v.pos.x, v.pos.y],
                uv: [v.uv.x, v.uv.y],
                color: u32::from_le_bytes(v.color.to_array()),
            }));
        }
        // Vertices are 20 bytes and indices u32: both multiples of 4, as write_buffer needs.
        self.vertices
            .write(device, queue, bytemuck::cast_slice(&vertices));
        self.indices
            .write(device, queue, bytemuck::cast_slice(&indices));
    }

    /// Draws the meshes uploaded by [`Self::update_buffers`] into `pass`, whose target has
    /// the size given there.
    pub fn render(&self, pass: &mut wgpu::RenderPass<'_>) {
        if self.draws.is_empty() {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.screen_group, &[]);
        pass.set_vertex_buffer(0, self.vertices.buffer.slice(..));
        pass.set_index_buffer(self.indices.buffer.slice(..), wgpu::IndexFormat::Uint32);
        for draw in &self.draws {
            // Every draw's texture was checked in update_buffers, and egui frees textures only
            // after the frame that uses them.
            let Some(texture) = self.textures.get(&draw.texture) else {
                continue;
            };
            let [x, y, w, h] = draw.scissor;
            pass.set_scissor_rect(x, y, w, h);
            pass.set_bind_group(1, &texture.group, &[]);
            pass.draw_indexed(draw.indices.clone(), 0, 0..1);
        }
    }
}

/// egui's clip rectangle (points) in whole pixels inside a `size` target, as egui-wgpu rounds.
fn scissor(clip: &egui::Rect, pixels_per_point: f32, size: (u32, u32)) -> [u32; 4] {
    let px = |v: f32, max: u32| ((v * pixels_per_point).round().max(0.0) as u32).min(max);
    let (x0, y0) = (px(clip.min.x, size.0), px(clip.min.y, size.1));
    let (x1, y1) = (
        px(clip.max.x, size.0).max(x0),
        px(clip.max.y, size.1).max(y0),
    );
    [x0, y0, x1 - x0, y1 - y0]
}

fn sampler(device: &wgpu::Device, options: epaint::textures::TextureOptions) -> wgpu::Sampler {
    use epaint::textures::{TextureFilter, TextureWrapMode};
    let filter = |f| match f {
        TextureFilter::Nearest => wgpu::FilterMode::Nearest,
        TextureFilter::Linear => wgpu::FilterMode::Linear,
    };
    let address = match options.wrap_mode {
        TextureWrapMode::ClampToEdge => wgpu::AddressMode::ClampToEdge,
        TextureWrapMode::Repeat => wgpu::AddressMode::Repeat,
        TextureWrapMode::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
    };
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("egui sampler"),
        mag_filter: filter(options.magnification),
        min_filter: filter(options.minification),
        address_mode_u: address,
        address_mode_v: address,
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scissor_rounds_to_pixels_and_stays_inside_the_target() {
        let r = |x0, y0, x1, y1| egui::Rect::from_min_max(egui::pos2(x0, y0), egui::pos2(x1, y1));
        assert_eq!(
            scissor(&r(0.0, 0.0, 10.0, 5.0), 2.0, (100, 100)),
            [0, 0, 20, 10]
        );
        assert_eq!(
            scissor(&r(10.2, 3.7, 20.6, 8.2), 1.0, (100, 100)),
            [10, 4, 11, 4]
        );
        // Partly or wholly outside: clipped, never negative or past the edge.
        assert_eq!(
            scissor(&r(-5.0, -5.0, 500.0, 50.0), 1.0, (100, 40)),
            [0, 0, 100, 40]
        );
        assert_eq!(
            scissor(&r(200.0, 0.0, 300.0, 10.0), 1.0, (100, 40)),
            [100, 0, 0, 10]
        );
        assert_eq!(
            scissor(
                &r(f32::NEG_INFINITY, 0.0, f32::INFINITY, 10.0),
                1.0,
                (64, 40)
            ),
            [0, 0, 64, 10]
        );
    }
}
