// Albedo baseline (thesis fig. 4.1): each surface's albedo, as if fully lit
// by white light; emitters show their emission, misses the background.
// Also seeds `lit` with what needs no lighting: emission and background.
#import scene

@group(0) @binding(0) var gbuf_id: texture_2d<u32>;
@group(0) @binding(1) var albedo: texture_storage_2d<rgba32float, write>;
@group(0) @binding(2) var lit: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let ids = textureLoad(gbuf_id, id.xy, 0);
    if ids.y == NO_OBJECT {
        textureStore(albedo, id.xy, vec4f(frame.background, 1.0));
        textureStore(lit, id.xy, vec4f(frame.background, 1.0));
        return;
    }
    let m = load_material(ids.x);
    if is_emissive(m) {
        textureStore(albedo, id.xy, vec4f(m.emission, 1.0));
        textureStore(lit, id.xy, vec4f(m.emission, 1.0));
        return;
    }
    textureStore(albedo, id.xy, vec4f(m.albedo, 1.0));
    textureStore(lit, id.xy, vec4f(0.0, 0.0, 0.0, 1.0));
}
