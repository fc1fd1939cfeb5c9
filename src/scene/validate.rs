//! Checks on the values RON accepted (it takes `NaN`, `inf`, negative radii,
//! ...). Each check names the offending item and finds its line in the file.

use glam::{DVec3, Vec3};

use super::locate::{Locator, Step};
use super::schema::{CameraDesc, EnvironmentDesc, LightDesc, MaterialDesc, MotionDesc, ObjectDesc, P3, V3};
use super::world::{Motion, SpotCone};
use crate::error::UserError;

type Res<T> = Result<T, UserError>;

/// How far from its camera, and how large, anything in a scene may be.
/// The GPU works in f32 relative to an origin near the camera; squared
/// distances overflow f32 past about 1.8e19, so sizes and distances stay
/// well below that (1e15 squared is 1e30).
pub(crate) const MAX_RANGE: f64 = 1e15;

/// The largest radius / (camera's distance from the surface) of a sphere
/// (see `Ctx::resolvable`).
pub(crate) const MAX_SPHERE_RATIO: f64 = 3e5;

/// A vector as written in RON: `(x, y, z)`.
fn show(v: impl Into<DVec3>) -> String {
    let v: DVec3 = v.into();
    // Huge values in exponent form (3e38, not 39 digits).
    let n = |x: f64| if x.is_finite() && x.abs() >= 1e7 { format!("{x:e}") } else { format!("{x}") };
    format!("({}, {}, {})", n(v.x), n(v.y), n(v.z))
}

/// A path into the file plus the name used in messages, e.g. `objects[2] (Sphere)`.
pub(crate) struct Ctx<'a, 'l> {
    loc: &'a Locator<'l>,
    at: Vec<Step<'a>>,
    name: String,
}

impl<'a, 'l> Ctx<'a, 'l> {
    pub(crate) fn new(loc: &'a Locator<'l>, at: Vec<Step<'a>>, name: String) -> Self {
        Ctx { loc, at, name }
    }

    /// An error at `field` of this item (or at the item if the field is not written).
    pub(crate) fn err(&self, field: &'a str, message: impl std::fmt::Display) -> UserError {
        let mut at = self.at.clone();
        at.push(Step::Field(field));
        self.loc.err(&at, format!("{}: {message}", self.name))
    }

    fn child(&self, field: &'a str, name: &str) -> Ctx<'a, 'l> {
        let mut at = self.at.clone();
        at.push(Step::Field(field));
        Ctx {
            loc: self.loc,
            at,
            name: format!("{} {name}", self.name),
        }
    }

    fn finite(&self, field: &'a str, v: V3) -> Res<Vec3> {
        let v = Vec3::from_array(v);
        if v.is_finite() { Ok(v) } else { Err(self.non_finite(field, show(v))) }
    }

    /// A finite position (f64).
    fn place(&self, field: &'a str, v: P3) -> Res<DVec3> {
        let v = DVec3::from_array(v);
        if v.is_finite() { Ok(v) } else { Err(self.non_finite(field, show(v))) }
    }

    fn non_finite(&self, field: &'a str, shown: String) -> UserError {
        self.err(field, format_args!("`{field}` has a NaN or infinite component: {shown}"))
    }

    /// Finite and every component >= 0 (colours, radiance, intensity).
    fn color(&self, field: &'a str, v: V3) -> Res<Vec3> {
        let v = self.finite(field, v)?;
        if v.min_element() < 0.0 {
            return Err(self.err(
                field,
                format_args!("`{field}` must not be negative, got {}", show(v)),
            ));
        }
        Ok(v)
    }

