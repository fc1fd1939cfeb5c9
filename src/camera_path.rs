//! Camera motion for headless renders (`glint render --camera-path`): an
//! orbit around the camera's target, or keyframes from a RON file,
//! evaluated at the scene time of each frame.

use std::path::Path;

use glam::{DQuat, DVec3};
use serde::Deserialize;

use crate::error::{ron_error, UserError};
use crate::scene::Camera;

/// How the camera moves over scene time.
#[derive(Debug, Clone, PartialEq)]
pub enum CameraPath {
    /// Orbit the target about +y at `deg_per_s`, keeping distance and height.
    Orbit {
        /// Degrees per second; positive turns counter-clockwise seen from above.
        deg_per_s: f32,
    },
    /// Linear interpolation between keyframes (clamped at the ends).
    Keys(Vec<Key>),
}

/// One keyframe: `Key(time_s: 0.0, position: (..), target: (..))`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Key {
    /// Scene time of the key, seconds.
    pub time_s: f32,
    /// f64, as scene positions are (a path may run far from the origin).
    pub position: (f64, f64, f64),
    /// The point looked at (f64, as `position`).
    pub target: (f64, f64, f64),
}

impl CameraPath {
    /// Parses `orbit:DEG_PER_S` or `keys:FILE.ron` (a list of `Key`s).
    pub fn parse(arg: &str) -> Result<CameraPath, UserError> {
        if let Some(rate) = arg.strip_prefix("orbit:") {
            // Beyond a turn per millisecond the path is noise, not motion.
            let deg_per_s: f32 = rate
                .trim()
                .parse()
                .ok()
                .filter(|r: &f32| r.is_finite() && r.abs() <= 360_000.0)
                .ok_or_else(|| UserError::new(format!("--camera-path orbit:{rate}: give degrees per second within +-360000, e.g. orbit:30")))?;
            return Ok(CameraPath::Orbit { deg_per_s });
        }
        if let Some(file) = arg.strip_prefix("keys:") {
            let path = Path::new(file);
            let text = crate::error::read_user_text(path, "camera path")?;
            let keys: Vec<Key> = ron::Options::default().from_str(&text).map_err(|e| ron_error(path, &e))?;
            let finite = |v: (f64, f64, f64)| v.0.is_finite() && v.1.is_finite() && v.2.is_finite();
            if keys.is_empty() || keys.iter().any(|k| !k.time_s.is_finite() || !finite(k.position) || !finite(k.target)) {
                return Err(UserError::in_file(path, "a camera path needs at least one key, all numbers finite"));
            }
            if keys.windows(2).any(|w| w[1].time_s <= w[0].time_s) {
                return Err(UserError::in_file(path, "camera keys must be in strictly increasing time_s"));
            }
            return Ok(CameraPath::Keys(keys));
        }
        Err(UserError::new(format!("--camera-path `{arg}`: write orbit:DEG_PER_S or keys:FILE.ron")))
    }

    /// Checks every key against the scene's camera as the scene file's
    /// camera is checked: the target must differ from the position and the
    /// view must not look along `up`, and the path must stay within 1e15 of
    /// the scene's camera (f32 squared distances on the GPU overflow past
    /// about 1e19).
    pub fn check(&self, base: &Camera) -> Result<(), UserError> {
        let CameraPath::Keys(keys) = self else { return Ok(()) };
        for (i, k) in keys.iter().enumerate() {
            let p = DVec3::new(k.position.0, k.position.1, k.position.2);
            let t = DVec3::new(k.target.0, k.target.1, k.target.2);
            let at = format!("camera path key {i} (time_s {})", k.time_s);
            let Some(dir) = (t - p).try_normalize() else {
                return Err(UserError::new(format!("{at}: `target` must differ from `position`")));
            };
            let up = base.up.as_dvec3().normalize_or_zero();
            if dir.cross(up).length_squared() < 1e-12 {
                return Err(UserError::new(format!("{at}: the view looks straight along the camera's `up` {:?}, which leaves no image orientation", base.up)));
            }
            let far = (p - base.position).abs().max_element().max((t - base.position).abs().max_element());
            if far > 1e15 {
                return Err(UserError::new(format!("{at}: {far:e} from the scene's camera; keys must stay within 1e15 of it")));
            }
        }
        Ok(())
    }

