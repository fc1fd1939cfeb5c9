//! The viewer's camera controls, as pure functions of input (unit-tested
//! without a window).
//!
//! - Fly: W/A/S/D move along the view and right axes, Q/E down and up,
//!   the mouse looks around while the right button is held; the wheel
//!   scales the speed.
//! - Orbit: dragging with the left button turns the camera about its
//!   target (yaw about +y, pitch clamped short of the poles).
//!
//! The camera's `up` stays +y; the look direction never reaches it.

use glam::{DQuat, DVec3};

use crate::scene::Camera;

/// Radians of turn per pixel of mouse motion.
const LOOK_PER_PIXEL: f32 = 0.004;
/// Seconds of a held W that cross the scene's largest side.
pub const SCENE_CROSSING_S: f32 = 4.0;
/// Closest the view direction gets to straight up or down (radians).
const POLE_MARGIN: f32 = 0.02;

/// The fly keys held down.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Keys {
    /// W: along the view direction.
    pub forward: bool,
    /// S: against the view direction.
    pub back: bool,
    /// A: against the right axis.
    pub left: bool,
    /// D: along the right axis (the view direction cross +y).
    pub right: bool,
    /// E: along +y.
    pub up: bool,
    /// Q: along -y.
    pub down: bool,
}

impl Keys {
    /// Whether any fly key is held.
    pub fn any(&self) -> bool {
        self.forward || self.back || self.left || self.right || self.up || self.down
    }
}

/// Fly-mode state: speed and the keys held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraControl {
    /// Fly speed in scene units per second.
    pub speed: f32,
    /// The fly keys held now.
    pub keys: Keys,
}

impl CameraControl {
    /// A speed that crosses the scene's camera-to-target distance in about
    /// two seconds.
    pub fn for_camera(c: &Camera) -> CameraControl {
        let d = (c.target - c.position).length() as f32;
        CameraControl { speed: if d.is_finite() && d > 0.0 { d * 0.5 } else { 1.0 }, keys: Keys::default() }
    }

    /// A speed that crosses the scene's largest side (`bounds`, as
    /// `Scene::bounds` gives them) in `SCENE_CROSSING_S` seconds; from the
    /// camera's distance to its target when the scene has no extent.
    pub fn for_scene(c: &Camera, bounds: Option<(DVec3, DVec3)>) -> CameraControl {
        let side = bounds.map_or(0.0, |(lo, hi)| (hi - lo).max_element()) as f32;
        if side.is_finite() && side > 0.0 {
            return CameraControl { speed: (side / SCENE_CROSSING_S).clamp(1e-6, 1e9), keys: Keys::default() };
        }
        CameraControl::for_camera(c)
    }

    /// The wheel: each notch scales the speed by 1.2.
    pub fn wheel(&mut self, notches: f32) {
        if notches.is_finite() {
            self.speed = (self.speed * 1.2f32.powf(notches)).clamp(1e-6, 1e9);
        }
    }

    /// Moves the camera (and its target, so the view direction is kept)
    /// for `dt` seconds of the held keys.
    pub fn fly(&self, c: &mut Camera, dt: f32) -> bool {
        if !self.keys.any() || dt.is_nan() || dt <= 0.0 {
            return false;
        }
        let forward = (c.target - c.position).normalize_or(DVec3::NEG_Z);
        let right = forward.cross(DVec3::Y).normalize_or(DVec3::X);
        let k = |on: bool| if on { 1.0 } else { 0.0 };
        let dir = forward * (k(self.keys.forward) - k(self.keys.back))
            + right * (k(self.keys.right) - k(self.keys.left))
            + DVec3::Y * (k(self.keys.up) - k(self.keys.down));
        if dir == DVec3::ZERO {
            return false;
        }
        let step = dir.normalize() * f64::from(self.speed * dt);
        c.position += step;
        c.target += step;
        true
    }
}

