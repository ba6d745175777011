// Prepended to every shader of the 3D renderer (see `SHADERS`): the colour a fragment writes.
// Colours are computed in linear light. An sRGB target (headless PNGs) encodes them as it
// stores them. Into a non-sRGB target (the app's, where egui's panels skip two sRGB
// conversions per pixel) the shader encodes them itself: the sRGB curve's linear toe exactly,
// above it 1.055 x^(1/2.4) - 0.055 fitted on x^(1/2), x^(1/4) and x^(1/8) (Ian Taylor's
// approximation), within 0.25 of an 8-bit level everywhere; pow() cost a CPU renderer more
// than egui saved. Blending then happens in gamma space, as in egui's panels.

override ENCODE_SRGB: bool = false;

fn output_colour(linear: vec4<f32>) -> vec4<f32> {
    if ENCODE_SRGB {
        let c = clamp(linear.rgb, vec3<f32>(0.0), vec3<f32>(1.0));
        let s1 = sqrt(c);
        let s2 = sqrt(s1);
        let s3 = sqrt(s2);
        let high = 0.662002687 * s1 + 0.684122060 * s2 - 0.323583601 * s3 - 0.0225411470 * c;
        return vec4<f32>(select(high, c * 12.92, c <= vec3<f32>(0.0031308)), linear.a);
    }
    return linear;
}
