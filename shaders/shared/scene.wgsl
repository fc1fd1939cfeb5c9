// The scene's arrays (mirrors src/scene/gpu_types.rs). Counts live in `frame`.
#import frame

// Spheres and triangles, what traversal reads at every step, live in
// read-only rgba32uint storage textures: record i is texels
// texel_count * i .. of a texture
// SCENE_TEXTURE_WIDTH texels wide, one texel per vec4 member below (the
// byte layout of src/scene/gpu_types.rs; src/scene/buffers.rs says
// why textures); so are the shading normals, to lift the storage-binding
// limit from meshes; so are materials and lights, which shading reads at
// every pixel (two texels each). Meshes are a storage buffer.
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

// Thesis (model MATERIAL_THESIS): albedo, a specular lobe taken with
// probability `specular`, leaning from the mirror toward a diffuse
// direction by `roughness`. Metallic-roughness (MATERIAL_METALLIC_ROUGHNESS,
// shared/brdf.wgsl): albedo is the base colour, roughness glTF's; its
// `specular` is the stand-in share the passes that shade thesis lobes only
// use (metallic + 0.04 (1 - metallic)). Three texels
// (src/scene/gpu_types.rs, MaterialGpu).
struct Material {
    albedo: vec3f,
    specular: f32,
    emission: vec3f,
    roughness: f32,
    metallic: f32,
    model: u32,
}

const MATERIAL_THESIS: u32 = 0u;
const MATERIAL_METALLIC_ROUGHNESS: u32 = 1u;
// Some material of the scene is metallic-roughness.
override SCENE_METALLIC_ROUGHNESS: bool = true;

fn is_metal_rough(m: Material) -> bool {
    return SCENE_METALLIC_ROUGHNESS && m.model == MATERIAL_METALLIC_ROUGHNESS;
}

const LIGHT_POINT: u32 = 0u;
const LIGHT_SPHERE: u32 = 1u;
// A light from infinitely far away: `position` is the unit direction
// toward it, `color` the irradiance on a surface facing it.
const LIGHT_DIRECTIONAL: u32 = 2u;
override SCENE_DIRECTIONAL_LIGHTS: bool = true;
// The environment light (shared/environment.wgsl), always the last light.
const LIGHT_ENVIRONMENT: u32 = 3u;
override SCENE_ENVIRONMENT: bool = true;

struct Light {
    position: vec3f,
    radius: f32,
    color: vec3f,
    kind: u32,
    // A spot light's cone: its factor is clamp(dot(spot.xyz, d) + spot.w,
    // 0, 1)^2 for the unit direction d from the light (src/scene/world.rs,
    // SpotCone); (0, 0, 0, 1) for every other light.
    spot: vec4f,
}

// Whether some point light has a cone (a spot light).
override SCENE_SPOT_LIGHTS: bool = true;

// How much of a point light's intensity leaves it along unit direction d.
fn spot_factor(l: Light, d: vec3f) -> f32 {
    if !SCENE_SPOT_LIGHTS {
        return 1.0;
    }
    let x = clamp(dot(l.spot.xyz, d) + l.spot.w, 0.0, 1.0);
    return x * x;
}

@group(1) @binding(1) var scene_spheres: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(2) var scene_geometry: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(3) var<storage, read> scene_meshes: array<Mesh>;
@group(1) @binding(4) var scene_materials: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(5) var scene_lights: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(8) var scene_normals: texture_storage_2d<rgba32uint, read>;
// What the engine works out per frame for a flat scene (src/scene/origins.rs):
// its triangles' edge planes through the camera and light 0
// (shared/origins.wgsl), then each light's occluder list.
@group(1) @binding(9) var scene_origins: texture_storage_2d<rgba32uint, read>;
// A flat scene's triangles and spheres again, in FLAT_LIMIT slots of each
// (src/scene/flat_uniform.rs): where a shader writes a flat loop out slot
// by slot, each load has a constant offset, which lavapipe loads once and
// broadcasts to the lanes; a texel fetch gathers per lane.
struct FlatScene {
    triangles: array<vec4u, 96>,
    spheres: array<vec4u, 64>,
}
@group(1) @binding(10) var<uniform> scene_flat: FlatScene;

// Mirrors SCENE_TEXTURE_WIDTH in src/scene/buffers.rs.
const SCENE_TEXTURE_WIDTH_LOG2: u32 = 12u;

