//! The app's own egui renderer (`ui::egui_renderer`, which replaced egui-wgpu's for speed on
//! CPU renderers) draws what egui asks: a flat colour comes out as the same sRGB bytes on gamma
//! and sRGB targets, translucent colours blend as premultiplied alpha, nothing is drawn outside
//! a clip rectangle, and text shows, including glyphs that reach the font atlas in a later frame
//! (egui patches its texture then, rather than sending it whole). And it draws what egui-wgpu
//! draws: the same frames (text, clipping and translucency, a translucent plot, a patched atlas,
//! a patch that changes the sampler) through both, pixel for pixel within dithering's noise; what
//! it cannot draw is reported, once per kind.
#![cfg(feature = "app")]

use rollphase::render::GpuContext;
use rollphase::render::gpu::OffscreenTarget;
use rollphase::ui::egui_renderer::EguiRenderer;
use rollphase::ui::workbench::offscreen_input;

const SIZE: (u32, u32) = (160, 120);
const CLEAR: [u8; 3] = [10, 20, 30];
const FILL: egui::Color32 = egui::Color32::from_rgb(200, 100, 50);

fn linear(c: f64) -> f64 {
    let v = c / 255.0;
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

fn gamma(l: f64) -> f64 {
    let v = if l <= 0.0031308 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    v * 255.0
}

fn translucent() -> egui::Color32 {
    egui::Color32::from_rgba_unmultiplied(255, 255, 255, 128)
}

/// One egui frame drawn by `draw` into a fresh `format` target cleared to [`CLEAR`], read back
/// as RGBA rows; and whether egui patched a texture (sent part of one) for it.
fn paint(
    gpu: &GpuContext,
    ctx: &egui::Context,
    renderer: &mut EguiRenderer,
    format: wgpu::TextureFormat,
    draw: impl FnMut(&egui::Context),
) -> (image::RgbaImage, bool) {
    let mut draw = draw;
    let mut output = ctx.run_ui(offscreen_input(SIZE, 0.0, Vec::new()), |ui| draw(ui.ctx()));
    let mut patched = false;
    for (id, deltas) in std::mem::take(&mut output.textures_delta.set) {
        for delta in deltas {
            renderer.update_texture(&gpu.device, &gpu.queue, id, &delta);
            patched |= delta.pos.is_some();
        }
    }
    let primitives = ctx.tessellate(output.shapes, output.pixels_per_point);
    renderer.update_buffers(
        &gpu.device,
        &gpu.queue,
        &primitives,
        SIZE,
        output.pixels_per_point,
    );
    let target = OffscreenTarget::with_format(&gpu.device, SIZE, format);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        // The clear colour given in the target's own encoding, so both read back as CLEAR.
        let channel = |c: u8| {
            if format.is_srgb() {
                linear(f64::from(c))
            } else {
                f64::from(c) / 255.0
            }
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: None,
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &target.view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color {
                        r: channel(CLEAR[0]),
                        g: channel(CLEAR[1]),
                        b: channel(CLEAR[2]),
                        a: 1.0,
                    }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        renderer.render(&mut pass);
    }
    gpu.queue.submit([encoder.finish()]);
    let pixels = target.read(&gpu.device, &gpu.queue).unwrap();
    for id in std::mem::take(&mut output.textures_delta.free) {
        renderer.free_texture(&id);
    }
    let image = image::RgbaImage::from_raw(SIZE.0, SIZE.1, pixels).unwrap();
    (image, patched)
}

fn close(p: image::Rgba<u8>, want: [u8; 3], tolerance: i32) -> bool {
    (0..3).all(|i| (i32::from(p.0[i]) - i32::from(want[i])).abs() <= tolerance)
}

/// Flat rectangles: an opaque one clipped to the left half, a half-transparent one below.
fn rectangles(ctx: &egui::Context) {
    let layer = egui::LayerId::background();
    let clipped = ctx
        .layer_painter(layer)
        .with_clip_rect(egui::Rect::from_min_max(
            egui::pos2(0.0, 0.0),
            egui::pos2(40.0, 120.0),
        ));
    clipped.rect_filled(
        egui::Rect::from_min_max(egui::pos2(10.0, 10.0), egui::pos2(70.0, 50.0)),
        0.0,
        FILL,
    );
    ctx.layer_painter(layer).rect_filled(
        egui::Rect::from_min_max(egui::pos2(10.0, 70.0), egui::pos2(70.0, 110.0)),
        0.0,
        translucent(),
    );
}

#[test]
fn colours_clipping_and_blending_match_egui_on_gamma_and_srgb_targets() {
    let gpu = GpuContext::headless().expect("a wgpu adapter (llvmpipe on CI)");
    for format in [
        wgpu::TextureFormat::Rgba8Unorm,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        wgpu::TextureFormat::Bgra8UnormSrgb,
    ] {
        let ctx = egui::Context::default();
        let mut renderer = EguiRenderer::new(&gpu.device, format);
        let (img, _) = paint(&gpu, &ctx, &mut renderer, format, rectangles);
        // Inside the clip: egui's sRGB bytes (dithering moves them by at most one step).
        let inside = img.get_pixel(25, 30);
        assert!(close(*inside, [200, 100, 50], 1), "{format:?}: {inside:?}");
        // The same rectangle past its clip edge, and the untouched corner: the clear colour.
        for (x, y) in [(55, 30), (150, 5)] {
            let p = img.get_pixel(x, y);
            assert!(close(*p, CLEAR, 1), "{format:?} at ({x}, {y}): {p:?}");
        }
        // Half-transparent white over the clear colour: premultiplied blending, which on a
        // gamma target mixes the bytes and on an sRGB target mixes linear light.
        // egui's own premultiplied bytes are the source; out = src + (1 − a)·dst.
        let [sr, sg, sb, sa] = translucent().to_array().map(f64::from);
        let keep = 1.0 - sa / 255.0;
        let want: [u8; 3] = std::array::from_fn(|i| {
            let (src, dst) = ([sr, sg, sb][i], f64::from(CLEAR[i]));
            let out = if format.is_srgb() {
                gamma(linear(src) + keep * linear(dst))
            } else {
                src + keep * dst
            };
            out.round() as u8
        });
        let p = *img.get_pixel(40, 90);
        assert!(close(p, want, 2), "{format:?} blend: {p:?}, want {want:?}");
    }
}

#[test]
fn text_shows_and_glyphs_added_in_a_later_frame_are_drawn_too() {
    let gpu = GpuContext::headless().expect("a wgpu adapter (llvmpipe on CI)");
    let format = wgpu::TextureFormat::Rgba8UnormSrgb;
    let ctx = egui::Context::default();
    let mut renderer = EguiRenderer::new(&gpu.device, format);
    let text = |s: &'static str| {
        move |ctx: &egui::Context| {
            ctx.layer_painter(egui::LayerId::background()).text(
                egui::pos2(5.0, 40.0),
                egui::Align2::LEFT_TOP,
                s,
                egui::FontId::proportional(24.0),
                egui::Color32::WHITE,
            );
        }
    };
    let bright = |img: &image::RgbaImage| img.pixels().filter(|p| p.0[0] > 180).count();
    let (first, _) = paint(&gpu, &ctx, &mut renderer, format, text("abc"));
    assert!(
        bright(&first) > 30,
        "\"abc\": {} bright pixels",
        bright(&first)
    );
    // New glyphs: egui adds them to its atlas and sends only the changed part (a patch at a
    // position), which must land in the texture made for the first frame.
    let (later, patched) = paint(&gpu, &ctx, &mut renderer, format, text("ΩΣ xyz WM"));
    assert!(patched, "egui sent the new glyphs as a patch of its atlas");
    assert!(
        bright(&later) > 2 * bright(&first),
        "new glyphs: {} bright pixels, \"abc\" alone {}",
        bright(&later),
        bright(&first)
    );
}

