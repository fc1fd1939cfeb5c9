// DDGI (Majercik et al., JCGT 2019; relocation from 2021), updated a step
// each frame it runs:
//   `trace`: R rays per probe in spherical-Fibonacci directions, randomly
//   rotated each update; at each hit, the light the surface sends back:
//   direct light from this engine's light sampling (next-event
//   estimation, so the volume's noise is that of indirect light only),
//   plus albedo times the previous volume's irradiance there (one more
//   bounce per update). Rays store radiance and hit distance (negative:
//   the back of a solid surface) and their direction.
//   `relocate`: a probe with over a quarter of its rays on back faces is
//   inside geometry: it moves out through the nearest back face (at most
//   0.45 of a cell from its grid point) and is off until it is out; a probe
//   too close to a front face moves away from it.
//   `blend_irradiance`, `blend_distance`: every ray into every texel of the
//   probe's octahedral maps, by cosine (irradiance) or cosine^50 (mean and
//   mean squared distance), blended in with weight (`blend_weight`)
//   max(2/(n+2), 2/(n_change + 2(1+K))), n updates in all and n_change
//   since the scene changed: a static scene converges as 1/n, a moving
//   one follows with hysteresis 1/(1+K).
#import ddgi_volume
#import lights
#import run
#import textures

// Updates of history a change is worth (K above): after a scene change the
// blend weight starts at 1 / (1 + K).
override HYSTERESIS_FRAMES: f32 = 9.0;
// Fraction of a probe's rays on back faces that puts it inside geometry.
override BACKFACE_FRACTION: f32 = 0.25;

struct Params {
    // 1: rays that hit a light see its radiance (the volume is all the
    // light, for irradiance.ron); 0: lights only through their light on
    // surfaces (indirect light, for a graph that shades direct light).
    emitters: u32, // ui: 0..1 "lights seen from the probe"
    // 1: a hit on the back of a surface means the probe is inside a solid
    // (relocated, or off); 0: surfaces are two-sided sheets (the inside of
    // a closed sphere is a room).
    solid_backfaces: u32, // ui: 0..1 "back faces are solid"
    // 0: direct light at hits only (one bounce); 1: plus the previous
    // volume's light there (every bounce, over updates).
    bounces: u32, // ui: 0..1 "multiple bounces"
}

@group(0) @binding(0) var<uniform> params: Params;
// Per probe a tile of R x 2: radiance and distance, then direction.
@group(0) @binding(1) var ddgi_rays: texture_storage_2d<rgba32float, write>;

const SALT: u32 = 0x64646769u;

fn rays_per_probe(rays: vec2u) -> u32 {
    return rays.x / max(frame.probe_n * frame.probe_n, 1u);
}

// The light leaving hit `hit` towards -`dir`, diffuse only.
fn shade_hit(hit: Hit, dir: vec3f, rng: ptr<function, Rng>) -> vec3f {
    // A probe's rays gather diffusely: a wide cone (one radian).
    let m = material_at(hit.material, hit.prim, hit.position, dir, hit.t);
    if hit.light >= 0 {
        return select(vec3f(0.0), m.emission, params.emitters != 0u);
    }
    var out = select(vec3f(0.0), m.emission, is_emissive(m));
    let f = facing(hit, dir);
    let ng = f.ng;
    let n = f.n;
    let base = m.albedo * (1.0 - m.specular);
    let o = offset_ray(hit.position, ng, hit.error);
    var e = vec3f(0.0);
    for (var i = 0u; i < light_count(); i++) {
        e += light_irradiance(i, load_light(i), hit.position, n, o, 1u, 0u, 0.0, rng);
    }
    if params.bounces != 0u {
        e += ddgi_irradiance_at(hit.position, n, -dir);
    }
    return out + base / PI * e;
}

@compute @workgroup_size(64, 1)
fn trace(@builtin(global_invocation_id) id: vec3u) {
    let dims = textureDimensions(ddgi_rays);
    let count = rays_per_probe(dims);
    if frame.probe_n < 2u || count == 0u || id.x >= dims.x || id.y >= frame.probe_n {
        return;
    }
    let i = id.x % count;
    let probe = id.x / count + id.y * frame.probe_n * frame.probe_n;
    let origin = probe_position(probe_coords(probe)) + probe_state(probe).xyz;
    // One rotation for every probe of this update.
    var rot_rng = rng_for(vec2u(0u), run.iteration, SALT, frame.seed);
    let rot = random_rotation(vec3f(rand2(&rot_rng), rand_f32(&rot_rng)));
    let dir = normalize(rot * fibonacci_dir(i, count));
    var rng = rng_for(id.xy, run.iteration, SALT ^ 0x5bd1e995u, frame.seed);
    let hit = trace_closest(origin, dir, 3.0e38);
    // (An environment light is a light: seen from the probe, it counts
    // only where lights do.)
    var radiance = select(frame.background, select(vec3f(0.0), sky(dir), params.emitters != 0u), SCENE_ENVIRONMENT);
    var t = ddgi_max_distance();
    if hit_found(hit) {
        t = hit.t;
        if params.solid_backfaces != 0u && dot(hit.geo_normal, dir) > 0.0 && hit.light < 0 {
            radiance = vec3f(0.0);
            t = -hit.t;
        } else {
            radiance = shade_hit(hit, dir, &rng);
        }
    }
    let texel = vec2u(id.x, 2u * id.y);
    textureStore(ddgi_rays, texel, vec4f(finite_or_zero(radiance), t));
    textureStore(ddgi_rays, texel + vec2u(0u, 1u), vec4f(dir, 0.0));
}

@group(0) @binding(2) var rays: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var state: texture_storage_2d<rgba32float, read_write>;

