//! The key map: one table the window, the scripts and the help overlay all read. Keys are
//! physical (winit `KeyCode`s), so WASD sits under the left hand on any layout; scripts name
//! them as winit does (`KeyW`, `Digit1`, `F12`, `ArrowUp`).

use leakless::Method;
use winit::keyboard::KeyCode;

/// What a key does once per press.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    Method(Method),
    CycleLayer,
    ToggleReuse,
    RadiusDown,
    RadiusUp,
    PathsDown,
    PathsUp,
    CapDown,
    CapUp,
    ToggleTrivialAccept,
    SwitchBackend,
    /// Moves the first light along x, y, z by one step.
    MoveLight([i8; 3]),
    FreezeSeed,
    /// Plays or stops the scene's animation.
    PlayAnimation,
    Pause,
    Capture,
    ResetCamera,
    Help,
    ToggleOverlay,
}

/// Keys held down to fly: right, up, forward (-1 or 1 on one axis).
pub const MOVE_KEYS: [(KeyCode, [f32; 3], &str); 6] = [
    (KeyCode::KeyW, [0.0, 0.0, 1.0], "forward"),
    (KeyCode::KeyS, [0.0, 0.0, -1.0], "back"),
    (KeyCode::KeyA, [-1.0, 0.0, 0.0], "left"),
    (KeyCode::KeyD, [1.0, 0.0, 0.0], "right"),
    (KeyCode::KeyQ, [0.0, -1.0, 0.0], "down"),
    (KeyCode::KeyE, [0.0, 1.0, 0.0], "up"),
];

/// Every key that acts once per press, with what the help shows.
pub const ACTIONS: &[(KeyCode, Action, &str, &str)] = &[
    (KeyCode::Digit1, Action::Method(Method::Direct), "1", "method: direct light only"),
    (KeyCode::Digit2, Action::Method(Method::Splat), "2", "method: splat (Moreau et al., leaks)"),
    (KeyCode::Digit3, Action::Method(Method::LeakLessCapped), "3", "method: leakless-capped (the thesis)"),
    (KeyCode::Digit4, Action::Method(Method::LeakLess), "4", "method: leakless (ours)"),
    (KeyCode::Digit5, Action::Method(Method::Reference), "5", "method: reference (accumulates while still)"),
    (KeyCode::KeyV, Action::CycleLayer, "V", "view layer: final, direct, indirect, leaked, heat maps"),
    (KeyCode::BracketLeft, Action::RadiusDown, "[", "gather radius ÷ 1.25"),
    (KeyCode::BracketRight, Action::RadiusUp, "]", "gather radius × 1.25"),
    (KeyCode::Minus, Action::PathsDown, "-", "light paths ÷ 2"),
    (KeyCode::Equal, Action::PathsUp, "=", "light paths × 2"),
    (KeyCode::Comma, Action::CapDown, ",", "cap (leakless-capped) − 5"),
    (KeyCode::Period, Action::CapUp, ".", "cap (leakless-capped) + 5"),
    (KeyCode::KeyT, Action::ToggleTrivialAccept, "T", "trivial accept on/off"),
    (KeyCode::KeyU, Action::ToggleReuse, "U", "temporal reuse of the indirect light on/off"),
    (KeyCode::KeyB, Action::SwitchBackend, "B", "trace backend: ray queries / compute BVH"),
    (KeyCode::ArrowLeft, Action::MoveLight([-1, 0, 0]), "Left", "first light −x"),
    (KeyCode::ArrowRight, Action::MoveLight([1, 0, 0]), "Right", "first light +x"),
    (KeyCode::ArrowUp, Action::MoveLight([0, 0, -1]), "Up", "first light −z"),
    (KeyCode::ArrowDown, Action::MoveLight([0, 0, 1]), "Down", "first light +z"),
    (KeyCode::PageUp, Action::MoveLight([0, 1, 0]), "PgUp", "first light +y"),
    (KeyCode::PageDown, Action::MoveLight([0, -1, 0]), "PgDn", "first light −y"),
    (KeyCode::KeyP, Action::FreezeSeed, "P", "freeze / unfreeze the photon seed"),
    (KeyCode::KeyM, Action::PlayAnimation, "M", "play / stop the scene's animation (time slider in the panel)"),
    (KeyCode::Space, Action::Pause, "Space", "pause (show the last image)"),
    (KeyCode::F12, Action::Capture, "F12", "capture to captures/<scene>-<n>.exr/.png/.json"),
    (KeyCode::KeyR, Action::ResetCamera, "R", "reset the camera"),
    (KeyCode::KeyH, Action::Help, "H", "this help"),
    (KeyCode::F1, Action::Help, "F1", "this help"),
    (KeyCode::Tab, Action::ToggleOverlay, "Tab", "hide / show the overlay"),
];

pub fn action(code: KeyCode) -> Option<Action> {
    ACTIONS.iter().find(|(k, ..)| *k == code).map(|&(_, a, ..)| a)
}

/// The direction a held key flies in.
pub fn motion(code: KeyCode) -> Option<[f32; 3]> {
    MOVE_KEYS.iter().find(|(k, ..)| *k == code).map(|&(_, m, _)| m)
}

/// A key by its winit name (`KeyW`, `F12`...), among the keys the app uses.
pub fn parse(name: &str) -> Option<KeyCode> {
    let used = MOVE_KEYS.iter().map(|(k, ..)| *k).chain(ACTIONS.iter().map(|(k, ..)| *k));
    used.into_iter().find(|k| format!("{k:?}") == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_is_mapped_once_and_named_as_winit_names_it() {
        let mut seen = Vec::new();
        for code in MOVE_KEYS.iter().map(|(k, ..)| *k).chain(ACTIONS.iter().map(|(k, ..)| *k)) {
            assert!(!seen.contains(&code), "{code:?} mapped twice");
            seen.push(code);
            assert_eq!(parse(&format!("{code:?}")), Some(code));
        }
        assert_eq!(parse("F12"), Some(KeyCode::F12));
        assert_eq!(parse("KeyZ"), None);
    }
}
