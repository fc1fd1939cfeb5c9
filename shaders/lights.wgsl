// Direct lighting, multiplied into the albedo and added to `lit`: `main`
// adds to what an albedo pass or an earlier light pass left (`lit_in`),
// `first` starts `lit` itself.
//   SPHERE_MODE 0: sphere lights are skipped (another pass handles them)
//               1: point mode, one shadow ray to the light centre, I = L pi r^2
//               2: area mode, `samples` cone samples per light with shadow rays
//   POINT_LIGHTS: whether point lights are shaded here.
// Falloff 0 is physical (inverse square); 1 is the thesis's exponential,
// exp(-falloff_k d) in place of 1/d^2.
#import origins
#import lights
#import textures

override SPHERE_MODE: u32 = 2u;
override POINT_LIGHTS: bool = true;

// Whether the scene's one light is shaded as a point (a point light, or a
// sphere light in point mode): known when the pipeline is built.
fn single_point() -> bool {
    let one = SCENE_ONE_LIGHT && (SCENE_POINT_LIGHTS != SCENE_AREA_LIGHTS);
    return one && ((SCENE_POINT_LIGHTS && POINT_LIGHTS) || (SCENE_AREA_LIGHTS && SPHERE_MODE == 1u));
}

struct Params {
    samples: u32, // ui: 1..64 limit "samples per light"
    falloff: u32, // ui: 0..1 "falloff (0 inverse-square, 1 exponential)"
    falloff_k: f32, // ui: 0..10 "exponential falloff k"
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var gbuf_pos: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var gbuf_normal: texture_storage_2d<rgba16float, read>;
@group(0) @binding(3) var gbuf_id: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(4) var lit_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(5) var lit: texture_storage_2d<rgba32float, write>;
@group(0) @binding(6) var gbuf_material: texture_storage_2d<rgba32uint, read>;

const SALT: u32 = 0x6c696768u;

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let ids = textureLoad(gbuf_id, id.xy);
    let miss = ids.y == NO_OBJECT;
    let m = stored_material(ids, textureLoad(gbuf_material, id.xy));
    // One store, the light added only where a lit surface is: CPU drivers
    // run every branch under a lane mask, so an early store for the other
    // pixels would be a second store for all of them.
    textureStore(lit, id.xy, shade(id.xy, !miss && !is_emissive(m), m, textureLoad(lit_in, id.xy), bitcast<f32>(ids.z)));
}

// The first light pass of a graph without an albedo pass: it seeds `lit`
// with what needs no lighting (emission, the background), as the albedo
// pass does. The same image with one full-screen pass and two full-screen
// textures fewer (hybrid-point.ron, hybrid.ron).
@compute @workgroup_size(128, 1)
fn first(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let ids = textureLoad(gbuf_id, id.xy);
    let miss = ids.y == NO_OBJECT;
    let m = stored_material(ids, textureLoad(gbuf_material, id.xy));
    let lit_surface = !miss && !is_emissive(m);
    textureStore(lit, id.xy, shade(id.xy, lit_surface, m, vec4f(unlit_radiance(m, miss, textureLoad(gbuf_pos, id.xy).xyz), 1.0), bitcast<f32>(ids.z)));
}

// `before` plus, on a lit surface (a hit on a non-emitter, known from the
// material m the caller loaded), the light falling on it times its diffuse
// albedo / pi, and on a metallic-roughness surface its whole BRDF toward
// point and directional lights.
// `error`: the hit's error along n (gbuf_id.z).
fn shade(id: vec2u, lit_surface: bool, m: Material, before: vec4f, error: f32) -> vec4f {
    let p = textureLoad(gbuf_pos, id.xy).xyz;
    let n = normalize(textureLoad(gbuf_normal, id.xy).xyz);
    let o = offset_by(p, n, error);
    var rng = rng_for(id.xy, frame.frame_index, SALT, frame.seed);
    var irradiance = vec3f(0.0); // sum of L cos / pdf, or I cos / d^2
    // A metallic-roughness surface's GGX lobe toward the lights no
    // reflected ray can meet (points, spots, directional lights); the
    // reflection passes take the lobe toward what rays do meet (sphere
    // lights, the sky, the scene), by light and lobe sampling.
    let metal_rough = is_metal_rough(m);
    let mr = as_metal_rough(m);
    let v = normalize(frame.camera.origin - p);
    var highlight = vec3f(0.0);
    let diffuse = shaded_diffuse(m, n, v);
    if single_point() {
        // One light, shaded as a point: one shadow ray, at the top level
        // of the shader (the written-out sweep pays there), traced from
        // the light on flat scenes (shared/origins.wgsl).
        var l = load_light(0u);
        let reflected = rays_meet(l);
        if l.kind == LIGHT_SPHERE {
            l = sphere_as_point(l);
        }
        let s = sample_light(l, o, rand2(&rng));
        let cos_n = dot(n, s.dir);
        let blocked = trace_any_from_light(l.position, o, s.dir, shadow_ray_length(s));
        let lit = s.valid && cos_n > 0.0 && !blocked;
        irradiance = select(vec3f(0.0), sample_irradiance(l, p, s, cos_n, params.falloff, params.falloff_k), lit);
        if metal_rough && !reflected {
            highlight = mr_specular(mr, n, v, s.dir) * irradiance;
        }
    }
    for (var i = 0u; i < select(light_count(), 0u, single_point()); i++) {
        var l = load_light(i);
        // (Before a sphere in point mode becomes a point.)
        let reflected = rays_meet(l);
        if l.kind != LIGHT_SPHERE && !POINT_LIGHTS {
            continue;
        }
        if l.kind == LIGHT_SPHERE {
            if SPHERE_MODE == 0u {
                continue;
            }
            if SPHERE_MODE == 1u {
                l = sphere_as_point(l); // raster style
            }
        }
        let count = select(max(params.samples, 1u), 1u, l.kind != LIGHT_SPHERE);
        let e = light_irradiance(i, l, p, n, o, count, params.falloff, params.falloff_k, &rng);
        irradiance += e;
        if metal_rough && !reflected {
            highlight += mr_specular(mr, n, v, toward_light(l, o)) * e;
        }
    }
    let radiance = finite_or_zero(diffuse / PI * irradiance + highlight);
    return select(before, vec4f(before.rgb + radiance, 1.0), lit_surface);
}