/// The same egui frames through egui-wgpu (a dev-dependency: the renderer this one replaced)
/// and through ours: each frame's texture deltas go to both, its primitives are drawn by each
/// into a fresh target of `format`, and both come back as RGBA rows.
struct Differential {
    ours: EguiRenderer,
    theirs: egui_wgpu::Renderer,
    format: wgpu::TextureFormat,
}

impl Differential {
    fn new(gpu: &GpuContext, format: wgpu::TextureFormat) -> Self {
        let options = egui_wgpu::RendererOptions {
            msaa_samples: 1,
            depth_stencil_format: None,
            // Both dither with the same noise (interleaved gradient noise, as ours copies).
            dithering: true,
            predictable_texture_filtering: false,
        };
        Self {
            ours: EguiRenderer::new(&gpu.device, format),
            theirs: egui_wgpu::Renderer::new(&gpu.device, format, options),
            format,
        }
    }

    fn frame(
        &mut self,
        gpu: &GpuContext,
        ctx: &egui::Context,
        draw: impl FnMut(&mut egui::Ui),
    ) -> (image::RgbaImage, image::RgbaImage, bool) {
        let mut draw = draw;
        let mut patched = false;
        let mut output = ctx.run_ui(offscreen_input(SIZE, 0.0, Vec::new()), |ui| draw(ui));
        for (id, deltas) in std::mem::take(&mut output.textures_delta.set) {
            for delta in deltas {
                patched |= delta.pos.is_some();
                self.ours
                    .update_texture(&gpu.device, &gpu.queue, id, &delta);
                self.theirs
                    .update_texture(&gpu.device, &gpu.queue, id, &delta);
            }
        }
        let primitives = ctx.tessellate(output.shapes, output.pixels_per_point);
        let target =
            |gpu: &GpuContext| OffscreenTarget::with_format(&gpu.device, SIZE, self.format);
        // Ours.
        let ours_target = target(gpu);
        self.ours.update_buffers(
            &gpu.device,
            &gpu.queue,
            &primitives,
            SIZE,
            output.pixels_per_point,
        );
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut p = cleared_pass(&mut encoder, &ours_target.view);
            self.ours.render(&mut p);
        }
        gpu.queue.submit([encoder.finish()]);
        // egui-wgpu's.
        let theirs_target = target(gpu);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [SIZE.0, SIZE.1],
            pixels_per_point: output.pixels_per_point,
        };
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let extra =
            self.theirs
                .update_buffers(&gpu.device, &gpu.queue, &mut encoder, &primitives, &screen);
        {
            let mut p = cleared_pass(&mut encoder, &theirs_target.view).forget_lifetime();
            self.theirs.render(&mut p, &primitives, &screen);
        }
        gpu.queue
            .submit(extra.into_iter().chain([encoder.finish()]));
        for id in std::mem::take(&mut output.textures_delta.free) {
            self.ours.free_texture(&id);
            self.theirs.free_texture(&id);
        }
        let read = |t: &OffscreenTarget| {
            image::RgbaImage::from_raw(SIZE.0, SIZE.1, t.read(&gpu.device, &gpu.queue).unwrap())
                .unwrap()
        };
        (read(&ours_target), read(&theirs_target), patched)
    }
}