/// Yaw about +y and pitch about the camera's right axis, applied to `v`,
/// with the pitch stopped short of the poles.
fn turn(v: DVec3, dx: f32, dy: f32) -> DVec3 {
    let (dx, dy, per_pixel) = (f64::from(dx), f64::from(dy), f64::from(LOOK_PER_PIXEL));
    let yaw = DQuat::from_rotation_y(-dx * per_pixel);
    let v = yaw * v;
    let len = v.length();
    let elevation = (v.y / len).clamp(-1.0, 1.0).asin();
    let limit = std::f64::consts::FRAC_PI_2 - f64::from(POLE_MARGIN);
    let new_elevation = (elevation - dy * per_pixel).clamp(-limit, limit);
    let right = v.cross(DVec3::Y).normalize_or(DVec3::X);
    DQuat::from_axis_angle(right, new_elevation - elevation) * v
}

/// Mouse look (fly mode): turns the view direction about the camera.
pub fn look(c: &mut Camera, dx: f32, dy: f32) {
    let v = c.target - c.position;
    if v.length_squared() > 0.0 && dx.is_finite() && dy.is_finite() {
        c.target = c.position + turn(v, dx, dy);
    }
}

/// Orbit drag: turns the camera position about the target.
pub fn orbit(c: &mut Camera, dx: f32, dy: f32) {
    let v = c.position - c.target;
    if v.length_squared() > 0.0 && dx.is_finite() && dy.is_finite() {
        c.position = c.target + turn(v, dx, -dy);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn cam() -> Camera {
        Camera { position: DVec3::new(0.0, 0.0, 3.0), target: DVec3::ZERO, up: Vec3::Y, vfov_deg: 40.0 }
    }

    #[test]
    fn fly_moves_position_and_target_together() {
        let mut c = cam();
        let mut ctl = CameraControl::for_camera(&c);
        assert_eq!(ctl.speed, 1.5);
        ctl.keys.forward = true;
        assert!(ctl.fly(&mut c, 1.0));
        assert!((c.position - DVec3::new(0.0, 0.0, 1.5)).length() < 1e-6);
        assert!((c.target - DVec3::new(0.0, 0.0, -1.5)).length() < 1e-6);
        ctl.keys = Keys { right: true, ..Keys::default() };
        ctl.fly(&mut c, 2.0);
        assert!((c.position.x - 3.0).abs() < 1e-5, "{:?}", c.position);
        assert!(!CameraControl::for_camera(&c).fly(&mut c, 1.0), "no key, no motion");
    }

    #[test]
    fn orbit_keeps_distance_and_never_reaches_the_pole() {
        let mut c = cam();
        orbit(&mut c, 400.0, 0.0);
        assert!((c.position.length() - 3.0).abs() < 1e-5);
        assert!(c.position.x.abs() > 1.0, "yawed: {:?}", c.position);
        for _ in 0..100 {
            orbit(&mut c, 0.0, 500.0);
        }
        let dir = (c.position - c.target).normalize();
        assert!(dir.y.abs() < 1.0 - 1e-5, "reached the pole: {dir:?}");
        assert!((c.position.length() - 3.0).abs() < 1e-4);
    }

    #[test]
    fn look_turns_the_target_about_the_position() {
        let mut c = cam();
        look(&mut c, 0.0, -100.0);
        assert!(c.target.y > 0.0, "moving the mouse up looks up: {:?}", c.target);
        assert!(((c.target - c.position).length() - 3.0).abs() < 1e-5);
        look(&mut c, f32::NAN, 1.0);
        assert!(c.target.is_finite());
        let mut ctl = CameraControl::for_camera(&c);
        ctl.wheel(1.0);
        assert!((ctl.speed - 1.8).abs() < 1e-5);
    }

    #[test]
    fn fly_speed_follows_the_scene_size() {
        let c = cam();
        let cornell = Some((DVec3::splat(-1.0), DVec3::splat(1.0)));
        assert!((CameraControl::for_scene(&c, cornell).speed - 2.0 / SCENE_CROSSING_S).abs() < 1e-6);
        let city = Some((DVec3::ZERO, DVec3::new(4000.0, 10.0, 10.0)));
        assert!((CameraControl::for_scene(&c, city).speed - 1000.0).abs() < 1e-3);
        // No extent (an empty scene, a single point): the camera's distance.
        assert_eq!(CameraControl::for_scene(&c, None).speed, CameraControl::for_camera(&c).speed);
        assert_eq!(CameraControl::for_scene(&c, Some((DVec3::ONE, DVec3::ONE))).speed, CameraControl::for_camera(&c).speed);
    }
}
