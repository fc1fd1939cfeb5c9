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

// Direct light at a hit (diffuse share), as the lights pass computes it,
// plus `extra` irradiance (an importer's indirect light).
fn shade(p: vec3f, n: vec3f, error: f32, m: Material, extra: vec3f, rng: ptr<function, Rng>) -> vec3f {
    let o = offset_by(p, n, error);
    var e = vec3f(0.0);
    for (var i = 0u; i < light_count(); i++) {
        let l = load_light(i);
        let count = select(max(params.samples, 1u), 1u, l.kind != LIGHT_SPHERE);
        e += light_irradiance(i, l, p, n, o, count, 0u, 0.0, rng);
    }
    e += extra;
    return finite_or_zero(m.albedo * (1.0 - m.specular) / PI * e);
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
    // 1 reused, 0 shaded, -1 not specular (reflect_reuse).
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
    // The ray cone's width so far (textures' level of detail).
    cone: f32,
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
    r.p = pos.xyz;
    r.n = normalize(textureLoad(gbuf_normal, id.xy).xyz);
    r.error = bitcast<f32>(ids.z);
    let view = normalize(r.p - frame.camera.origin);
    r.dir = reflect(view, r.n);
    r.atten = specular_tint(m0, -dot(view, r.n));
    r.reused = 0.0;
    r.depth = 0u;
    r.done = false;
    return r;
}

// Moves on to the next hit: adds what a miss, an emitter or the screen (a
// reused colour) gives, and returns true at a hit that needs shading.
fn reflect_next(r: ptr<function, Reflection>) -> bool {
    while !(*r).done && (*r).depth < params.max_depth {
        let hit = trace_closest(offset_by((*r).p, (*r).n, (*r).error), (*r).dir, 3.0e38);
        if !hit_found(hit) {
            (*r).color += (*r).atten * sky((*r).dir);
            (*r).done = true;
            return false;
        }
        (*r).cone += hit.t * pixel_spread();
        let m = material_at(hit.material, hit.prim, hit.position, (*r).dir, (*r).cone);
        if is_emissive(m) {
            (*r).color += (*r).atten * m.emission;
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
    if m.specular <= 0.0 {
        (*r).done = true;
        return;
    }
    (*r).atten *= specular_tint(m, -dot((*r).dir, (*r).hit_n));
    (*r).p = (*r).hit_p;
    (*r).n = (*r).hit_n;
    (*r).error = (*r).hit_error;
    (*r).dir = reflect((*r).dir, (*r).hit_n);
    (*r).depth += 1u;
}

// Shades the hit `reflect_next` stopped at, with `extra` irradiance.
fn reflect_shade(r: ptr<function, Reflection>, extra: vec3f) {
    var rng = (*r).rng;
    let diffuse = shade((*r).hit_p, (*r).hit_n, (*r).hit_error, (*r).hit_mat, extra, &rng);
    (*r).rng = rng;
    reflect_advance(r, diffuse);
}

fn reflect_end(id: vec3u, r: Reflection) {
    textureStore(lit, id.xy, vec4f(finite_or_zero(r.color), 1.0));
    textureStore(reflect_reuse, id.xy, vec4f(r.reused, 0.0, 0.0, 1.0));
}
