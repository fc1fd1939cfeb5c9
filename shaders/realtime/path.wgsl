// The real-time graph's samples: the path tracer (shared/path_render.wgsl),
// one path a pixel, storing its sample with the camera ray's first hit,
// for the denoiser's demodulation and reprojection: the hit's position
// with the sample (pack_position_sample), and the rest packed in one
// texel with the light the hit received directly (SPLIT_DIRECT, which the
// graph sets; shared/realtime_common.wgsl, pack_first_hit).
#import path_render
#import realtime_common

@group(0) @binding(2) var gbuf_sample: texture_storage_2d<rgba32uint, write>;
@group(0) @binding(3) var gbuf_hit: texture_storage_2d<rgba32uint, write>;

// The first hit's position with the sample (pack_position_sample), and the
// rest of the hit.
fn store_sample(pixel: vec2u, radiance_in: vec3f, pos: vec4f, normal: vec4f, ids: vec4u) {
    textureStore(gbuf_sample, pixel, pack_position_sample(pos.xyz, radiance_in, sample_dither(pixel)));
    // (Without SPLIT_DIRECT the direct light is a constant 0, and its
    // packing, which runs on every trip of the path loop, folds away.)
    let direct = select(vec3f(0.0), path_pixel_direct, SPLIT_DIRECT);
    textureStore(gbuf_hit, pixel, pack_first_hit(normal, path_primary_albedo, first_hit_error_bits(pos, ids.z), direct));
}