fn min_spacing() -> f32 {
    return min(frame.probe_spacing.x, min(frame.probe_spacing.y, frame.probe_spacing.z));
}

// One invocation per probe (the state atlas has a texel per probe).
@compute @workgroup_size(8, 8)
fn relocate(@builtin(global_invocation_id) id: vec3u) {
    let dims = textureDimensions(state);
    if frame.probe_n < 2u || any(id.xy >= dims) {
        return;
    }
    let count = rays_per_probe(textureDimensions(rays));
    let corner = vec2u(id.x * count, 2u * id.y);
    var backfaces = 0u;
    var back_t = 3.0e38;
    var back_dir = vec3f(0.0);
    var front_t = 3.0e38;
    var front_dir = vec3f(0.0);
    for (var i = 0u; i < count; i++) {
        let t = textureLoad(rays, corner + vec2u(i, 0u)).w;
        let dir = textureLoad(rays, corner + vec2u(i, 1u)).xyz;
        if t < 0.0 {
            backfaces++;
            if -t < back_t {
                back_t = -t;
                back_dir = dir;
            }
        } else if t < front_t {
            front_t = t;
            front_dir = dir;
        }
    }
    var s = textureLoad(state, id.xy);
    let keep_off = 0.1 * min_spacing();
    let inside = f32(backfaces) > BACKFACE_FRACTION * f32(count);
    if inside {
        // Out through the nearest back face, a little past it.
        s = vec4f(s.xyz + back_dir * (back_t + keep_off), 0.0);
    } else {
        if front_t < keep_off {
            s = vec4f(s.xyz - front_dir * (keep_off - front_t), s.w);
        }
        s.w = 1.0;
    }
    let limit = 0.45 * frame.probe_spacing;
    textureStore(state, id.xy, vec4f(clamp(s.xyz, -limit, limit), s.w));
}

// The blend weight of this update: update k (from 0) weighs k + 1, so the
// volume is a mean weighted towards later updates. Each update sees one
// more bounce through the previous volume; with equal weights the early,
// fewer-bounce updates kept the furnace 3.5% dark after 256 (the error
// falls as 1/sqrt(n)); with linear weights it falls as 1/n, while the
// noise still falls as 1/n (4/3 of the equal-weight variance). After a
// scene change the weight starts at 1 / (1 + K) (hysteresis).
fn blend_weight() -> f32 {
    let all = 2.0 / (f32(run.iteration) + 2.0);
    let since = 2.0 / (f32(run.since_change) + 2.0 * (1.0 + HYSTERESIS_FRAMES));
    return max(all, since);
}

@group(0) @binding(4) var irradiance_maps: texture_storage_2d<rgba32float, read_write>;

// A texel of a probe's map in an atlas of `dims`: its probe's first ray,
// the ray count and the direction the texel stands for (a border texel
// the direction of the interior texel it repeats); `ok` is false outside.
struct MapTexel {
    ok: bool,
    rays_from: vec2u,
    count: u32,
    dir: vec3f,
}

fn map_texel(id: vec2u, dims: vec2u) -> MapTexel {
    let tile = dims.y / max(frame.probe_n, 1u);
    if frame.probe_n < 2u || tile < 3u || any(id >= dims) {
        return MapTexel(false, vec2u(0u), 0u, vec3f(0.0));
    }
    let n = tile - 2u;
    let t = id / tile;
    let count = rays_per_probe(textureDimensions(rays));
    return MapTexel(true, vec2u(t.x * count, 2u * t.y), count, oct_texel_dir(border_source(id % tile, n), n));
}

@compute @workgroup_size(8, 8)
fn blend_irradiance(@builtin(global_invocation_id) id: vec3u) {
    let m = map_texel(id.xy, textureDimensions(irradiance_maps));
    if !m.ok {
        return;
    }
    var sum = vec3f(0.0);
    var weights = 0.0;
    for (var i = 0u; i < m.count; i++) {
        let r = textureLoad(rays, m.rays_from + vec2u(i, 0u));
        let w = max(dot(textureLoad(rays, m.rays_from + vec2u(i, 1u)).xyz, m.dir), 0.0);
        if r.w >= 0.0 {
            sum += w * r.rgb;
            weights += w;
        }
    }
    if weights <= 0.0 {
        return;
    }
    let before = textureLoad(irradiance_maps, id.xy);
    // The cosine-weighted mean radiance is irradiance / pi.
    let e = PI * sum / weights;
    textureStore(irradiance_maps, id.xy, vec4f(mix(before.rgb, e, blend_weight()), 1.0));
}

@group(0) @binding(5) var distance_maps: texture_storage_2d<rgba32float, read_write>;

@compute @workgroup_size(8, 8)
fn blend_distance(@builtin(global_invocation_id) id: vec3u) {
    let m = map_texel(id.xy, textureDimensions(distance_maps));
    if !m.ok {
        return;
    }
    let far = ddgi_max_distance();
    var sum = vec2f(0.0);
    var weights = 0.0;
    for (var i = 0u; i < m.count; i++) {
        let d = min(abs(textureLoad(rays, m.rays_from + vec2u(i, 0u)).w), far);
        let w = pow(max(dot(textureLoad(rays, m.rays_from + vec2u(i, 1u)).xyz, m.dir), 0.0), 50.0);
        sum += w * vec2f(d, d * d);
        weights += w;
    }
    if weights <= 0.0 {
        return;
    }
    let before = textureLoad(distance_maps, id.xy);
    let moments = mix(before.rg, sum / weights, blend_weight());
    textureStore(distance_maps, id.xy, vec4f(moments, 0.0, 1.0));
}
