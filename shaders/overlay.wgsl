// Screen-space textured quads: the text panels and colour legends rasterised on the CPU, and
// solid quads (texture left white) that clear an inset view to its background. Positions are in
// normalised device coordinates; depth is written as given, so a background quad at depth 1
// resets the depth buffer of its inset.

struct VsIn {
    // xy: NDC position, z: depth
    @location(0) position: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) color: vec4<f32>,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) color: vec4<f32>,
};

@group(0) @binding(0) var panel_texture: texture_2d<f32>;
@group(0) @binding(1) var panel_sampler: sampler;

@vertex
fn vs_main(v: VsIn) -> VsOut {
    var out: VsOut;
    out.clip = vec4<f32>(v.position.xy, v.position.z, 1.0);
    out.uv = v.uv;
    out.color = v.color;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    return output_colour(textureSample(panel_texture, panel_sampler, in.uv) * in.color);
}
