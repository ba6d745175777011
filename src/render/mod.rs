//! The wgpu renderer: plain draw data in ([`Frame`]: views with cameras, mesh instances and line
//! segments, plus 2D panels of text and colour legends), pixels out. It never sees a model, a
//! scene or a window: the window (app) and the headless mode call the same
//! [`Renderer::render`] on a `TextureView`.
//!
//! Three pipelines, one shader file each (`shaders/*.wgsl`): lit meshes (opaque and translucent
//! variants), screen-space thick lines, and textured overlay quads. Everything is drawn in one
//! render pass with 4× MSAA (configurable) and a Depth32Float buffer; inset views get their own
//! viewport, and a background quad at depth 1 clears their region of colour and depth.
//!
//! Imports wgpu, glam, bytemuck and ab_glyph only.

pub mod gpu;
pub mod overlay;

use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

pub use gpu::{GpuContext, GpuError};
pub use overlay::{Panel, PanelItem};

/// Format of the depth buffer.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// A mesh to upload: positions, normals and per-vertex linear RGBA colours.
#[derive(Debug, Clone, Default)]
pub struct MeshData {
    /// Positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit normals.
    pub normals: Vec<[f32; 3]>,
    /// Linear RGBA per vertex.
    pub colors: Vec<[f32; 4]>,
    /// Triangles.
    pub indices: Vec<[u32; 3]>,
}

/// A mesh uploaded to the GPU, referred to by frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MeshHandle(usize);

/// How a mesh instance is shaded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Multiplies the vertex colour (linear RGBA).
    pub tint: [f32; 4],
    /// 1 opaque; below 1 drawn blended after the opaque geometry, without writing depth.
    pub opacity: f32,
    /// Spacing of a grid drawn in the mesh's own x, y coordinates (0: none).
    pub grid_spacing: f32,
    /// Strength of the specular highlight.
    pub specular: f32,
    /// Drawn without lighting.
    pub unlit: bool,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            tint: [1.0; 4],
            opacity: 1.0,
            grid_spacing: 0.0,
            specular: 0.35,
            unlit: false,
        }
    }
}

/// One mesh drawn with a model matrix (rotation, uniform scale, translation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshInstance {
    /// Which mesh.
    pub mesh: MeshHandle,
    /// World from mesh.
    pub model: Mat4,
    /// Shading.
    pub material: Material,
}

/// A line segment `width_px` pixels wide.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Start (world).
    pub a: Vec3,
    /// End (world).
    pub b: Vec3,
    /// Linear RGBA.
    pub color: [f32; 4],
    /// Width in pixels.
    pub width_px: f32,
}

/// A perspective camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up direction.
    pub up: Vec3,
    /// Vertical field of view, radians.
    pub fov_y_rad: f32,
    /// Near plane.
    pub near: f32,
    /// Far plane.
    pub far: f32,
}

impl Camera {
    /// Projection × view for a viewport of the given aspect ratio (wgpu's 0..1 depth).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        // wgpu's clip space is DirectX's: depth 0..1, y up.
        glam::camera::rh::proj::directx::perspective(self.fov_y_rad, aspect, self.near, self.far)
            * glam::camera::rh::view::look_at_mat4(self.eye, self.target, self.up)
    }
}

/// One 3D view drawn into a rectangle of the target.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// x, y (from the top left), width, height in pixels.
    pub viewport: [u32; 4],
    /// Fill colour of the rectangle (linear RGBA); the frame's clear colour shows if `None`.
    pub background: Option<[f32; 4]>,
    /// The camera.
    pub camera: Camera,
    /// Direction towards the light (world).
    pub light_dir: Vec3,
    /// Meshes.
    pub meshes: Vec<MeshInstance>,
    /// Line segments.
    pub segments: Vec<Segment>,
}

