// The environment light (docs/scenes.md, "Environment"; its Rust mirror,
// with the layout and the tests, is src/scene/environment.rs): radiance
// from infinitely far away, a latitude-longitude map turned about +y,
// sampled by a piecewise-constant distribution over its texels (luminance
// times sin(theta)). It is the scene's last light, of kind
// LIGHT_ENVIRONMENT: position = (width, height, rotation). Without one
// (SCENE_ENVIRONMENT false) a ray that leaves the scene sees `background`,
// which nothing samples.
#import scene
#import sampling

// Per texel (r, g, b, pdf in map space) as f32 bits, rows first; then each
// row's conditional CDF, four values a texel; then the marginal CDF.
@group(1) @binding(21) var scene_environment: texture_storage_2d<rgba32uint, read>;

// The environment light (the last light).
fn env_light() -> Light {
    return load_light(light_count() - 1u);
}

fn env_size(l: Light) -> vec2u {
    return vec2u(u32(l.position.x), u32(l.position.y));
}

// Where world direction `dir` (unit) lies on the map, (u, v) in [0, 1]:
// u = atan2(x, -z) / 2 pi, v = acos(y) / pi in the map's frame (Mitsuba's).
fn env_uv(l: Light, dir: vec3f) -> vec2f {
    let c = cos(l.position.z);
    let s = sin(l.position.z);
    let x = c * dir.x - s * dir.z;
    let z = s * dir.x + c * dir.z;
    var u = atan2(x, -z) / (2.0 * PI);
    u = select(u, u + 1.0, u < 0.0);
    return vec2f(u, acos(clamp(dir.y, -1.0, 1.0)) / PI);
}

// The world direction at (u, v): the inverse of env_uv.
fn env_dir(l: Light, uv: vec2f) -> vec3f {
    let phi = 2.0 * PI * uv.x;
    let theta = PI * uv.y;
    let st = sin(theta);
    let x = sin(phi) * st;
    let z = -cos(phi) * st;
    let c = cos(l.position.z);
    let s = sin(l.position.z);
    return vec3f(c * x + s * z, cos(theta), -s * x + c * z);
}

// The pdf in map space of the texel at (u, v).
fn env_map_pdf(l: Light, uv: vec2f) -> f32 {
    let size = env_size(l);
    let x = min(u32(uv.x * f32(size.x)), size.x - 1u);
    let y = min(u32(uv.y * f32(size.y)), size.y - 1u);
    return bitcast<f32>(scene_texel(scene_environment, y * size.x + x).w);
}

// The radiance at (u, v) of the map: filtered bilinearly between texel
// centres, wrapping across u and clamped in v (Mitsuba's `envmap` filters
// so; the sampling pdf stays per texel, which keeps every estimate
// unbiased where it is not zero).
fn env_radiance_at(l: Light, uv: vec2f) -> vec3f {
    let size = env_size(l);
    let p = uv * vec2f(size) - 0.5;
    let f = floor(p);
    let t = p - f;
    let x0 = u32(i32(f.x) + i32(size.x)) % size.x;
    let x1 = (x0 + 1u) % size.x;
    let y0 = u32(clamp(i32(f.y), 0, i32(size.y) - 1));
    let y1 = u32(clamp(i32(f.y) + 1, 0, i32(size.y) - 1));
    let a = bitcast<vec4f>(scene_texel(scene_environment, y0 * size.x + x0)).rgb;
    let b = bitcast<vec4f>(scene_texel(scene_environment, y0 * size.x + x1)).rgb;
    let c = bitcast<vec4f>(scene_texel(scene_environment, y1 * size.x + x0)).rgb;
    let d = bitcast<vec4f>(scene_texel(scene_environment, y1 * size.x + x1)).rgb;
    return mix(mix(a, b, t.x), mix(c, d, t.x), t.y);
}

// The radiance seen looking along `dir`.
fn env_radiance(l: Light, dir: vec3f) -> vec3f {
    return env_radiance_at(l, env_uv(l, dir));
}

// The solid-angle pdf env_sample draws `dir` with, given its map
// coordinates `uv` (env_uv: computed once where the radiance is read too).
fn env_pdf_at(l: Light, uv: vec2f, dir: vec3f) -> f32 {
    let sin_t = sqrt(1.0 - min(dir.y * dir.y, 1.0));
    if !(sin_t > 0.0) {
        return 0.0;
    }
    return env_map_pdf(l, uv) / (2.0 * PI * PI * sin_t);
}

// Value i of the tables (four to a texel).
fn env_table(i: u32) -> f32 {
    return bitcast<f32>(scene_texel(scene_environment, i >> 2u)[i & 3u]);
}

struct EnvPick {
    i: u32,
    t: f32,
}

// The first of `n` cells (CDF values from value `base` on) whose CDF
// exceeds u, and where u falls within it.
fn env_search(base: u32, n: u32, u: f32) -> EnvPick {
    var lo = 0u;
    var hi = n - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if env_table(base + mid) > u {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    // (base > 0: the tables follow the map, so lo - 1 stays in range.)
    let start = select(env_table(base + lo - 1u), 0.0, lo == 0u);
    let width = env_table(base + lo) - start;
    return EnvPick(lo, select(0.5, clamp((u - start) / width, 0.0, 0.99999994), width > 0.0));
}

struct EnvSample {
    dir: vec3f,
    pdf: f32,
    radiance: vec3f,
}

// A direction drawn in proportion to the map's luminance (times
// sin(theta)), its solid-angle pdf and the radiance along it.
fn env_sample(l: Light, u: vec2f) -> EnvSample {
    let size = env_size(l);
    let row_texels = (size.x + 3u) / 4u;
    let tables = size.x * size.y;
    let row = env_search(4u * (tables + size.y * row_texels), size.y, u.y);
    let col = env_search(4u * (tables + row.i * row_texels), size.x, u.x);
    let uv = vec2f((f32(col.i) + col.t) / f32(size.x), (f32(row.i) + row.t) / f32(size.y));
    let map_pdf = bitcast<f32>(scene_texel(scene_environment, row.i * size.x + col.i).w);
    let sin_t = sin(PI * uv.y);
    let pdf = select(0.0, map_pdf / (2.0 * PI * PI * sin_t), sin_t > 0.0);
    return EnvSample(env_dir(l, uv), pdf, env_radiance_at(l, uv));
}

// What a ray that leaves the scene along `dir` sees.
fn sky(dir: vec3f) -> vec3f {
    if SCENE_ENVIRONMENT {
        return env_radiance(env_light(), dir);
    }
    return frame.background;
}

// What a pixel shows before any light falls on it, its material `m`
// (material 0 on a miss, looking along `dir`): an emitter's emission, the
// sky on a miss, else black. The albedo pass and a graph's first light
// pass seed `lit` with it.
fn unlit_radiance(m: Material, miss: bool, dir: vec3f) -> vec3f {
    return select(select(vec3f(0.0), m.emission, is_emissive(m)), sky(dir), miss);
}