    fn positive(&self, field: &'a str, x: f32) -> Res<f32> {
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(
                field,
                format_args!("`{field}` must be a positive finite number, got {x}"),
            ))
        }
    }

    /// A positive finite size within `MAX_RANGE` (radii, scales).
    fn size(&self, field: &'a str, x: f32) -> Res<f32> {
        self.positive(field, x)?;
        if f64::from(x) > MAX_RANGE {
            return Err(self.err(
                field,
                format_args!("`{field}` {x:e} is beyond glint's range of {MAX_RANGE:e} (the GPU works in f32, where squared distances overflow past about 1.8e19)"),
            ));
        }
        Ok(x)
    }

    /// A position within `MAX_RANGE` of the camera in every axis.
    pub(crate) fn near(&self, field: &'a str, p: DVec3, camera: DVec3) -> Res<()> {
        let far = (p - camera).abs().max_element();
        if far > MAX_RANGE {
            return Err(self.err(
                field,
                format_args!("`{field}` {} is {far:e} from the camera at {}; glint renders what lies within {MAX_RANGE:e} of its camera (f32 on the GPU)", show(p), show(camera)),
            ));
        }
        Ok(())
    }

    /// A sphere whose surface f32 can resolve where the camera sees it:
    /// `ray_sphere` computes r^2 - |l|^2, whose rounding (about r^2 6e-8)
    /// swamps the true value (about 2 r h at height h above the surface)
    /// once r / h passes about 3e5 (radius 1e8 seen from 3 away shaded to
    /// 4e-17).
    pub(crate) fn resolvable(&self, center: DVec3, radius: f32, camera: DVec3) -> Res<()> {
        let r = f64::from(radius);
        let h = ((center - camera).length() - r).abs();
        if r > MAX_SPHERE_RATIO * h {
            return Err(self.err(
                "radius",
                format_args!(
                    "a sphere of radius {r:e} seen from {} off its surface is beyond what f32 resolves (radius / distance must stay below {MAX_SPHERE_RATIO:e}); model a large ground or wall as a Quad", h as f32
                ),
            ));
        }
        Ok(())
    }

    fn unit(&self, field: &'a str, x: f32) -> Res<f32> {
        if (0.0..=1.0).contains(&x) {
            Ok(x)
        } else {
            Err(self.err(field, format_args!("`{field}` must be in 0..1, got {x}")))
        }
    }
}

pub(crate) fn camera(c: &CameraDesc, loc: &Locator) -> Res<()> {
    let ctx = Ctx::new(loc, vec![Step::Field("camera")], "camera".into());
    let position = ctx.place("position", c.position)?;
    let target = ctx.place("target", c.target)?;
    let up = ctx.finite("up", c.up)?.as_dvec3();
    if !(c.vfov_deg > 0.0 && c.vfov_deg < 180.0) {
        return Err(ctx.err(
            "vfov_deg",
            format_args!("`vfov_deg` must be in (0, 180) degrees, got {}", c.vfov_deg),
        ));
    }
    let Some(dir) = (target - position).try_normalize() else {
        return Err(ctx.err("target", "`target` must differ from `position`"));
    };
    if up.try_normalize().is_none_or(|u| dir.cross(u).length_squared() < 1e-12) {
        return Err(ctx.err(
            "up",
            format_args!(
                "`up` {} must not be zero or parallel to the view direction",
                show(up)
            ),
        ));
    }
    Ok(())
}

pub(crate) fn background(v: V3, loc: &Locator) -> Res<Vec3> {
    Ctx::new(loc, vec![], "scene".into()).color("background", v)
}

/// An environment's colour (or 1 for a map) times its intensity, and its
/// rotation in radians; `path` or `color`, not both, and not beside a
/// `background`.
pub(crate) fn environment(e: &EnvironmentDesc, background: Vec3, loc: &Locator) -> Res<(Vec3, f32)> {
    let ctx = Ctx::new(loc, vec![Step::Field("environment")], "environment".into());
    if background != Vec3::ZERO {
        return Err(ctx.err("path", "give `background` or `environment`, not both (the environment is what rays that leave the scene see)"));
    }
    let color = match (&e.path, e.color) {
        (Some(_), Some(_)) => return Err(ctx.err("color", "give `path` (a map) or `color`, not both")),
        (None, None) => return Err(ctx.err("path", "give `path` (an EXR or PFM latitude-longitude map) or `color`")),
        (Some(_), None) => Vec3::ONE,
        (None, Some(c)) => ctx.color("color", c)?,
    };
    if !(e.intensity.is_finite() && e.intensity >= 0.0) {
        return Err(ctx.err("intensity", format_args!("`intensity` must be a finite number >= 0, got {}", e.intensity)));
    }
    if !e.rotation_deg.is_finite() {
        return Err(ctx.err("rotation_deg", format_args!("`rotation_deg` must be finite, got {}", e.rotation_deg)));
    }
    Ok((color * e.intensity, e.rotation_deg.to_radians()))
}

