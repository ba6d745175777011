//! The colour maps, one module for the PNG charts (`plot`, the figures), the 3D views (`view`)
//! and the overlay's colour bars (`render::overlay`): evenly spaced sRGB stops, interpolated in
//! sRGB, and the sRGB → linear conversion the renderer's colours need. Imports nothing.

/// sRGB stops of the diverging map for curvature (blue below the sphere's K = 1, red above).
pub const DIVERGING: [[u8; 3]; 5] = [
    [59, 76, 192],
    [141, 176, 254],
    [221, 221, 221],
    [244, 154, 123],
    [180, 4, 38],
];

/// sRGB stops of the sequential map (viridis): |V| on the Poincaré field, α* and time in charts.
pub const VIRIDIS: [[u8; 3]; 5] = [
    [68, 1, 84],
    [59, 82, 139],
    [33, 145, 140],
    [94, 201, 98],
    [253, 231, 37],
];

/// Interpolates evenly spaced sRGB stops at t ∈ [0, 1] (clamped; a non-finite t gives the
/// first stop, no stops give white).
pub fn sample(stops: &[[u8; 3]], t: f32) -> [u8; 3] {
    match stops.len() {
        0 => [255; 3],
        1 => stops[0],
        n => {
            let t = if t.is_finite() {
                t.clamp(0.0, 1.0)
            } else {
                0.0
            };
            let s = t * (n - 1) as f32;
            let i = (s.floor() as usize).min(n - 2);
            let f = s - i as f32;
            let (a, b) = (stops[i], stops[i + 1]);
            [0, 1, 2].map(|k| (a[k] as f32 + (b[k] as f32 - a[k] as f32) * f).round() as u8)
        }
    }
}

/// Viridis at t ∈ [0, 1] as the (r, g, b) the chart series take.
pub fn viridis(t: f64) -> (u8, u8, u8) {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = t * 4.0;
    let i = (s.floor() as usize).min(3);
    let f = s - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |k: usize| (a[k] as f64 + (b[k] as f64 - a[k] as f64) * f).round() as u8;
    (mix(0), mix(1), mix(2))
}

/// sRGB (0–255) to linear RGBA, for the renderer.
pub fn linear(c: [u8; 3], alpha: f32) -> [f32; 4] {
    let f = |v: u8| {
        let s = v as f32 / 255.0;
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    };
    [f(c[0]), f(c[1]), f(c[2]), alpha]
}

/// sRGB colour of each body on one ramp (a scene's own, then its `[[bodies]]`): the same in
/// the 3D view, the overlay and every plot. Okabe–Ito's orange, sky blue, bluish green and
/// reddish purple, told apart with any colour vision, on the dark panels and the light ramp.
pub const BODY_COLOURS: [[u8; 3]; 4] = [
    [230, 90, 20],
    [86, 180, 233],
    [0, 158, 115],
    [204, 121, 167],
];

/// The colour of body `n` on the ramp (0: the scene's own), cycling past four.
pub fn body_colour(n: usize) -> [u8; 3] {
    BODY_COLOURS[n % BODY_COLOURS.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_and_midpoints_are_the_stops() {
        assert_eq!(sample(&DIVERGING, 0.0), DIVERGING[0]);
        assert_eq!(sample(&DIVERGING, 0.5), DIVERGING[2]);
        assert_eq!(sample(&DIVERGING, 1.0), DIVERGING[4]);
        assert_eq!(sample(&DIVERGING, 7.0), DIVERGING[4]);
        assert_eq!(sample(&VIRIDIS, f32::NAN), VIRIDIS[0]);
        assert_eq!(viridis(0.75), (94, 201, 98));
        assert_eq!(viridis(f64::NAN), (68, 1, 84));
        // Halfway between the first two viridis stops, in both precisions.
        assert_eq!(viridis(0.125), (64, 42, 112));
        assert_eq!(sample(&VIRIDIS, 0.125), [64, 42, 112]);
    }

    #[test]
    fn linear_maps_black_and_white_exactly() {
        assert_eq!(linear([0, 0, 0], 1.0), [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(linear([255, 255, 255], 0.5), [1.0, 1.0, 1.0, 0.5]);
    }
}
