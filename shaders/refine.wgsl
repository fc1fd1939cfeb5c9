// Refinement (thesis 4.2.2): pixels in the noise mask take `samples` more
// samples of every sphere light and merge them with the frame's estimate
// (made with `base_samples` per light) by sample count.
#import lights
#import work_list
#import textures

struct Params {
    samples: u32, // ui: 1..64 limit "extra samples"
    base_samples: u32, // ui: 1..64 "samples of the base pass"
    falloff: u32, // ui: 0..1
    falloff_k: f32, // ui: 0..10
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var mask: texture_storage_2d<r32float, read>;
@group(0) @binding(2) var gbuf_pos: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var gbuf_normal: texture_storage_2d<rgba16float, read>;
@group(0) @binding(4) var gbuf_id: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(5) var lit_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(6) var lit: texture_storage_2d<rgba32float, write>;
@group(0) @binding(7) var gbuf_material: texture_storage_2d<rgba32uint, read>;

const SALT: u32 = 0x72656669u;

// Per texel: lists the masked texels for `listed` (the graph's `listed:`
// entry), which alone take the extra samples; the others pass through.
@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let ids = textureLoad(gbuf_id, id.xy);
    if textureLoad(mask, id.xy).x >= 0.5 && is_lit_surface(ids) {
        work_list_push(id.xy);
    } else {
        textureStore(lit, id.xy, textureLoad(lit_in, id.xy));
    }
}

@compute @workgroup_size(64)
fn listed(@builtin(global_invocation_id) gid: vec3u) {
    let id = work_list_id(gid.x);
    if id.z != 0u {
        return;
    }
    let before = textureLoad(lit_in, id.xy);
    let ids = textureLoad(gbuf_id, id.xy);
    let pos = textureLoad(gbuf_pos, id.xy);
    let p = pos.xyz;
    let n = normalize(textureLoad(gbuf_normal, id.xy).xyz);
    // A lit surface (main listed no other): its diffuse albedo as the
    // light passes shade it (their estimate is merged with this one).
    let base = shaded_diffuse(stored_material(ids, textureLoad(gbuf_material, id.xy)), n, normalize(frame.camera.origin - p));
    let o = offset_by(p, n, bitcast<f32>(ids.z));
    var rng = rng_for(id.xy, frame.frame_index, SALT, frame.seed);
    var direct = vec3f(0.0);
    for (var i = 0u; i < light_count(); i++) {
        let l = load_light(i);
        if l.kind == LIGHT_SPHERE {
            direct += light_irradiance(i, l, p, n, o, max(params.samples, 1u), params.falloff, params.falloff_k, &rng);
        }
    }
    let extra = finite_or_zero(base / PI * direct);
    // `before` must hold only the sphere-light estimate (the graph runs
    // refine right after the area-light pass, before point lights are
    // added), so merging by sample count is exact.
    let n0 = f32(max(params.base_samples, 1u));
    let n1 = f32(max(params.samples, 1u));
    textureStore(lit, id.xy, vec4f((before.rgb * n0 + extra * n1) / (n0 + n1), 1.0));
}
