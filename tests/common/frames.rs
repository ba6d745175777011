//! Pixel checks of app frames: the egui controls panel and the curvature-coloured body.

use image::RgbaImage;

/// (dark, light) pixels in columns `0..x_end` and `rows`: egui's dark panel and the text on it.
pub fn panel_pixels(img: &RgbaImage, x_end: u32, rows: std::ops::Range<u32>) -> (usize, usize) {
    let (mut dark, mut light) = (0, 0);
    for y in rows {
        for x in 0..x_end {
            let p = img.get_pixel(x, y).0;
            let lum = (u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2])) / 3;
            dark += usize::from(lum < 40);
            light += usize::from(lum > 150);
        }
    }
    (dark, light)
}

/// Pixels in columns `columns` whose colour is clearly the curvature map's red or blue.
pub fn curvature_coloured_pixels(img: &RgbaImage, columns: std::ops::Range<u32>) -> usize {
    img.enumerate_pixels()
        .filter(|(x, _, _)| columns.contains(x))
        .filter(|(_, _, p)| {
            let [r, g, b, _] = p.0.map(i32::from);
            (r - g > 60 && r - b > 60) || (b - r > 60 && b - g > 20)
        })
        .count()
}
