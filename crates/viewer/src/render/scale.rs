//! The 3D views drawn at a lower resolution and stretched over their rectangle, with the panels
//! (text, colour legends) drawn on top at full resolution: [`Renderer::render_scaled_in`].
//!
//! On a CPU renderer (llvmpipe) a 1920×1080 app frame is bound by shaded pixels (64 % of a
//! profile's samples in its fragment code), so drawing the 3D views at 70 % of the width and
//! height shades half the pixels. The app picks the scale (`ui::render_scale`); headless
//! frames, screenshots and clips never call this.

use super::pass::Layers;
use super::pipelines::texture_group;
use super::{Frame, Renderer, View};

/// Below this a scale is taken as this: a quarter of the pixels is the least worth drawing.
pub const SCALE_MIN: f32 = 0.25;

/// The scaled picture: a texture the views draw into and the overlay samples.
pub(super) struct ScaledPicture {
    size: (u32, u32),
    view: wgpu::TextureView,
    group: wgpu::BindGroup,
}

impl Renderer {
    /// [`Renderer::render_in`] with the 3D views drawn at `scale` (0.25–1) of the picture's
    /// width and height and stretched over it with linear filtering; the panels are drawn at
    /// full resolution over that. A scale of 1 or more (or NaN) is [`Renderer::render_in`].
    pub fn render_scaled_in(
        &mut self,
        target: &wgpu::TextureView,
        size: (u32, u32),
        rect: [u32; 4],
        frame: &Frame,
        scale: f32,
    ) {
        if scale.is_nan() || scale >= 1.0 {
            self.render_in(target, size, rect, frame);
            return;
        }
        let scale = scale.max(SCALE_MIN);
        let [ox, oy, _, _] = super::pass::clamp_viewport(rect, size);
        let picture = (
            rect[2].min(size.0 - ox).max(1),
            rect[3].min(size.1 - oy).max(1),
        );
        let small = (
            ((picture.0 as f32 * scale).round() as u32).max(1),
            ((picture.1 as f32 * scale).round() as u32).max(1),
        );
        let sx = small.0 as f32 / picture.0 as f32;
        let sy = small.1 as f32 / picture.1 as f32;
        let scaled = self.ensure_scaled(small);
        let views = Frame {
            clear: frame.clear,
            views: frame.views.iter().map(|v| scaled_view(v, sx, sy)).collect(),
            panels: Vec::new(),
        };
        let views_only = Layers {
            views: true,
            panels: false,
            underlay: None,
        };
        self.draw(
            &scaled.view,
            small,
            [0, 0, small.0, small.1],
            &views,
            views_only,
        );
        let panels_over = Layers {
            views: false,
            panels: true,
            underlay: Some(&scaled.group),
        };
        self.draw(target, size, rect, frame, panels_over);
        self.scaled = Some(scaled);
    }

    /// The scaled picture's texture at `size`, made anew only when the size changed; taken out
    /// of `self` so the draws can borrow the renderer (put back after).
    fn ensure_scaled(&mut self, size: (u32, u32)) -> ScaledPicture {
        if let Some(scaled) = self.scaled.take().filter(|s| s.size == size) {
            return scaled;
        }
        let texture = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("scaled view"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: self.format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let group = texture_group(
            &self.device,
            &self.texture_layout,
            &texture,
            &self.linear_sampler,
        );
        ScaledPicture {
            size,
            view: texture.create_view(&Default::default()),
            group,
        }
    }
}

/// `view` laid out for a picture `sx` × `sy` times the size: its viewport, and the widths of its
/// lines, so that stretched back they cover what they would have; but never under one pixel
/// of the small picture, where a thin line would break into dashes.
fn scaled_view(view: &View, sx: f32, sy: f32) -> View {
    let [x, y, w, h] = view.viewport;
    let at = |v: u32, s: f32| (v as f32 * s).round() as u32;
    let width = (sx + sy) / 2.0;
    let thinner = |segments: &[super::Segment]| {
        segments
            .iter()
            .map(|s| super::Segment {
                width_px: (s.width_px * width).max(s.width_px.min(1.0)),
                ..*s
            })
            .collect()
    };
    View {
        viewport: [at(x, sx), at(y, sy), at(w, sx).max(1), at(h, sy).max(1)],
        segments: thinner(&view.segments),
        segments_on_top: thinner(&view.segments_on_top),
        ..view.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scaled_view_keeps_its_place_and_its_lines_their_width_once_stretched() {
        let view = View {
            viewport: [100, 50, 400, 300],
            background: None,
            camera: super::super::Camera {
                eye: glam::Vec3::new(0.0, -5.0, 2.0),
                target: glam::Vec3::ZERO,
                up: glam::Vec3::Z,
                fov_y_rad: 0.8,
                near: 0.1,
                far: 100.0,
            },
            light_dir: glam::Vec3::Z,
            meshes: Vec::new(),
            segments: vec![super::super::Segment {
                a: glam::Vec3::ZERO,
                b: glam::Vec3::X,
                color: [1.0; 4],
                width_px: 4.0,
            }],
            segments_on_top: Vec::new(),
        };
        let half = scaled_view(&view, 0.5, 0.5);
        assert_eq!(half.viewport, [50, 25, 200, 150]);
        assert_eq!(half.segments[0].width_px, 2.0);
        assert_eq!(half.camera, view.camera);
    }
}