// Texel i of a scene texture.
fn scene_texel(t: texture_storage_2d<rgba32uint, read>, i: u32) -> vec4u {
    return textureLoad(t, vec2u(i & ((1u << SCENE_TEXTURE_WIDTH_LOG2) - 1u), i >> SCENE_TEXTURE_WIDTH_LOG2));
}

fn load_sphere(i: u32) -> Sphere {
    return Sphere(bitcast<vec4f>(scene_texel(scene_spheres, 2u * i)), scene_texel(scene_spheres, 2u * i + 1u));
}

fn load_triangle(i: u32) -> Triangle {
    return Triangle(
        bitcast<vec4f>(scene_texel(scene_geometry, 3u * i)),
        bitcast<vec4f>(scene_texel(scene_geometry, 3u * i + 1u)),
        bitcast<vec4f>(scene_texel(scene_geometry, 3u * i + 2u)),
    );
}

// Triangle i and sphere i of a flat scene (i a constant), from an entry
// point's copy of scene_flat (see trace_pair in flat.wgsl).
fn flat_triangle_at(flat: ptr<function, FlatScene>, i: u32) -> Triangle {
    return Triangle(
        bitcast<vec4f>((*flat).triangles[3u * i]),
        bitcast<vec4f>((*flat).triangles[3u * i + 1u]),
        bitcast<vec4f>((*flat).triangles[3u * i + 2u]),
    );
}

fn flat_sphere_at(flat: ptr<function, FlatScene>, i: u32) -> Sphere {
    return Sphere(bitcast<vec4f>((*flat).spheres[2u * i]), (*flat).spheres[2u * i + 1u]);
}

// Vertex k (0, 1 or 2) of triangle i.
fn load_triangle_vertex(i: u32, k: u32) -> vec3f {
    return bitcast<vec4f>(scene_texel(scene_geometry, 3u * i + k)).xyz;
}

fn load_normals(i: u32) -> TriangleNormals {
    let n0 = bitcast<vec4f>(scene_texel(scene_normals, 3u * i));
    let n1 = bitcast<vec4f>(scene_texel(scene_normals, 3u * i + 1u));
    let n2 = bitcast<vec4f>(scene_texel(scene_normals, 3u * i + 2u));
    return TriangleNormals(n0.xyz, n0.w, n1.xyz, n1.w, n2.xyz, n2.w);
}

// Specialisation (src/scene/specialise.rs): the engine sets these per
// scene to what it lacks, so the code for it is compiled out; the defaults
// are right for any scene (`--no-specialise` keeps them).
override SCENE_SPHERES: bool = true;
override SCENE_MESHES: bool = true;
override SCENE_POINT_LIGHTS: bool = true;
override SCENE_AREA_LIGHTS: bool = true;
override SCENE_SPECULAR: bool = true;
// Some material is a coat: a specular share between 0 and 1 over a
// diffuse base, not metallic-roughness (shared/path.wgsl, SPLIT_LOBES).
override SCENE_COATS: bool = true;
// A sphere light may hold a shading point inside it (src/scene/specialise.rs).
override SCENE_INSIDE_LIGHTS: bool = true;
override SCENE_ONE_LIGHT: bool = false;

// How many lights the light loops visit: a constant where the scene has
// one or none, so the loop is straight code.
fn light_count() -> u32 {
    if !SCENE_POINT_LIGHTS && !SCENE_AREA_LIGHTS {
        return 0u;
    }
    if SCENE_ONE_LIGHT {
        return 1u;
    }
    return frame.n_lights;
}

// Light i, its kind a constant where the scene has lights of one kind
// (the other kind's code folds away).
fn load_light(i: u32) -> Light {
    let a = bitcast<vec4f>(scene_texel(scene_lights, 3u * i));
    let b = scene_texel(scene_lights, 3u * i + 1u);
    var spot = vec4f(0.0, 0.0, 0.0, 1.0);
    if SCENE_SPOT_LIGHTS {
        spot = bitcast<vec4f>(scene_texel(scene_lights, 3u * i + 2u));
    }
    var l = Light(a.xyz, a.w, bitcast<vec3f>(b.xyz), b.w, spot);
    // (A directional or environment light counts as a point light in the
    // features.)
    if !SCENE_POINT_LIGHTS {
        l.kind = LIGHT_SPHERE;
    } else if !SCENE_AREA_LIGHTS && !SCENE_DIRECTIONAL_LIGHTS && !SCENE_ENVIRONMENT {
        l.kind = LIGHT_POINT;
    }
    return l;
}

