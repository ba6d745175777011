//! The pipelines: shader modules, bind-group layouts, the GPU-side vertex and uniform structs,
//! the growable scratch buffers, and [`Renderer::new`], which builds them all.

use wgpu::util::DeviceExt;

use super::{DEPTH_FORMAT, Renderer, overlay};

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct Vertex {
    pub(super) position: [f32; 3],
    pub(super) normal: [f32; 3],
    pub(super) color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct CameraUniform {
    pub(super) view_proj: [[f32; 4]; 4],
    pub(super) eye: [f32; 4],
    pub(super) light: [f32; 4],
    pub(super) viewport: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct DrawUniform {
    pub(super) model: [[f32; 4]; 4],
    pub(super) tint: [f32; 4],
    pub(super) params: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct SegmentInstance {
    pub(super) a: [f32; 4],
    pub(super) b: [f32; 4],
    pub(super) color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct QuadVertex {
    pub(super) position: [f32; 3],
    pub(super) uv: [f32; 2],
    pub(super) color: [f32; 4],
}

pub(super) struct GpuMesh {
    pub(super) vertices: wgpu::Buffer,
    pub(super) indices: wgpu::Buffer,
    pub(super) index_count: u32,
}

/// A growable GPU buffer rewritten each frame (the renderer's uniforms and instances, egui's
/// vertices and indices in the app).
pub struct Scratch {
    /// The buffer; replaced by a larger one when a write does not fit.
    pub buffer: wgpu::Buffer,
    usage: wgpu::BufferUsages,
    label: &'static str,
}

impl Scratch {
    /// A 4 KiB buffer for `usage` (COPY_DST added).
    pub fn new(device: &wgpu::Device, label: &'static str, usage: wgpu::BufferUsages) -> Self {
        Self {
            buffer: Self::alloc(device, label, usage, 4096),
            usage,
            label,
        }
    }

    fn alloc(
        device: &wgpu::Device,
        label: &'static str,
        usage: wgpu::BufferUsages,
        size: u64,
    ) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// Writes `bytes` (a multiple of 4 long); returns whether the buffer was reallocated.
    pub fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) -> bool {
        let mut grown = false;
        if bytes.len() as u64 > self.buffer.size() {
            let size = (bytes.len() as u64).next_power_of_two();
            self.buffer = Self::alloc(device, self.label, self.usage, size);
            grown = true;
        }
        if !bytes.is_empty() {
            queue.write_buffer(&self.buffer, 0, bytes);
        }
        grown
    }
}

pub(super) struct Targets {
    pub(super) size: (u32, u32),
    pub(super) msaa: Option<wgpu::TextureView>,
    pub(super) depth: wgpu::TextureView,
}

/// The WGSL sources, by file name: compiled here and validated by `tests/app/shaders.rs`. Each
/// is compiled after [`OUTPUT_COLOUR`], the colour a fragment writes (`output_colour`, with the
/// `ENCODE_SRGB` constant that [`Renderer::new`] sets from the target's format).
pub const SHADERS: &[(&str, &str)] = &[
    (
        "mesh.wgsl",
        concat!(
            include_str!("../../../../shaders/output_colour.wgsl"),
            include_str!("../../../../shaders/mesh.wgsl")
        ),
    ),
    (
        "lines.wgsl",
        concat!(
            include_str!("../../../../shaders/output_colour.wgsl"),
            include_str!("../../../../shaders/lines.wgsl")
        ),
    ),
    (
        "overlay.wgsl",
        concat!(
            include_str!("../../../../shaders/output_colour.wgsl"),
            include_str!("../../../../shaders/overlay.wgsl")
        ),
    ),
];

/// `shaders/output_colour.wgsl`, the prelude every source in [`SHADERS`] begins with.
pub const OUTPUT_COLOUR: &str = include_str!("../../../../shaders/output_colour.wgsl");

pub(super) fn shader(device: &wgpu::Device, name: &str) -> wgpu::ShaderModule {
    let source = SHADERS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| *s)
        .unwrap_or("");
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(name),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

pub(super) fn uniform_layout(
    device: &wgpu::Device,
    label: &str,
    size: u64,
) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: true,
                min_binding_size: wgpu::BufferSize::new(size),
            },
            count: None,
        }],
    })
}

