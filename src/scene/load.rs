//! Scene file → `Scene`: parse the RON, check every value, load the OBJ
//! meshes, and spawn the entities.

use std::path::{Path, PathBuf};

use glam::{DVec3, EulerRot, Quat, Vec2, Vec3};
use hecs::{EntityBuilder, World};
use ron::extensions::Extensions;

use super::features::SceneFeatures;
use super::gltf_file::{GltfFile, GltfLoaded};
use super::gpu_types::MaterialGpu;
use super::locate::{Locator, Step};
use super::obj;
use super::environment::Environment;
use super::schema::{EnvironmentDesc, LightDesc, ObjectDesc, SceneDesc};
use super::validate::{self, Ctx};
use super::world::{
    BasePosition, Camera, Light, LightIndex, LocalTriangle, MaterialId, MaterialTextures, MeshData, MeshShape,
    Motion, ObjectId, Scene, SphereShape, SpotCone, TextureImage, TextureSlot, Transform,
};
use crate::error::{ron_error, UserError};

/// Used by OBJ faces that have neither an MTL material nor a `material:`.
const DEFAULT_MATERIAL: MaterialGpu = MaterialGpu::thesis([0.8; 3], 0.0, [0.0; 3], 1.0);

/// The file kinds `load` opens: a RON scene, or an OBJ or glTF file
/// opened as a scene of its own.
pub const SCENE_EXTENSIONS: [&str; 4] = ["ron", "obj", "gltf", "glb"];

/// Whether `load` opens `path`, by its extension.
pub fn opens(path: &Path) -> bool {
    path.extension().is_some_and(|e| SCENE_EXTENSIONS.iter().any(|x| e.eq_ignore_ascii_case(x)))
}

/// Reads, parses and checks a scene file; OBJ and glTF paths are relative
/// to its folder. An `.obj`, `.gltf` or `.glb` file opens as a scene of its
/// own (`obj_scene`, `gltf_scene`).
pub fn load(path: &Path) -> Result<Scene, UserError> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("obj") => return super::obj_scene::open_obj(path),
        Some("gltf" | "glb") => return super::gltf_scene::open_gltf(path),
        _ => {}
    }
    let text = crate::error::read_user_text(path, "scene file")?;
    parse(&text, path)
}

/// Like `load`, from text; `path` names the file in messages and OBJ paths
/// are resolved relative to its folder.
pub fn parse(text: &str, path: &Path) -> Result<Scene, UserError> {
    parse_with(text, path, Vec::new())
}

/// Like `parse`, with glTF files already read (resolved path, file).
pub(crate) fn parse_with(text: &str, path: &Path, preloaded: Vec<(PathBuf, GltfFile)>) -> Result<Scene, UserError> {
    // A UTF-8 byte order mark is not RON; editors may write one.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    // implicit_some: optional fields are written bare (`motion: Orbit(..)`).
    let desc: SceneDesc = ron::Options::default()
        .with_default_extension(Extensions::IMPLICIT_SOME)
        .from_str(text)
        .map_err(|e| ron_error(path, &e))?;
    let loc = Locator::new(path, text);
    let mut builder = Builder::new(&loc);
    for (path, file) in preloaded {
        builder.gltf_cache.push(GltfLoaded::new(path, file));
    }
    let mut scene = builder.build(&desc)?;
    // Start at t = 0, so a scene that is never animated still shows movers
    // where their motion puts them.
    scene.animate(0.0);
    Ok(scene)
}

