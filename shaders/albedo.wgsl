// Albedo baseline (thesis fig. 4.1): each surface's albedo, as if fully lit
// by white light; emitters show their emission, misses the sky.
// Also seeds `lit` with what needs no lighting: emission and the sky.
#import scene
#import textures
#import environment

@group(0) @binding(0) var gbuf_id: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(1) var albedo: texture_storage_2d<rgba32float, write>;
@group(0) @binding(2) var lit: texture_storage_2d<rgba32float, write>;
// (What the hit's textures multiply its material by.)
@group(0) @binding(3) var gbuf_material: texture_storage_2d<rgba32uint, read>;

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let ids = textureLoad(gbuf_id, id.xy);
    let miss = ids.y == NO_OBJECT;
    // One store per texture, chosen by select: CPU drivers run every
    // branch under a lane mask, so a store in each would cost three.
    let m = stored_material(ids, textureLoad(gbuf_material, id.xy));
    // (A miss shows the sky at the pixel's centre: the albedo pass has no
    // G-buffer position, which holds a miss's jittered direction.)
    let dir = camera_dir(frame.camera, id.xy, vec2f(0.5));
    let unlit = unlit_radiance(m, miss, dir);
    let shown = select(select(m.albedo, m.emission, is_emissive(m)), unlit, miss);
    textureStore(albedo, id.xy, vec4f(shown, 1.0));
    textureStore(lit, id.xy, vec4f(unlit, 1.0));
}
