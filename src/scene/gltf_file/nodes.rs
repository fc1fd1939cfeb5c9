//! The node hierarchy of a glTF file's scene flattened: each node's world
//! matrix composed in f64 (so an asset far from the origin keeps its
//! precision), with the meshes, point lights and cameras it places.

use glam::{DMat4, DQuat, DVec3, Vec3};
use gltf::khr_lights_punctual::Kind;

use super::{GltfCamera, Instance, PointLight, LUMENS_PER_WATT};

/// What the scene's nodes place.
pub(crate) struct Placed {
    pub instances: Vec<Instance>,
    pub lights: Vec<PointLight>,
    pub cameras: Vec<GltfCamera>,
    pub warnings: Vec<String>,
}

/// Walks the default scene (the first when the file names none; every
/// root node when it has no scenes).
pub(crate) fn walk(doc: &gltf::Document) -> Result<Placed, String> {
    let count = doc.nodes().len();
    let mut parent = vec![None; count];
    for node in doc.nodes() {
        for child in node.children() {
            if let Some(p) = parent[child.index()].replace(node.index()) {
                return Err(format!("nodes[{}]: is a child of both nodes[{p}] and nodes[{}]; a glTF node has at most one parent", child.index(), node.index()));
            }
        }
    }
    // With one parent each, a chain of parents that comes back to a node of
    // the same walk is a cycle (each node is walked once: O(nodes)).
    let mut state = vec![0u8; count]; // 0 unseen, 1 on this walk, 2 done
    for start in 0..count {
        let mut walk = Vec::new();
        let mut at = Some(start);
        while let Some(i) = at {
            match state[i] {
                2 => break,
                1 => return Err(format!("nodes[{i}]: is its own ancestor (the node hierarchy has a cycle)")),
                _ => {
                    state[i] = 1;
                    walk.push(i);
                    at = parent[i];
                }
            }
        }
        for i in walk {
            state[i] = 2;
        }
    }
    let (roots, scene_at): (Vec<usize>, String) = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(s) => (s.nodes().map(|n| n.index()).collect(), format!("scenes[{}]", s.index())),
        None => ((0..count).filter(|&i| parent[i].is_none()).collect(), "the root nodes".into()),
    };
    for (k, &r) in roots.iter().enumerate() {
        if let Some(p) = parent[r] {
            return Err(format!("{scene_at}.nodes[{k}]: nodes[{r}] is a child of nodes[{p}], so it cannot be a root of the scene"));
        }
    }
    let nodes: Vec<gltf::Node> = doc.nodes().collect();
    let mut placed = Placed { instances: Vec::new(), lights: Vec::new(), cameras: Vec::new(), warnings: Vec::new() };
    let (mut orthographic, mut skinned) = (0, 0);
    let mut stack: Vec<(usize, DMat4)> = roots.iter().rev().map(|&r| (r, DMat4::IDENTITY)).collect();
    while let Some((i, parent_matrix)) = stack.pop() {
        let node = &nodes[i];
        let world = parent_matrix * local_matrix(node)?;
        if !world.is_finite() {
            return Err(format!("nodes[{i}]: its world transform is not finite (its matrix or a parent's overflows)"));
        }
        if let Some(mesh) = node.mesh() {
            placed.instances.push(Instance { mesh: mesh.index(), matrix: world });
            skinned += usize::from(node.skin().is_some());
        }
        if let Some(light) = node.light() {
            let at = format!("extensions.KHR_lights_punctual.lights[{}]", light.index());
            match light.kind() {
                Kind::Point => placed.lights.push(point_light(&light, world, &at)?),
                Kind::Spot { inner_cone_angle, outer_cone_angle } => {
                    let direction = world.transform_vector3(DVec3::NEG_Z).as_vec3();
                    let spot = crate::scene::validate::spot_cone(direction, inner_cone_angle, outer_cone_angle).ok_or_else(|| {
                        format!("{at}.spot: the cone needs 0 <= innerConeAngle < outerConeAngle <= pi/2, got {inner_cone_angle} and {outer_cone_angle} (or the node collapses its direction)")
                    })?;
                    placed.lights.push(PointLight { spot: Some(spot), ..point_light(&light, world, &at)? });
                }
                Kind::Directional => {
                    let direction = world.transform_vector3(DVec3::NEG_Z).normalize_or_zero().as_vec3();
                    if direction == Vec3::ZERO {
                        return Err(format!("nodes[{i}]: places {at} with a transform that collapses its direction"));
                    }
                    placed.lights.push(PointLight { directional: Some(direction), ..point_light(&light, world, &at)? });
                }
            }
        }
        if let Some(camera) = node.camera() {
            match camera.projection() {
                gltf::camera::Projection::Perspective(p) => {
                    let yfov = f64::from(p.yfov());
                    if !(yfov > 0.0 && yfov < std::f64::consts::PI) {
                        return Err(format!("cameras[{}].perspective.yfov: {yfov} radians is outside (0, pi)", camera.index()));
                    }
                    let position = world.transform_point3(DVec3::ZERO);
                    let forward = world.transform_vector3(DVec3::NEG_Z).normalize_or_zero();
                    let up = world.transform_vector3(DVec3::Y);
                    if forward == DVec3::ZERO || up.cross(forward).length_squared() == 0.0 {
                        return Err(format!("nodes[{i}]: places cameras[{}] with a transform that collapses its view direction", camera.index()));
                    }
                    placed.cameras.push(GltfCamera { position, target: position + forward, up, vfov_deg: yfov.to_degrees() });
                }
                gltf::camera::Projection::Orthographic(_) => orthographic += 1,
            }
        }
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child.index(), world));
        }
    }
    let mut say = |n: usize, what: &str| {
        if n > 0 {
            placed.warnings.push(format!("{n} {what}"));
        }
    };
    say(orthographic, "orthographic camera(s) skipped: glint's cameras are perspective");
    say(skinned, "skinned mesh instance(s) shown unskinned, in their mesh's own pose");
    Ok(placed)
}

/// A node's own transform: its matrix, or T x R x S with the rotation
/// normalised.
fn local_matrix(node: &gltf::Node) -> Result<DMat4, String> {
    let at = format!("nodes[{}]", node.index());
    let m = match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from))),
        gltf::scene::Transform::Decomposed { translation, rotation, scale } => {
            let q = DQuat::from_array(rotation.map(f64::from));
            if !(q.is_finite() && q.length() > 1e-6) {
                return Err(format!("{at}.rotation: {rotation:?} is not a rotation (glTF wants a unit quaternion)"));
            }
            DMat4::from_scale_rotation_translation(DVec3::from_array(scale.map(f64::from)), q.normalize(), DVec3::from_array(translation.map(f64::from)))
        }
    };
    if !m.is_finite() {
        return Err(format!("{at}: its transform is not finite"));
    }
    Ok(m)
}

/// A point light at the node's origin: candela to W/sr by 683 lm/W.
fn point_light(light: &gltf::khr_lights_punctual::Light, world: DMat4, at: &str) -> Result<PointLight, String> {
    let color = Vec3::from_array(light.color());
    if !(color.is_finite() && color.min_element() >= 0.0) {
        return Err(format!("{at}.color: {:?} is not a colour (finite, >= 0)", light.color()));
    }
    let candela = light.intensity();
    if !(candela.is_finite() && candela >= 0.0) {
        return Err(format!("{at}.intensity: {candela} is not a finite value >= 0"));
    }
    Ok(PointLight { position: world.transform_point3(DVec3::ZERO), intensity: color * (candela / LUMENS_PER_WATT), spot: None, directional: None })
}
