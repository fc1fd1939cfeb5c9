// The real-time graph's samples: the path tracer (shared/path_render.wgsl),
// one path a pixel, storing the camera ray's first hit as the G-buffer
// does, with its ids, for the denoiser's demodulation and reprojection.
#import path_render

@group(0) @binding(2) var gbuf_pos: texture_storage_2d<rgba32float, write>;
@group(0) @binding(3) var gbuf_normal: texture_storage_2d<rgba16float, write>;
@group(0) @binding(5) var gbuf_id: texture_storage_2d<rgba32uint, write>;

fn store_first_hit(pixel: vec2u, pos: vec4f, normal: vec4f, ids: vec4u) {
    textureStore(gbuf_pos, pixel, pos);
    textureStore(gbuf_normal, pixel, normal);
    textureStore(gbuf_id, pixel, ids);
}
