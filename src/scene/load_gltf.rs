//! A `Gltf(..)` object in a scene: the file read once, its materials added
//! once, and each mesh instance spawned as an entity. An instance whose
//! world matrix is a rotation and a uniform scale shares its mesh (one BLAS
//! for all such copies); any other (non-uniform scale, shear, mirroring)
//! gets the matrix baked into a mesh of its own. Translations stay f64.


use glam::{DMat3, DMat4, DQuat, DVec3};

use super::gltf_file::{self, GltfLoaded, GltfTriangle};
use super::load::Builder;
use super::validate::Ctx;
use super::world::{Camera, Light, LocalTriangle, MaterialTextures, MeshData, MeshShape, ObjectId, SpotCone, TextureSlot, Transform};
use crate::error::UserError;

/// A RON placement as a matrix: translate + rotate(scale x p).
fn placement(translate: [f64; 3], scale: f32, rotate_deg: [f32; 3]) -> DMat4 {
    let [x, y, z] = rotate_deg.map(|d| f64::from(d).to_radians());
    let q = DQuat::from_euler(glam::EulerRot::XYZ, x, y, z);
    DMat4::from_scale_rotation_translation(DVec3::splat(f64::from(scale)), q, DVec3::from_array(translate))
}

/// The rotation and uniform scale of `m`, when it is one (no shear, no
/// mirroring, the same scale on every axis to 1 part in 1e6).
fn similarity(m: DMat3) -> Option<(DQuat, f64)> {
    let det = m.determinant();
    if det.is_nan() || det <= 0.0 {
        return None;
    }
    let s = det.cbrt();
    let r = m * (1.0 / s);
    let off = (r.transpose() * r - DMat3::IDENTITY).to_cols_array().iter().fold(0.0f64, |a, &x| a.max(x.abs()));
    (off < 1e-6).then(|| (DQuat::from_mat3(&r).normalize(), s))
}

impl Builder<'_, '_> {
    /// Spawns the instances of the glTF file at `rel` as object `i`, placed
    /// by the RON object's translate, scale and rotation, and queues its
    /// lights and cameras.
    pub(super) fn gltf_object(&mut self, ctx: &Ctx, i: usize, rel: &str, (translate, scale, rotate_deg): ([f64; 3], f32, [f32; 3]), camera: DVec3) -> Result<(), UserError> {
        let placement = placement(translate, scale, rotate_deg);
        let resolved = self.loc.path.parent().unwrap_or(std::path::Path::new("")).join(rel);
        let g = match self.gltf_cache.iter().position(|g| g.path == resolved) {
            Some(g) => g,
            None => {
                let resolved = self.resolve(ctx, rel, "glTF", "a .gltf or .glb file")?;
                let file = gltf_file::read(&resolved).map_err(|e| ctx.err("path", e))?;
                for w in &file.warnings {
                    eprintln!("glint: {}: {w}", resolved.display());
                }
                self.gltf_cache.push(GltfLoaded::new(resolved, file));
                self.gltf_cache.len() - 1
            }
        };
        if self.gltf_cache[g].materials_base.is_none() {
            let base = self.materials.len() as u32;
            self.materials.extend_from_slice(&self.gltf_cache[g].file.materials);
            self.gltf_cache[g].materials_base = Some(base);
            self.gltf_textures(g, base as usize);
        }
        let instances = self.gltf_cache[g].file.instances.clone();
        for inst in instances {
            let world = placement * inst.matrix;
            let translation = world.w_axis.truncate();
            ctx.near("translate", translation, camera)?;
            let linear = DMat3::from_mat4(world);
            // (mesh, how far it reaches from its origin, placement): a shared
            // mesh's reach is measured once, whatever its instances.
            let (mesh, reach, transform) = match similarity(linear) {
                Some((rotation, scale)) => {
                    let (mesh, reach) = match self.gltf_cache[g].shared[inst.mesh] {
                        Some(m) => m,
                        None => {
                            let m = self.gltf_mesh(g, inst.mesh, DMat3::IDENTITY);
                            let shared = (m, self.reach(m));
                            self.gltf_cache[g].shared[inst.mesh] = Some(shared);
                            shared
                        }
                    };
                    (mesh, reach, Transform { translation, rotation: rotation.as_quat(), scale: scale as f32 })
                }
                // A collapsed instance (a zero scale) shows nothing.
                None if linear.determinant() == 0.0 => continue,
                None => {
                    let mesh = self.gltf_mesh(g, inst.mesh, linear);
                    (mesh, self.reach(mesh), Transform::from_translation(translation))
                }
            };
            self.check_reach(ctx, reach, f64::from(transform.scale))?;
            self.world.spawn((ObjectId(i as u32), transform, MeshShape { mesh }));
        }
        for c in &self.gltf_cache[g].file.cameras {
            let up = placement.transform_vector3(c.up);
            // A scaled placement leaves the field of view as it is.
            self.gltf_cameras.push(Camera {
                position: placement.transform_point3(c.position),
                target: placement.transform_point3(c.target),
                up: up.as_vec3(),
                vfov_deg: c.vfov_deg as f32,
            });
        }
        for l in &self.gltf_cache[g].file.lights {
            let position = placement.transform_point3(l.position);
            ctx.near("translate", position, camera)?;
            let turn = |d: glam::Vec3| placement.transform_vector3(d.as_dvec3()).normalize_or_zero().as_vec3();
            let spot = l.spot.map(|s| SpotCone { direction: turn(s.direction), ..s });
            let light = match l.directional {
                Some(d) => Light::Directional { irradiance: l.intensity, direction: turn(d) },
                None => Light::Point { intensity: l.intensity },
            };
            self.gltf_lights.push((position, light, spot));
        }
        Ok(())
    }

