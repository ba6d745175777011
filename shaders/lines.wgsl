// Thick line segments (trails, trajectories, arrows, axes): each instance is one segment,
// expanded in screen space to a quad `width` pixels wide with square caps, depth-tested.

struct Camera {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    light: vec4<f32>,
    viewport: vec4<f32>,
};

@group(0) @binding(0) var<uniform> camera: Camera;

struct Segment {
    // xyz: start, w: width in pixels
    @location(0) a: vec4<f32>,
    // xyz: end
    @location(1) b: vec4<f32>,
    @location(2) color: vec4<f32>,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) vi: u32, s: Segment) -> VsOut {
    var corners = array<u32, 6>(0u, 1u, 2u, 2u, 1u, 3u);
    let corner = corners[vi];
    let ca = camera.view_proj * vec4<f32>(s.a.xyz, 1.0);
    let cb = camera.view_proj * vec4<f32>(s.b.xyz, 1.0);
    let half_vp = camera.viewport.xy * 0.5;
    let pa = ca.xy / max(ca.w, 1e-4) * half_vp;
    let pb = cb.xy / max(cb.w, 1e-4) * half_vp;
    var dir = pb - pa;
    if (length(dir) < 1e-6) {
        dir = vec2<f32>(1.0, 0.0);
    }
    dir = normalize(dir);
    let normal = vec2<f32>(-dir.y, dir.x);
    let at_end = corner >= 2u;
    let side = select(-1.0, 1.0, (corner % 2u) == 1u);
    let along = select(-1.0, 1.0, at_end);
    let half_width = 0.5 * s.a.w;
    var c = select(ca, cb, at_end);
    let offset = (normal * side + dir * along) * half_width;
    c = vec4<f32>(c.xy + offset / half_vp * c.w, c.z, c.w);
    var out: VsOut;
    out.clip = c;
    out.color = s.color;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    return output_colour(in.color);
}