/// One frame's UI, drawn by both renderers.
type UiFrame = dyn FnMut(&mut egui::Ui);

/// A render pass into `view`, cleared to black.
fn cleared_pass<'a>(
    encoder: &'a mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
) -> wgpu::RenderPass<'a> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: None,
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// How two frames differ: the largest difference of any channel, and the share of pixels
/// where some channel differs by more than 2 levels (of 255).
fn difference(a: &image::RgbaImage, b: &image::RgbaImage) -> (u8, f64) {
    let mut worst = 0u8;
    let mut off = 0usize;
    for (p, q) in a.pixels().zip(b.pixels()) {
        let d = (0..3).map(|i| p.0[i].abs_diff(q.0[i])).max().unwrap();
        worst = worst.max(d);
        off += usize::from(d > 2);
    }
    (worst, off as f64 / f64::from(SIZE.0 * SIZE.1))
}

/// Whether a frame shows anything but the black it was cleared to.
fn drawn(img: &image::RgbaImage) -> usize {
    img.pixels().filter(|p| p.0[..3] != [0, 0, 0]).count()
}

#[test]
fn egui_wgpu_and_ours_draw_the_same_frames() {
    let gpu = GpuContext::headless().expect("a wgpu adapter (llvmpipe on CI)");
    for format in [
        wgpu::TextureFormat::Rgba8Unorm,
        wgpu::TextureFormat::Rgba8UnormSrgb,
    ] {
        let ctx = egui::Context::default();
        let mut both = Differential::new(&gpu, format);
        let mut texture: Option<egui::TextureHandle> = None;
        let frames: Vec<(&str, Box<UiFrame>)> = vec![
            (
                "text",
                Box::new(|ui: &mut egui::Ui| {
                    ui.label("Rolling down a ramp: α = 0.15000");
                    ui.heading("T = 82.31");
                }),
            ),
            (
                "clipping and translucency",
                Box::new(|ui: &mut egui::Ui| rectangles(ui.ctx())),
            ),
            (
                "a translucent plot",
                Box::new(|ui: &mut egui::Ui| {
                    let wave: Vec<[f64; 2]> = (0..60)
                        .map(|i| [f64::from(i) * 0.1, (f64::from(i) * 0.3).sin()])
                        .collect();
                    egui_plot::Plot::new("plot").show(ui, |p| {
                        p.polygon(
                            egui_plot::Polygon::new(
                                "band",
                                egui_plot::PlotPoints::from(vec![
                                    [0.0, -0.5],
                                    [6.0, -0.5],
                                    [6.0, 0.5],
                                    [0.0, 0.5],
                                ]),
                            )
                            .fill_color(egui::Color32::from_rgba_unmultiplied(80, 160, 255, 90)),
                        );
                        p.line(egui_plot::Line::new(
                            "wave",
                            egui_plot::PlotPoints::from(wave),
                        ));
                    });
                }),
            ),
            (
                "a patched atlas",
                // Glyphs the atlas lacks: egui sends them as a patch of its font texture.
                Box::new(|ui: &mut egui::Ui| {
                    ui.label(egui::RichText::new("ΩΦΨ ∂Ω 0123456789").size(22.0));
                }),
            ),
            (
                "a patch that changes the sampler",
                Box::new(move |ui: &mut egui::Ui| {
                    let checker = egui::ColorImage::new(
                        [4, 4],
                        (0..16)
                            .map(|i| {
                                if (i + i / 4) % 2 == 0 {
                                    egui::Color32::WHITE
                                } else {
                                    egui::Color32::from_rgb(200, 30, 30)
                                }
                            })
                            .collect(),
                    );
                    let handle = texture.get_or_insert_with(|| {
                        ui.ctx().load_texture(
                            "checker",
                            checker.clone(),
                            egui::TextureOptions::LINEAR,
                        )
                    });
                    handle.set_partial([0, 0], checker, egui::TextureOptions::NEAREST);
                    ui.image((handle.id(), egui::vec2(120.0, 100.0)));
                }),
            ),
        ];
        for (name, mut draw) in frames {
            let (ours, theirs, patched) = both.frame(&gpu, &ctx, &mut draw);
            if name.starts_with("a patch") {
                assert!(patched, "{name}: egui sent a patch");
            }
            assert!(drawn(&theirs) > 100, "{name}: egui-wgpu drew nothing");
            let (worst, share) = difference(&ours, &theirs);
            // On llvmpipe the two agree to the byte (the same dither noise included); a few
            // pixels' rounding is left for other drivers.
            assert!(
                share < 0.001 && worst <= 4,
                "{name} ({format:?}): {:.2} % of pixels differ by more than 2 levels, the worst \
                 by {worst}",
                share * 100.0
            );
        }
        assert_eq!(
            both.ours.skipped(),
            vec![],
            "nothing of these frames is skipped"
        );
    }
}

