//! World → flat GPU arrays, in a deterministic order: entities sorted by
//! `ObjectId` (objects in file order, then lights; the quads and meshes
//! that never move before those that do). Positions are f64 in
//! the world and f32 on the GPU, relative to an origin the session keeps
//! near the camera (camera-relative rendering; docs/ARCHITECTURE.md).

use glam::{DVec3, Vec3};

use super::features::SceneFeatures;
use super::light_clusters::light_clusters;
use super::gpu_types::{
    LightGpu, MaterialTexturesGpu, MeshGpu, SceneData, SphereGpu, TriangleGpu, TriangleNormalsGpu, TriangleUvGpu, FLAT_LIMIT,
    LIGHT_DIRECTIONAL, LIGHT_POINT, LIGHT_SPHERE, pack_color, pack_tangent,
};
use super::texture_classes;
use super::world::{
    Light, LightIndex, MaterialId, MeshShape, Motion, ObjectId, Scene, SphereShape, SpotCone, TextureSlot, Transform,
};

impl Scene {
    /// `pack_at` the world origin.
    pub fn pack(&self) -> SceneData {
        self.pack_at(DVec3::ZERO)
    }

    /// Flatten the world into GPU arrays, every position relative to
    /// `origin` (computed in f64, rounded to f32 once). Deterministic order.
    ///
    /// Spheres: sphere objects, then one per sphere light (`light` = its
    /// index in `lights`). Meshes: one for every quad and mesh object that
    /// does not move, then one per object that does, each with a
    /// world-space box over its slice of `triangles`.
    pub fn pack_at(&self, origin: DVec3) -> SceneData {
        let at = |t: &Transform| (t.translation - origin).as_vec3();
        let mut spheres: Vec<(ObjectId, SphereGpu)> = Vec::new();
        for (id, t, s, m) in self
            .world
            .query::<(&ObjectId, &Transform, &SphereShape, &MaterialId)>()
            .iter()
        {
            spheres.push((*id, sphere(*id, at(t), s.radius, m.0, -1)));
        }

        let mut lights: Vec<(LightIndex, ObjectId, LightGpu, Option<SphereGpu>)> = Vec::new();
        let mut query = self.world.query::<(
            &ObjectId,
            &LightIndex,
            &Transform,
            &Light,
            Option<&MaterialId>,
            Option<&SpotCone>,
        )>();
        for (id, index, t, light, material, spot) in query.iter() {
            let p = at(t);
            let (gpu, ball) = match (*light, material) {
                (Light::Sphere { radius, radiance }, Some(m)) => (
                    light_gpu(p, radius, radiance, LIGHT_SPHERE),
                    Some(sphere(*id, p, radius, m.0, index.0 as i32)),
                ),
                // A sphere light always has its material; without one it
                // is still a light, just not visible to rays.
                (Light::Sphere { radius, radiance }, None) => {
                    (light_gpu(p, radius, radiance, LIGHT_SPHERE), None)
                }
                (Light::Point { intensity }, _) => {
                    let spot = spot.map_or(NO_SPOT, SpotCone::gpu);
                    (LightGpu { spot, ..light_gpu(p, 0.0, intensity, LIGHT_POINT) }, None)
                }
                // `position` holds the direction toward the light (no
                // place, so no rebasing).
                (Light::Directional { irradiance, direction }, _) => (light_gpu(-direction, 0.0, irradiance, LIGHT_DIRECTIONAL), None),
            };
            lights.push((*index, *id, gpu, ball));
        }
        lights.sort_by_key(|l| l.0);
        spheres.sort_by_key(|s| s.0);
        spheres.extend(lights.iter().filter_map(|l| l.3.map(|s| (l.1, s))));

        // Objects that never move first, in one run: their triangles share
        // one MeshGpu, so one BLAS (a TLAS instance per quad cost a CPU
        // driver a BLAS traversal per instance a ray's path crosses:
        // docs/acceleration.md, "Objects that never move in one BLAS").
        // Each moving object keeps its own, which motion refits alone.
        let mut instances: Vec<(bool, ObjectId, Transform, usize)> = self
            .world
            .query::<(&ObjectId, &Transform, &MeshShape, Option<&Motion>)>()
            .iter()
            .map(|(id, t, m, motion)| (motion.is_some(), *id, *t, m.mesh))
            .collect();
        instances.sort_by_key(|i| (i.0, i.1));
        let mut triangles = Vec::with_capacity(self.triangle_count());
        let mut normals = Vec::with_capacity(self.triangle_count());
        let mut meshes: Vec<MeshGpu> = Vec::with_capacity(instances.len());
        let textured = self.features.textures;
        let mut uvs = Vec::with_capacity(if textured { self.triangle_count() } else { 0 });
        for (moves, id, t, mesh) in instances {
            let Some(data) = self.meshes.get(mesh) else {
                continue;
            };
            let first = triangles.len() as u32;
            let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
            for tri in &data.triangles {
                let p = tri.p.map(|p| t.point_from(origin, p));
                let n = tri.n.map(|n| t.normal(n));
                for q in p {
                    lo = lo.min(q);
                    hi = hi.max(q);
                }
                triangles.push(TriangleGpu {
                    p0: p[0].into(),
                    material: tri.material,
                    p1: p[1].into(),
                    object: id.0,
                    p2: p[2].into(),
                    _pad0: 0,
                });
                if textured {
                    let [a, b, c] = tri.uv.map(|v| v.to_array());
                    // Placements are similarities (others are baked into
                    // the mesh), so a tangent turns as a normal does; no
                    // tangent (zero) stays zero, packed as none.
                    let tangents = tri.tangent.map(|v| pack_tangent(t.normal(v.truncate()).extend(v.w)));
                    uvs.push(TriangleUvGpu { uv0: a, uv1: b, uv2: c, tangents, colors: tri.color.map(pack_color) });
                }
                normals.push(TriangleNormalsGpu {
                    n0: n[0].into(),
                    _pad1: 0.0,
                    n1: n[1].into(),
                    _pad2: 0.0,
                    n2: n[2].into(),
                    _pad3: 0.0,
                });
            }
            let count = triangles.len() as u32 - first;
            if count == 0 {
                continue;
            }
            // (Sorted, so a still object's predecessors are still too.)
            match meshes.last_mut() {
                Some(run) if !moves => {
                    run.bmin = Vec3::from(run.bmin).min(lo).into();
                    run.bmax = Vec3::from(run.bmax).max(hi).into();
                    run.count += count;
                }
                _ => meshes.push(MeshGpu { bmin: lo.into(), first, bmax: hi.into(), count }),
            }
        }

        // The environment light last (shared/environment.wgsl finds it there).
        let lights: Vec<LightGpu> = lights.into_iter().map(|l| l.2).chain(self.environment.as_ref().map(|e| e.light_gpu())).collect();
        SceneData {
            light_clusters: light_clusters(&lights),
            spheres: spheres.into_iter().map(|s| s.1).collect(),
            triangles,
            normals,
            meshes,
            materials: self.materials.clone(),
            uvs,
            // Every material's slots, textured scene or not: a generic
            // pipeline (SCENE_TEXTURES on) reads them and finds none.
            material_textures: self.material_textures_gpu(),
            lights,
            background: self.background.into(),
            environment: self.environment_texels.clone(),
            ..Default::default()
        }
    }