/// Everything one frame shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Clear colour (linear RGBA).
    pub clear: [f32; 4],
    /// 3D views, drawn in order (insets after the main view).
    pub views: Vec<View>,
    /// 2D panels drawn on top.
    pub panels: Vec<Panel>,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Vertex {
    position: [f32; 3],
    normal: [f32; 3],
    color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CameraUniform {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    light: [f32; 4],
    viewport: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct DrawUniform {
    model: [[f32; 4]; 4],
    tint: [f32; 4],
    params: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SegmentInstance {
    a: [f32; 4],
    b: [f32; 4],
    color: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct QuadVertex {
    position: [f32; 3],
    uv: [f32; 2],
    color: [f32; 4],
}

struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
}

/// A growable GPU buffer rewritten each frame.
struct Scratch {
    buffer: wgpu::Buffer,
    usage: wgpu::BufferUsages,
    label: &'static str,
}

impl Scratch {
    fn new(device: &wgpu::Device, label: &'static str, usage: wgpu::BufferUsages) -> Self {
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

    /// Writes `bytes`; returns whether the buffer was reallocated.
    fn write(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: &[u8]) -> bool {
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

struct Targets {
    size: (u32, u32),
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
}

/// The renderer: pipelines, uploaded meshes and per-frame scratch buffers.
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    format: wgpu::TextureFormat,
    sample_count: u32,
    mesh_opaque: wgpu::RenderPipeline,
    mesh_blended: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
    overlay: wgpu::RenderPipeline,
    camera_layout: wgpu::BindGroupLayout,
    draw_layout: wgpu::BindGroupLayout,
    texture_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    white: wgpu::BindGroup,
    uniform_align: u64,
    cameras: Scratch,
    draws: Scratch,
    camera_group: wgpu::BindGroup,
    draw_group: wgpu::BindGroup,
    segments: Scratch,
    quads: Scratch,
    meshes: Vec<GpuMesh>,
    targets: Option<Targets>,
    font: overlay::Font,
}

/// The WGSL sources, by file name: compiled here and validated by `tests/shaders.rs`.
pub const SHADERS: &[(&str, &str)] = &[
    ("mesh.wgsl", include_str!("../../shaders/mesh.wgsl")),
    ("lines.wgsl", include_str!("../../shaders/lines.wgsl")),
    ("overlay.wgsl", include_str!("../../shaders/overlay.wgsl")),
];

fn shader(device: &wgpu::Device, name: &str) -> wgpu::ShaderModule {
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

fn uniform_layout(device: &wgpu::Device, label: &str, size: u64) -> wgpu::BindGroupLayout {
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

fn uniform_group(
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

const CAMERA_SIZE: u64 = std::mem::size_of::<CameraUniform>() as u64;
const DRAW_SIZE: u64 = std::mem::size_of::<DrawUniform>() as u64;

struct PipelineSpec<'a> {
    label: &'a str,
    module: &'a wgpu::ShaderModule,
    layout: &'a wgpu::PipelineLayout,
    buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    blend: wgpu::BlendState,
    depth_write: bool,
    depth_compare: wgpu::CompareFunction,
    cull: Option<wgpu::Face>,
}

impl Renderer {
    /// Builds the pipelines for targets of `format`, with `sample_count` (1 or 4) MSAA.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        format: wgpu::TextureFormat,
        sample_count: u32,
    ) -> Self {
        let camera_layout = uniform_layout(device, "camera", CAMERA_SIZE);
        let draw_layout = uniform_layout(device, "draw", DRAW_SIZE);
        let texture_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("panel texture"),
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
        });
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
                    compilation_options: Default::default(),
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
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("panel"),
            mag_filter: wgpu::FilterMode::Nearest,
            min_filter: wgpu::FilterMode::Nearest,
            ..Default::default()
        });
        let white_texture = device.create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some("white"),
                size: wgpu::Extent3d {
                    width: 1,
                    height: 1,
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
            &[255, 255, 255, 255],
        );
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
            targets: None,
            font: overlay::Font::bundled(),
        }
    }

    /// The colour format this renderer draws into.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// Uploads a mesh once; frames refer to it by the handle.
    pub fn upload_mesh(&mut self, mesh: &MeshData) -> MeshHandle {
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
        self.meshes.push(GpuMesh {
            vertices,
            indices,
            index_count: mesh.indices.len() as u32 * 3,
        });
        MeshHandle(self.meshes.len() - 1)
    }

    fn ensure_targets(&mut self, size: (u32, u32)) {
        if self.targets.as_ref().is_some_and(|t| t.size == size) {
            return;
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
        self.targets = Some(Targets {
            size,
            msaa: (self.sample_count > 1).then(|| make(self.format, "msaa colour")),
            depth: make(DEPTH_FORMAT, "depth"),
        });
    }

    /// Draws `frame` into `target` (a `width`×`height` view of this renderer's format) and
    /// submits the work.
    pub fn render(&mut self, target: &wgpu::TextureView, size: (u32, u32), frame: &Frame) {
        self.render_in(target, size, [0, 0, size.0, size.1], frame);
    }

    /// Draws `frame`, laid out for a `rect[2]`×`rect[3]` picture, into the pixel rectangle
    /// `rect` (x, y, w, h) of `target` (`size` pixels): the app's 3D area beside its controls.
    /// The whole target is cleared to `frame.clear` first.
    pub fn render_in(
        &mut self,
        target: &wgpu::TextureView,
        size: (u32, u32),
        rect: [u32; 4],
        frame: &Frame,
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
        }
        let mut plans = Vec::new();
        for view in &frame.views {
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
                if inst.mesh.0 >= self.meshes.len() {
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
            let start = seg_data.len() as u32;
            seg_data.extend(view.segments.iter().map(|s| SegmentInstance {
                a: s.a.extend(s.width_px).to_array(),
                b: s.b.extend(0.0).to_array(),
                color: s.color,
            }));
            plans.push(ViewPlan {
                viewport: [x as f32, y as f32, w as f32, h as f32],
                cam_offset,
                background,
                opaque,
                blended,
                segments: start..seg_data.len() as u32,
            });
        }
        // Panels: rasterised on the CPU, one texture each.
        let mut panel_draws = Vec::new();
        for panel in &frame.panels {
            let image = overlay::rasterise(panel, &self.font);
            if image.width == 0 || image.height == 0 {
                continue;
            }
            let texture = self.device.create_texture_with_data(
                &self.queue,
                &wgpu::TextureDescriptor {
                    label: Some("panel"),
                    size: wgpu::Extent3d {
                        width: image.width,
                        height: image.height,
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
                &image.rgba,
            );
            let group = texture_group(&self.device, &self.texture_layout, &texture, &self.sampler);
            let (px, py) = panel.anchor.place(image.width, image.height, picture);
            let (px, py) = (px + ox, py + oy);
            let start = quad_data.len() as u32;
            quad_data.extend(quad(
                [px, py, image.width, image.height],
                size,
                0.0,
                [0.0, 0.0, 1.0, 1.0],
                [1.0; 4],
            ));
            panel_draws.push((group, start..quad_data.len() as u32));
        }
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
            let Some(targets) = self.targets.as_ref() else {
                return;
            };
            let (view, resolve) = match &targets.msaa {
                Some(msaa) => (msaa, Some(target)),
                None => (target, None),
            };
            let [r, g, b, a] = frame.clear.map(f64::from);
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

    fn draw_mesh(&self, pass: &mut wgpu::RenderPass<'_>, mesh: usize, offset: u32) {
        let m = &self.meshes[mesh];
        pass.set_bind_group(1, &self.draw_group, &[offset]);
        pass.set_vertex_buffer(0, m.vertices.slice(..));
        pass.set_index_buffer(m.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..m.index_count, 0, 0..1);
    }
}

fn texture_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    texture: &wgpu::Texture,
    sampler: &wgpu::Sampler,
) -> wgpu::BindGroup {
    let view = texture.create_view(&Default::default());
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("panel"),
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

fn push_aligned(out: &mut Vec<u8>, bytes: &[u8], stride: u64) {
    out.extend_from_slice(bytes);
    out.resize(out.len() + (stride as usize - bytes.len()), 0);
}

fn clamp_viewport(v: [u32; 4], size: (u32, u32)) -> [u32; 4] {
    let x = v[0].min(size.0.saturating_sub(1));
    let y = v[1].min(size.1.saturating_sub(1));
    let w = v[2].clamp(1, size.0 - x);
    let h = v[3].clamp(1, size.1 - y);
    [x, y, w, h]
}

/// Two triangles covering a pixel rectangle, at `depth`.
fn quad(
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