    /// The textures of file `g`'s materials (the first at scene material
    /// `base`): each image used moves into the scene's textures once per
    /// use as colour (sRGB) or as data (linear: normals, metalness).
    fn gltf_textures(&mut self, g: usize, base: usize) {
        let mut scene_index: Vec<[Option<usize>; 2]> = vec![[None; 2]; self.gltf_cache[g].file.images.len()];
        for k in 0..self.gltf_cache[g].file.material_textures.len() {
            let mt = self.gltf_cache[g].file.material_textures[k];
            let mut slot = |r: Option<gltf_file::TextureRef>, linear: bool, builder: &mut Self| -> Option<TextureSlot> {
                let r = r?;
                let uses = &mut scene_index[r.image];
                let texture = match uses[usize::from(linear)] {
                    Some(t) => t,
                    None => {
                        // Moved out on its first use, copied from there for
                        // a use in the other colour space.
                        let mut image = match uses[usize::from(!linear)] {
                            Some(other) => builder.textures[other].clone(),
                            None => builder.gltf_cache[g].file.images[r.image].take()?,
                        };
                        image.linear = linear;
                        builder.textures.push(image);
                        uses[usize::from(linear)] = Some(builder.textures.len() - 1);
                        builder.textures.len() - 1
                    }
                };
                let wrap = r.wrap.map(|w| match w {
                    gltf_file::Wrap::Repeat => 0,
                    gltf_file::Wrap::Clamp => 1,
                    gltf_file::Wrap::Mirror => 2,
                });
                Some(TextureSlot { texture, wrap, transform: r.transform })
            };
            let textures = MaterialTextures {
                base_color: slot(mt.base_color, false, self),
                emissive: slot(mt.emissive, false, self),
                alpha_mask: mt.alpha_mask,
                metallic_roughness: slot(mt.metallic_roughness, true, self),
                normal: mt.normal.and_then(|(r, scale)| Some((slot(Some(r), true, self)?, scale))),
            };
            if textures != MaterialTextures::default() {
                let id = base + k;
                if self.material_textures.len() <= id {
                    self.material_textures.resize(id + 1, MaterialTextures::default());
                }
                self.material_textures[id] = textures;
            }
        }
    }

    /// A scene mesh of glTF mesh `mesh` of file `g` with `linear` applied
    /// (positions by it, normals by its inverse transpose, and the winding
    /// turned back where it mirrors).
    fn gltf_mesh(&mut self, g: usize, mesh: usize, linear: DMat3) -> usize {
        let normal_matrix = linear.inverse().transpose();
        let mirrored = linear.determinant() < 0.0;
        let mut triangles = Vec::with_capacity(self.gltf_cache[g].file.meshes[mesh].len());
        for k in 0..self.gltf_cache[g].file.meshes[mesh].len() {
            let t: GltfTriangle = self.gltf_cache[g].file.meshes[mesh][k];
            let material = self.gltf_material(g, t.material);
            let mut p = t.p.map(|p| (linear * p.as_dvec3()).as_vec3());
            let mut n = t.n.map(|n| (normal_matrix * n.as_dvec3()).as_vec3().normalize_or(n));
            // A tangent lies in the surface: it goes by `linear` itself. A
            // mirror turns cross(n, t) the other way, so w turns too.
            let mut tangent = t.tangent.map(|v| {
                let xyz = (linear * v.truncate().as_dvec3()).as_vec3().normalize_or_zero();
                xyz.extend(if mirrored { -v.w } else { v.w })
            });
            let (mut uv, mut color) = (t.uv, t.color);
            if mirrored {
                p.swap(1, 2);
                n.swap(1, 2);
                uv.swap(1, 2);
                tangent.swap(1, 2);
                color.swap(1, 2);
            }
            triangles.push(LocalTriangle { p, n, uv, tangent, color, material });
        }
        self.meshes.push(MeshData { triangles });
        self.meshes.len() - 1
    }

    /// The scene material id of glTF material `m` of file `g` (None: the
    /// glTF default material, added the first time it is used).
    fn gltf_material(&mut self, g: usize, m: Option<usize>) -> u32 {
        match (m, self.gltf_cache[g].materials_base) {
            (Some(m), Some(base)) => base + m as u32,
            _ => match self.gltf_cache[g].default_material {
                Some(id) => id,
                None => {
                    let id = self.push_material(gltf_file::DEFAULT_MATERIAL);
                    self.gltf_cache[g].default_material = Some(id);
                    id
                }
            },
        }
    }
}


#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotations_with_uniform_scale_are_shared_and_the_rest_baked() {
        let q = DQuat::from_rotation_y(0.7);
        let m = DMat3::from_quat(q) * 2.5;
        let (r, s) = similarity(m).expect("a similarity");
        assert!((s - 2.5).abs() < 1e-12 && r.angle_between(q) < 1e-9);
        assert!(similarity(DMat3::from_diagonal(DVec3::new(1.0, 2.0, 1.0))).is_none(), "non-uniform");
        assert!(similarity(DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0))).is_none(), "mirrored");
        assert!(similarity(DMat3::ZERO).is_none());
    }
}
