// A Monte Carlo path (thesis 2.4): Lambertian diffuse and a specular lobe
// chosen with probability `specular` (mirror direction blended toward a
// diffuse one by `roughness`). Next-event estimation on the diffuse lobe,
// combined with BSDF sampling by the power heuristic. A metallic-roughness
// surface (shared/brdf.wgsl) takes next-event estimation and samples its
// whole BRDF, both weighted by the power heuristic. Shared by the path
// tracer and the probe bakes (shaders/probes_*.wgsl).
#import flat
#import lights
#import light_choice
#import rng
#import blue_noise
#import textures
#import brdf

// The first hit of the last path traced, as the G-buffer stores it:
// position and distance (direction and -1 on a miss), and the normal
// facing the ray with the specular share in w, and the (material, object)
// ids (NO_HIT for the object on a miss). Kept only with FIRST_HIT (the
// path tracer's, for accumulation that reprojects or a denoiser).
override FIRST_HIT: bool = true;
var<private> path_primary_pos: vec4f;
var<private> path_primary_normal: vec4f;
// (material, object, the hit's error along the stored normal as f32 bits,
// the triangle: NO_HIT for a sphere)
var<private> path_primary_ids: vec4u;
// With THROUGH_MIRRORS, the first hit recorded is the first one past any
// perfect mirrors (specular share 1, roughness 0: a path goes on from them
// in one direction only), with the specular share 1 in the normal's w (what
// it shows depends on the view): a denoiser then filters what a mirror
// shows as the surface it shows, and keeps the reflection sharp. While
// `path_primary_open`, the path has met only such mirrors.
override THROUGH_MIRRORS: bool = false;
var<private> path_primary_open: bool;
// With THROUGH_MIRRORS: the camera ray's direction, the direction of the
// ray that met the recorded hit and the path's length to it, and whether
// mirrors came before it (the real-time path pass unfolds what a mirror
// shows into the camera's view: shaders/realtime/path.wgsl).
var<private> path_camera_dir: vec3f;
var<private> path_primary_dir: vec3f;
var<private> path_primary_len: f32;
var<private> path_primary_through: bool;

// Next-event estimation toward one light a bounce instead of every light:
// a bounce then traces one shadow ray however many lights the scene has
// (more noise with many lights, the same mean). The light is chosen by
// what it could bring to the shading point (shared/light_choice.wgsl).
// Off: every light, one sample each.
override NEE_ONE: bool = false;

// With FIRST_DIRECT_APART, the direct light of the recorded first hit's
// diffuse lobe is left to another pass (shaders/realtime/restir.wgsl:
// reservoir resampling over all lights): the path takes no next-event
// estimation there, and a light its diffuse bounce then hits counts
// nothing. What that pass needs is recorded with the hit:
// `path_primary_direct`, the factor its light arrives with (the
// throughput to the hit, the diffuse share and albedo / pi; 0: none) and
// `path_primary_ng`, the geometric normal facing the ray.
override FIRST_DIRECT_APART: bool = false;
var<private> path_primary_direct: vec3f;
var<private> path_primary_ng: vec3f;

// The recorded first hit's albedo (FIRST_HIT), w 1 where it is a lit
// surface (an object that does not glow), else 0.
var<private> path_primary_albedo: vec4f;

// With SPLIT_LOBES, the recorded first hit of a surface that is partly
// specular (a specular share between 0 and 1: a coat over a diffuse
// base) takes both lobes instead of one chosen at random: the path goes
// on along the diffuse lobe, weighted by its share (1 - specular), and
// once it ends, the same loop traces the specular lobe's path from the
// hit, weighted by its share. A coat's reflection of a light is then in
// every sample, not in half of them at twice the brightness: that coin's
// noise was the largest a denoiser saw on such a surface. The specular
// lobe's pending path: its origin, direction, throughput and ray cone.
override SPLIT_LOBES: bool = false;
var<private> path_lobe_pending: bool;
var<private> path_lobe_o: vec3f;
var<private> path_lobe_dir: vec3f;
var<private> path_lobe_throughput: vec3f;
var<private> path_lobe_cone: vec2f;
// Where the specular lobe's path began: the result then (with
// SPLIT_DIRECT, what it brings is kept apart with the direct light, which
// the denoiser filters by its own variance, its mean never blurred: a
// coat's reflection stays as sharp as its noise allows).
var<private> path_lobe_from: vec3f;
var<private> path_lobe_traced: bool;

