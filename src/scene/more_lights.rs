//! More lights for the light-scaling benchmarks (`glint bench thesis`,
//! the thesis's 4.3.1/4.3.2): copies of every light beside it.

use glam::DVec3;

use super::world::{Light, LightIndex, MaterialId, ObjectId, Scene, Transform};

impl Scene {
    /// Gives the scene `factor` times its lights: each light gets
    /// `factor - 1` static copies, as bright, beside it: in a horizontal
    /// row across the line from the scene's centre (+s, -s, +2s, ...), so a
    /// ceiling light's copies stay under the ceiling and a light outside a
    /// wall stays outside it; s is 4 radii or 5% of the scene's size,
    /// whichever is more. Returns how many lights it added.
    pub fn multiply_lights(&mut self, factor: u32) -> u32 {
        if factor <= 1 {
            return 0;
        }
        let (center, extent) = self.bounds().map_or((DVec3::ZERO, 1.0), |(lo, hi)| ((lo + hi) * 0.5, (hi - lo).max_element()));
        let mut lights: Vec<(LightIndex, Transform, Light, Option<MaterialId>)> =
            self.world.query::<(&LightIndex, &Transform, &Light, Option<&MaterialId>)>().iter().map(|(i, t, l, m)| (*i, *t, *l, m.copied())).collect();
        lights.sort_by_key(|l| l.0);
        let mut next_id = self.world.query::<&ObjectId>().iter().map(|id| id.0 + 1).max().unwrap_or(0);
        let mut next_index = lights.iter().map(|l| l.0 .0 + 1).max().unwrap_or(0);
        let mut added = 0;
        for (_, t, light, material) in lights {
            let radius = match light {
                Light::Sphere { radius, .. } => f64::from(radius),
                Light::Point { .. } | Light::Directional { .. } => 0.0,
            };
            let spread = (4.0 * radius).max(0.05 * extent);
            // Up is the camera's (+y in every shipped scene).
            let up = self.camera.up.as_dvec3().try_normalize().unwrap_or(DVec3::Y);
            let away = t.translation - center;
            let across = up.cross(away - up * away.dot(up)).try_normalize().unwrap_or_else(|| up.any_orthonormal_vector());
            for k in 1..factor {
                let step = f64::from(k.div_ceil(2)) * if k % 2 == 1 { 1.0 } else { -1.0 };
                let mut copy = t;
                copy.translation = t.translation + spread * step * across;
                let e = self.world.spawn((ObjectId(next_id), LightIndex(next_index), copy, light));
                if let Some(m) = material {
                    let _ = self.world.insert_one(e, m);
                }
                next_id += 1;
                next_index += 1;
                added += 1;
            }
        }
        self.features.lights = self.features.lights.saturating_add(added);
        added
    }
}