pub(super) struct Builder<'a, 'l> {
    pub(super) loc: &'a Locator<'l>,
    names: Vec<&'a str>,
    pub(super) materials: Vec<MaterialGpu>,
    pub(super) meshes: Vec<MeshData>,
    /// OBJ meshes already loaded: (resolved path, material override, mesh index).
    obj_cache: Vec<(PathBuf, Option<u32>, usize)>,
    /// glTF files already read, in the order first met.
    pub(super) gltf_cache: Vec<GltfLoaded>,
    /// Point, spot and directional lights that glTF files place
    /// (position, light, a spot light's cone), spawned after the scene's
    /// own lights.
    pub(super) gltf_lights: Vec<(DVec3, Light, Option<SpotCone>)>,
    /// Per material id, its textures (filled up to the last textured one).
    pub(super) material_textures: Vec<MaterialTextures>,
    pub(super) textures: Vec<TextureImage>,
    /// Image files read for OBJ materials: (path, read as data (linear),
    /// scene texture).
    image_files: Vec<(PathBuf, bool, usize)>,
    /// The glTF files' perspective cameras, placed.
    pub(super) gltf_cameras: Vec<Camera>,
    default_material: Option<u32>,
    pub(super) world: World,
}

impl<'a, 'l> Builder<'a, 'l> {
    fn new(loc: &'a Locator<'l>) -> Self {
        Builder {
            loc,
            names: Vec::new(),
            materials: Vec::new(),
            meshes: Vec::new(),
            obj_cache: Vec::new(),
            gltf_cache: Vec::new(),
            gltf_lights: Vec::new(),
            gltf_cameras: Vec::new(),
            material_textures: Vec::new(),
            textures: Vec::new(),
            image_files: Vec::new(),
            default_material: None,
            world: World::new(),
        }
    }