pub(crate) fn material(i: usize, name: &str, m: &MaterialDesc, loc: &Locator) -> Res<()> {
    let ctx = Ctx::new(
        loc,
        vec![Step::Field("materials"), Step::Item(i)],
        format!("material \"{name}\""),
    );
    let albedo = ctx.color("albedo", m.albedo)?;
    if albedo.max_element() > 1.0 {
        return Err(ctx.err(
            "albedo",
            format_args!("`albedo` components must be in 0..1, got {}", show(albedo)),
        ));
    }
    ctx.unit("specular", m.specular)?;
    if let Some(metallic) = m.metallic {
        ctx.unit("metallic", metallic)?;
        if m.specular > 0.0 {
            return Err(ctx.err(
                "metallic",
                "a material has `specular` (the thesis material) or `metallic` (glTF's metallic-roughness), not both",
            ));
        }
    }
    ctx.unit("roughness", m.roughness)?;
    ctx.color("emission", m.emission)?;
    Ok(())
}

/// Checks an object's numbers (material names are resolved by the loader).
pub(crate) fn object(ctx: &Ctx, o: &ObjectDesc) -> Res<()> {
    match o {
        ObjectDesc::Quad { vertices, .. } => {
            let v: Vec<DVec3> = vertices
                .iter()
                .map(|&v| ctx.place("vertices", v))
                .collect::<Res<_>>()?;
            if v.len() != 4 {
                return Err(ctx.err(
                    "vertices",
                    format_args!("a quad needs exactly 4 vertices, got {}", v.len()),
                ));
            }
            if quad_normal(&v).is_none() {
                return Err(ctx.err("vertices", "the quad is degenerate (zero area)"));
            }
        }
        ObjectDesc::Sphere { center, radius, .. } => {
            ctx.place("center", *center)?;
            ctx.size("radius", *radius)?;
        }
        ObjectDesc::Mesh {
            path,
            translate,
            scale,
            rotate_deg,
            ..
        }
        | ObjectDesc::Gltf {
            path,
            translate,
            scale,
            rotate_deg,
        } => {
            if path.trim().is_empty() {
                return Err(ctx.err("path", "`path` is empty"));
            }
            ctx.place("translate", *translate)?;
            ctx.size("scale", *scale)?;
            ctx.finite("rotate_deg", *rotate_deg)?;
        }
    }
    Ok(())
}

/// The unit normal of a quad `v0 v1 v2 v3` (counter-clockwise = front):
/// the cross product of the diagonals, which is twice the (vector) area even
/// for a slightly non-planar quad. `None` when the area is zero.
pub(crate) fn quad_normal(v: &[DVec3]) -> Option<Vec3> {
    let [v0, v1, v2, v3] = v else { return None };
    let n = (*v2 - *v0).cross(*v3 - *v1);
    let scale = (*v2 - *v0)
        .length_squared()
        .max((*v3 - *v1).length_squared());
    // Relative test: a sliver far thinner than its size is degenerate too.
    (n.length_squared() > 1e-12 * scale * scale).then(|| n.normalize().as_vec3())
}