// Material i, its specular share a constant 0 where no surface of the
// scene reflects (reflection and mirror-bounce code folds away).
fn load_material(i: u32) -> Material {
    let a = bitcast<vec4f>(scene_texel(scene_materials, 3u * i));
    let b = bitcast<vec4f>(scene_texel(scene_materials, 3u * i + 1u));
    var m = Material(a.xyz, a.w, b.xyz, b.w, 0.0, MATERIAL_THESIS);
    if SCENE_METALLIC_ROUGHNESS {
        let c = scene_texel(scene_materials, 3u * i + 2u);
        m.metallic = bitcast<f32>(c.x);
        m.model = c.y;
    }
    if !SCENE_SPECULAR {
        m.specular = 0.0;
    }
    return m;
}

// Some material is single-sided (glTF's doubleSided false; its flags,
// the third texel's z, bit 0): traversal then takes one of its triangles
// only where the ray meets the front (counter-clockwise) face.
override SCENE_SINGLE_SIDED: bool = true;
const MATERIAL_SINGLE_SIDED: u32 = 1u;

// Whether a ray along rd may hit triangle (p0, p1, p2) of `material`.
fn face_passes(material: u32, rd: vec3f, p0: vec3f, p1: vec3f, p2: vec3f) -> bool {
    if !SCENE_SINGLE_SIDED {
        return true;
    }
    let single = (scene_texel(scene_materials, 3u * material + 2u).z & MATERIAL_SINGLE_SIDED) != 0u;
    return !single || dot(cross(p1 - p0, p2 - p0), rd) < 0.0;
}

// Material i's specular share alone, for the per-pixel passes that need
// no more of it: one load (storage loads cost per component on CPU
// drivers), none where no surface of the scene reflects.
fn material_specular(i: u32) -> f32 {
    if !SCENE_SPECULAR {
        return 0.0;
    }
    return bitcast<f32>(scene_texel(scene_materials, 3u * i).w);
}

fn is_emissive(m: Material) -> bool {
    return max(m.emission.x, max(m.emission.y, m.emission.z)) > 0.0;
}

// gbuf_id's object (y) where the pixel's ray hit nothing (as NO_HIT in
// intersect.wgsl).
const NO_OBJECT: u32 = 0xffffffffu;

// Whether a G-buffer id (material, object) is a surface that light falls
// on: a hit, and not an emitter (those show their own emission).
fn is_lit_surface(ids: vec4u) -> bool {
    return ids.y != NO_OBJECT && !is_emissive(load_material(ids.x));
}

// The diffuse share of a lit surface's albedo (the specular share is the
// reflections pass's to shade). The light passes take it from the
// material, not from an albedo pass's texture, which holds the same for a
// lit surface: a load from the small material table costs no more than one
// from a full-screen texture.
// (A metallic-roughness surface's: base (1 - metallic) (1 - 0.04), what
// its Fresnel lets through head-on.)
fn diffuse_albedo(m: Material) -> vec3f {
    return m.albedo * (1.0 - m.specular);
}

// The layout of scene_origins (mirrors src/scene/origins.rs): ORIGIN_ROWS
// rows of edge planes (three texels a triangle slot), the camera's and
// light 0's, then an occluder list for each of the first OCCLUDER_LIGHTS
// lights (a count, then one triangle index a texel).
const ORIGIN_ROW_TEXELS: u32 = 96u;
const ORIGIN_ROWS: u32 = 2u;
const ORIGIN_CAMERA: u32 = 0u;
const ORIGIN_LIGHT: u32 = 1u;
const OCCLUDER_LIGHTS: u32 = 8u;
const OCCLUDER_ROW_TEXELS: u32 = 33u;
// A shadow ray toward no light in particular: every triangle may block it.
const NO_LIGHT: u32 = 0xffffffffu;

// The first texel of light `light`'s occluder list.
fn occluder_row(light: u32) -> u32 {
    return ORIGIN_ROWS * ORIGIN_ROW_TEXELS + min(light, OCCLUDER_LIGHTS - 1u) * OCCLUDER_ROW_TEXELS;
}

// How many of a flat scene's triangles can block a shadow ray toward light
// `light`: its list's count, or every triangle for a light without a list.
fn occluder_count(light: u32) -> u32 {
    return select(frame.n_triangles, scene_texel(scene_origins, occluder_row(light)).x, light < OCCLUDER_LIGHTS);
}

// The j-th of them.
fn occluder(light: u32, j: u32) -> u32 {
    return select(j, scene_texel(scene_origins, occluder_row(light) + 1u + j).x, light < OCCLUDER_LIGHTS);
}
