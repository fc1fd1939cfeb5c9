// The body of the reflections pass (reflections.wgsl explains it), shared
// by reflections.wgsl and reflections_gi.wgsl (which adds indirect light
// at the hits it shades).
#import lights
#import work_list
#import textures

struct Params {
    max_depth: u32, // ui: 1..8 limit "max depth"
    samples: u32, // ui: 1..16 limit
    reuse: u32, // ui: bool "screen-space reuse"
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var gbuf_pos: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var gbuf_normal: texture_storage_2d<rgba16float, read>;
@group(0) @binding(3) var gbuf_id: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(4) var lit_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(5) var lit: texture_storage_2d<rgba32float, write>;
@group(0) @binding(6) var reflect_reuse: texture_storage_2d<r32float, write>;
@group(0) @binding(7) var gbuf_material: texture_storage_2d<rgba32uint, read>;

const SALT: u32 = 0x7265666cu;
// A GGX lobe narrower than this alpha (roughness 0.1) finds lights by its
// reflected ray alone: light samples would add a shadow ray for weights
// near 0.
const LIGHT_SAMPLED_ALPHA: f32 = 0.01;
// A rough lobe's first reflected ray is traced with probability RR_GAIN
// times its weight (at most 1): a quarter of a weight's worth of rays.
const RR_GAIN: f32 = 4.0;
// Screen-space reuse accepts a G-buffer point this close to the hit's
// tangent plane, as a share of the hit's distance from the camera.
const REUSE_PLANE_TOL: f32 = 0.01;

// The pixel showing world point x, or (-1, -1) when off screen.
fn screen_pixel(x: vec3f) -> vec2i {
    let px = project(frame.camera, x);
    if px.z <= 0.0 || any(px.xy < vec2f(0.0)) || any(px.xy >= vec2f(frame.size)) {
        return vec2i(-1);
    }
    return vec2i(px.xy);
}

// Direct light at a hit seen from v, as the lights pass computes it: the
// diffuse lobe's, plus `extra` irradiance (an importer's indirect light),
// and a metallic-roughness surface's GGX lobe toward the lights no
// reflected ray can meet (the ray reflected on from the hit meets the
// others).
fn shade(p: vec3f, n: vec3f, v: vec3f, error: f32, m: Material, extra: vec3f, rng: ptr<function, Rng>) -> vec3f {
    let o = offset_by(p, n, error);
    let metal_rough = is_metal_rough(m);
    var e = vec3f(0.0);
    var highlight = vec3f(0.0);
    for (var i = 0u; i < light_count(); i++) {
        let l = load_light(i);
        let count = select(max(params.samples, 1u), 1u, l.kind != LIGHT_SPHERE);
        let li = light_irradiance(i, l, p, n, o, count, 0u, 0.0, rng);
        e += li;
        if metal_rough && !rays_meet(l) {
            highlight += mr_specular(as_metal_rough(m), n, v, toward_light(l, o)) * li;
        }
    }
    e += extra;
    return finite_or_zero(shaded_diffuse(m, n, v) / PI * e + highlight);
}

// A metallic-roughness surface's GGX lobe lit by the lights its reflected
// rays can meet, by light sampling: one sample a light, weighed against
// the lobe's own sampling (specular_bounce) by the power heuristic, so a
// small bright sphere light is found by light samples on a rough surface
// and by the reflected ray on a smooth one, with no fireflies from either.
// p (offset to o) faces v with shading normal n.
fn specular_light(mr: MetalRough, p: vec3f, n: vec3f, o: vec3f, v: vec3f, rng: ptr<function, Rng>) -> vec3f {
    var sum = vec3f(0.0);
    if !SCENE_AREA_LIGHTS && !SCENE_ENVIRONMENT {
        return sum;
    }
    for (var i = 0u; i < light_count(); i++) {
        let l = load_light(i);
        if !rays_meet(l) {
            continue;
        }
        let s = sample_light(l, o, rand2(rng));
        let cos_n = dot(n, s.dir);
        if !s.valid || cos_n <= 0.0 || !light_visible(i, o, s) {
            continue;
        }
        let w = power_heuristic(s.pdf, mr_specular_pdf(mr, n, v, s.dir));
        sum += mr_specular(mr, n, v, s.dir) * sample_irradiance(l, p, s, cos_n, 0u, 0.0) * w;
    }
    return sum;
}

// One pixel's reflection, walked a hit at a time so the importer can add
// light at the hits that are shaded: `reflect_begin`, then while
// `reflect_next` finds a hit to shade, `reflect_shade` it (with extra
// irradiance there, or none), then `reflect_end`.
struct Reflection {
    rng: Rng,
    // Where the ray leaves from, the surface's facing normal, its direction.
    p: vec3f,
    n: vec3f,
    // p's error along n (offset_by).
    error: f32,
    dir: vec3f,
    atten: vec3f,
    color: vec3f,
    // 1 reused, 0 shaded, 0.5 not traced (roulette), -1 not specular
    // (reflect_reuse).
    reused: f32,
    depth: u32,
    done: bool,
    // The hit to shade: position, facing normal, material.
    hit_p: vec3f,
    hit_n: vec3f,
    hit_error: f32,
    hit_m: u32,
    // The hit's material with its textures read (hit_m's).
    hit_mat: Material,
    // The pdf the ray's direction was drawn with from a GGX lobe (0: a
    // mirror's), to weigh a light it meets against light sampling.
    bsdf_pdf: f32,
    // The ray cone's width so far and its spread angle (textures' level
    // of detail; wider after a rough bounce, as the path tracer's).
    cone: f32,
    spread: f32,
}

// Where a specular surface sends a reflected ray, and what the ray's light
// is multiplied by: a thesis material's mirror direction and tint
// (specular_tint); a metallic-roughness one's direction drawn from its GGX
// lobe's visible normals (Heitz 2018), weighed by f cos / pdf
// (mr_specular_weight), so that over the frames the graph accumulates, a
// rough surface's reflection is as blurred and as bright as its lobe. `n`
// faces the ray, which arrives along `dir`.
// `light`: what light sampling adds there (specular_light), for the ray's
// weight so far to multiply; `pdf`: the direction's, for the power
// heuristic where a light was also sampled, else 0 (the ray's light then
// counts whole).
struct SpecularBounce {
    dir: vec3f,
    weight: vec3f,
    pdf: f32,
    light: vec3f,
}

// p (offset to o) is the surface point, for the light samples, which are
// taken where `sample_lights` (the first surface: a shadow ray toward each
// light rays meet at every bounce cost 1.6x the frame on a room whose every surface
// is metallic-roughness) and the lobe is wide enough for them to help.
fn specular_bounce(m: Material, p: vec3f, n: vec3f, o: vec3f, dir: vec3f, sample_lights: bool, rng: ptr<function, Rng>) -> SpecularBounce {
    if is_metal_rough(m) {
        let mr = as_metal_rough(m);
        var light = vec3f(0.0);
        let lights = sample_lights && mr_alpha(mr) > LIGHT_SAMPLED_ALPHA;
        if lights {
            light = specular_light(mr, p, n, o, -dir, rng);
        }
        let l = mr_sample_specular(mr, n, -dir, rand2(rng));
        let pdf = select(0.0, mr_specular_pdf(mr, n, -dir, l), lights);
        return SpecularBounce(l, mr_specular_weight(mr, n, -dir, l), pdf, light);
    }
    return SpecularBounce(reflect(dir, n), specular_tint(m, -dot(dir, n)), 0.0, vec3f(0.0));
}

// The ray cone's spread angle after a bounce off m: a rough lobe's width
// at the least (alpha), as the path tracer widens it.
fn spread_after(m: Material, spread: f32) -> f32 {
    if is_metal_rough(m) {
        return max(spread, mr_alpha(as_metal_rough(m)));
    }
    return spread;
}

// The pass's own entry, per texel: lists the texels whose surface
// reflects for the `listed` entry, and passes the others' light through.
fn reflect_select(id: vec3u) {
    let ids = textureLoad(gbuf_id, id.xy);
    if is_lit_surface(ids) && material_specular(ids.x) > 0.0 {
        work_list_push(id.xy);
    } else {
        textureStore(lit, id.xy, textureLoad(lit_in, id.xy));
        textureStore(reflect_reuse, id.xy, vec4f(-1.0, 0.0, 0.0, 1.0));
    }
}

// Only for the texels reflect_select listed: their surface reflects, so
// nothing here checks it again.
fn reflect_begin(id: vec3u) -> Reflection {
    let before = textureLoad(lit_in, id.xy);
    let ids = textureLoad(gbuf_id, id.xy);
    var r: Reflection;
    r.color = before.rgb;
    r.rng = rng_for(id.xy, frame.frame_index, SALT, frame.seed);
    let pos = textureLoad(gbuf_pos, id.xy);
    let m0 = stored_material(ids, textureLoad(gbuf_material, id.xy));
    r.cone = pos.w * pixel_spread();
    r.spread = spread_after(m0, pixel_spread());
    r.p = pos.xyz;
    r.n = normalize(textureLoad(gbuf_normal, id.xy).xyz);
    r.error = bitcast<f32>(ids.z);
    var rng = r.rng;
    let bounce = specular_bounce(m0, r.p, r.n, offset_by(r.p, r.n, r.error), normalize(r.p - frame.camera.origin), true, &rng);
    r.color += bounce.light;
    r.dir = bounce.dir;
    r.atten = bounce.weight;
    r.bsdf_pdf = bounce.pdf;
    if is_metal_rough(m0) && mr_alpha(as_metal_rough(m0)) > LIGHT_SAMPLED_ALPHA {
        // Russian roulette on a rough lobe's ray: it goes on with
        // probability RR_GAIN times what it carries, its weight divided by
        // that, so a rough dielectric, whose coat reflects a few percent,
        // traces a fraction of its rays (sharp reflections trace all).
        let q = min(RR_GAIN * max(r.atten.x, max(r.atten.y, r.atten.z)), 1.0);
        if rand_f32(&rng) >= q {
            r.atten = vec3f(0.0);
        } else {
            r.atten /= q;
        }
    }
    r.rng = rng;
    r.done = all(r.atten == vec3f(0.0));
    r.reused = select(0.0, 0.5, r.done);
    r.depth = 0u;
    return r;
}

// Moves on to the next hit: adds what a miss, an emitter or the screen (a
// reused colour) gives, and returns true at a hit that needs shading.
fn reflect_next(r: ptr<function, Reflection>) -> bool {
    while !(*r).done && (*r).depth < params.max_depth {
        let hit = trace_closest(offset_by((*r).p, (*r).n, (*r).error), (*r).dir, 3.0e38);
        if !hit_found(hit) {
            var w = 1.0;
            if SCENE_ENVIRONMENT && (*r).bsdf_pdf > 0.0 {
                let l = env_light();
                w = power_heuristic((*r).bsdf_pdf, env_pdf_at(l, env_uv(l, (*r).dir), (*r).dir));
            }
            (*r).color += (*r).atten * sky((*r).dir) * w;
            (*r).done = true;
            return false;
        }
        (*r).cone += hit.t * (*r).spread;
        let m = material_at(hit.material, hit.prim, hit.position, (*r).dir, (*r).cone);
        if is_emissive(m) {
            var w = 1.0;
            if hit.light >= 0 && (*r).bsdf_pdf > 0.0 {
                w = power_heuristic((*r).bsdf_pdf, light_pdf(load_light(u32(hit.light)), (*r).p));
            }
            (*r).color += (*r).atten * m.emission * w;
            (*r).done = true;
            return false;
        }
        var hn = hit.normal;
        if dot(hn, (*r).dir) > 0.0 {
            hn = -hn;
        }
        (*r).hit_p = hit.position;
        (*r).hit_n = hn;
        (*r).hit_error = gbuffer_offset_error(hit);
        (*r).hit_m = hit.material;
        (*r).hit_mat = m;
        if params.reuse == 1u {
            let q = screen_pixel(hit.position);
            if q.x >= 0 {
                let qid = textureLoad(gbuf_id, q);
                let qn = textureLoad(gbuf_normal, q).xyz;
                // The same object, facing the same way, and the same surface:
                // the G-buffer point lies on the hit's tangent plane within a
                // share of the distance from the camera (relative, so it holds
                // at any scale; a face of the object hidden behind another
                // face of it projects to the same pixel and is rejected here).
                let qp = textureLoad(gbuf_pos, q).xyz;
                let on_plane = abs(dot(qp - hit.position, hn)) <= REUSE_PLANE_TOL * length(hit.position - frame.camera.origin);
                if qid.y == hit.object && dot(qn, hn) > 0.95 && on_plane {
                    if (*r).depth == 0u {
                        (*r).reused = 1.0;
                    }
                    reflect_advance(r, textureLoad(lit_in, q).rgb);
                    continue;
                }
            }
        }
        return true;
    }
    return false;
}

// Adds the hit's diffuse light and follows a specular surface on.
fn reflect_advance(r: ptr<function, Reflection>, diffuse: vec3f) {
    (*r).color += (*r).atten * diffuse;
    let m = (*r).hit_mat;
    // (No ray left to trace past the last depth.)
    if m.specular <= 0.0 || (*r).depth + 1u >= params.max_depth {
        (*r).done = true;
        return;
    }
    var rng = (*r).rng;
    let bounce = specular_bounce(m, (*r).hit_p, (*r).hit_n, offset_by((*r).hit_p, (*r).hit_n, (*r).hit_error), (*r).dir, false, &rng);
    (*r).color += (*r).atten * bounce.light;
    (*r).atten *= bounce.weight;
    if is_metal_rough(m) {
        // Russian roulette: a ray reflected twice off metallic-roughness
        // surfaces goes on with the probability of what it still carries
        // (a dielectric's coat reflects a few percent), its weight divided
        // by it, so the mean stays and most such rays are not traced.
        let q = min(max((*r).atten.x, max((*r).atten.y, (*r).atten.z)), 1.0);
        if rand_f32(&rng) >= q {
            (*r).atten = vec3f(0.0);
        } else {
            (*r).atten /= q;
        }
    }
    (*r).rng = rng;
    (*r).bsdf_pdf = bounce.pdf;
    (*r).spread = spread_after(m, (*r).spread);
    (*r).p = (*r).hit_p;
    (*r).n = (*r).hit_n;
    (*r).error = (*r).hit_error;
    (*r).dir = bounce.dir;
    (*r).depth += 1u;
    (*r).done = all((*r).atten == vec3f(0.0));
}

// Shades the hit `reflect_next` stopped at, with `extra` irradiance.
fn reflect_shade(r: ptr<function, Reflection>, extra: vec3f) {
    var rng = (*r).rng;
    let diffuse = shade((*r).hit_p, (*r).hit_n, -(*r).dir, (*r).hit_error, (*r).hit_mat, extra, &rng);
    (*r).rng = rng;
    reflect_advance(r, diffuse);
}

fn reflect_end(id: vec3u, r: Reflection) {
    textureStore(lit, id.xy, vec4f(finite_or_zero(r.color), 1.0));
    textureStore(reflect_reuse, id.xy, vec4f(r.reused, 0.0, 0.0, 1.0));
}