pub(super) fn uniform_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    buffer: &wgpu::Buffer,
    size: u64,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer,
                offset: 0,
                size: wgpu::BufferSize::new(size),
            }),
        }],
    })
}

pub(super) const CAMERA_SIZE: u64 = std::mem::size_of::<CameraUniform>() as u64;
pub(super) const DRAW_SIZE: u64 = std::mem::size_of::<DrawUniform>() as u64;

pub(super) struct PipelineSpec<'a> {
    label: &'a str,
    module: &'a wgpu::ShaderModule,
    layout: &'a wgpu::PipelineLayout,
    buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    blend: wgpu::BlendState,
    depth_write: bool,
    depth_compare: wgpu::CompareFunction,
    cull: Option<wgpu::Face>,
    /// Writes the colour as sampled, never sRGB-encoding it: a copy of a picture already
    /// encoded for this format (the scaled 3D view).
    pass_through: bool,
}

impl Renderer {
    /// Builds the pipelines for targets of `format`, with `sample_count` (1 or 4) MSAA.
    #[expect(
        clippy::too_many_lines,
        reason = "a flat list of wgpu descriptors (shaders, layouts, one pipeline each), read top \
                  to bottom; each is used once"
    )]
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        format: wgpu::TextureFormat,
        sample_count: u32,
    ) -> Self {
        let camera_layout = uniform_layout(device, "camera", CAMERA_SIZE);
        let draw_layout = uniform_layout(device, "draw", DRAW_SIZE);
        let texture_layout = texture_sampler_layout(device, "panel texture");
        let mesh_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("mesh"),
            bind_group_layouts: &[Some(&camera_layout), Some(&draw_layout)],
            immediate_size: 0,
        });
        let lines_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("lines"),
            bind_group_layouts: &[Some(&camera_layout)],
            immediate_size: 0,
        });
        let overlay_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("overlay"),
            bind_group_layouts: &[Some(&texture_layout)],
            immediate_size: 0,
        });
        let mesh_module = shader(device, "mesh.wgsl");
        let lines_module = shader(device, "lines.wgsl");
        let overlay_module = shader(device, "overlay.wgsl");
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4],
        };
        let segment_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<SegmentInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x4],
        };
        let quad_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<QuadVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x2, 2 => Float32x4],
        };
        let make = |s: PipelineSpec| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(s.label),
                layout: Some(s.layout),
                vertex: wgpu::VertexState {
                    module: s.module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: s.buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    cull_mode: s.cull,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(s.depth_write),
                    depth_compare: Some(s.depth_compare),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState {
                    count: sample_count,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: s.module,
                    entry_point: Some("fs_main"),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: &[(
                            "ENCODE_SRGB",
                            f64::from(u8::from(!format.is_srgb() && !s.pass_through)),
                        )],
                        ..Default::default()
                    },
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: Some(s.blend),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let vbuf = [Some(vertex_layout)];
        let mesh_opaque = make(PipelineSpec {
            label: "mesh opaque",
            module: &mesh_module,
            layout: &mesh_layout,
            buffers: &vbuf,
            blend: wgpu::BlendState::REPLACE,
            depth_write: true,
            depth_compare: wgpu::CompareFunction::Less,
            cull: Some(wgpu::Face::Back),
            pass_through: false,
        });
        let mesh_blended = make(PipelineSpec {
            label: "mesh blended",
            module: &mesh_module,
            layout: &mesh_layout,
            buffers: &vbuf,
            blend: wgpu::BlendState::ALPHA_BLENDING,
            depth_write: false,
            depth_compare: wgpu::CompareFunction::Less,
            cull: Some(wgpu::Face::Back),
            pass_through: false,
        });
        let sbuf = [Some(segment_layout)];
        let lines = make(PipelineSpec {
            label: "lines",
            module: &lines_module,
            layout: &lines_layout,
            buffers: &sbuf,
            blend: wgpu::BlendState::ALPHA_BLENDING,
            depth_write: true,
            depth_compare: wgpu::CompareFunction::LessEqual,
            cull: None,
            pass_through: false,
        });
        let lines_on_top = make(PipelineSpec {
            label: "lines on top",
            module: &lines_module,
            layout: &lines_layout,
            buffers: &sbuf,
            blend: wgpu::BlendState::ALPHA_BLENDING,
            depth_write: false,
            depth_compare: wgpu::CompareFunction::Always,
            cull: None,
            pass_through: false,
        });
        let qbuf = [Some(quad_layout)];
        let overlay = make(PipelineSpec {
            label: "overlay",
            module: &overlay_module,
            layout: &overlay_layout,
            buffers: &qbuf,
            blend: wgpu::BlendState::ALPHA_BLENDING,
            depth_write: true,
            depth_compare: wgpu::CompareFunction::Always,
            cull: None,
            pass_through: false,
        });
        // The scaled 3D view, stretched over the picture: as the overlay's quads, but the colour
        // is copied as sampled (it is already encoded for the format) and replaces what is there.
        let blit = make(PipelineSpec {
            label: "scaled view",
            module: &overlay_module,
            layout: &overlay_layout,
            buffers: &qbuf,
            blend: wgpu::BlendState::REPLACE,
            depth_write: false,
            depth_compare: wgpu::CompareFunction::Always,
            cull: None,
            pass_through: true,
        });
        let linear_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("scaled view"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("panel"),
            mag_filter: wgpu::FilterMode::Nearest,
            min_filter: wgpu::FilterMode::Nearest,
            ..Default::default()
        });
        let white_texture = srgba_texture(device, queue, "white", (1, 1), &[255; 4]);
        let white = texture_group(device, &texture_layout, &white_texture, &sampler);
        let uniform_align = device.limits().min_uniform_buffer_offset_alignment as u64;
        let cameras = Scratch::new(device, "cameras", wgpu::BufferUsages::UNIFORM);
        let draws = Scratch::new(device, "draws", wgpu::BufferUsages::UNIFORM);
        let camera_group = uniform_group(device, &camera_layout, &cameras.buffer, CAMERA_SIZE);
        let draw_group = uniform_group(device, &draw_layout, &draws.buffer, DRAW_SIZE);
        Self {
            device: device.clone(),
            queue: queue.clone(),
            format,
            sample_count,
            mesh_opaque,
            mesh_blended,
            lines,
            lines_on_top,
            overlay,
            camera_layout,
            draw_layout,
            texture_layout,
            sampler,
            white,
            uniform_align,
            cameras,
            draws,
            camera_group,
            draw_group,
            segments: Scratch::new(device, "segments", wgpu::BufferUsages::VERTEX),
            quads: Scratch::new(device, "quads", wgpu::BufferUsages::VERTEX),
            meshes: Vec::new(),
            targets: Vec::new(),
            scaled: None,
            blit,
            linear_sampler,
            font: overlay::Font::bundled(),
            panel_cache: Vec::new(),
        }
    }
}

/// A sampled sRGBA texture of `size` holding `rgba` (the overlay's panels, the white texel).
pub(super) fn srgba_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    size: (u32, u32),
    rgba: &[u8],
) -> wgpu::Texture {
    device.create_texture_with_data(
        queue,
        &wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        rgba,
    )
}

/// The layout of a fragment shader's filtered 2D texture (binding 0) and its sampler (1): the
/// panels' here, egui's in the app.
pub fn texture_sampler_layout(device: &wgpu::Device, label: &str) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    })
}

/// A bind group of `texture` (whole) and `sampler` for a [`texture_sampler_layout`] layout.
pub fn texture_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    texture: &wgpu::Texture,
    sampler: &wgpu::Sampler,
) -> wgpu::BindGroup {
    let view = texture.create_view(&Default::default());
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("texture"),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
        ],
    })
}