pub(crate) fn light(ctx: &Ctx, l: &LightDesc) -> Res<()> {
    match l {
        LightDesc::SphereLight {
            center,
            radius,
            radiance,
            ..
        } => {
            ctx.place("center", *center)?;
            if *radius == 0.0 {
                // Decided: not silently a point light, whose intensity
                // would have to be invented from a radiance.
                return Err(ctx.err(
                    "radius",
                    "a sphere light of radius 0 has no area to emit from; for a light without size write \
                     PointLight(position: .., intensity: ..) (intensity = radiance x pi r^2 matches a small sphere's far field)",
                ));
            }
            ctx.size("radius", *radius)?;
            ctx.color("radiance", *radiance)?;
        }
        LightDesc::PointLight {
            position,
            intensity,
            ..
        } => {
            ctx.place("position", *position)?;
            ctx.color("intensity", *intensity)?;
        }
        LightDesc::DirectionalLight { direction, irradiance } => {
            ctx.color("irradiance", *irradiance)?;
            let d = ctx.finite("direction", *direction)?;
            if d.as_dvec3().length_squared() == 0.0 {
                return Err(ctx.err("direction", "`direction` is (0, 0, 0); give the way the light travels"));
            }
        }
        LightDesc::SpotLight { position, direction, intensity, inner_deg, outer_deg, .. } => {
            ctx.place("position", *position)?;
            ctx.color("intensity", *intensity)?;
            let d = ctx.finite("direction", *direction)?;
            if d.as_dvec3().length_squared() == 0.0 {
                return Err(ctx.err("direction", "`direction` is (0, 0, 0); give the way the cone points"));
            }
            if !(inner_deg.is_finite() && outer_deg.is_finite() && 0.0 <= *inner_deg && inner_deg < outer_deg && *outer_deg <= 90.0) {
                return Err(ctx.err("outer_deg", format_args!("the cone needs 0 <= inner_deg < outer_deg <= 90, got {inner_deg} and {outer_deg}")));
            }
        }
    }
    Ok(())
}

/// `v` at unit length, normalised in f64 so that neither a tiny nor a
/// huge (finite) direction fails; None for zero or non-finite.
pub(crate) fn unit(v: Vec3) -> Option<Vec3> {
    v.as_dvec3().try_normalize().map(|u| u.as_vec3())
}

/// The cone of a spot light pointing along `direction` (any length) with
/// these half angles in radians; None where they do not make a cone
/// (checked before: `light`, and the glTF reader).
pub(crate) fn spot_cone(direction: Vec3, inner: f32, outer: f32) -> Option<SpotCone> {
    let direction = unit(direction)?;
    (0.0 <= inner && inner < outer && outer <= std::f32::consts::FRAC_PI_2).then(|| SpotCone { direction, cos_inner: inner.cos(), cos_outer: outer.cos() })
}

/// Checks a `motion:` and converts it.
pub(crate) fn motion(parent: &Ctx, m: &MotionDesc) -> Res<Motion> {
    match *m {
        MotionDesc::Orbit {
            center,
            axis,
            radius,
            period_s,
            phase_deg,
        } => {
            let ctx = parent.child("motion", "Orbit");
            let center = ctx.place("center", center)?;
            let axis_v = ctx.finite("axis", axis)?;
            if !(radius.is_finite() && radius >= 0.0) {
                return Err(ctx.err(
                    "radius",
                    format_args!("`radius` must be a finite number >= 0, got {radius}"),
                ));
            }
            ctx.positive("period_s", period_s)?;
            if !phase_deg.is_finite() {
                return Err(ctx.err(
                    "phase_deg",
                    format_args!("`phase_deg` must be finite, got {phase_deg}"),
                ));
            }
            Motion::orbit(center, axis_v, radius, period_s, phase_deg)
                .ok_or_else(|| ctx.err("axis", "`axis` must not be zero"))
        }
        MotionDesc::Linear { velocity } => {
            let ctx = parent.child("motion", "Linear");
            Ok(Motion::Linear {
                velocity: ctx.place("velocity", velocity)?,
            })
        }
    }
}
