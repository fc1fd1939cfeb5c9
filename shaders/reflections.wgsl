// Reflections (thesis 4.2.1): specular surfaces bounce the view ray by the
// law of reflection and add what they see, weighted by a running specular
// attenuation, up to `max_depth` bounces (the roughness term is dropped, as
// in the thesis). When a reflected hit is on screen and the G-buffer there
// holds the same object with the same normal, its already lit colour is
// reused (`reuse` 1) instead of shading it again; otherwise the hit is
// shaded with `samples` samples per sphere light and the point lights.
// `reflect_reuse` records per pixel: 1 reused, 0 shaded, -1 not specular.
#import lights

struct Params {
    max_depth: u32, // ui: 1..8 limit "max depth"
    samples: u32, // ui: 1..16 limit
    reuse: u32, // ui: bool "screen-space reuse"
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var gbuf_pos: texture_2d<f32>;
@group(0) @binding(2) var gbuf_normal: texture_2d<f32>;
@group(0) @binding(3) var gbuf_id: texture_2d<u32>;
@group(0) @binding(4) var lit_in: texture_2d<f32>;
@group(0) @binding(5) var lit: texture_storage_2d<rgba32float, write>;
@group(0) @binding(6) var reflect_reuse: texture_storage_2d<r32float, write>;

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

// Direct light at a hit (diffuse share), as the lights pass computes it.
fn shade(p: vec3f, n: vec3f, m: Material, rng: ptr<function, Rng>) -> vec3f {
    let o = offset_ray(p, n);
    var e = vec3f(0.0);
    for (var i = 0u; i < frame.n_lights; i++) {
        let l = scene_lights[i];
        let count = select(max(params.samples, 1u), 1u, l.kind == LIGHT_POINT);
        e += light_irradiance(l, p, n, o, count, 0u, 0.0, rng);
    }
    return finite_or_zero(m.albedo * (1.0 - m.specular) / PI * e);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let before = textureLoad(lit_in, id.xy, 0);
    let ids = textureLoad(gbuf_id, id.xy, 0);
    if !is_lit_surface(ids) || scene_materials[ids.x].specular <= 0.0 {
        textureStore(lit, id.xy, before);
        textureStore(reflect_reuse, id.xy, vec4f(-1.0, 0.0, 0.0, 1.0));
        return;
    }
    var rng = rng_for(id.xy, frame.frame_index, SALT, frame.seed);
    let m0 = scene_materials[ids.x];
    var p = textureLoad(gbuf_pos, id.xy, 0).xyz;
    var n = normalize(textureLoad(gbuf_normal, id.xy, 0).xyz);
    var dir = reflect(normalize(p - frame.camera.origin), n);
    var atten = m0.specular * m0.albedo;
    var color = before.rgb;
    var reused = 0.0;
    for (var depth = 0u; depth < params.max_depth; depth++) {
        let hit = trace_closest(offset_ray(p, n), dir, 3.0e38);
        if !hit_found(hit) {
            color += atten * frame.background;
            break;
        }
        let m = scene_materials[hit.material];
        if is_emissive(m) {
            color += atten * m.emission;
            break;
        }
        var hn = hit.normal;
        if dot(hn, dir) > 0.0 {
            hn = -hn;
        }
        var diffuse = vec3f(0.0);
        var from_screen = false;
        if params.reuse == 1u {
            let q = screen_pixel(hit.position);
            if q.x >= 0 {
                let qid = textureLoad(gbuf_id, q, 0);
                let qn = textureLoad(gbuf_normal, q, 0).xyz;
                // The same object, facing the same way, and the same surface:
                // the G-buffer point lies on the hit's tangent plane within a
                // share of the distance from the camera (relative, so it holds
                // at any scale; a face of the object hidden behind another
                // face of it projects to the same pixel and is rejected here).
                let qp = textureLoad(gbuf_pos, q, 0).xyz;
                let on_plane = abs(dot(qp - hit.position, hn)) <= REUSE_PLANE_TOL * length(hit.position - frame.camera.origin);
                if qid.y == hit.object && dot(qn, hn) > 0.95 && on_plane {
                    diffuse = textureLoad(lit_in, q, 0).rgb;
                    from_screen = true;
                }
            }
        }
        if !from_screen {
            diffuse = shade(hit.position, hn, m, &rng);
        }
        if depth == 0u {
            reused = select(0.0, 1.0, from_screen);
        }
        color += atten * diffuse;
        if m.specular <= 0.0 {
            break;
        }
        atten *= m.specular * m.albedo;
        p = hit.position;
        n = hn;
        dir = reflect(dir, hn);
    }
    textureStore(lit, id.xy, vec4f(finite_or_zero(color), 1.0));
    textureStore(reflect_reuse, id.xy, vec4f(reused, 0.0, 0.0, 1.0));
}
