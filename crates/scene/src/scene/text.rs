//! What a name or a label shows: the characters refused in one (those that break the line,
//! reorder or hide the text around them) and a name as it looks (composed, its ignorable
//! characters left out), for the bodies' names and labels (`lanes`) and a saved state's
//! drag-law labels (`setup`).

use super::SceneError;
use super::error::invalid;

/// Refuses a name's characters that reorder, break or hide the text around them (the checks a
/// label gets, less its length: a scene's `name` names its own body where it has no label).
pub(super) fn check_characters(text: &str, field: &str) -> Result<(), SceneError> {
    if let Some(c) = text.chars().find(|c| c.is_control()) {
        return Err(invalid(format!(
            "{field} {text:?} is not allowed: it holds the control character {c:?} (needs one \
             line of printable text)"
        )));
    }
    if let Some(c) = text.chars().find(|&c| hides_or_reorders(c)) {
        return Err(invalid(format!(
            "{field} {text:?} is not allowed: it holds the invisible character U+{:04X}, which \
             breaks the line, reorders or hides the text around it (needs one line of printable \
             text)",
            u32::from(c)
        )));
    }
    Ok(())
}

/// Characters that break a line (U+2028, U+2029), turn the text around them (the direction
/// embeddings, overrides and isolates: "abc" shown as "cba"), or hide text: the zero-width
/// space, the soft hyphen, the word joiner and invisible operators, the byte-order mark,
/// interlinear annotations and tags. The ones spelling needs stay allowed: the zero-width
/// joiner and non-joiner (Persian, Indic scripts, emoji sequences) and the left-to-right and
/// right-to-left marks (numbers in Hebrew or Arabic text).
fn hides_or_reorders(c: char) -> bool {
    matches!(
        c,
        '\u{00AD}'
            | '\u{200B}'
            | '\u{2028}'..='\u{202E}'
            | '\u{2060}'..='\u{2064}'
            | '\u{2066}'..='\u{206F}'
            | '\u{FEFF}'
            | '\u{FFF9}'..='\u{FFFB}'
            | '\u{E0000}'..='\u{E007F}'
    )
}

/// Unicode's default-ignorable characters, and the blank Braille pattern (U+2800, which the
/// bundled font draws blank): drawn as nothing (or as a box where a font lacks them), so two
/// names that differ only in them look the same.
fn ignorable(c: char) -> bool {
    matches!(
        c,
        '\u{00AD}'
            | '\u{034F}'
            | '\u{061C}'
            | '\u{115F}'..='\u{1160}'
            | '\u{17B4}'..='\u{17B5}'
            | '\u{180B}'..='\u{180F}'
            | '\u{200B}'..='\u{200F}'
            | '\u{202A}'..='\u{202E}'
            | '\u{2060}'..='\u{206F}'
            | '\u{2800}'
            | '\u{3164}'
            | '\u{FE00}'..='\u{FE0F}'
            | '\u{FEFF}'
            | '\u{FFA0}'
            | '\u{FFF0}'..='\u{FFF8}'
            | '\u{1BCA0}'..='\u{1BCA3}'
            | '\u{1D173}'..='\u{1D17A}'
            | '\u{E0000}'..='\u{E0FFF}'
    )
}

/// A name as it looks: in Unicode's canonical composition (NFC: "cafe" with a combining acute
/// is "café", the Ohm sign is Ω), its ignorable characters left out and its white space
/// trimmed, each run of it one space. Two bodies whose names look the same are refused as one
/// name. (NFC, not the compatibility form NFKC: "x²" and "x2" look different and stay apart.)
pub(super) fn as_shown(name: &str) -> String {
    use unicode_normalization::UnicodeNormalization;
    let visible: String = name.nfc().filter(|&c| !ignorable(c)).collect();
    visible.split_whitespace().collect::<Vec<_>>().join(" ")
}