    /// A stable hash of what the scene holds as loaded (geometry, normals,
    /// materials, lights, environment, background), packed at the world origin: a baked
    /// volume names its scene by it.
    pub fn content_hash(&self) -> u64 {
        use crate::probes::volume_file::{fnv1a, FNV_START};
        let d = self.pack_at(DVec3::ZERO);
        let mut h = FNV_START;
        h = fnv1a(bytemuck::cast_slice(&d.spheres), h);
        h = fnv1a(bytemuck::cast_slice(&d.triangles), h);
        h = fnv1a(bytemuck::cast_slice(&d.normals), h);
        h = fnv1a(bytemuck::cast_slice(&d.meshes), h);
        h = fnv1a(bytemuck::cast_slice(&d.materials), h);
        h = fnv1a(bytemuck::cast_slice(&d.lights), h);
        h = fnv1a(bytemuck::cast_slice(d.environment.as_slice()), h);
        fnv1a(bytemuck::cast_slice(&d.background), h)
    }

    /// The f64 bounds of every sphere (sphere lights included) and mesh
    /// triangle; `None` for a scene without any.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        let mut grow = |p: DVec3, r: f64| {
            lo = lo.min(p - r);
            hi = hi.max(p + r);
        };
        for (t, s) in self.world.query::<(&Transform, &SphereShape)>().iter() {
            grow(t.translation, f64::from(s.radius));
        }
        for (t, l) in self.world.query::<(&Transform, &Light)>().iter() {
            if let Light::Sphere { radius, .. } = *l {
                grow(t.translation, f64::from(radius));
            }
        }
        for (mesh_lo, mesh_hi) in self.mesh_bounds() {
            grow(mesh_lo, 0.0);
            grow(mesh_hi, 0.0);
        }
        (lo.x <= hi.x).then_some((lo, hi))
    }

    /// The world-space box of each mesh instance that has triangles.
    fn mesh_bounds(&self) -> Vec<(DVec3, DVec3)> {
        let mut out = Vec::new();
        for (t, m) in self.world.query::<(&Transform, &MeshShape)>().iter() {
            let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            for tri in self.meshes.get(m.mesh).map_or(&[][..], |d| &d.triangles) {
                for p in tri.p {
                    let w = t.point(p);
                    lo = lo.min(w);
                    hi = hi.max(w);
                }
            }
            if lo.x <= hi.x {
                out.push((lo, hi));
            }
        }
        out
    }

    /// Spheres `pack` gives the GPU: sphere objects and sphere lights
    /// with a material (the ones rays can hit).
    pub fn sphere_count(&self) -> usize {
        let objects = self.world.query::<(&ObjectId, &Transform, &SphereShape, &MaterialId)>().iter().count();
        let lights = self
            .world
            .query::<(&ObjectId, &LightIndex, &Transform, &Light, &MaterialId)>()
            .iter()
            .filter(|(_, _, _, light, _)| matches!(light, Light::Sphere { .. }))
            .count();
        objects + lights
    }

    /// Whether `pack` gives a flat scene (`SceneData::is_flat`), counted
    /// without packing.
    pub fn is_flat(&self) -> bool {
        self.sphere_count() + self.triangle_count() <= FLAT_LIMIT && !self.features.alpha_mask && !self.features.directional_lights
    }

    /// What a graph is compiled for: the features found at load, with
    /// `flat` as the scene is now (entities added since count).
    pub fn compile_features(&self) -> SceneFeatures {
        SceneFeatures { flat: self.is_flat(), enclosing_lights: self.may_enclose(), ..self.features }
    }

    /// Whether a sphere light may hold a shading point inside it: its
    /// sphere reaches the camera, a sphere object or a mesh's bounds, or
    /// anything moves (conservative: a moving light or object may get
    /// there). Boxes, not triangles: cheap, and false for every shipped
    /// static scene.
    pub fn may_enclose(&self) -> bool {
        let lights: Vec<(DVec3, f64)> = self
            .world
            .query::<(&Transform, &Light)>()
            .iter()
            .filter_map(|(t, l)| match *l {
                Light::Sphere { radius, .. } => Some((t.translation, f64::from(radius))),
                Light::Point { .. } | Light::Directional { .. } => None,
            })
            .collect();
        if lights.is_empty() {
            return false;
        }
        if self.features.motion {
            return true;
        }
        let reaches = |lo: DVec3, hi: DVec3| lights.iter().any(|&(c, r)| c.clamp(lo, hi).distance_squared(c) <= r * r * 1.0001);
        if reaches(self.camera.position, self.camera.position) {
            return true;
        }
        for (t, s) in self.world.query::<(&Transform, &SphereShape)>().iter() {
            let r = DVec3::splat(f64::from(s.radius));
            if reaches(t.translation - r, t.translation + r) {
                return true;
            }
        }
        self.mesh_bounds().into_iter().any(|(lo, hi)| reaches(lo, hi))
    }

    /// Every material's texture slots where they go on the GPU
    /// (`texture_classes`), by material id.
    fn material_textures_gpu(&self) -> Vec<MaterialTexturesGpu> {
        let layout = texture_classes::layout(&self.textures);
        let mut out = vec![MaterialTexturesGpu::default(); self.materials.len()];
        for (gpu, m) in out.iter_mut().zip(&self.material_textures) {
            // (slot, uv transform rows) of `s`, its wrap modes put at `shift`.
            let place = |s: &TextureSlot, shift: u32, wrap: &mut u32| {
                *wrap |= (s.wrap[0] << shift) | (s.wrap[1] << (shift + 2));
                let row = |r: [f32; 3]| [r[0], r[1], r[2], 0.0];
                (layout.slot(s.texture), row(s.transform[0]), row(s.transform[1]))
            };
            if let Some(s) = &m.base_color {
                (gpu.base, gpu.base_u, gpu.base_v) = place(s, 0, &mut gpu.wrap);
            }
            if let Some((cutoff, factor)) = m.alpha_mask {
                // factor x texture >= cutoff, as texture >= cutoff / factor
                // (above 1: never there).
                gpu.alpha_threshold = if factor > 0.0 { cutoff / factor } else { 2.0 };
            }
            if let Some(s) = &m.emissive {
                (gpu.emissive, gpu.emissive_u, gpu.emissive_v) = place(s, 4, &mut gpu.wrap);
            }
            if let Some(s) = &m.metallic_roughness {
                (gpu.metallic_roughness, gpu.metallic_roughness_u, gpu.metallic_roughness_v) = place(s, 8, &mut gpu.wrap);
            }
            if let Some((s, scale)) = &m.normal {
                (gpu.normal, gpu.normal_u, gpu.normal_v) = place(s, 12, &mut gpu.wrap);
                gpu.normal_scale = *scale;
            }
        }
        out
    }

    /// Triangles over all mesh instances (quads count two).
    pub fn triangle_count(&self) -> usize {
        self.world
            .query::<&MeshShape>()
            .iter()
            .filter_map(|m| self.meshes.get(m.mesh))
            .map(|d| d.triangles.len())
            .sum()
    }
}

fn sphere(id: ObjectId, center: Vec3, radius: f32, material: u32, light: i32) -> SphereGpu {
    SphereGpu {
        center: center.into(),
        radius,
        material,
        light,
        object: id.0,
        _pad: 0,
    }
}

fn light_gpu(position: Vec3, radius: f32, color: Vec3, kind: u32) -> LightGpu {
    LightGpu {
        position: position.into(),
        radius,
        color: color.into(),
        kind,
        spot: NO_SPOT,
    }
}

/// The spot factor of a light without a cone: 1 everywhere.
const NO_SPOT: [f32; 4] = [0.0, 0.0, 0.0, 1.0];
