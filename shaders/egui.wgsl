// egui's panels: its tessellated meshes (positions in points, sRGB-gamma colours with
// premultiplied alpha, one texture per mesh), drawn by crates/viewer/src/ui/egui_renderer.rs.
//
// Straight-line code on purpose: egui-wgpu's shader chooses between hardware sampling and four
// manual texel loads with a branch on a uniform, and a CPU renderer (llvmpipe) runs both sides
// for every pixel. The two framebuffer kinds are two entry points, chosen when the pipeline is
// built, not a branch.

struct VsIn {
    @location(0) position: vec2<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) color: u32,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    // sRGB gamma, premultiplied alpha
    @location(1) color: vec4<f32>,
};

struct Screen {
    // the target's size in points
    size: vec2<f32>,
    _pad: vec2<f32>,
};

@group(0) @binding(0) var<uniform> screen: Screen;
@group(1) @binding(0) var egui_texture: texture_2d<f32>;
@group(1) @binding(1) var egui_sampler: sampler;

fn unpack(c: u32) -> vec4<f32> {
    return vec4<f32>(
        f32(c & 255u),
        f32((c >> 8u) & 255u),
        f32((c >> 16u) & 255u),
        f32((c >> 24u) & 255u),
    ) / 255.0;
}

@vertex
fn vs_main(v: VsIn) -> VsOut {
    var out: VsOut;
    out.clip = vec4<f32>(
        2.0 * v.position.x / screen.size.x - 1.0,
        1.0 - 2.0 * v.position.y / screen.size.y,
        0.0,
        1.0,
    );
    out.uv = v.uv;
    out.color = unpack(v.color);
    return out;
}

// Interleaved gradient noise (Jimenez 2014), as egui-wgpu dithers: a fraction of one 8-bit
// step, so gradients do not band.
fn dither(rgb: vec3<f32>, frag: vec2<f32>) -> vec3<f32> {
    let noise = fract(52.9829189 * fract(0.06711056 * frag.x + 0.00583715 * frag.y));
    return rgb + (noise - 0.5) * 0.95 / 255.0;
}

fn linear_from_gamma(srgb: vec3<f32>) -> vec3<f32> {
    let lower = srgb / 12.92;
    let higher = pow((srgb + 0.055) / 1.055, vec3<f32>(2.4));
    return select(higher, lower, srgb < vec3<f32>(0.04045));
}

// The target stores gamma values (Rgba8Unorm, Bgra8Unorm): egui's colours go out as they are.
@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let c = in.color * textureSample(egui_texture, egui_sampler, in.uv);
    return vec4<f32>(dither(c.rgb, in.clip.xy), c.a);
}

// The target is sRGB-encoding (…Srgb): hand it linear values, which it encodes back.
@fragment
fn fs_main_linear(in: VsOut) -> @location(0) vec4<f32> {
    let c = in.color * textureSample(egui_texture, egui_sampler, in.uv);
    return vec4<f32>(linear_from_gamma(dither(c.rgb, in.clip.xy)), c.a);
}
