// The thesis's irradiance volume (chapter 3), baked on the GPU. Each probe
// keeps two S x S hemisphere maps (Shirley-Chiu concentric, equal area) in
// a tile of 2S x S texels of a `ProbeTiles(2S, S)` atlas.
//   `radiance` (progressive): one path a dispatch per bucket, from the
//   probe in a random direction within the bucket; the running mean of
//   those paths is the bucket's radiance.
//   `integrate` (when the radiance changed): each bucket's irradiance, the
//   quadrature over every bucket of its radiance times the cosine to the
//   bucket's centre direction (averaged over points within the bucket),
//   each bucket 2 pi / S^2 of solid angle. The
//   thesis read the samples back to solve this on the CPU; here it stays
//   on the GPU.
#import path
#import probes
#import run

struct Params {
    bounces: u32, // ui: 1..16 limit "bounces per path"
    rr_depth: u32, // ui: 0..16 "roulette from bounce"
    // 1: radiance includes lights seen straight from the probe (chapter 3:
    // the volume is all the light); 0: only light from surfaces (indirect,
    // for a graph that shades direct light itself).
    emitters: u32, // ui: 0..1 "lights seen from the probe"
    // 0: path traced (chapter 3); 1: Greger et al.'s diffuse radiance, the
    // method the thesis compares with (table 3.2): every surface counts as
    // fully lit, the first diffuse hit's albedo (after mirrors) is the
    // radiance.
    method: u32, // ui: 0..1 "method (0 path traced, 1 diffuse radiance)"
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var thesis_radiance: texture_storage_2d<rgba32float, read_write>;

const SALT: u32 = 0x74686573u;

// Samples per axis: the height of a probe's tile.
fn spa(dims: vec2u) -> u32 {
    return dims.y / max(frame.probe_n, 1u);
}

// Greger et al. 1998: the radiance seen along a ray is the albedo of the
// first diffuse surface (as if it were fully lit by white light), scaled
// by the mirrors on the way; emitters show their emission.
fn diffuse_radiance(o: vec3f, d: vec3f) -> vec3f {
    var origin = o;
    var dir = d;
    var atten = vec3f(1.0);
    for (var depth = 0u; depth < 8u; depth++) {
        let hit = trace_closest(origin, dir, 3.0e38);
        if !hit_found(hit) {
            return atten * select(sky(dir), vec3f(0.0), SCENE_ENVIRONMENT && params.emitters == 0u);
        }
        // A probe's rays gather diffusely: a wide cone (one radian).
        let m = material_at(hit.material, hit.prim, hit.position, dir, hit.t);
        if is_emissive(m) {
            return select(vec3f(0.0), atten * m.emission, params.emitters != 0u || hit.light < 0);
        }
        if m.specular <= 0.0 {
            return atten * m.albedo;
        }
        let ng = facing(hit, dir).ng;
        atten *= specular_tint(m, -dot(dir, ng));
        dir = reflect(dir, ng);
        origin = offset_ray(hit.position, ng, hit.error);
    }
    return vec3f(0.0);
}

// Point lights are deltas no ray finds: each one visible from probe
// position p whose direction falls in bucket `texel` gives the radiance
// that spreads its irradiance I / d^2 over the bucket's solid angle, so
// `integrate` counts it (at the bucket's cosine) like any light the probe
// sees. Without it a surface lit only by point lights, seen from the
// probes' side, had no light in the volume.
fn point_lights_in_bucket(p: vec3f, texel: vec2u, s: u32) -> vec3f {
    var sum = vec3f(0.0);
    let solid_angle = 2.0 * PROBE_PI / f32(s * s);
    for (var i = 0u; i < light_count(); i++) {
        let l = load_light(i);
        if l.kind == LIGHT_SPHERE || (SCENE_ENVIRONMENT && l.kind == LIGHT_ENVIRONMENT) {
            continue;
        }
        let ls = sample_light(l, p, vec2f(0.5));
        if ls.valid && all(hemisphere_texel(ls.dir, s) == texel) && light_visible(i, p, ls) {
            sum += ls.weight / solid_angle;
        }
    }
    return sum;
}

@compute @workgroup_size(8, 8)
fn radiance(@builtin(global_invocation_id) id: vec3u) {
    // First thing, where every lane runs (see trace_pair).
    var flat = scene_flat;
    let dims = textureDimensions(thesis_radiance);
    let s = spa(dims);
    if frame.probe_n < 2u || s == 0u || any(id.xy >= dims) {
        return;
    }
    let tile = id.xy / vec2u(2u * s, s);
    let probe = tile.x + tile.y * frame.probe_n * frame.probe_n;
    let origin = probe_position(probe_coords(probe));
    var rng = rng_for(id.xy, run.iteration, SALT, frame.seed);
    let dir = hemisphere_texel_dir(id.xy % vec2u(2u * s, s), s, rand2(&rng));
    var l: vec3f;
    if params.method == 1u {
        l = diffuse_radiance(origin, dir);
    } else {
        // A texel's cone: s x s texels cover each hemisphere's 2 pi sr.
        l = trace_path(&flat, origin, dir, sqrt(2.0 * PI) / f32(s), params.bounces, params.rr_depth, params.emitters != 0u, &rng);
        if params.emitters != 0u {
            l += point_lights_in_bucket(origin, id.xy % vec2u(2u * s, s), s);
        }
    }
    let before = textureLoad(thesis_radiance, id.xy);
    let n = f32(run.since_change) + 1.0;
    var mean = before.rgb + (l - before.rgb) / n;
    if run.since_change == 0u {
        mean = l;
    }
    textureStore(thesis_radiance, id.xy, vec4f(mean, n));
}

@group(0) @binding(2) var radiance_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var thesis_irradiance: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 8)
fn integrate(@builtin(global_invocation_id) id: vec3u) {
    let dims = textureDimensions(thesis_irradiance);
    let s = spa(dims);
    if frame.probe_n < 2u || s == 0u || any(id.xy >= dims) {
        return;
    }
    let size = vec2u(2u * s, s);
    let corner = (id.xy / size) * size;
    let normal = hemisphere_texel_dir(id.xy % size, s, vec2f(0.5));
    // Each bucket's cosine weight from k x k points within it: the bucket
    // centre alone (the midpoint rule) is 7.8% off at S = 5 and 1.5% at
    // S = 8; 16 points or more across a map keep it under 0.4%.
    let k = clamp((16u + s - 1u) / s, 1u, 4u);
    var sum = vec3f(0.0);
    for (var y = 0u; y < s; y++) {
        for (var x = 0u; x < 2u * s; x++) {
            var w = 0.0;
            for (var j = 0u; j < k * k; j++) {
                let u = (vec2f(f32(j % k), f32(j / k)) + 0.5) / f32(k);
                w += max(dot(hemisphere_texel_dir(vec2u(x, y), s, u), normal), 0.0);
            }
            if w > 0.0 {
                sum += textureLoad(radiance_in, corner + vec2u(x, y)).rgb * (w / f32(k * k));
            }
        }
    }
    let solid_angle = 2.0 * PROBE_PI / f32(s * s);
    textureStore(thesis_irradiance, id.xy, vec4f(sum * solid_angle, 1.0));
}
