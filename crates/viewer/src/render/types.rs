//! The renderer's input: plain draw data (meshes to upload, instances with materials, line
//! segments, cameras, views and the frame). No wgpu here: `view` builds these values and the
//! renderer turns them into pixels.

use glam::{Mat4, Vec3};

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
pub struct MeshHandle(pub(super) usize);

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
    /// Line segments drawn last and through everything in the view (no depth test): markers
    /// that must show even where a body hides them, such as the contact point under a sphere.
    pub segments_on_top: Vec<Segment>,
}

/// Everything one frame shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Clear colour (linear RGBA).
    pub clear: [f32; 4],
    /// 3D views, drawn in order (insets after the main view).
    pub views: Vec<View>,
    /// 2D panels drawn on top.
    pub panels: Vec<OverlayPanel>,
}

/// Where a panel sits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Anchor {
    /// Top-left corner at (x, y) pixels from the target's top left.
    TopLeft(u32, u32),
    /// Top-right corner at (x, y) pixels from the target's top right.
    TopRight(u32, u32),
    /// Bottom-left corner at (x, y) pixels from the target's bottom left.
    BottomLeft(u32, u32),
    /// Bottom-right corner at (x, y) pixels from the target's bottom right.
    BottomRight(u32, u32),
    /// Centred across the target, its bottom edge y pixels above the target's bottom.
    BottomCentre(u32),
}

impl Anchor {
    /// Top-left pixel of a `w`×`h` panel in a target of `size`.
    pub fn place(&self, w: u32, h: u32, size: (u32, u32)) -> (u32, u32) {
        let (sw, sh) = size;
        let (x, y) = match *self {
            Anchor::TopLeft(x, y) => (x as i64, y as i64),
            Anchor::TopRight(x, y) => (sw as i64 - w as i64 - x as i64, y as i64),
            Anchor::BottomLeft(x, y) => (x as i64, sh as i64 - h as i64 - y as i64),
            Anchor::BottomCentre(y) => {
                ((sw as i64 - w as i64) / 2, sh as i64 - h as i64 - y as i64)
            }
            Anchor::BottomRight(x, y) => (
                sw as i64 - w as i64 - x as i64,
                sh as i64 - h as i64 - y as i64,
            ),
        };
        (x.max(0) as u32, y.max(0) as u32)
    }
}

/// One element of a panel, stacked top to bottom.
#[derive(Debug, Clone, PartialEq)]
pub enum PanelItem {
    /// A line of text.
    Text {
        /// The text.
        text: String,
        /// Font size in pixels.
        size_px: f32,
        /// sRGB colour.
        color: [u8; 3],
    },
    /// A horizontal colour bar with labels under it.
    ColorBar {
        /// Bar width in pixels.
        width: u32,
        /// Bar height in pixels.
        height: u32,
        /// sRGB colours from left to right (interpolated).
        colors: Vec<[u8; 3]>,
        /// Labels: position in [0, 1] along the bar and text.
        labels: Vec<(f32, String)>,
        /// Label font size in pixels.
        size_px: f32,
    },
}

/// A panel: items on a translucent rounded background.
#[derive(Debug, Clone, PartialEq)]
pub struct OverlayPanel {
    /// Position.
    pub anchor: Anchor,
    /// Content, top to bottom.
    pub items: Vec<PanelItem>,
    /// Background sRGBA.
    pub background: [u8; 4],
    /// Inner margin in pixels.
    pub padding: u32,
}

/// Where meshes are uploaded once and then referred to by handle: the renderer. `view` builds
/// its meshes through this trait, so it needs no more of the renderer than these types.
pub trait MeshStore {
    /// Uploads a mesh; frames refer to it by the handle.
    fn upload_mesh(&mut self, mesh: &MeshData) -> MeshHandle;
    /// Frees a mesh no frame will refer to again.
    fn free_mesh(&mut self, mesh: MeshHandle);
}
