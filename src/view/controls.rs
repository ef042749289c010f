//! The viewer's keys: which key does what, and the help line that says so.

use winit::keyboard::{Key, NamedKey};

/// Something a key asks the viewer to do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    /// Close the window and end the run.
    Quit,
    /// Print the key list ([`HELP`]).
    Help,
    /// Orbit <-> fly.
    ToggleRig,
    /// Go back to the scene's own camera.
    ResetCamera,
    /// +1 next, -1 previous.
    CycleMethod(i32),
    /// Next self-shadow mode on every relief material.
    CycleShadows,
    /// Next ambient-occlusion mode on every relief material.
    CycleAo,
    /// Level of detail on or off.
    ToggleLod,
    /// Multiply every depth scale by this.
    ScaleDepth(f32),
    /// Switch between waiting for the display and presenting unpaced.
    ToggleVsync,
    /// Write the next presented frame to a PNG in the current folder.
    Screenshot,
}

/// Keys held down to fly: (right, up, forward) in -1..1 each.
pub fn fly_axis(key: &Key) -> Option<(usize, f32)> {
    let Key::Character(c) = key else {
        return None;
    };
    match c.to_lowercase().as_str() {
        "d" => Some((0, 1.0)),
        "a" => Some((0, -1.0)),
        "r" => Some((1, 1.0)),
        "f" => Some((1, -1.0)),
        "w" => Some((2, 1.0)),
        "s" => Some((2, -1.0)),
        _ => None,
    }
}

/// The action of a pressed key, if any.
pub fn action(key: &Key) -> Option<Action> {
    match key {
        Key::Named(NamedKey::Escape) => return Some(Action::Quit),
        Key::Named(NamedKey::F1) => return Some(Action::Help),
        Key::Named(NamedKey::Tab) => return Some(Action::ToggleRig),
        _ => {}
    }
    let Key::Character(c) = key else {
        return None;
    };
    Some(match c.as_str() {
        "?" | "h" => Action::Help,
        "c" | "C" => Action::ResetCamera,
        "m" => Action::CycleMethod(1),
        "M" | "n" | "N" => Action::CycleMethod(-1),
        "x" | "X" => Action::CycleShadows,
        "o" | "O" => Action::CycleAo,
        "l" | "L" => Action::ToggleLod,
        "]" | "+" | "=" => Action::ScaleDepth(1.25),
        "[" | "-" => Action::ScaleDepth(0.8),
        "v" | "V" => Action::ToggleVsync,
        "p" | "P" => Action::Screenshot,
        _ => return None,
    })
}

/// What the keys do, as printed at start and on F1.
pub const HELP: &str = "\
relief view controls:
  mouse drag      orbit around the scene (fly mode: look around)
  wheel           zoom (fly mode: flying speed)
  Tab             orbit <-> fly;  fly with W/S forward/back, A/D left/right, R/F up/down
  C               back to the scene's camera
  M / N           next / previous displacement method
  X               next self-shadow mode (none, hard, pom-soft, horizon, cone)
  O               next ambient occlusion mode
  L               level of detail on/off
  [ / ]           depth scale x0.8 / x1.25
  V               vsync on/off
  P               screenshot (relief-view-N.png in the current folder)
  H, ?, F1        this help;  Esc quits
The title shows the device, the method and settings, frames per second and each pass's GPU time.";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_in_the_help_does_what_it_says() {
        let ch = |s: &str| Key::Character(s.into());
        assert_eq!(action(&ch("m")), Some(Action::CycleMethod(1)));
        assert_eq!(action(&ch("n")), Some(Action::CycleMethod(-1)));
        assert_eq!(action(&ch("x")), Some(Action::CycleShadows));
        assert_eq!(action(&ch("o")), Some(Action::CycleAo));
        assert_eq!(action(&ch("l")), Some(Action::ToggleLod));
        assert_eq!(action(&ch("]")), Some(Action::ScaleDepth(1.25)));
        assert_eq!(action(&ch("[")), Some(Action::ScaleDepth(0.8)));
        assert_eq!(action(&ch("v")), Some(Action::ToggleVsync));
        assert_eq!(action(&ch("p")), Some(Action::Screenshot));
        assert_eq!(action(&ch("c")), Some(Action::ResetCamera));
        assert_eq!(action(&Key::Named(NamedKey::Tab)), Some(Action::ToggleRig));
        assert_eq!(action(&Key::Named(NamedKey::Escape)), Some(Action::Quit));
        assert_eq!(action(&ch("w")), None, "W flies, it is no action");
        assert_eq!(fly_axis(&ch("W")), Some((2, 1.0)));
        assert_eq!(fly_axis(&ch("a")), Some((0, -1.0)));
        for key in [
            "Tab", "W/S", "M / N", "X ", "O ", "L ", "[ / ]", "V ", "P ", "Esc",
        ] {
            assert!(HELP.contains(key), "help names {key}");
        }
    }
}
