// Ground truth (thesis 2.4): Monte Carlo path tracing with Lambertian
// diffuse and a specular lobe chosen with probability `specular` (mirror
// direction blended toward a diffuse one by `roughness`). Next-event
// estimation on the diffuse lobe, combined with BSDF sampling by the power
// heuristic, so the image converges to the same answer as plain path
// tracing. Russian roulette after `rr_depth` bounces.
#import lights
#import rng

struct Params {
    spp: u32, // ui: 1..64 "samples per pixel"
    max_depth: u32, // ui: 1..64 limit "max bounces"
    rr_depth: u32, // ui: 0..16 "roulette from bounce"
    // Samples already in `radiance` from earlier dispatches this frame: the
    // engine splits spp across dispatches of at most 8 (drivers bound the
    // loop iterations of one invocation; src/graph/compile/split.rs).
    spp_done: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var radiance: texture_storage_2d<rgba32float, write>;
// The camera ray's first hit, as the G-buffer stores it (for reprojection
// in accumulate): position and distance (direction and -1 on a miss), and
// the normal facing the camera with the specular share in w.
@group(0) @binding(2) var gbuf_pos: texture_storage_2d<rgba32float, write>;
@group(0) @binding(3) var gbuf_normal: texture_storage_2d<rgba16float, write>;
// `radiance` again, for the later dispatches of a split frame (main_more).
@group(0) @binding(4) var radiance_acc: texture_storage_2d<rgba32float, read_write>;

var<private> primary_pos: vec4f;
var<private> primary_normal: vec4f;

const SALT: u32 = 0x70617468u;

// a^2 / (a^2 + b^2) for pdfs a, b >= 0, written with their ratio: squaring
// the pdf of a light too small for f32 (about 1e36 at the cone_pdf floor)
// overflowed to inf / inf = NaN, and the path sample was dropped.
fn power_heuristic(a: f32, b: f32) -> f32 {
    if !(a > 0.0) {
        return 0.0;
    }
    let r = b / a;
    return 1.0 / (1.0 + r * r);
}

fn trace_path(ro_in: vec3f, rd_in: vec3f, rng: ptr<function, Rng>) -> vec3f {
    var ro = ro_in;
    var rd = rd_in;
    var throughput = vec3f(1.0);
    var result = vec3f(0.0);
    // The BSDF pdf of the last bounce if it was diffuse (then a light hit
    // is weighted against NEE), or a negative value (camera / specular).
    var bsdf_pdf = -1.0;
    var prev_p = ro;
    for (var depth = 0u; depth < params.max_depth; depth++) {
        let hit = trace_closest(ro, rd, 3.0e38);
        if depth == 0u {
            primary_pos = select(vec4f(hit.position, hit.t), vec4f(rd, -1.0), !hit_found(hit));
            let facing = hit.normal * select(1.0, -1.0, dot(hit.geo_normal, rd) > 0.0);
            primary_normal = select(vec4f(facing, scene_materials[hit.material].specular), vec4f(0.0), !hit_found(hit));
        }
        if !hit_found(hit) {
            result += throughput * frame.background;
            break;
        }
        let m = scene_materials[hit.material];
        let p = hit.position;
        if is_emissive(m) {
            var w = 1.0;
            if hit.light >= 0 && bsdf_pdf > 0.0 {
                w = power_heuristic(bsdf_pdf, light_pdf(scene_lights[u32(hit.light)], prev_p));
            }
            result += throughput * m.emission * w;
        }
        if hit.light >= 0 {
            break; // lights do not reflect
        }
        let flip = select(1.0, -1.0, dot(hit.geo_normal, rd) > 0.0);
        let ng = hit.geo_normal * flip;
        var n = hit.normal * flip;
        if dot(n, rd) > 0.0 {
            n = ng;
        }
        let o = offset_ray(p, ng);
        if rand_f32(rng) < m.specular {
            var dir = reflect(rd, n);
            if m.roughness > 0.0 {
                dir = sample_glossy(dir, n, m.roughness, rand2(rng));
            }
            if dot(dir, ng) <= 0.0 {
                break;
            }
            throughput *= m.albedo;
            bsdf_pdf = -1.0;
            rd = dir;
        } else {
            // Next-event estimation: every light, one sample each.
            for (var i = 0u; i < frame.n_lights; i++) {
                let l = scene_lights[i];
                let s = sample_light(l, o, rand2(rng));
                let cos_n = dot(n, s.dir);
                if !s.valid || cos_n <= 0.0 || dot(s.dir, ng) <= 0.0 || !light_visible(o, s) {
                    continue;
                }
                var w = 1.0;
                if s.pdf > 0.0 {
                    w = power_heuristic(s.pdf, cos_n / PI);
                }
                result += throughput * m.albedo / PI * s.weight * cos_n * w;
            }
            let dir = sample_cosine(n, rand2(rng));
            let cos_d = dot(n, dir);
            if dot(dir, ng) <= 0.0 || cos_d <= 0.0 {
                break;
            }
            throughput *= m.albedo;
            bsdf_pdf = cos_d / PI;
            rd = dir;
        }
        prev_p = o;
        ro = o;
        if depth + 1u >= params.rr_depth {
            let q = min(max3(throughput), 0.95);
            if rand_f32(rng) >= q {
                break;
            }
            throughput /= q;
        }
    }
    return finite_or_zero(result);
}

// The sum of this dispatch's `spp` samples of pixel `id`. Each dispatch of
// a split frame draws its own random stream (the first one's is what an
// unsplit frame draws).
fn sample_sum(id: vec2u) -> vec3f {
    var rng = rng_for(id, frame.frame_index, SALT + params.spp_done * 0x9e3779b9u, frame.seed);
    let spp = max(params.spp, 1u);
    var sum = vec3f(0.0);
    for (var s = 0u; s < spp; s++) {
        let rd = camera_dir(frame.camera, id, rand2(&rng));
        sum += trace_path(frame.camera.origin, rd, &rng);
    }
    return sum;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let sum = sample_sum(id.xy);
    textureStore(radiance, id.xy, vec4f(sum / f32(max(params.spp, 1u)), 1.0));
    textureStore(gbuf_pos, id.xy, primary_pos);
    textureStore(gbuf_normal, id.xy, primary_normal);
}

// A later dispatch of a split frame: the mean of spp_done samples already
// in radiance_acc, updated with this dispatch's spp more.
@compute @workgroup_size(8, 8)
fn main_more(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let sum = sample_sum(id.xy);
    let before = textureLoad(radiance_acc, id.xy).rgb;
    let n = f32(params.spp_done) + f32(max(params.spp, 1u));
    textureStore(radiance_acc, id.xy, vec4f(before + (sum - f32(max(params.spp, 1u)) * before) / n, 1.0));
}
