// Diffuse light from the irradiance volume: at each lit surface of the
// G-buffer, albedo / pi times the volume's irradiance for its normal, added
// to `lit`. Entry `thesis` reads chapter 3's maps (probes_thesis.wgsl):
// trilinear over the 8 probes of the point's cell, the normal mapped back
// to its bucket, no filtering within a map (as the thesis did). Entry
// `ddgi` reads DDGI's maps (probes_ddgi.wgsl) with visibility
// (shared/ddgi_volume.wgsl). `thesis_view` and `ddgi_view` draw each probe
// as a small sphere showing the irradiance / pi its maps hold for the
// sphere's normal (a debug view; DDGI's probes at their relocated places,
// inactive ones black).
#import ddgi_volume
#import lights
#import light_choice
#import textures

@group(0) @binding(0) var gbuf_pos: texture_storage_2d<rgba32float, read>;
@group(0) @binding(1) var gbuf_normal: texture_storage_2d<rgba16float, read>;
@group(0) @binding(2) var gbuf_id: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(3) var albedo: texture_storage_2d<rgba32float, read>;
@group(0) @binding(4) var lit_in: texture_storage_2d<rgba32float, read>;
@group(0) @binding(5) var lit: texture_storage_2d<rgba32float, write>;
@group(0) @binding(6) var thesis_irradiance: texture_storage_2d<rgba32float, read>;

// Samples per axis of the thesis maps.
fn thesis_spa() -> u32 {
    return textureDimensions(thesis_irradiance).y / max(frame.probe_n, 1u);
}

// The irradiance probe `probe` holds for normal `n` (its bucket's value).
fn thesis_probe(probe: u32, n: vec3f, s: u32) -> vec3f {
    let corner = probe_tile(probe) * vec2u(2u * s, s);
    return textureLoad(thesis_irradiance, corner + hemisphere_texel(n, s)).rgb;
}

// Trilinear over the 8 probes of `p`'s cell.
fn thesis_at(p: vec3f, n: vec3f) -> vec3f {
    let s = thesis_spa();
    if frame.probe_n < 2u || s == 0u {
        return vec3f(0.0);
    }
    let cell = probe_cell(p);
    var e = vec3f(0.0);
    for (var c = 0u; c < 8u; c++) {
        e += corner_weight(cell, c) * thesis_probe(probe_index(cell_corner(cell, c)), n, s);
    }
    return e;
}

// The G-buffer's lit surface at a pixel: where, facing, diffuse albedo.
struct Surface {
    lit: bool,
    p: vec3f,
    n: vec3f,
    // The hit's error along n (gbuf_id.z).
    error: f32,
    base: vec3f,
    before: vec4f,
}

fn surface(id: vec3u) -> Surface {
    let before = textureLoad(lit_in, id.xy);
    let ids = textureLoad(gbuf_id, id.xy);
    if !is_lit_surface(ids) {
        return Surface(false, vec3f(0.0), vec3f(0.0), 0.0, vec3f(0.0), before);
    }
    let p = textureLoad(gbuf_pos, id.xy).xyz;
    let n = normalize(textureLoad(gbuf_normal, id.xy).xyz);
    let base = textureLoad(albedo, id.xy).rgb * (1.0 - material_specular(ids.x));
    return Surface(true, p, n, bitcast<f32>(ids.z), base, before);
}

// `lit` plus the diffuse light irradiance `e` gives the surface.
fn store_lit(id: vec3u, s: Surface, e: vec3f) {
    textureStore(lit, id.xy, vec4f(s.before.rgb + finite_or_zero(s.base / PI * e), 1.0));
}

@compute @workgroup_size(128, 1)
fn thesis(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let s = surface(id);
    var e = vec3f(0.0);
    if s.lit {
        e = thesis_at(s.p, s.n);
    }
    store_lit(id, s, e);
}

@compute @workgroup_size(128, 1)
fn ddgi(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let s = surface(id);
    var e = vec3f(0.0);
    if s.lit {
        e = ddgi_irradiance_at(s.p, s.n, normalize(frame.camera.origin - s.p));
    }
    store_lit(id, s, e);
}

const SALT: u32 = 0x67617468u;

// Gather rays on 1 / GATHER_PHASES of the pixels a frame (1, 2 or 4; see
// ddgi_gather).
override GATHER_PHASES: u32 = 4u;

// Mirror bounces a gather ray follows: light reaching a surface by way of
// a mirror (a caustic) is indirect light the light passes cannot shade.
const GATHER_SPECULAR_DEPTH: u32 = 4u;