    fn build(mut self, desc: &'a SceneDesc) -> Result<Scene, UserError> {
        let loc = self.loc;
        validate::camera(&desc.camera, loc)?;
        let background = validate::background(desc.background, loc)?;
        let (environment, environment_file) = match &desc.environment {
            Some(e) => {
                let (env, file) = self.environment(e, background)?;
                (Some(env), file)
            }
            None => (None, None),
        };
        for (i, (name, m)) in desc.materials.0.iter().enumerate() {
            validate::material(i, name, m, loc)?;
            if self.names.contains(&name.as_str()) {
                let at = [Step::Field("materials"), Step::Item(i)];
                return Err(loc.err(&at, format!("material \"{name}\" is defined twice")));
            }
            self.names.push(name);
            self.materials.push(match m.metallic {
                Some(metallic) => MaterialGpu::metal_rough(m.albedo, metallic, m.roughness, m.emission),
                None => MaterialGpu::thesis(m.albedo, m.specular, m.emission, m.roughness),
            });
        }

        let mut features = SceneFeatures::default();
        for (i, o) in desc.objects.iter().enumerate() {
            let at = vec![Step::Field("objects"), Step::Item(i)];
            let ctx = Ctx::new(loc, at, format!("objects[{i}] ({})", o.kind()));
            validate::object(&ctx, o)?;
            if let ObjectDesc::Gltf { path, translate, scale, rotate_deg } = o {
                self.gltf_object(&ctx, i, path, (*translate, *scale, *rotate_deg), DVec3::from_array(desc.camera.position))?;
                features.meshes = true;
                continue;
            }
            let mut e = EntityBuilder::new();
            e.add(ObjectId(i as u32));
            let mut translation = DVec3::ZERO;
            match o {
                ObjectDesc::Quad { vertices, material } => {
                    let material = self.material(&ctx, material)?;
                    let (mesh, at) = self.quad(&ctx, vertices, material)?;
                    e.add(Transform::from_translation(at)).add(MeshShape { mesh });
                    features.meshes = true;
                }
                ObjectDesc::Sphere {
                    center,
                    radius,
                    material,
                    ..
                } => {
                    translation = DVec3::from_array(*center);
                    let material = self.material(&ctx, material)?;
                    e.add(Transform::from_translation(translation))
                        .add(SphereShape { radius: *radius })
                        .add(MaterialId(material));
                    features.spheres = true;
                }
                ObjectDesc::Mesh {
                    path,
                    translate,
                    scale,
                    rotate_deg,
                    material,
                    ..
                } => {
                    let material = match material {
                        Some(name) => Some(self.material(&ctx, name)?),
                        None => None,
                    };
                    let mesh = self.obj_mesh(&ctx, path, material)?;
                    self.check_mesh_extent(&ctx, mesh, f64::from(*scale))?;
                    translation = DVec3::from_array(*translate);
                    let rotation = rotation(*rotate_deg);
                    e.add(Transform {
                        translation,
                        rotation,
                        scale: *scale,
                    })
                    .add(MeshShape { mesh });
                    features.meshes = true;
                }
                // Spawned above, one entity per instance.
                ObjectDesc::Gltf { .. } => {}
            }
            let camera = DVec3::from_array(desc.camera.position);
            match o {
                ObjectDesc::Quad { vertices, .. } => {
                    for v in vertices {
                        ctx.near("vertices", DVec3::from_array(*v), camera)?;
                    }
                }
                ObjectDesc::Sphere { radius, .. } => {
                    ctx.near("center", translation, camera)?;
                    ctx.resolvable(translation, *radius, camera)?;
                }
                ObjectDesc::Mesh { .. } => ctx.near("translate", translation, camera)?,
                ObjectDesc::Gltf { .. } => {}
            }
            if let Some(m) = o.motion() {
                e.add(validate::motion(&ctx, m)?)
                    .add(BasePosition(translation));
                features.motion = true;
            }
            self.world.spawn(e.build());
        }

        for (j, l) in desc.lights.iter().enumerate() {
            let at = vec![Step::Field("lights"), Step::Item(j)];
            let ctx = Ctx::new(loc, at, format!("lights[{j}] ({})", l.kind()));
            validate::light(&ctx, l)?;
            let mut e = EntityBuilder::new();
            e.add(ObjectId((desc.objects.len() + j) as u32))
                .add(LightIndex(j as u32));
            let translation = match *l {
                LightDesc::SphereLight {
                    center,
                    radius,
                    radiance,
                    ..
                } => {
                    // Rays can hit a sphere light: it gets an emissive,
                    // non-reflecting material of its own.
                    let material = self.push_material(MaterialGpu::thesis([0.0; 3], 0.0, radiance, 1.0));
                    let radiance = Vec3::from_array(radiance);
                    e.add(Light::Sphere { radius, radiance })
                        .add(MaterialId(material));
                    features.area_lights = true;
                    DVec3::from_array(center)
                }
                LightDesc::PointLight {
                    position,
                    intensity,
                    ..
                } => {
                    e.add(Light::Point {
                        intensity: Vec3::from_array(intensity),
                    });
                    features.point_lights = true;
                    DVec3::from_array(position)
                }
                LightDesc::DirectionalLight { direction, irradiance } => {
                    let direction = validate::unit(Vec3::from_array(direction)).ok_or_else(|| ctx.err("direction", "`direction` has no length"))?;
                    e.add(Light::Directional { irradiance: Vec3::from_array(irradiance), direction });
                    features.point_lights = true;
                    features.directional_lights = true;
                    // No place: the camera's, for whatever asks one.
                    DVec3::from_array(desc.camera.position)
                }
                LightDesc::SpotLight { position, direction, intensity, inner_deg, outer_deg, .. } => {
                    e.add(Light::Point { intensity: Vec3::from_array(intensity) });
                    let cone = validate::spot_cone(Vec3::from_array(direction), inner_deg.to_radians(), outer_deg.to_radians())
                        .ok_or_else(|| ctx.err("outer_deg", "not a cone"))?;
                    e.add(cone);
                    features.point_lights = true;
                    features.spot_lights = true;
                    DVec3::from_array(position)
                }
            };
            let field = if matches!(l, LightDesc::SphereLight { .. }) { "center" } else { "position" };
            ctx.near(field, translation, DVec3::from_array(desc.camera.position))?;
            if let LightDesc::SphereLight { radius, .. } = l {
                ctx.resolvable(translation, *radius, DVec3::from_array(desc.camera.position))?;
            }
            e.add(Transform::from_translation(translation));
            if let Some(m) = l.motion() {
                let motion: Motion = validate::motion(&ctx, m)?;
                e.add(motion).add(BasePosition(translation));
                features.motion = true;
            }
            self.world.spawn(e.build());
        }

        let gltf_lights = std::mem::take(&mut self.gltf_lights);
        for (k, &(position, light, spot)) in gltf_lights.iter().enumerate() {
            let j = desc.lights.len() + k;
            let e = self.world.spawn((
                ObjectId((desc.objects.len() + j) as u32),
                LightIndex(j as u32),
                light,
                Transform::from_translation(position),
            ));
            features.directional_lights |= matches!(light, Light::Directional { .. });
            if let Some(cone) = spot {
                let _ = self.world.insert_one(e, cone);
                features.spot_lights = true;
            }
            features.point_lights = true;
        }
        let used = self.used_material_features();
        features.specular = used.specular;
        features.emissive = used.emissive;
        features.metal_rough = used.metal_rough;
        features.coats = used.coats;
        let triangles = || self.meshes.iter().flat_map(|m| &m.triangles);
        let textures_of = |t: &LocalTriangle| self.material_textures.get(t.material as usize);
        let used = |f: &dyn Fn(&MaterialTextures) -> bool| triangles().any(|t| textures_of(t).is_some_and(f));
        features.vertex_colors = triangles().any(|t| t.color != [Vec3::ONE; 3]);
        features.vertex_tangents = triangles().any(|t| t.tangent != [glam::Vec4::ZERO; 3] && textures_of(t).is_some_and(|m| m.normal.is_some()));
        features.textures =
            features.vertex_colors || used(&|m| m.base_color.is_some() || m.emissive.is_some() || m.metallic_roughness.is_some() || m.normal.is_some());
        features.alpha_mask = used(&|m| m.alpha_mask.is_some());
        features.single_sided = triangles().any(|t| self.materials.get(t.material as usize).is_some_and(MaterialGpu::is_single_sided));
        features.texture_classes = super::texture_classes::layout(&self.textures).layers.map(|n| n > 0);
        features.texture_transforms = used(&|m| {
            let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
            [m.base_color, m.emissive, m.metallic_roughness, m.normal.map(|n| n.0)].iter().flatten().any(|s| s.transform != identity)
        });
        features.lights = u32::try_from(desc.lights.len() + gltf_lights.len() + usize::from(environment.is_some())).unwrap_or(u32::MAX);
        features.environment = environment.is_some();
        // The passes that shade point lights shade it (one sample each).
        features.point_lights |= environment.is_some();
        let c = &desc.camera;
        Ok(Scene {
            world: self.world,
            camera: Camera {
                position: DVec3::from_array(c.position),
                target: DVec3::from_array(c.target),
                up: Vec3::from_array(c.up),
                vfov_deg: c.vfov_deg,
            },
            background,
            environment_texels: std::sync::Arc::new(environment.as_ref().map(Environment::texels).unwrap_or_default()),
            environment,
            features,
            path: loc.path.to_path_buf(),
            cameras: self.gltf_cameras,
            mesh_files: {
                let mut files: Vec<PathBuf> = self.obj_cache.iter().map(|(p, _, _)| p.clone()).collect();
                for g in &self.gltf_cache {
                    files.push(g.path.clone());
                    files.extend(g.file.files.iter().cloned());
                }
                files.extend(self.image_files.iter().map(|(p, _, _)| p.clone()));
                files.extend(environment_file.clone());
                files.dedup();
                files
            },
            meshes: self.meshes,
            materials: self.materials,
            material_textures: self.material_textures,
            textures: self.textures,
        })
    }

