// Ray throughput benchmark (`glint bench rays`): one primary ray per pixel
// through the pixel centre, then per hit one shadow ray (toward a fixed
// directional light) and one cosine-distributed diffuse ray. The `query`
// pass traces the primary rays again and keeps only their hit records.
#import flat
#import rng
#import sampling
#import tile_pool

@group(0) @binding(0) var bench_hit: texture_storage_2d<rgba32float, write>;
@group(0) @binding(1) var bench_normal: texture_storage_2d<rgba32float, write>;
@group(0) @binding(2) var hit_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var normal_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(4) var bench_out: texture_storage_2d<rgba32float, write>;
@group(0) @binding(5) var out_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(6) var bench_query: texture_storage_2d<rgba32float, write>;

const SUN: vec3f = vec3f(0.28734789, 0.95782629, 0.19156526);
const INF: f32 = 3.0e38;

// Query: the primary rays as a ray query alone, what Embree's
// rtcIntersect1 gives (tools/embree): the hit record (distance, the
// triangle's barycentrics, the primitive), without the surface point and
// normals `primary` makes of it. The primitive as a number, not as bits
// (a driver may flush the denormals small ids would be): triangle i as i
// (exact below 2^24), sphere i as -1 - i. On a miss (-1, 0, 0, 0). The
// same traversal as `primary` (closest_pixel), so the same distances.
@compute @workgroup_size(64, 1)
fn query() {
    var cursor = PoolCursor();
    loop {
        let id = pool_next(&cursor);
        if id.z != 0u {
            break;
        }
        if in_frame(id) {
            query_texel(id.xy);
        }
    }
}

fn query_texel(id: vec2u) {
    let rd = camera_dir(frame.camera, id.xy, vec2f(0.5));
    let c = closest_pixel(id, rd, INF);
    let found = c.prim != NO_HIT;
    let sphere = (c.prim & SPHERE_BIT) != 0u;
    let prim = select(f32(c.prim), -1.0 - f32(c.prim & ~SPHERE_BIT), sphere);
    textureStore(bench_query, id, select(vec4f(-1.0, 0.0, 0.0, 0.0), vec4f(c.t, c.uv, prim), found));
}

// Primary: xyz hit point, w distance along the unit direction (-1: miss).
@compute @workgroup_size(64, 1)
fn primary() {
    var cursor = PoolCursor();
    loop {
        let id = pool_next(&cursor);
        if id.z != 0u {
            break;
        }
        if in_frame(id) {
            primary_texel(id.xy);
        }
    }
}

fn primary_texel(id: vec2u) {
    // The counts are the ray's own: an invocation traces many texels.
    trips_node = 0u;
    trips_triangle = 0u;
    let rd = camera_dir(frame.camera, id.xy, vec2f(0.5));
    let hit = closest_hit(closest_pixel(id.xy, rd, INF), frame.camera.origin, rd, INF);
    let found = hit_found(hit);
    let n = select(hit.geo_normal, -hit.geo_normal, dot(hit.geo_normal, rd) > 0.0);
    // One store per texture, hit or miss: CPU drivers run both sides of a
    // branch under a lane mask, so a store on each side costs two.
    textureStore(bench_hit, id.xy, select(vec4f(0.0, 0.0, 0.0, -1.0), vec4f(hit.position, hit.t), found));
    // w: the BLAS trips of the ray (COUNT_TRIPS, `--trips`): node trips +
    // 4096 x triangle trips, each capped at 4095 (exact in an f32).
    let trips = f32(min(trips_node, 4095u) + 4096u * min(trips_triangle, 4095u));
    textureStore(bench_normal, id.xy, vec4f(select(vec3f(0.0), n, found), trips));
}

// Shadow: out.x = primary distance (inf on a miss), out.y = 1 if occluded.
@compute @workgroup_size(128, 1)
fn shadow(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let h = textureLoad(hit_in, id.xy);
    if h.w < 0.0 {
        textureStore(bench_out, id.xy, vec4f(bitcast<f32>(0x7f800000u), 0.0, 0.0, 0.0));
        return;
    }
    let n = textureLoad(normal_in, id.xy).xyz;
    let o = offset_by(h.xyz, n, bench_error(h.xyz, n));
    let blocked = dot(n, SUN) <= 0.0 || trace_any(o, SUN, INF);
    textureStore(bench_out, id.xy, vec4f(h.w, select(0.0, 1.0, blocked), 0.0, 0.0));
}

// Diffuse: out.z = distance of a cosine-distributed bounce (-1: miss).
// The bench keeps no per-hit error bound beside the hit (its textures are
// full): a triangle's is at least gamma(7) |p| per component, the smallest
// it can be; a timing, not an image, rests on it.
fn bench_error(p: vec3f, n: vec3f) -> f32 {
    return f32_gamma(7.0) * dot(abs(n), abs(p));
}

@compute @workgroup_size(128, 1)
fn diffuse(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let before = textureLoad(out_in, id.xy);
    let h = textureLoad(hit_in, id.xy);
    if h.w < 0.0 {
        textureStore(bench_out, id.xy, before);
        return;
    }
    let n = textureLoad(normal_in, id.xy).xyz;
    var rng = rng_for(id.xy, frame.frame_index, 0x62656e63u, frame.seed);
    let dir = sample_cosine(n, rand2(&rng));
    let hit = trace_closest(offset_by(h.xyz, n, bench_error(h.xyz, n)), dir, INF);
    textureStore(bench_out, id.xy, vec4f(before.x, before.y, select(-1.0, hit.t, hit_found(hit)), 0.0));
}
