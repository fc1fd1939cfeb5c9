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

// Where the camera sees a hit that it sees through mirrors (UNFOLD_MIRRORS,
// with THROUGH_MIRRORS): the point as far along the camera ray as the path
// ran to it, and its normal reflected by the mirror that turns its ray back
// into the camera's (exact for one mirror). The filters and the history
// then compare what a mirror shows as the camera sees it: at a mirror
// sphere's foot the floor it shows, which lies in the plane of the floor
// beside it, unfolds to a surface facing the camera, behind the sphere, and
// is not blended with that floor; what it shows at a grazing angle, the
// room beside it, unfolds next to the room itself. (Between two pixels
// that both show a mirror's hits the filters test the normals alone:
// shared/realtime_common.wgsl, geometry_exponent.) 0: the hit's own
// position and normal (to measure what unfolding brings).
override UNFOLD_MIRRORS: bool = true;

// THIN_STORES (the graph's, set on `temporal` too, which then reads it):
// in a frame whose filter does not run (THINNED, set by the engine per
// frame, src/graph/frame_kind.rs), one texel a pixel, what `temporal`
// folds into the history (pack_thin_sample), instead of two: a CPU driver
// runs each store of the path loop on every trip under its lane mask.
// gbuf_hit is then left as it was: no pass but `temporal` may read the
// path pass's outputs in such a frame.
override THIN_STORES: bool = false;
override THINNED: bool = false;

// The first hit's position with the sample (pack_position_sample), and the
// rest of the hit.
fn store_sample(pixel: vec2u, radiance_in: vec3f, pos: vec4f, normal: vec4f, ids: vec4u) {
    // (Without SPLIT_DIRECT the direct light is a constant 0, and its
    // packing, which runs on every trip of the path loop, folds away.)
    let direct = select(vec3f(0.0), path_pixel_direct, SPLIT_DIRECT);
    if THIN_STORES && THINNED {
        let surface = pos.w >= 0.0 && path_primary_albedo.w > 0.0;
        textureStore(gbuf_sample, pixel, pack_thin_sample(pack_sample(radiance_in, sample_dither(pixel)), path_primary_albedo.rgb, surface, direct));
        return;
    }
    var p = pos.xyz;
    var n = normal.xyz;
    if UNFOLD_MIRRORS && THROUGH_MIRRORS && path_primary_through && pos.w >= 0.0 {
        p = frame.camera.origin + path_camera_dir * path_primary_len;
        let turn = path_camera_dir - path_primary_dir;
        if dot(turn, turn) > 1e-12 {
            let m = normalize(turn);
            n -= 2.0 * dot(n, m) * m;
        }
    }
    textureStore(gbuf_sample, pixel, pack_position_sample(p, radiance_in, sample_dither(pixel)));
    textureStore(gbuf_hit, pixel, pack_first_hit(vec4f(n, normal.w), path_primary_albedo, first_hit_error_bits(pos, ids.z, path_primary_through), direct));
}