    /// The path a scene names, resolved against the scene file's folder,
    /// or an error saying why it is not a readable file.
    pub(super) fn resolve(&self, ctx: &Ctx, rel: &str, what: &str, give: &str) -> Result<PathBuf, UserError> {
        let dir = self.loc.path.parent().unwrap_or(Path::new(""));
        let resolved = dir.join(rel);
        match std::fs::metadata(&resolved) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                Err(ctx.err("path", format_args!("{what} file \"{rel}\" not found (looked for {})", resolved.display())))
            }
            Err(e) => Err(ctx.err("path", format_args!("{what} file \"{rel}\" cannot be opened (looked for {}): {e}", resolved.display()))),
            Ok(m) if m.is_dir() => Err(ctx.err("path", format_args!("{what} file \"{rel}\" is a directory ({}); give {give}", resolved.display()))),
            Ok(m) if !m.is_file() => {
                Err(ctx.err("path", format_args!("{what} file \"{rel}\" is not a regular file ({}: a device, FIFO or socket); give {give}", resolved.display())))
            }
            Ok(_) => Ok(resolved),
        }
    }

    /// The scene's environment light, its map read and checked, and the
    /// map's file (hot reload watches it).
    fn environment(&self, e: &EnvironmentDesc, background: Vec3) -> Result<(Environment, Option<PathBuf>), UserError> {
        let (scale, rotation) = validate::environment(e, background, self.loc)?;
        let Some(rel) = &e.path else {
            return Ok((Environment::constant(scale, rotation), None));
        };
        let ctx = Ctx::new(self.loc, vec![Step::Field("environment")], "environment".into());
        let path = self.resolve(&ctx, rel, "environment map", "an .exr or .pfm image")?;
        let (env, note) = super::environment::load_map(&path, scale, rotation).map_err(|m| ctx.err("path", format_args!("\"{rel}\": {m}")))?;
        if let Some(note) = note {
            eprintln!("glint: {}: {note}", path.display());
        }
        Ok((env, Some(path)))
    }

    /// Mesh `mesh`, scaled, must fit in `validate::MAX_RANGE`.
    fn check_mesh_extent(&self, ctx: &Ctx, mesh: usize, scale: f64) -> Result<(), UserError> {
        self.check_reach(ctx, self.reach(mesh), scale)
    }

    /// How far mesh `mesh` reaches from its origin along any axis.
    pub(super) fn reach(&self, mesh: usize) -> f64 {
        self.meshes.get(mesh).map_or(0.0, |m| m.triangles.iter().flat_map(|t| t.p).map(|p| f64::from(p.abs().max_element())).fold(0.0, f64::max))
    }

    /// A mesh reaching `local` from its origin, scaled, must fit in
    /// `validate::MAX_RANGE`.
    pub(super) fn check_reach(&self, ctx: &Ctx, local: f64, scale: f64) -> Result<(), UserError> {
        let extent = local * scale;
        if extent > validate::MAX_RANGE {
            return Err(ctx.err(
                "scale",
                format_args!(
                    "the mesh reaches {} from its origin; scaled by {scale:e} that is {}, beyond glint's range of {:e} (f32 on the GPU)",
                    crate::error::figure(local),
                    crate::error::figure(extent),
                    validate::MAX_RANGE
                ),
            ));
        }
        Ok(())
    }

    pub(super) fn push_material(&mut self, m: MaterialGpu) -> u32 {
        self.materials.push(m);
        (self.materials.len() - 1) as u32
    }

    /// The id of a named material, or an error listing the names defined.
    fn material(&self, ctx: &Ctx, name: &str) -> Result<u32, UserError> {
        if let Some(i) = self.names.iter().position(|n| *n == name) {
            return Ok(i as u32);
        }
        let defined = if self.names.is_empty() {
            "the scene defines no materials".to_string()
        } else {
            format!("the scene defines: {}", self.names.join(", "))
        };
        Err(ctx.err(
            "material",
            format_args!("unknown material \"{name}\"; {defined}"),
        ))
    }

    /// Two triangles (v0 v1 v2) and (v0 v2 v3) with the quad's flat normal,
    /// in a mesh local to v0 (returned: the quad's translation), so a quad
    /// far from the origin keeps its f64 precision.
    fn quad(
        &mut self,
        ctx: &Ctx,
        vertices: &[[f64; 3]],
        material: u32,
    ) -> Result<(usize, DVec3), UserError> {
        let v: Vec<DVec3> = vertices.iter().map(|&p| DVec3::from_array(p)).collect();
        let n = validate::quad_normal(&v)
            .ok_or_else(|| ctx.err("vertices", "the quad is degenerate (zero area)"))?;
        let at = v[0];
        let local: Vec<Vec3> = v.iter().map(|&p| (p - at).as_vec3()).collect();
        let tri = |a: usize, b: usize, c: usize| LocalTriangle::plain([local[a], local[b], local[c]], [n; 3], [Vec2::ZERO; 3], material);
        self.meshes.push(MeshData {
            triangles: vec![tri(0, 1, 2), tri(0, 2, 3)],
        });
        Ok((self.meshes.len() - 1, at))
    }

    /// Loads (once per file and material override) the OBJ at `rel`, relative
    /// to the scene file's folder.
    fn obj_mesh(
        &mut self,
        ctx: &Ctx,
        rel: &str,
        material: Option<u32>,
    ) -> Result<usize, UserError> {
        let dir = self.loc.path.parent().unwrap_or(Path::new(""));
        let cached = self
            .obj_cache
            .iter()
            .find(|(p, m, _)| *p == dir.join(rel) && *m == material);
        if let Some(&(_, _, mesh)) = cached {
            return Ok(mesh);
        }
        let resolved = self.resolve(ctx, rel, "mesh", "an .obj file")?;
        let file = obj::read(&resolved, material.is_none()).map_err(|e| ctx.err("path", e))?;
        // An override replaces the MTL materials, which are then not added.
        let base = self.materials.len() as u32;
        if material.is_none() {
            self.materials.extend_from_slice(&file.materials);
        }
        if material.is_none() {
            // Every image the MTL names, decoded on every core first, in the
            // order the loops below take them (so textures keep their order).
            let wanted: Vec<(&Path, bool)> = file
                .diffuse_maps
                .iter()
                .flatten()
                .map(|(_, image)| (image.as_path(), false))
                .chain(file.normal_maps.iter().flatten().map(|(_, image, _)| (image.as_path(), true)))
                .collect();
            self.prefetch_images(&wanted);
            for (k, map) in file.diffuse_maps.iter().enumerate() {
                let Some((name, image)) = map else { continue };
                let texture = self.image_file(image).map_err(|e| {
                    ctx.err("path", format_args!("OBJ file {}: material \"{name}\": map_Kd {}: {e}", resolved.display(), image.display()))
                })?;
                let id = base as usize + k;
                if self.material_textures.len() <= id {
                    self.material_textures.resize(id + 1, MaterialTextures::default());
                }
                self.material_textures[id].base_color = Some(TextureSlot { texture, wrap: [0, 0], transform: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] });
            }
            for (k, map) in file.normal_maps.iter().enumerate() {
                let Some((name, image, scale)) = map else { continue };
                let texture = self.image_file_as(image, true).map_err(|e| {
                    ctx.err("path", format_args!("OBJ file {}: material \"{name}\": normal map {}: {e}", resolved.display(), image.display()))
                })?;
                let id = base as usize + k;
                if self.material_textures.len() <= id {
                    self.material_textures.resize(id + 1, MaterialTextures::default());
                }
                self.material_textures[id].normal = Some((TextureSlot { texture, wrap: [0, 0], transform: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] }, *scale));
            }
        }
        let mut triangles = Vec::with_capacity(file.triangles.len());
        for t in &file.triangles {
            let id = match (material, t.material) {
                (Some(m), _) => m,
                (None, Some(m)) => base + m as u32,
                (None, None) => self.default_material(),
            };
            triangles.push(LocalTriangle::plain(t.p, t.n, t.uv, id));
        }
        self.meshes.push(MeshData { triangles });
        let mesh = self.meshes.len() - 1;
        self.obj_cache.push((resolved, material, mesh));
        Ok(mesh)
    }

    /// The scene texture of an image file used as colour (sRGB), read once
    /// per file.
    fn image_file(&mut self, path: &Path) -> Result<usize, String> {
        self.image_file_as(path, false)
    }

    /// The scene texture of an image file used as colour or, `linear`, as
    /// data (normals): read once per file and use.
    fn image_file_as(&mut self, path: &Path, linear: bool) -> Result<usize, String> {
        if let Some(&(_, _, t)) = self.image_files.iter().find(|(p, l, _)| p == path && *l == linear) {
            return Ok(t);
        }
        let image = read_image(path, linear)?;
        self.textures.push(image);
        self.image_files.push((path.to_path_buf(), linear, self.textures.len() - 1));
        Ok(self.textures.len() - 1)
    }

    /// Reads the image files of `wanted` (path, use) not read yet into the
    /// scene's textures, in that order, decoding on every core; one that
    /// cannot be read is left for `image_file_as` to report where it is used.
    fn prefetch_images(&mut self, wanted: &[(&Path, bool)]) {
        let mut new: Vec<(&Path, bool)> = Vec::new();
        for &(path, linear) in wanted {
            if !new.contains(&(path, linear)) && !self.image_files.iter().any(|(p, l, _)| p == path && *l == linear) {
                new.push((path, linear));
            }
        }
        crate::batches::in_batches(&new, |&(path, linear)| read_image(path, linear), |&(path, linear), image| {
            if let Ok(image) = image {
                self.textures.push(image);
                self.image_files.push((path.to_path_buf(), linear, self.textures.len() - 1));
            }
        });
    }

    fn default_material(&mut self) -> u32 {
        match self.default_material {
            Some(id) => id,
            None => {
                let id = self.push_material(DEFAULT_MATERIAL);
                self.default_material = Some(id);
                id
            }
        }
    }

    /// What the materials that objects use have; sphere lights' own
    /// materials do not count.
    fn used_material_features(&mut self) -> UsedMaterials {
        let mut used = vec![false; self.materials.len()];
        let spheres = self
            .world
            .query_mut::<(&MaterialId, &SphereShape)>()
            .into_iter()
            .map(|(m, _)| m.0);
        let triangles = self
            .meshes
            .iter()
            .flat_map(|m| &m.triangles)
            .map(|t| t.material);
        for id in spheres.chain(triangles) {
            if let Some(u) = used.get_mut(id as usize) {
                *u = true;
            }
        }
        let mut flags = UsedMaterials::default();
        for (m, _) in self.materials.iter().zip(&used).filter(|(_, u)| **u) {
            flags.specular |= m.specular > 0.0;
            flags.emissive |= m.emission.iter().any(|&e| e > 0.0);
            flags.metal_rough |= m.is_metal_rough();
            flags.coats |= m.is_coat();
        }
        flags
    }
}

/// What the materials objects use have (`SceneFeatures`).
#[derive(Default)]
struct UsedMaterials {
    specular: bool,
    emissive: bool,
    metal_rough: bool,
    coats: bool,
}

/// A RON object's rotation: degrees about x, then y, then z.
/// An image file as a texture: colour (sRGB) or, `linear`, data.
fn read_image(path: &Path, linear: bool) -> Result<TextureImage, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read it: {e}"))?;
    let mut image = TextureImage::decode(&bytes)?;
    image.linear = linear;
    Ok(image)
}

fn rotation(rotate_deg: [f32; 3]) -> Quat {
    let [x, y, z] = rotate_deg.map(f32::to_radians);
    Quat::from_euler(EulerRot::XYZ, x, y, z)
}
