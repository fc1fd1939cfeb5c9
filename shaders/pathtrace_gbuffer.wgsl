// The path tracer (shaders/pathtrace.wgsl) that also stores the camera
// ray's first hit as the G-buffer does, for a graph that reprojects its
// accumulation (accumulate.wgsl `main`, mode 1). Needs FIRST_HIT (the
// default in shared/path.wgsl).
#import path_render

// The camera ray's first hit, as the G-buffer stores it (for reprojection
// in accumulate): position and distance (direction and -1 on a miss), and
// the normal facing the camera with the specular share in w. The stores
// sit inside the path loop, where a CPU driver runs them on every trip
// under the lane mask (the pass took 0.89x the time without them on the
// Cornell box), so pathtrace.wgsl leaves them out.
@group(0) @binding(2) var gbuf_pos: texture_storage_2d<rgba32float, write>;
@group(0) @binding(3) var gbuf_normal: texture_storage_2d<rgba16float, write>;

fn store_sample(pixel: vec2u, radiance_in: vec3f, pos: vec4f, normal: vec4f, ids: vec4u) {
    textureStore(radiance, pixel, vec4f(radiance_in, 1.0));
    textureStore(gbuf_pos, pixel, pos);
    textureStore(gbuf_normal, pixel, normal);
}
