//! Every WGSL shader parses and validates with naga (the compiler wgpu uses), so a broken
//! shader fails `cargo test` on a machine without a GPU; and every file in `shaders/` is one the
//! renderer loads.
#![cfg(feature = "render")]

use naga::valid::{Capabilities, ValidationFlags, Validator};
use rollphase::render::{OUTPUT_COLOUR, SHADERS};

/// The renderer's shaders.
fn all_shaders() -> Vec<(&'static str, &'static str)> {
    SHADERS.to_vec()
}

/// The patched egui-wgpu shader the app's panels use (vendor/egui-wgpu) parses and validates
/// too, with its two override constants.
#[test]
fn the_patched_egui_shader_validates() {
    let source = include_str!("../../vendor/egui-wgpu/src/egui.wgsl");
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("egui.wgsl: {}", e.emit_to_string(source)));
    Validator::new(ValidationFlags::all(), Capabilities::empty())
        .validate(&module)
        .unwrap_or_else(|e| panic!("egui.wgsl: {}", e.emit_to_string(source)));
    let overrides: Vec<_> = module
        .overrides
        .iter()
        .filter_map(|(_, o)| o.name.clone())
        .collect();
    assert_eq!(overrides, ["DITHERING", "PREDICTABLE_TEXTURE_FILTERING"]);
}

#[test]
fn every_shader_parses_and_validates() {
    for (name, source) in all_shaders() {
        let module = naga::front::wgsl::parse_str(source)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
        // The GL path (llvmpipe) gets WebGL2-level capabilities: validate with none extra.
        Validator::new(ValidationFlags::all(), Capabilities::empty())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
        for entry in ["vs_main", "fs_main"] {
            assert!(
                module.entry_points.iter().any(|e| e.name == entry),
                "{name} lacks {entry}"
            );
        }
    }
}

#[test]
fn the_renderer_loads_every_file_in_the_shaders_folder() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders");
    let mut on_disk: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".wgsl"))
        .collect();
    on_disk.sort();
    let mut loaded: Vec<String> = all_shaders().iter().map(|(n, _)| n.to_string()).collect();
    loaded.push("output_colour.wgsl".into());
    loaded.sort();
    assert_eq!(on_disk, loaded);
}

/// Every shader begins with the colour prelude, so each can encode sRGB for a non-sRGB target
/// (the app's), and each has the one constant the renderer sets.
#[test]
fn every_shader_writes_its_colour_through_the_prelude() {
    for (name, source) in all_shaders() {
        assert!(
            source.starts_with(OUTPUT_COLOUR),
            "{name} lacks the prelude"
        );
        assert!(
            source[OUTPUT_COLOUR.len()..].contains("output_colour("),
            "{name} never calls output_colour"
        );
        let module = naga::front::wgsl::parse_str(source).unwrap();
        let overrides: Vec<_> = module
            .overrides
            .iter()
            .filter_map(|(_, o)| o.name.clone())
            .collect();
        assert_eq!(overrides, ["ENCODE_SRGB"], "{name}");
    }
}

#[test]
fn a_broken_shader_is_caught() {
    let broken = "@vertex fn vs_main() -> @builtin(position) vec4<f32> { return vec3<f32>(0.0); }";
    let module = naga::front::wgsl::parse_str(broken);
    let invalid = match module {
        Err(_) => true,
        Ok(m) => Validator::new(ValidationFlags::all(), Capabilities::empty())
            .validate(&m)
            .is_err(),
    };
    assert!(invalid, "a type error in a shader must not validate");
}
