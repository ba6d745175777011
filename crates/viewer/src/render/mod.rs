//! The wgpu renderer: plain draw data in ([`Frame`]: views with cameras, mesh instances and line
//! segments, plus 2D panels of text and colour legends), pixels out. It never sees a model, a
//! scene or a window: the window (app) and the headless mode call the same
//! [`Renderer::render`] on a `TextureView`.
//!
//! Three pipelines, one shader file each (`shaders/*.wgsl`): lit meshes (opaque and translucent
//! variants), screen-space thick lines, and textured overlay quads. Each writes its colour
//! through `shaders/output_colour.wgsl`: as is into an sRGB target, sRGB-encoded by the shader
//! into a non-sRGB one (the app's, where egui's panels are cheaper). Everything is drawn in one
//! render pass with 4× MSAA (configurable) and a Depth32Float buffer; inset views get their own
//! viewport, and a background quad at depth 1 clears their region of colour and depth.
//!
//! Imports wgpu, glam, bytemuck and ab_glyph only.
//!
//! | file | owns |
//! |---|---|
//! | `types` | the plain draw data: [`Frame`], [`View`], [`Camera`], [`MeshData`], … (no wgpu) |
//! | `pipelines` | the shaders, bind-group layouts, GPU-side structs and [`Renderer::new`] |
//! | `pass` | uploads and the render pass ([`Renderer::render`]) |
//! | `scale` | the 3D views drawn at a lower resolution and stretched ([`Renderer::render_scaled_in`]) |
//! | `overlay` | text and colour-bar panels rasterised to a texture |
//! | `gpu` | adapter and device set-up, offscreen targets |

pub mod gpu;
pub mod overlay;
mod pass;
mod pipelines;
mod scale;
pub mod types;

pub use gpu::{GpuContext, GpuError};
pub use pipelines::{OUTPUT_COLOUR, SHADERS, Scratch, texture_group, texture_sampler_layout};
pub use types::*;

use pipelines::{GpuMesh, Targets};

/// Format of the depth buffer.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The renderer: pipelines, uploaded meshes and per-frame scratch buffers.
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    format: wgpu::TextureFormat,
    sample_count: u32,
    mesh_opaque: wgpu::RenderPipeline,
    mesh_blended: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
    lines_on_top: wgpu::RenderPipeline,
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
    /// Uploaded meshes by handle; a freed one leaves its slot empty for the next upload.
    meshes: Vec<Option<GpuMesh>>,
    /// Depth and MSAA targets of the two sizes drawn most recently, the latest last.
    targets: Vec<Targets>,
    /// The 3D view's picture at a lower resolution, and the pipeline and sampler that stretch
    /// it over the target (`scale`).
    scaled: Option<scale::ScaledPicture>,
    blit: wgpu::RenderPipeline,
    linear_sampler: wgpu::Sampler,
    font: overlay::Font,
    /// Panels rasterised and uploaded in recent frames, with their size and texture, reused
    /// while a frame shows the same panel: the legends and titles are the same frame after
    /// frame, and rasterising and uploading each anew was a steady cost on a CPU renderer.
    panel_cache: Vec<(OverlayPanel, (u32, u32), wgpu::BindGroup)>,
}