// With SPLIT_DIRECT, what the recorded first hit's light samples bring
// (next-event estimation, as multiple importance sampling weighs it) is
// also kept apart, in `path_direct`: the path's result after them less
// its result before them (path_bounce takes the one, path_render.wgsl the
// other, once the last light's shadow ray is traced; `path_direct_state`
// says where the path is: 0 before the recorded hit, 1 at it, 2 sampling
// its lights, 3 its bounce ray in flight, 4 done). What a light its
// bounce ray meets brings, as multiple importance sampling weighs it
// against those samples, is its direct light too: kept with the rest, it
// was a narrow peak above a light near a wall (a Cornell box's ceiling)
// that the wide filter steps flattened for dozens of frames. The
// real-time denoiser filters the direct light apart, by its own variance
// (shaders/realtime/atrous.wgsl).
//
// The recorded hit then samples every light, one sample each, where the
// scene has at most SPLIT_DIRECT_LIGHTS (one light chosen at random would
// leave its choice's noise unfiltered); with more it keeps NEE_ONE's one
// light and nothing is kept apart (all is filtered).
override SPLIT_DIRECT: bool = false;
const SPLIT_DIRECT_LIGHTS: u32 = 4u;
var<private> path_direct: vec3f;
var<private> path_direct_from: vec3f;
var<private> path_direct_state: u32;

// SPLIT_DIRECT: the recorded hit's light samples are all in `result` (the
// last light's shadow ray traced): what they brought is its direct light.
fn end_direct(result: vec3f) {
    if SPLIT_DIRECT && path_direct_state == 2u {
        path_direct = result - path_direct_from;
        path_direct_state = 3u;
    }
}

// With BLUE_NOISE_FIRST, a path's first hit that is not a perfect mirror
// draws its light choice, light sample and bounce direction from blue
// noise (shared/blue_noise.wgsl) instead of white: set per path by
// start_blue_noise, which the caller (path_render.wgsl, the gradient
// pass's replay) calls for a pixel's first path.
override BLUE_NOISE_FIRST: bool = false;
var<private> path_bn: BlueNoise;
var<private> path_bn_pending: bool;

fn start_blue_noise(pixel: vec2u, frame_index: u32) {
    path_bn_pending = BLUE_NOISE_FIRST;
    if BLUE_NOISE_FIRST {
        path_bn = blue_noise_at(pixel, frame_index);
    }
}

// The path tracer's random streams (shared/path_render.wgsl): a pixel's
// path in frame f draws from rng_at(rng_frame_key(f, PATH_RENDER_SALT,
// seed), pixel), so a pass can trace last frame's path again
// (shaders/realtime/gradient.wgsl).
const PATH_RENDER_SALT: u32 = 0x70617468u;

// A path in flight: the ray in hand's direction, what it carries, and
// what the bounce before left for multiple importance sampling.
struct PathState {
    rd: vec3f,
    throughput: vec3f,
    result: vec3f,
    // The BSDF pdf of the last bounce if it was diffuse (then a light hit
    // is weighted against NEE), or a negative value (camera / specular).
    bsdf_pdf: f32,
    prev_p: vec3f,
    // The shading normal at prev_p, and the sum of the light choice's
    // weights there (NEE_ONE; below 0: every light was sampled): a light a
    // bounce ray meets is weighed against the chance that next-event
    // estimation chose it.
    prev_n: vec3f,
    choice_sum: f32,
    // What next-event estimation at prev_p gave as the pdf of the scene's
    // one light (SCENE_ONE_LIGHT): light_pdf there, bit for bit.
    light_pdf: f32,
    depth: u32,
    // The last bounce was the first hit's diffuse one under
    // FIRST_DIRECT_APART: a light it hits is another pass's to count.
    direct_apart: bool,
    // The ray cone textures are read with (shared/textures.wgsl): its
    // width at the last hit and its spread angle (a pixel's from the
    // camera; wider after a rough bounce).
    cone: vec2f,
}

// `spread`: the camera cone's spread angle (pixel_spread).
fn new_path(ro: vec3f, rd: vec3f, spread: f32) -> PathState {
    return PathState(rd, vec3f(1.0), vec3f(0.0), -1.0, ro, vec3f(0.0, 0.0, 1.0), -1.0, 0.0, 0u, false, vec2f(0.0, spread));
}