#[test]
fn what_the_renderer_cannot_draw_is_reported_once_per_kind() {
    use rollphase::ui::egui_renderer::Skipped;
    let gpu = GpuContext::headless().expect("a wgpu adapter (llvmpipe on CI)");
    let mut renderer = EguiRenderer::new(&gpu.device, wgpu::TextureFormat::Rgba8Unorm);
    let clip = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(100.0, 100.0));
    // A mesh on a texture egui never sent.
    let mut mesh = egui::epaint::Mesh::default();
    mesh.add_colored_rect(clip, egui::Color32::RED);
    mesh.texture_id = egui::TextureId::User(77);
    let primitives = [
        egui::epaint::ClippedPrimitive {
            clip_rect: clip,
            primitive: egui::epaint::Primitive::Mesh(mesh.clone()),
        },
        egui::epaint::ClippedPrimitive {
            clip_rect: clip,
            primitive: egui::epaint::Primitive::Mesh(mesh),
        },
    ];
    renderer.update_buffers(&gpu.device, &gpu.queue, &primitives, SIZE, 1.0);
    assert_eq!(renderer.skipped(), vec![Skipped::MissingTexture]);
    let patch = egui::epaint::ImageDelta::partial(
        [0, 0],
        egui::ColorImage::new([1, 1], vec![egui::Color32::WHITE]),
        egui::TextureOptions::LINEAR,
    );
    renderer.update_texture(&gpu.device, &gpu.queue, egui::TextureId::User(78), &patch);
    assert_eq!(
        renderer.skipped(),
        vec![Skipped::MissingTexture, Skipped::PatchOfUnknownTexture]
    );
}
