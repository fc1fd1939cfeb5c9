// Scene buffers (mirrors src/scene/gpu_types.rs). Counts live in `frame`.
#import frame

// Sphere and Triangle are read as whole vec4s: each load of a member is a
// loop over the SIMD lanes on CPU drivers (lavapipe), so fewer, wider
// members are faster; the layout is that of src/scene/gpu_types.rs.
// geo = (center, radius); ids = (material, light as i32 bits, object, _).
struct Sphere {
    geo: vec4f,
    ids: vec4u,
}

// What intersection reads (48 bytes); shading normals live apart.
// p0 = (p0, material bits), p1 = (p1, object bits), p2 = (p2, _).
struct Triangle {
    p0: vec4f,
    p1: vec4f,
    p2: vec4f,
}

struct TriangleNormals {
    n0: vec3f,
    _pad1: f32,
    n1: vec3f,
    _pad2: f32,
    n2: vec3f,
    _pad3: f32,
}

struct Mesh {
    bmin: vec3f,
    first: u32,
    bmax: vec3f,
    count: u32,
}

struct Material {
    albedo: vec3f,
    specular: f32,
    emission: vec3f,
    roughness: f32,
}

const LIGHT_POINT: u32 = 0u;
const LIGHT_SPHERE: u32 = 1u;

struct Light {
    position: vec3f,
    radius: f32,
    color: vec3f,
    kind: u32,
}

@group(1) @binding(1) var<storage, read> scene_spheres: array<Sphere>;
@group(1) @binding(2) var<storage, read> scene_triangles: array<Triangle>;
@group(1) @binding(3) var<storage, read> scene_meshes: array<Mesh>;
@group(1) @binding(4) var<storage, read> scene_materials: array<Material>;
@group(1) @binding(5) var<storage, read> scene_lights: array<Light>;
@group(1) @binding(8) var<storage, read> scene_normals: array<TriangleNormals>;

fn is_emissive(m: Material) -> bool {
    return max(m.emission.x, max(m.emission.y, m.emission.z)) > 0.0;
}

// gbuf_id's object (y) where the pixel's ray hit nothing (as NO_HIT in
// intersect.wgsl).
const NO_OBJECT: u32 = 0xffffffffu;

// Whether a G-buffer id (material, object) is a surface that light falls
// on: a hit, and not an emitter (those show their own emission).
fn is_lit_surface(ids: vec4u) -> bool {
    return ids.y != NO_OBJECT && !is_emissive(scene_materials[ids.x]);
}