// What a bounce leaves to trace: the next ray from `o` along the state's
// rd if `go_on`, and the shadow ray of the last light it sampled,
// `shadow_light` (shadow_tmax 0: none), whose light counts if nothing
// blocks it. `ended`: the path ended before any ray (a miss, a light).
struct Bounce {
    ended: bool,
    go_on: bool,
    o: vec3f,
    shadow_dir: vec3f,
    shadow_tmax: f32,
    shadowed_light: vec3f,
    shadow_light: u32,
}

// A bounce that traces nothing.
fn ended_bounce() -> Bounce {
    return Bounce(true, false, vec3f(0.0), vec3f(0.0, 0.0, 1.0), 0.0, vec3f(0.0), max(light_count(), 1u) - 1u);
}

// One bounce of a path at `hit` (the closest hit of the ray in hand).
fn path_bounce(st: ptr<function, PathState>, hit: Hit, rr_depth: u32, first_emission: bool, rng: ptr<function, Rng>) -> Bounce {
    var out = ended_bounce();
    let depth = (*st).depth;
    // SPLIT_DIRECT: this hit ends the recorded hit's bounce ray (a coat's
    // specular lobe counts as direct light whole: path_direct_total).
    let direct_bounce = SPLIT_DIRECT && path_direct_state == 3u && !path_lobe_traced;
    if direct_bounce {
        path_direct_state = 4u;
    }
    let rd = (*st).rd;
    // Loaded before the miss test (a miss has material 0): the G-buffer's
    // specular share comes from the same two texels.
    (*st).cone.x += (*st).cone.y * hit.t;
    let surface = shaded_surface_at(hit.material, hit.prim, hit.position, rd, (*st).cone.x, hit.normal);
    let m = surface.m;
    // The hit with its shading normal bent by the material's normal
    // texture, if it has one.
    var shaded = hit;
    shaded.normal = surface.n;
    let recording = FIRST_HIT && (depth == 0u || (THROUGH_MIRRORS && path_primary_open));
    if recording {
        path_primary_pos = select(vec4f(hit.position, hit.t), vec4f(rd, -1.0), !hit_found(hit));
        let facing = shaded.normal * select(1.0, -1.0, dot(hit.geo_normal, rd) > 0.0);
        var view_dependent = select(m.specular, 1.0, depth > 0u);
        if is_metal_rough(m) && depth == 0u {
            // The share of what it shows that depends on the view, roughly.
            view_dependent = mr_specular_probability(as_metal_rough(m), abs(dot(shaded.normal, rd))) * (1.0 - m.roughness);
        }
        path_primary_normal = select(vec4f(facing, view_dependent), vec4f(0.0), !hit_found(hit));
        path_primary_ids = select(vec4u(hit.material, hit.object, bitcast<u32>(gbuffer_offset_error(hit)), hit.prim), vec4u(NO_HIT, NO_HIT, 0u, NO_HIT), !hit_found(hit));
        path_primary_open = THROUGH_MIRRORS && hit_found(hit) && hit.light < 0 && m.specular >= 1.0 && m.roughness <= 0.0 && !is_metal_rough(m);
        path_primary_direct = vec3f(0.0);
        let lit = hit_found(hit) && hit.object != NO_OBJECT && !is_emissive(m);
        // Seen through mirrors, times their colours (the throughput so far:
        // 1 at the camera's first hit), so the light a denoiser divides out
        // is the light at the surface, as beside the mirror.
        path_primary_albedo = select(vec4f(0.0), vec4f(m.albedo * (*st).throughput, 1.0), lit);
        path_direct_state = select(0u, 1u, SPLIT_DIRECT && !path_primary_open && light_count() <= SPLIT_DIRECT_LIGHTS);
        if THROUGH_MIRRORS {
            if depth == 0u {
                path_camera_dir = rd;
                path_primary_len = 0.0;
            }
            path_primary_len += hit.t;
            path_primary_dir = rd;
            path_primary_through = depth > 0u;
        }
    }
    // This hit's diffuse direct light is another pass's (FIRST_DIRECT_APART;
    // that pass shades Lambert surfaces only: a metallic-roughness one
    // takes its own).
    let direct_apart = FIRST_DIRECT_APART && recording && !path_primary_open && !is_metal_rough(m);
    let light_hit_apart = (*st).direct_apart;
    (*st).direct_apart = false;
    if !hit_found(hit) {
        var seen = frame.background;
        if SCENE_ENVIRONMENT {
            // The environment is a light: weighted against next-event
            // estimation after a bounce that took it; like a light, it
            // counts nothing first without first_emission, nor where
            // another pass takes the first hit's direct light.
            let l = env_light();
            let env_index = light_count() - 1u;
            let uv = env_uv(l, rd);
            var w = select(1.0, 0.0, light_hit_apart || (depth == 0u && !first_emission));
            if w > 0.0 && (*st).bsdf_pdf > 0.0 {
                var pdf = env_pdf_at(l, uv, rd);
                if NEE_ONE {
                    pdf *= light_choice_prob(env_index, l, (*st).prev_p, (*st).prev_n, (*st).choice_sum);
                }
                w = power_heuristic((*st).bsdf_pdf, pdf);
            }
            seen = env_radiance_at(l, uv) * w;
        }
        (*st).result += (*st).throughput * seen;
        if direct_bounce && SCENE_ENVIRONMENT {
            path_direct += (*st).throughput * seen;
        }
        return out;
    }
    let p = hit.position;
    if is_emissive(m) && (depth > 0u || first_emission || hit.light < 0) {
        var w = 1.0;
        if hit.light >= 0 && light_hit_apart {
            w = 0.0;
        } else if hit.light >= 0 && (*st).bsdf_pdf > 0.0 {
            var pdf = (*st).light_pdf;
            if !SCENE_ONE_LIGHT {
                let l = load_light(u32(hit.light));
                pdf = light_pdf(l, (*st).prev_p);
                if NEE_ONE {
                    pdf *= light_choice_prob(u32(hit.light), l, (*st).prev_p, (*st).prev_n, (*st).choice_sum);
                }
            }
            w = power_heuristic((*st).bsdf_pdf, pdf);
        }
        (*st).result += (*st).throughput * m.emission * w;
        if direct_bounce {
            path_direct += (*st).throughput * m.emission * w;
        }
    }
    // SPLIT_DIRECT: the result before the recorded hit's light samples.
    if SPLIT_DIRECT && path_direct_state == 1u {
        path_direct_from = (*st).result;
        path_direct_state = 2u;
    }
    if hit.light >= 0 {
        return out; // lights do not reflect
    }
    out.ended = false;
    let f = facing(shaded, rd);
    let ng = f.ng;
    let n = f.n;
    let o = offset_ray(p, ng, hit.error);
    out.o = o;
    out.shadow_dir = n;
    if direct_apart {
        // The diffuse lobe's expected share: the path below takes it with
        // probability 1 - specular.
        let diffuse = select(1.0, 1.0 - m.specular, SCENE_SPECULAR);
        path_primary_direct = (*st).throughput * diffuse * m.albedo / PI;
        path_primary_ng = ng;
    }
    var go_on = true;
    // Drawn whether or not the scene has specular surfaces, so a
    // specialised shader draws the same random numbers as a generic one.
    let u_lobe = rand_f32(rng);
    // The white numbers below are drawn all the same, so the rest of the
    // path draws what it would without blue noise.
    let blue = BLUE_NOISE_FIRST && path_bn_pending && !(m.specular >= 1.0 && m.roughness <= 0.0);
    if blue {
        path_bn_pending = false;
    }
    // (A metallic-roughness surface's specular share is a stand-in for
    // other passes: its whole BRDF is sampled below.)
    // Both lobes at a recorded coat (SPLIT_LOBES): the diffuse one below,
    // weighted by its share, the specular one traced after the path ends.
    let split = SPLIT_LOBES && SCENE_COATS && SCENE_SPECULAR && recording && m.specular > 0.0 && m.specular < 1.0 && !is_metal_rough(m);
    let diffuse_share = select(1.0, 1.0 - m.specular, split);
    if split {
        var dir = reflect(rd, n);
        if m.roughness > 0.0 {
            dir = sample_glossy(dir, n, m.roughness, rand2(rng));
        }
        path_lobe_pending = !(dot(dir, ng) <= 0.0);
        path_lobe_o = o;
        path_lobe_dir = dir;
        path_lobe_throughput = (*st).throughput * m.albedo * m.specular;
        path_lobe_cone = vec2f((*st).cone.x, max((*st).cone.y, m.roughness));
    }
    if SCENE_SPECULAR && u_lobe < m.specular && !is_metal_rough(m) && !split {
        var dir = reflect(rd, n);
        if m.roughness > 0.0 {
            dir = sample_glossy(dir, n, m.roughness, select(rand2(rng), path_bn.a.xy, blue));
        }
        // (Written as the negated stop test: a NaN goes on, as it did.)
        go_on = !(dot(dir, ng) <= 0.0);
        if go_on {
            (*st).throughput *= m.albedo;
            (*st).bsdf_pdf = -1.0;
            (*st).rd = dir;
            (*st).cone.y = max((*st).cone.y, m.roughness);
        }
    } else {
        // Next-event estimation: every light, one sample each; with
        // NEE_ONE one light, chosen by what it could bring here
        // (light_choice.wgsl), but every light at a recorded hit whose
        // direct light is kept apart.
        var first = 0u;
        var lights = light_count();
        var chosen = 1.0;
        (*st).choice_sum = -1.0;
        if NEE_ONE && light_count() > 1u && !(SPLIT_DIRECT && path_direct_state == 2u) {
            // (Drawn all the same where another pass takes this hit's
            // direct light, which needs no choice: the numbers after it
            // stay where they were.)
            let u_light = select(rand_f32(rng), path_bn.b.x, blue);
            if !direct_apart {
                let c = choose_light(o, n, u_light);
                first = c.pick;
                lights = select(0u, 1u, c.pick_weight > 0.0);
                chosen = c.pick_weight / max(c.sum, 1e-30);
                (*st).choice_sum = c.sum;
            }
        }
        // (Skipped as a whole under FIRST_DIRECT_APART: a loop count that
        // is not a constant would keep the shadow test of lights before the
        // last, which a one-light scene folds away, and cost 1.3x the pass.)
        let mr = as_metal_rough(m);
        let metal_rough = is_metal_rough(m);
        if !direct_apart {
            for (var j = 0u; j < lights; j++) {
                let i = first + j;
                let l = load_light(i);
                let s = sample_light(l, o, select(rand2(rng), path_bn.a.zw, blue));
                (*st).light_pdf = s.pdf;
                let cos_n = dot(n, s.dir);
                if !s.valid || cos_n <= 0.0 || dot(s.dir, ng) <= 0.0 {
                    continue;
                }
                // The BRDF toward the light and the pdf of sampling it.
                var f = m.albedo * (diffuse_share / PI);
                var f_pdf = cos_n / PI;
                if metal_rough {
                    f = mr_eval(mr, n, -rd, s.dir);
                    f_pdf = mr_pdf(mr, n, -rd, s.dir);
                }
                var w = 1.0;
                if s.pdf > 0.0 {
                    w = power_heuristic(s.pdf * chosen, f_pdf);
                }
                let light = (*st).throughput * f * s.weight * cos_n * w / chosen;
                // The last light sampled (NEE_ONE's one) waits for the
                // next ray: traced together, the lanes of a SIMD group
                // trace their shadow rays at once, and a flat scene's
                // sweep takes both rays in one pass.
                if j + 1u == lights {
                    out.shadow_dir = s.dir;
                    out.shadow_tmax = shadow_ray_length(s);
                    out.shadowed_light = light;
                    out.shadow_light = i;
                } else if light_visible(i, o, s) {
                    (*st).result += light;
                }
            }
        }
        let u_dir = select(rand2(rng), path_bn.a.xy, blue);
        if metal_rough {
            // The whole BRDF, sampled as a mixture of its lobes (the lobe
            // chosen with u_lobe, which the thesis's specular test drew).
            let dir = mr_sample(mr, n, -rd, u_lobe, u_dir);
            let cos_d = dot(n, dir);
            let pdf = mr_pdf(mr, n, -rd, dir);
            go_on = !(dot(dir, ng) <= 0.0 || cos_d <= 0.0 || pdf <= 0.0);
            if go_on {
                (*st).throughput *= mr_eval(mr, n, -rd, dir) * cos_d / pdf;
                (*st).bsdf_pdf = pdf;
                (*st).rd = dir;
                (*st).cone.y = max((*st).cone.y, m.roughness * m.roughness);
            }
        } else {
            let dir = sample_cosine(n, u_dir);
            let cos_d = dot(n, dir);
            go_on = !(dot(dir, ng) <= 0.0 || cos_d <= 0.0);
            if go_on {
                (*st).throughput *= m.albedo * diffuse_share;
                (*st).bsdf_pdf = cos_d / PI;
                (*st).rd = dir;
                (*st).cone.y = max((*st).cone.y, 1.0);
                (*st).direct_apart = direct_apart;
            }
        }
    }
    if go_on {
        (*st).prev_p = o;
        (*st).prev_n = n;
        if depth + 1u >= rr_depth {
            let q = min(max3((*st).throughput), 0.95);
            go_on = !(rand_f32(rng) >= q);
            if go_on {
                (*st).throughput /= q;
            }
        }
    }
    out.go_on = go_on;
    return out;
}

