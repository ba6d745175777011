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

fn grid_line(coord: f32, spacing: f32) -> f32 {
    let x = coord / spacing;
    let width = fwidth(x) * 1.2;
    let d = abs(fract(x + 0.5) - 0.5);
    return 1.0 - smoothstep(0.0, width, d);
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var base = in.color.rgb;
    if (draw.params.y > 0.0) {
        let g = max(grid_line(in.local.x, draw.params.y), grid_line(in.local.y, draw.params.y));
        let major = max(grid_line(in.local.x, draw.params.y * 5.0), grid_line(in.local.y, draw.params.y * 5.0));
        base = mix(base, base * 0.55, g * 0.6);
        base = mix(base, base * 0.35, major * 0.8);
    }
    if (draw.params.w > 0.5) {
        return vec4<f32>(base, in.color.a * draw.params.x);
    }
    var n = normalize(in.normal);
    if (!front) {
        n = -n;
    }
    let l = normalize(camera.light.xyz);
    let v = normalize(camera.eye.xyz - in.world);
    let h = normalize(l + v);
    let diffuse = max(dot(n, l), 0.0);
    let fill = 0.25 * max(dot(n, -l), 0.0);
    let spec = draw.params.z * pow(max(dot(n, h), 0.0), 48.0);
    let rgb = base * (camera.light.w + 0.75 * diffuse + fill) + vec3<f32>(spec);
    return vec4<f32>(rgb, in.color.a * draw.params.x);
}
