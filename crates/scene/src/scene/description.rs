//! The words the app writes into a saved scene's description ("Saved from the app at α = …",
//! "Saved state at t = …"), and the description a scene started with beneath any number of them:
//! each save names the run once, however often a scene was saved, opened and saved again (the
//! old words were nested inside the new, and the title grew without end), and files written
//! from a run (the plots' metadata) carry the scene's own words, not a stale α.

/// How a description saved from the app starts when α or m/m0 were changed.
pub const SAVED_PREFIX: &str = "Saved from the app at α = ";
/// What follows it: the description the scene started with.
pub const STARTED_AS: &str = "; it started as: ";
/// How Save state's description starts.
pub const STATE_PREFIX: &str = "Saved state at t = ";
/// What ends Save state's own words.
pub const STATE_END: &str = "opening it goes on from there. ";

/// The description a scene started with, under any number of the app's own "Saved …" words.
///
/// # Example
/// ```
/// use rollphase_scene::scene::description::original_description;
/// let saved = "Saved from the app at α = 0.1500 rad (0.849 α*), m/m0 = 0; it started as: A ball.";
/// assert_eq!(original_description(saved), "A ball.");
/// ```
pub fn original_description(text: &str) -> &str {
    let mut rest = text.trim();
    loop {
        let peeled = if rest.starts_with(SAVED_PREFIX) {
            rest.split_once(STARTED_AS).map_or("", |(_, first)| first)
        } else if rest.starts_with(STATE_PREFIX) {
            rest.split_once(STATE_END).map_or("", |(_, first)| first)
        } else {
            return rest;
        };
        rest = peeled.trim();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn saved_words_are_peeled_however_often_a_scene_was_saved() {
        let first = "An irregular sphere cruising down a ramp.";
        assert_eq!(original_description(first), first);
        let once = format!("{SAVED_PREFIX}0.1500 rad (0.849 α*), m/m0 = 0{STARTED_AS}{first}");
        let state = format!("{STATE_PREFIX}12.5 (α = 0.15000 rad, m/m0 = 0); {STATE_END}{once}");
        let again = format!("{SAVED_PREFIX}0.1392 rad (0.788 α*), m/m0 = 0{STARTED_AS}{state}");
        assert_eq!(original_description(&again), first);
        assert_eq!(original_description(&format!("{SAVED_PREFIX}0.2 rad")), "");
    }
}