// Whether a path that `ends` at this bounce goes on along its coat's
// specular lobe (SPLIT_LOBES): its next ray is then path_lobe_o,
// path_lobe_dir, and start_lobe sets up the rest once that ray is traced.
fn lobe_follows(ends: bool) -> bool {
    let follows = SPLIT_LOBES && SCENE_COATS && path_lobe_pending && ends;
    if follows {
        path_lobe_pending = false;
    }
    return follows;
}

// The path state of a coat's specular lobe (SPLIT_LOBES), its ray the
// one just traced: the path goes on from the coat's bounce, at depth 1.
fn start_lobe(st: ptr<function, PathState>) {
    (*st).throughput = path_lobe_throughput;
    (*st).rd = path_lobe_dir;
    (*st).bsdf_pdf = -1.0;
    (*st).prev_p = path_lobe_o;
    (*st).cone = path_lobe_cone;
    (*st).direct_apart = false;
    (*st).depth = 1u;
    path_lobe_from = (*st).result;
    path_lobe_traced = true;
}

// The first hit's direct light (SPLIT_DIRECT) of a path that ended with
// `result`: its light samples' share and its coat's specular lobe's.
fn path_direct_total(result: vec3f) -> vec3f {
    if path_direct_state >= 3u && path_lobe_traced {
        return path_direct + (result - path_lobe_from);
    }
    return path_direct;
}