    /// The camera at time `t`, starting from the scene's camera.
    pub fn at(&self, base: &Camera, t: f32) -> Camera {
        match self {
            CameraPath::Orbit { deg_per_s } => {
                let rot = DQuat::from_rotation_y(f64::from(deg_per_s * t).to_radians());
                Camera { position: base.target + rot * (base.position - base.target), ..*base }
            }
            CameraPath::Keys(keys) => {
                let v = |p: (f64, f64, f64)| DVec3::new(p.0, p.1, p.2);
                let i = keys.iter().rposition(|k| k.time_s <= t).unwrap_or(0);
                let (a, b) = (keys[i], keys[(i + 1).min(keys.len() - 1)]);
                let s = if b.time_s > a.time_s { f64::from(((t - a.time_s) / (b.time_s - a.time_s)).clamp(0.0, 1.0)) } else { 0.0 };
                Camera {
                    position: v(a.position).lerp(v(b.position), s),
                    target: v(a.target).lerp(v(b.target), s),
                    ..*base
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn base() -> Camera {
        Camera { position: DVec3::new(0.0, 1.0, 3.0), target: DVec3::ZERO, up: Vec3::Y, vfov_deg: 40.0 }
    }

    #[test]
    fn orbit_keeps_distance_and_height() {
        let p = CameraPath::parse("orbit:90").unwrap();
        let c = p.at(&base(), 1.0);
        assert!((c.position - DVec3::new(3.0, 1.0, 0.0)).length() < 1e-5, "{:?}", c.position);
        assert_eq!(p.at(&base(), 0.0).position, base().position);
    }

    #[test]
    fn keys_interpolate_and_clamp() {
        let dir = std::env::temp_dir().join(format!("glint-cam-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("path.ron");
        std::fs::write(&file, "[Key(time_s: 0.0, position: (0.0, 0.0, 4.0), target: (0.0, 0.0, 0.0)),\n Key(time_s: 2.0, position: (2.0, 0.0, 4.0), target: (1.0, 0.0, 0.0))]").unwrap();
        let p = CameraPath::parse(&format!("keys:{}", file.display())).unwrap();
        assert!((p.at(&base(), 1.0).position - DVec3::new(1.0, 0.0, 4.0)).length() < 1e-6);
        assert_eq!(p.at(&base(), 5.0).target, DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(p.at(&base(), -1.0).position, DVec3::new(0.0, 0.0, 4.0));
        std::fs::write(&file, "[Key(time_s: 1.0, position: (0.0, 0.0, 4.0), target: (0.0, 0.0, 0.0)),\n Key(time_s: 1.0, position: (2.0, 0.0, 4.0), target: (1.0, 0.0, 0.0))]").unwrap();
        assert!(CameraPath::parse(&format!("keys:{}", file.display())).unwrap_err().to_string().contains("increasing"));
        std::fs::write(&file, "[Key(time_s: 0.0, position: (0.0, 0.0), target: (0.0, 0.0, 0.0))]").unwrap();
        assert!(CameraPath::parse(&format!("keys:{}", file.display())).unwrap_err().to_string().contains("path.ron:1"));
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn keys_are_checked_like_the_scene_camera() {
        let keys = |p: (f64, f64, f64), t: (f64, f64, f64)| CameraPath::Keys(vec![Key { time_s: 0.0, position: p, target: t }]);
        assert!(keys((0.0, 0.0, 4.0), (0.0, 0.0, 0.0)).check(&base()).is_ok());
        let e = |p, t| keys(p, t).check(&base()).unwrap_err().to_string();
        assert!(e((1.0, 1.0, 1.0), (1.0, 1.0, 1.0)).contains("must differ"));
        assert!(e((0.0, 0.0, 0.0), (0.0, 5.0, 0.0)).contains("along the camera's `up`"));
        assert!(e((0.0, 0.0, 3e38), (0.0, 0.0, 0.0)).contains("within 1e15"));
    }

    #[test]
    fn bad_arguments_are_refused() {
        assert!(CameraPath::parse("orbit:3e38").is_err());
        assert!(CameraPath::parse("orbit:fast").is_err());
        assert!(CameraPath::parse("orbit:NaN").is_err());
        assert!(CameraPath::parse("spiral:3").is_err());
        assert!(CameraPath::parse("keys:/nonexistent/x.ron").is_err());
    }
}
