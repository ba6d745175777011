//! The app's fonts: DejaVu Sans (bundled for the overlay and the charts) first in the
//! proportional family, and the last fallback of the monospace one, so every character the
//! presets, lessons and panels use has a glyph (egui's own fonts lack "∝", for one, which showed
//! as a box), and α is an α: egui's Ubuntu Light draws it as "ɑ", which on a projector reads as
//! the letter a ("a (rad)", "a up" on the 1/T plot) beside the overlay's clear α.

use std::sync::Arc;

use egui::{FontData, FontDefinitions, FontFamily};

/// The name of the bundled fallback font.
pub const FALLBACK: &str = "DejaVuSans";

/// egui's default fonts plus the bundled fallback.
pub fn definitions() -> FontDefinitions {
    let mut fonts = FontDefinitions::default();
    fonts.font_data.insert(
        FALLBACK.into(),
        Arc::new(FontData::from_static(crate::assets::FONT)),
    );
    fonts
        .families
        .entry(FontFamily::Proportional)
        .or_default()
        .insert(0, FALLBACK.into());
    fonts
        .families
        .entry(FontFamily::Monospace)
        .or_default()
        .push(FALLBACK.into());
    fonts
}

#[cfg(test)]
mod tests {
    use ab_glyph::{Font, FontRef};

    use super::*;
    use crate::scene::{PRESETS, Scene};

    /// Every character of every preset's name, description and lesson captions, and the
    /// overlay's own words.
    fn bundled_text() -> String {
        let mut text = String::from(
            "α* = rad ° α/α* m/m0 model t = 1/T: measuring… halted ∂Ω to ∂Ω one full turn period \
             ||q|−1| ≤ — contact error ≤ NOT TRUSTWORTHY STOPPED: step of θ θ̇ ψ ω φ π ∞ ± × · ≈ ❚❚ paused (Space plays)",
        );
        for (name, _) in PRESETS {
            let scene = Scene::preset(name).unwrap();
            text.push_str(&scene.name);
            text.push_str(&scene.description);
            for step in scene.setup(None).unwrap().timeline {
                if let Some(c) = step.caption {
                    text.push_str(&c);
                }
            }
        }
        text
    }

    /// egui takes each character from the first font of the family that has it: α, ω, θ and
    /// the plot's other symbols come from DejaVu Sans, as in the overlay, not from Ubuntu Light,
    /// whose α reads as an a.
    #[test]
    fn greek_letters_in_the_panels_and_plots_are_the_overlays() {
        let fonts = definitions();
        let proportional = &fonts.families[&FontFamily::Proportional];
        for c in "αωθφπκ∂Ω√∝".chars() {
            let first = proportional
                .iter()
                .find(|name| {
                    FontRef::try_from_slice((*fonts.font_data[*name].font).as_ref())
                        .unwrap()
                        .glyph_id(c)
                        .0
                        != 0
                })
                .unwrap();
            assert_eq!(first, FALLBACK, "{c} is drawn by {first}");
        }
    }

    #[test]
    fn every_character_of_the_presets_has_a_glyph_in_the_app_and_the_overlay() {
        let text = bundled_text();
        let fonts = definitions();
        let faces: Vec<FontRef> = fonts.families[&FontFamily::Proportional]
            .iter()
            .map(|name| FontRef::try_from_slice((*fonts.font_data[name].font).as_ref()).unwrap())
            .collect();
        let overlay = FontRef::try_from_slice(crate::assets::FONT).unwrap();
        let mut missing_app = Vec::new();
        let mut missing_overlay = Vec::new();
        for c in text
            .chars()
            .filter(|c| !c.is_whitespace() && !c.is_control())
        {
            // Combining marks (θ̇) are drawn on their base letter.
            if ('\u{300}'..='\u{36f}').contains(&c) {
                continue;
            }
            if faces.iter().all(|f| f.glyph_id(c).0 == 0) && !missing_app.contains(&c) {
                missing_app.push(c);
            }
            if overlay.glyph_id(c).0 == 0 && !missing_overlay.contains(&c) {
                missing_overlay.push(c);
            }
        }
        assert!(
            missing_app.is_empty(),
            "no glyph in the app's fonts: {missing_app:?}"
        );
        assert!(
            missing_overlay.is_empty(),
            "no glyph in the overlay's font: {missing_overlay:?}"
        );
        // The check can fail: egui's own fonts alone lack "∝", which a preset uses.
        let defaults = FontDefinitions::default();
        let plain: Vec<FontRef> = defaults.families[&FontFamily::Proportional]
            .iter()
            .map(|name| FontRef::try_from_slice((*defaults.font_data[name].font).as_ref()).unwrap())
            .collect();
        assert!(text.contains('∝'));
        assert!(plain.iter().all(|f| f.glyph_id('∝').0 == 0));
    }
}
