// G-buffer: one primary ray per pixel (jittered per frame when `jitter` is
// 1, for accumulation). Writes hit position and distance, the shading
// normal faced toward the camera (w: the material's specular share),
// (material, object) ids, and in a textured scene what the hit's textures
// multiply its material by (the passes that shade it read them there
// instead of sampling the textures again).
// A miss stores distance -1 and the ray direction in xyz, object NO_HIT.
#import origins
#import rng

struct Params {
    jitter: u32, // ui: bool "jitter"
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var gbuf_pos: texture_storage_2d<rgba32float, write>;
@group(0) @binding(2) var gbuf_normal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(3) var gbuf_id: texture_storage_2d<rgba32uint, write>;
@group(0) @binding(4) var gbuf_material: texture_storage_2d<rgba32uint, write>;

const SALT: u32 = 0x67627566u;

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    var rng = rng_for(id.xy, frame.frame_index, SALT, frame.seed);
    var jitter = vec2f(0.5);
    if params.jitter != 0u {
        jitter = rand2(&rng);
    }
    let rd = camera_dir(frame.camera, id.xy, jitter);
    let hit = trace_camera_pixel(id.xy, rd, 3.0e38);
    let found = hit_found(hit);
    // One store per texture, hit or miss: CPU drivers run both sides of a
    // branch under a lane mask, so a store on each side costs two.
    // Two-sided surfaces: face the normals toward the viewer; w: the
    // specular share, so accumulate knows what is view-dependent.
    // (Bent by the material's normal texture, where it has one.)
    // (The material is loaded only where textures can change it: an
    // untextured scene's G-buffer reads no more than it did.)
    var surface = SurfaceFactors(hit.normal, NO_FACTORS);
    if SCENE_TEXTURES {
        surface = surface_factors(load_material(hit.material), hit.material, select(NO_OBJECT, hit.prim, found), hit.position, rd, hit.t * pixel_spread(), hit.normal);
    }
    var shaded = hit;
    shaded.normal = surface.n;
    let normal = vec4f(facing(shaded, rd).n, material_specular(hit.material));
    textureStore(gbuf_pos, id.xy, select(vec4f(rd, -1.0), vec4f(hit.position, hit.t), found));
    textureStore(gbuf_normal, id.xy, select(vec4f(0.0), normal, found));
    // z: the hit's error bound (f32 bits), which the passes that start
    // rays here offset them by (offset_by); w: the triangle, whose uvs
    // textured materials read (shared/textures.wgsl).
    let error = bitcast<u32>(gbuffer_offset_error(hit));
    textureStore(gbuf_id, id.xy, select(vec4u(NO_HIT, NO_HIT, 0u, NO_HIT), vec4u(hit.material, hit.object, error, hit.prim), found));
    // (Not written in a scene without textures: nothing reads it there.)
    if SCENE_TEXTURES {
        textureStore(gbuf_material, id.xy, pack_factors(surface.factors));
    }
}
