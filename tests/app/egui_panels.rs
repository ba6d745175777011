//! The app's egui panels, drawn as the app draws them (egui-wgpu, patched in vendor/egui-wgpu so
//! its shader's options are pipeline constants): a flat colour comes out as the same sRGB bytes
//! on gamma and sRGB targets, translucent colours blend as premultiplied alpha, nothing is drawn
//! outside a clip rectangle, and text shows, including glyphs that reach the font atlas in a
//! later frame (egui patches its texture then, rather than sending it whole). And the patch is
//! in effect: the shader declares the constants and the renderer's options reach them.
#![cfg(feature = "app")]

use rollphase::render::GpuContext;
use rollphase::render::gpu::OffscreenTarget;
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
    renderer: &mut egui_wgpu::Renderer,
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
    let screen = egui_wgpu::ScreenDescriptor {
        size_in_pixels: [SIZE.0, SIZE.1],
        pixels_per_point: output.pixels_per_point,
    };
    let target = OffscreenTarget::with_format(&gpu.device, SIZE, format);
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let extra =
        renderer.update_buffers(&gpu.device, &gpu.queue, &mut encoder, &primitives, &screen);
    {
        // The clear colour given in the target's own encoding, so both read back as CLEAR.
        let channel = |c: u8| {
            if format.is_srgb() {
                linear(f64::from(c))
            } else {
                f64::from(c) / 255.0
            }
        };
        let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
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
        renderer.render(&mut pass.forget_lifetime(), &primitives, &screen);
    }
    gpu.queue
        .submit(extra.into_iter().chain([encoder.finish()]));
    let pixels = target.read(&gpu.device, &gpu.queue).unwrap();
    for id in std::mem::take(&mut output.textures_delta.free) {
        renderer.free_texture(&id);
    }
    let image = image::RgbaImage::from_raw(SIZE.0, SIZE.1, pixels).unwrap();
    (image, patched)
}

/// egui-wgpu's renderer with the app's options (crates/viewer/src/ui/painter.rs).
fn app_renderer(
    gpu: &GpuContext,
    format: wgpu::TextureFormat,
    dithering: bool,
) -> egui_wgpu::Renderer {
    egui_wgpu::Renderer::new(
        &gpu.device,
        format,
        egui_wgpu::RendererOptions {
            msaa_samples: 1,
            depth_stencil_format: None,
            dithering,
            predictable_texture_filtering: false,
        },
    )
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
        let mut renderer = app_renderer(&gpu, format, true);
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
    let mut renderer = app_renderer(&gpu, format, true);
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

/// The patch of vendor/egui-wgpu is what the app builds with, and the renderer's options reach
/// the shader's constants: with dithering on, a smooth gradient gets the noise that breaks its
/// banding; with it off, the gradient's bytes are the same in every row. Stock egui-wgpu would
/// pass the second half too, but not the first; a patch whose constant were stuck would fail
/// the second.
#[test]
fn the_patched_shader_takes_its_options_as_constants() {
    let shader = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/vendor/egui-wgpu/src/egui.wgsl"
    ))
    .unwrap();
    assert!(
        shader.contains("override DITHERING: bool"),
        "the patch is applied"
    );
    assert!(
        !shader.contains("r_locals.dithering =="),
        "the uniform branch is gone"
    );
    let gpu = GpuContext::headless().expect("a wgpu adapter (llvmpipe on CI)");
    let format = wgpu::TextureFormat::Rgba8Unorm;
    // A horizontal gradient from one grey to the next few: most pixels fall between two bytes.
    let gradient = |ctx: &egui::Context| {
        let mut mesh = egui::epaint::Mesh::default();
        let r = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(160.0, 120.0));
        let (a, b) = (egui::Color32::from_gray(100), egui::Color32::from_gray(104));
        mesh.colored_vertex(r.left_top(), a);
        mesh.colored_vertex(r.right_top(), b);
        mesh.colored_vertex(r.right_bottom(), b);
        mesh.colored_vertex(r.left_bottom(), a);
        mesh.add_triangle(0, 1, 2);
        mesh.add_triangle(0, 2, 3);
        ctx.layer_painter(egui::LayerId::background()).add(mesh);
    };
    let rows_alike = |img: &image::RgbaImage| {
        (1..SIZE.1).all(|y| (0..SIZE.0).all(|x| img.get_pixel(x, y) == img.get_pixel(x, 0)))
    };
    let ctx = egui::Context::default();
    let (plain, _) = paint(
        &gpu,
        &ctx,
        &mut app_renderer(&gpu, format, false),
        format,
        gradient,
    );
    assert!(
        rows_alike(&plain),
        "without dithering every row is the same gradient"
    );
    let ctx = egui::Context::default();
    let (dithered, _) = paint(
        &gpu,
        &ctx,
        &mut app_renderer(&gpu, format, true),
        format,
        gradient,
    );
    assert!(
        !rows_alike(&dithered),
        "with dithering the rows differ by the noise"
    );
    // The noise moves a byte by at most one step.
    for (p, q) in plain.pixels().zip(dithered.pixels()) {
        assert!((0..3).all(|i| p.0[i].abs_diff(q.0[i]) <= 1), "{p:?} {q:?}");
    }
}
