// Lit triangle meshes: the body (vertex colours = curvature), the ramp (procedural grid), the
// SO(3) ball (translucent) and the markers. Blinn–Phong: ambient + diffuse + specular.

struct Camera {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    // xyz: direction towards the light (unit), w: ambient level
    light: vec4<f32>,
    // xy: viewport size in pixels
    viewport: vec4<f32>,
};

struct Draw {
    model: mat4x4<f32>,
    // multiplies the vertex colour
    tint: vec4<f32>,
    // x: opacity, y: grid spacing (0: no grid), z: specular strength, w: 1 = unlit
    params: vec4<f32>,
};

@group(0) @binding(0) var<uniform> camera: Camera;
@group(1) @binding(0) var<uniform> draw: Draw;

struct VsIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) local: vec3<f32>,
};

@vertex
fn vs_main(v: VsIn) -> VsOut {
    var out: VsOut;
    let world = draw.model * vec4<f32>(v.position, 1.0);
    out.clip = camera.view_proj * world;
    out.world = world.xyz;
    // The model matrices are rotations and uniform scales, so they carry normals directly.
    out.normal = normalize((draw.model * vec4<f32>(v.normal, 0.0)).xyz);
    out.color = v.color * draw.tint;
    out.local = v.position;
    return out;
}

// The line's coverage at `x` (the coordinate in spacings) with `width` = fwidth(x) * 1.2.
fn grid_line(x: f32, width: f32) -> f32 {
    let d = abs(fract(x + 0.5) - 0.5);
    return 1.0 - smoothstep(0.0, width, d);
}

// x^48 by five multiplications: pow() is exp2(48 log2 x), two polynomial approximations per
// pixel on a CPU renderer (llvmpipe).
fn pow48(x: f32) -> f32 {
    let x2 = x * x;
    let x4 = x2 * x2;
    let x8 = x4 * x4;
    let x16 = x8 * x8;
    return x16 * x16 * x16;
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var base = in.color.rgb;
    if (draw.params.y > 0.0) {
        // fwidth is linear: one derivative per axis serves both the minor and the major lines.
        let minor = in.local.xy / draw.params.y;
        let width = fwidth(minor) * 1.2;
        let major = minor * 0.2;
        let g = max(grid_line(minor.x, width.x), grid_line(minor.y, width.y));
        let m = max(grid_line(major.x, width.x * 0.2), grid_line(major.y, width.y * 0.2));
        base = mix(base, base * 0.55, g * 0.6);
        base = mix(base, base * 0.35, m * 0.8);
    }
    if (draw.params.w > 0.5) {
        return output_colour(vec4<f32>(base, in.color.a * draw.params.x));
    }
    var n = normalize(in.normal);
    if (!front) {
        n = -n;
    }
    // camera.light.xyz is a unit vector (normalised on the CPU).
    let l = camera.light.xyz;
    let v = normalize(camera.eye.xyz - in.world);
    let h = normalize(l + v);
    let diffuse = max(dot(n, l), 0.0);
    let fill = 0.25 * max(-dot(n, l), 0.0);
    let spec = draw.params.z * pow48(max(dot(n, h), 0.0));
    let rgb = base * (camera.light.w + 0.75 * diffuse + fill) + vec3<f32>(spec);
    return output_colour(vec4<f32>(rgb, in.color.a * draw.params.x));
}
