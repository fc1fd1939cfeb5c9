// realtime-restir.ron's samples: realtime/path.wgsl's (its sample and
// first hit stored the same way), with the first hit's diffuse direct light left
// to restir.wgsl (FIRST_DIRECT_APART, shared/path.wgsl, which the graph
// sets): `di_surface` gets what that pass needs.
#import path_render
#import reproject
#import realtime_common

@group(0) @binding(2) var gbuf_sample: texture_storage_2d<rgba32uint, write>;
@group(0) @binding(3) var gbuf_hit: texture_storage_2d<rgba32uint, write>;
// The factor the hit's direct light arrives with (f32 bits; 0: none) and
// its geometric normal facing the ray (octahedral, packed).
@group(0) @binding(6) var di_surface: texture_storage_2d<rgba32uint, write>;

fn store_sample(pixel: vec2u, radiance_in: vec3f, pos: vec4f, normal: vec4f, ids: vec4u) {
    textureStore(gbuf_sample, pixel, pack_position_sample(pos.xyz, radiance_in, sample_dither(pixel)));
    textureStore(gbuf_hit, pixel, pack_first_hit(normal, path_primary_albedo, first_hit_error_bits(pos, ids.z, path_primary_through), vec3f(0.0)));
    let ng = pack2x16snorm(normal_to_oct(path_primary_ng));
    textureStore(di_surface, pixel, vec4u(bitcast<vec3u>(path_primary_direct), ng));
}
