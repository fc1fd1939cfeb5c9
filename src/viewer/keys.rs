//! The viewer's key commands (beside the fly keys in `camera`), the help
//! overlay's list of every binding, saved viewpoints, and the camera as a
//! scene-file line. Pure (unit-tested without a window).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use winit::keyboard::KeyCode;

use crate::scene::Camera;

/// What a key press asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeyCommand {
    /// Esc: close the viewer.
    Quit,
    /// F1 or `?`: show or hide the help overlay.
    ToggleHelp,
    /// Home: back to the scene file's camera.
    ResetCamera,
    /// Print the camera as a scene-file line and copy it.
    CopyCamera,
    /// Ctrl + 1..9: keep the camera as viewpoint n.
    SaveView(usize),
    /// 1..9: go to viewpoint n.
    RecallView(usize),
    /// P: pause or resume scene time (the camera still moves).
    Pause,
    /// F12: PNG of the window, EXR of the render.
    Screenshot,
}

/// Viewpoint slots (keys 1 to 9).
pub const VIEW_SLOTS: usize = 9;

/// The command of a pressed key (`text`: the character it typed, for `?`
/// whichever key a layout puts it on).
pub fn command(code: KeyCode, text: Option<&str>, ctrl: bool) -> Option<KeyCommand> {
    if text == Some("?") {
        return Some(KeyCommand::ToggleHelp);
    }
    let digit = match code {
        KeyCode::Digit1 => Some(1),
        KeyCode::Digit2 => Some(2),
        KeyCode::Digit3 => Some(3),
        KeyCode::Digit4 => Some(4),
        KeyCode::Digit5 => Some(5),
        KeyCode::Digit6 => Some(6),
        KeyCode::Digit7 => Some(7),
        KeyCode::Digit8 => Some(8),
        KeyCode::Digit9 => Some(9),
        _ => None,
    };
    if let Some(n) = digit {
        return Some(if ctrl { KeyCommand::SaveView(n) } else { KeyCommand::RecallView(n) });
    }
    match code {
        KeyCode::Escape => Some(KeyCommand::Quit),
        KeyCode::F1 => Some(KeyCommand::ToggleHelp),
        KeyCode::Home => Some(KeyCommand::ResetCamera),
        KeyCode::KeyC => Some(KeyCommand::CopyCamera),
        KeyCode::KeyP => Some(KeyCommand::Pause),
        KeyCode::F12 => Some(KeyCommand::Screenshot),
        _ => None,
    }
}

/// Every key and mouse binding, as the help overlay lists them.
pub const BINDINGS: &[(&str, &str)] = &[
    ("W / A / S / D", "fly forward, left, back, right"),
    ("Q / E", "fly down, up"),
    ("wheel", "fly speed (x1.2 a notch)"),
    ("right-drag", "look around"),
    ("left-drag", "orbit the target"),
    ("Home", "the scene file's camera again"),
    ("1 ... 9", "go to a saved viewpoint"),
    ("Ctrl + 1 ... 9", "save the camera as that viewpoint (kept per scene)"),
    ("C", "print the camera as a scene-file line and copy it"),
    ("P", "pause or resume scene time"),
    ("F12", "screenshot (PNG of the window, EXR of the render)"),
    ("F1 or ?", "this help"),
    ("Esc", "quit"),
    ("drop a .ron, .obj, .gltf or .glb", "open that scene (a mesh framed, lit by default)"),
];

/// Saved viewpoints, per scene file.
#[derive(Debug, Default)]
pub struct Viewpoints {
    by_scene: HashMap<PathBuf, [Option<Camera>; VIEW_SLOTS]>,
}

impl Viewpoints {
    /// Keeps `camera` as viewpoint `n` (1-based) of `scene`.
    pub fn save(&mut self, scene: &Path, n: usize, camera: Camera) {
        if let Some(slot) = n.checked_sub(1).filter(|&i| i < VIEW_SLOTS) {
            self.by_scene.entry(scene.to_path_buf()).or_insert([None; VIEW_SLOTS])[slot] = Some(camera);
        }
    }

    /// Viewpoint `n` (1-based) of `scene`, if one was saved.
    pub fn get(&self, scene: &Path, n: usize) -> Option<Camera> {
        let slot = n.checked_sub(1).filter(|&i| i < VIEW_SLOTS)?;
        self.by_scene.get(scene).and_then(|s| s[slot])
    }
}

/// A float as RON reads it back as a float (always a point or exponent).
fn num(x: f64) -> String {
    let s = format!("{x}");
    if s.contains(['.', 'e', 'E']) || !x.is_finite() {
        s
    } else {
        format!("{s}.0")
    }
}

fn triple(v: [f64; 3]) -> String {
    format!("({}, {}, {})", num(v[0]), num(v[1]), num(v[2]))
}

/// The camera as a scene file writes it (`camera: Camera(...)`).
pub fn camera_line(c: &Camera) -> String {
    format!(
        "camera: Camera(position: {}, target: {}, up: {}, vfov_deg: {}),",
        triple(c.position.to_array()),
        triple(c.target.to_array()),
        triple(c.up.as_dvec3().to_array()),
        num(f64::from(c.vfov_deg))
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3};

    fn cam(x: f64) -> Camera {
        Camera { position: DVec3::new(x, 0.25, 3.4), target: DVec3::ZERO, up: Vec3::Y, vfov_deg: 40.0 }
    }

    #[test]
    fn keys_map_to_commands() {
        assert_eq!(command(KeyCode::Escape, None, false), Some(KeyCommand::Quit));
        assert_eq!(command(KeyCode::F1, None, false), Some(KeyCommand::ToggleHelp));
        assert_eq!(command(KeyCode::Slash, Some("?"), false), Some(KeyCommand::ToggleHelp));
        assert_eq!(command(KeyCode::Slash, Some("/"), false), None);
        assert_eq!(command(KeyCode::Digit3, Some("3"), false), Some(KeyCommand::RecallView(3)));
        assert_eq!(command(KeyCode::Digit3, None, true), Some(KeyCommand::SaveView(3)));
        assert_eq!(command(KeyCode::Home, None, false), Some(KeyCommand::ResetCamera));
        assert_eq!(command(KeyCode::KeyW, Some("w"), false), None);
    }

    #[test]
    fn viewpoints_are_kept_per_scene() {
        let mut v = Viewpoints::default();
        let (a, b) = (Path::new("scenes/a.ron"), Path::new("scenes/b.ron"));
        v.save(a, 1, cam(1.0));
        v.save(b, 1, cam(2.0));
        v.save(a, 10, cam(3.0));
        assert_eq!(v.get(a, 1), Some(cam(1.0)));
        assert_eq!(v.get(b, 1), Some(cam(2.0)));
        assert_eq!(v.get(a, 2), None);
        assert_eq!(v.get(a, 0), None);
        assert_eq!(v.get(a, 10), None);
    }

    #[test]
    fn the_camera_line_reads_back_as_the_same_camera() {
        let c = Camera { position: DVec3::new(-1.0, 0.5, 1e-7), target: DVec3::new(0.1, 2.0, -3.0), up: Vec3::Y, vfov_deg: 55.5 };
        let line = camera_line(&c);
        assert!(line.starts_with("camera: Camera(position: (-1.0, 0.5, 0.0000001)"), "{line}");
        let text = format!("Scene({line} objects: [])");
        let scene = crate::scene::parse(&text, Path::new("camera-line.ron")).unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(scene.camera, c);
    }
}