// The light a gather ray from a surface brings back, diffuse reflection
// only: at each hit, emission of an emissive surface (not of a light hit
// straight away: the light passes shade that) and albedo / pi times direct
// light (one light sample) plus the volume's irradiance there; a specular
// surface reflects the ray on, up to GATHER_SPECULAR_DEPTH times, so a
// light seen in a mirror counts.
fn gather(o: vec3f, dir_in: vec3f, rng: ptr<function, Rng>) -> vec3f {
    var dir = dir_in;
    var origin = o;
    var atten = vec3f(1.0);
    var out = vec3f(0.0);
    for (var depth = 0u; depth <= GATHER_SPECULAR_DEPTH; depth++) {
        let hit = trace_closest(origin, dir, 3.0e38);
        if !hit_found(hit) {
            // An environment light seen straight away is the light passes'
            // to shade, as a light is.
            let seen = select(sky(dir), vec3f(0.0), SCENE_ENVIRONMENT && depth == 0u);
            return out + atten * seen;
        }
        // A probe's rays gather diffusely: a wide cone (one radian).
        let m = material_at(hit.material, hit.prim, hit.position, dir, hit.t);
        if hit.light >= 0 {
            return out + select(vec3f(0.0), atten * m.emission, depth > 0u);
        }
        let f = facing(hit, dir);
        let n = f.n;
        let next = offset_ray(hit.position, f.ng, hit.error);
        let base = m.albedo * (1.0 - m.specular);
        if max3(base) > 0.0 {
            var e = ddgi_irradiance_at(hit.position, n, -dir);
            // One light, chosen by what it could bring here
            // (shared/light_choice.wgsl): one shadow ray however many
            // lights there are, divided by the chance of the choice.
            if light_count() > 0u {
                let c = choose_light(hit.position, n, rand_f32(rng));
                if c.pick_weight > 0.0 {
                    e += light_irradiance(c.pick, load_light(c.pick), hit.position, n, next, 1u, 0u, 0.0, rng) * (c.sum / c.pick_weight);
                }
            }
            out += atten * base / PI * e;
        }
        if is_emissive(m) {
            out += atten * m.emission;
        }
        if m.specular <= 0.0 {
            break;
        }
        atten *= specular_tint(m, -dot(dir, n));
        dir = reflect(dir, n);
        origin = next;
    }
    return out;
}

// Indirect light by one gather ray a pixel a frame: a cosine-distributed
// ray from the surface, the light its hit sends back (`gather_hit`). The
// first bounce is traced, so contact shadows and near walls are exact;
// the volume supplies only the light arriving at the gather hits. Its
// mean over frames is the indirect light (`accumulate` takes it).
@compute @workgroup_size(64, 1)
fn ddgi_gather(@builtin(global_invocation_id) id: vec3u, @builtin(workgroup_id) group: vec3u) {
    if !in_frame(id) {
        return;
    }
    let s = surface(id);
    if !s.lit {
        store_lit(id, s, vec3f(0.0));
        return;
    }
    // 1 / GATHER_PHASES of the pixels a frame, in turn, each weighing
    // GATHER_PHASES (the mean over that many frames is the same; the cost
    // is a fraction): whole workgroups (64-pixel runs of a row) in
    // diagonal stripes, so they and their SIMD groups skip together; a
    // per-pixel checkerboard saved nothing on lavapipe.
    let phase = (group.x + group.y) % max(GATHER_PHASES, 1u);
    if GATHER_PHASES > 1u && phase != frame.frame_index % GATHER_PHASES {
        store_lit(id, s, vec3f(0.0));
        return;
    }
    let weight = f32(max(GATHER_PHASES, 1u));
    var rng = rng_for(id.xy, frame.frame_index, SALT, frame.seed);
    let o = offset_by(s.p, s.n, s.error);
    let dir = sample_cosine(s.n, rand2(&rng));
    let l = gather(o, dir, &rng);
    // Cosine sampling: albedo / pi x L cos / pdf = albedo x L, which
    // store_lit writes as base / pi x (pi L).
    store_lit(id, s, weight * PI * l);
}

@group(0) @binding(7) var probe_view: texture_storage_2d<rgba32float, write>;

// Radius of a drawn probe: a fifth of the smallest spacing.
fn probe_radius() -> f32 {
    let sp = frame.probe_spacing;
    return 0.2 * min(sp.x, min(sp.y, sp.z));
}

// The nearest probe sphere on a pixel's ray: probe index (n^3 for none)
// and the sphere's normal there.
struct ProbeHit {
    probe: u32,
    normal: vec3f,
}

// Tests probe i's sphere at c against the ray, keeping the nearest.
fn probe_test(id: vec3u, i: u32, c: vec3f, hit: ptr<function, ProbeHit>, best: ptr<function, f32>) {
    let ro = frame.camera.origin;
    let rd = camera_dir(frame.camera, id.xy, vec2f(0.5));
    let t = ray_sphere(ro, rd, c, probe_radius(), 0.0, *best);
    if t > 0.0 {
        *best = t;
        *hit = ProbeHit(i, normalize(ro + rd * t - c));
    }
}

@compute @workgroup_size(128, 1)
fn thesis_view(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let n = frame.probe_n;
    let s = thesis_spa();
    var shown = vec3f(0.0);
    if n >= 2u && s > 0u {
        var h = ProbeHit(n * n * n, vec3f(0.0));
        var best = 3.0e38;
        for (var i = 0u; i < n * n * n; i++) {
            probe_test(id, i, probe_position(probe_coords(i)), &h, &best);
        }
        if h.probe < n * n * n {
            shown = thesis_probe(h.probe, h.normal, s) / PI;
        }
    }
    textureStore(probe_view, id.xy, vec4f(finite_or_zero(shown), 1.0));
}

@compute @workgroup_size(128, 1)
fn ddgi_view(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let n = frame.probe_n;
    var shown = vec3f(0.0);
    if n >= 2u {
        var h = ProbeHit(n * n * n, vec3f(0.0));
        var best = 3.0e38;
        for (var i = 0u; i < n * n * n; i++) {
            probe_test(id, i, probe_position(probe_coords(i)) + probe_state(i).xyz, &h, &best);
        }
        if h.probe < n * n * n && probe_state(h.probe).w >= 0.5 {
            let irr_n = tile_interior(textureDimensions(ddgi_irradiance));
            shown = irradiance_bilinear(h.probe, oct_tile_point(h.normal, irr_n), irr_n) / PI;
        }
    }
    textureStore(probe_view, id.xy, vec4f(finite_or_zero(shown), 1.0));
}