// The radiance arriving at `ro_in` from direction -`rd_in`: at most
// `max_depth` bounces, Russian roulette from bounce `rr_depth`. Without
// `first_emission`, a light hit first counts nothing (what the hybrid's
// light passes shade is left out: indirect light at a probe; emissive
// surfaces still count, as no light pass samples them).
// `flat`: the entry point's copy of scene_flat (see trace_pair); `spread`:
// the ray cone's spread angle, which textures are read with (new_path).
fn trace_path(flat: ptr<function, FlatScene>, ro_in: vec3f, rd_in: vec3f, spread: f32, max_depth: u32, rr_depth: u32, first_emission: bool, rng: ptr<function, Rng>) -> vec3f {
    var st = new_path(ro_in, rd_in, spread);
    // The hit of the ray in hand: the camera ray's traced here, each
    // bounce's at the end of the bounce before, with that bounce's last
    // shadow ray (trace_pair: one loop over a flat scene for both).
    var hit = trace_closest(ro_in, rd_in, 3.0e38);
    path_lobe_pending = false;
    path_lobe_traced = false;
    for (var depth = 0u; depth < max_depth; depth++) {
        st.depth = depth;
        let b = path_bounce(&st, hit, rr_depth, first_emission, rng);
        // A path that ends here (or at max_depth) needs no next hit,
        // unless a coat's specular lobe waits (SPLIT_LOBES): its ray is
        // then the one traced, in the same loop (a second loop would cost
        // every lane its body once on a CPU driver).
        var ray_o = b.o;
        var ray_d = st.rd;
        var go_on = b.go_on && depth + 1u < max_depth;
        let switch_lobe = lobe_follows(b.ended || !go_on);
        if switch_lobe {
            ray_o = path_lobe_o;
            ray_d = path_lobe_dir;
            go_on = true;
        } else if b.ended {
            break;
        }
        let next = trace_pair(flat, ray_o, ray_d, go_on, b.o, b.shadow_dir, b.shadow_tmax, b.shadow_light);
        if !next.blocked {
            st.result += b.shadowed_light;
        }
        end_direct(st.result);
        if switch_lobe {
            start_lobe(&st);
            depth = 0u;
            hit = next.hit;
            continue;
        }
        if !b.go_on {
            break;
        }
        hit = next.hit;
    }
    return finite_or_zero(st.result);
}
