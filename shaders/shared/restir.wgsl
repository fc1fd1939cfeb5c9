// Reservoirs of light samples for direct light by resampling (ReSTIR DI:
// Bitterli et al. 2020), shared by shaders/realtime/restir.wgsl, which
// builds and reuses them, and shaders/realtime/gradient.wgsl, which shades
// last frame's again in a changed scene.
//
// A sample y is a point on a light: light index and, for a sphere light,
// the direction from its centre (a point light is its centre; for the
// environment light, the direction toward it). It is kept
// as a point on the light, not a direction from the surface, so another
// pixel, or the next frame with the light moved, can shade it again.
// Weights are in the light's own measure (area on a sphere light, a
// discrete choice for a point light); the target p̂ is the luminance of
// the unshadowed light the sample brings: the surface's factor (its
// `direct` weight: diffuse albedo / pi, times the path's throughput to
// it) times L cos_s cos_l / d^2 (I cos_s / d^2 for a point light).
#import lights
#import reproject
#import realtime_common

// Reservoir texels (Rgba32Uint): the light index in the low 20 bits and
// the candidate count M (at most 4095) in the high 12, the unbiased
// contribution weight W (f32 bits), the octahedral direction from the
// light's centre (two f32s). An empty reservoir has light NO_SAMPLE. (So
// a scene of more than 2^20 - 1 lights would need another layout.)
const NO_SAMPLE: u32 = 0xfffffu;
const MAX_M: f32 = 4095.0;

struct Reservoir {
    light: u32,
    oct: vec2f,
    // While building: the sum of resampling weights; once finished, W.
    w: f32,
    m: f32,
    // p̂ of the chosen sample at this pixel's surface.
    p_hat: f32,
}

fn empty_reservoir() -> Reservoir {
    return Reservoir(NO_SAMPLE, vec2f(0.0), 0.0, 0.0, 0.0);
}

fn encode_reservoir(r: Reservoir) -> vec4u {
    let m = u32(clamp(r.m, 0.0, MAX_M));
    return vec4u((r.light & NO_SAMPLE) | (m << 20u), bitcast<u32>(r.w), bitcast<vec2u>(r.oct));
}

fn decode_reservoir(t: vec4u) -> Reservoir {
    let light = t.x & NO_SAMPLE;
    let w = bitcast<f32>(t.y);
    let m = f32(t.x >> 20u);
    // A weight that is not finite (it should never be) empties it. An
    // empty reservoir keeps its M: its candidates all had p̂ 0, and they
    // count in the weights of samples its surface could have drawn.
    if light == NO_SAMPLE || !(w >= 0.0 && w < 3.0e38) || light >= light_count() {
        return Reservoir(NO_SAMPLE, vec2f(0.0), 0.0, m, 0.0);
    }
    return Reservoir(light, bitcast<vec2f>(t.zw), w, m, 0.0);
}

// The surface a pixel's direct light falls on: the hit p, the ray origin
// o offset off it, the shading normal n and geometric normal ng (both
// facing the viewer), and the factor its light arrives with (0: none).
struct Surface {
    p: vec3f,
    o: vec3f,
    n: vec3f,
    ng: vec3f,
    weight: vec3f,
    valid: bool,
}

// `error`: p's error bound (gbuffer_offset_error).
fn make_surface(p: vec3f, n: vec3f, ng: vec3f, weight: vec3f, error: f32) -> Surface {
    let valid = max3(weight) > 0.0 && light_count() > 0u;
    return Surface(p, offset_by(p, ng, error), n, ng, weight, valid);
}

// The sample's point on its light seen from `s`: the light it brings
// unshadowed (rgb, before the surface's factor; 0 where the point faces
// away or lies below the surface), the shadow ray toward it, and the
// cosine at the light and squared distance (a point light: 1 and d^2).
struct LightPoint {
    light: vec3f,
    dir: vec3f,
    dist: f32,
    shadow_tmax: f32,
    cos_l: f32,
    d2: f32,
}

fn light_point(s: Surface, light: u32, oct: vec2f) -> LightPoint {
    return light_point_of(s, load_light(light), oct);
}

// light_point with the light already loaded.
fn light_point_of(s: Surface, l: Light, oct: vec2f) -> LightPoint {
    var out = LightPoint(vec3f(0.0), vec3f(0.0, 1.0, 0.0), 0.0, 0.0, 0.0, 0.0);
    let env = SCENE_ENVIRONMENT && l.kind == LIGHT_ENVIRONMENT;
    if env || (SCENE_DIRECTIONAL_LIGHTS && l.kind == LIGHT_DIRECTIONAL) {
        // Infinitely far: a direction the same from every surface (the
        // environment's the sample's `oct`, measured in solid angle; a
        // directional light's its own, a delta), unit "distance", no
        // falloff, shadow rays as far as rays go.
        out.dir = l.position;
        var radiance = l.color;
        if env {
            out.dir = oct_to_normal(oct);
            radiance = env_radiance(l, out.dir);
        }
        out.dist = 3.0e38;
        out.d2 = 1.0;
        out.cos_l = 1.0;
        out.shadow_tmax = 3.0e38;
        let cos_s = dot(s.n, out.dir);
        if cos_s > 0.0 && dot(out.dir, s.ng) > 0.0 {
            out.light = radiance * cos_s;
        }
        return out;
    }
    if l.kind == LIGHT_POINT {
        let to = l.position - s.o;
        let d2 = dot(to, to);
        let d = sqrt(d2);
        // As sample_light: no light from inside its radius.
        if !(d > l.radius) {
            return out;
        }
        out.dir = to / d;
        out.dist = d;
        out.d2 = d2;
        out.cos_l = 1.0;
        out.shadow_tmax = (d - l.radius) * (1.0 - 1e-4);
        let cos_s = dot(s.n, out.dir);
        if cos_s > 0.0 && dot(out.dir, s.ng) > 0.0 {
            out.light = l.color * spot_factor(l, -out.dir) * cos_s / d2;
        }
        return out;
    }
    if length(l.position - s.o) <= l.radius * 1.0001 {
        return out; // inside the light: it lights nothing from here
    }
    let nl = oct_to_normal(oct);
    let to = l.position + l.radius * nl - s.o;
    let d2 = dot(to, to);
    let d = sqrt(d2);
    if !(d > 0.0) {
        return out;
    }
    out.dir = to / d;
    out.dist = d;
    out.d2 = d2;
    out.shadow_tmax = d * (1.0 - 1e-4);
    out.cos_l = -dot(nl, out.dir);
    let cos_s = dot(s.n, out.dir);
    if cos_s > 0.0 && out.cos_l > 0.0 && dot(out.dir, s.ng) > 0.0 {
        out.light = l.color * cos_s * out.cos_l / d2;
    }
    return out;
}

// p̂ of a sample's light at surface `s`.
fn p_hat_of(s: Surface, lp: LightPoint) -> f32 {
    return luminance(s.weight * lp.light);
}

// One candidate drawn from `s` by light sampling: a light chosen
// uniformly, a point on it by uniform cone sampling (sample_light). Its
// resampling weight p̂ / p with p the candidate's pdf in the light's own
// measure (area: the cone's solid-angle pdf times cos_l / d^2).
struct Candidate {
    light: u32,
    oct: vec2f,
    p_hat: f32,
    w: f32,
}

fn draw_candidate(s: Surface, rng: ptr<function, Rng>) -> Candidate {
    let count = light_count();
    let i = min(u32(rand_f32(rng) * f32(count)), count - 1u);
    let l = load_light(i);
    let ls = sample_light(l, s.o, rand2(rng));
    var c = Candidate(i, vec2f(0.0), 0.0, 0.0);
    if !ls.valid {
        return c;
    }
    let env = SCENE_ENVIRONMENT && l.kind == LIGHT_ENVIRONMENT;
    if l.kind == LIGHT_SPHERE {
        c.oct = normal_to_oct(normalize(s.o + ls.dir * ls.dist - l.position));
    }
    if env {
        c.oct = normal_to_oct(ls.dir);
    }
    let lp = light_point_of(s, l, c.oct);
    c.p_hat = p_hat_of(s, lp);
    var pdf = 1.0 / f32(count);
    if l.kind == LIGHT_SPHERE {
        pdf *= ls.pdf * max(lp.cos_l, 0.0) / max(lp.d2, 1e-30);
    }
    if env {
        pdf *= ls.pdf;
    }
    c.w = select(0.0, c.p_hat / pdf, pdf > 0.0 && c.p_hat > 0.0);
    return c;
}

// Streams a sample with resampling weight `w` (p̂ at this pixel: `p_hat`)
// and `m` candidates behind it into reservoir `r`; `u` in [0, 1).
fn stream(r: ptr<function, Reservoir>, light: u32, oct: vec2f, p_hat: f32, w: f32, m: f32, u: f32) {
    (*r).m += m;
    if !(w > 0.0) {
        return;
    }
    (*r).w += w;
    if u * (*r).w < w {
        (*r).light = light;
        (*r).oct = oct;
        (*r).p_hat = p_hat;
    }
}

// Resampling reservoirs built at other surfaces into this pixel's
// (generalised RIS: Lin et al. 2022) with pairwise MIS (Bitterli's 2022
// thesis; Wyman et al.'s 2023 course notes): the pixel's own reservoir,
// the canonical one c, is paired with each of k others i; in pair i, a
// sample y counts for i by the balance heuristic
// b_i(y) = M_i q̂_i(y) / (M_i q̂_i(y) + (M_c / k) q̂_c(y)), for c by 1 - b_i(y),
// and pair i weighs (M_i + M_c / k) / (M_c + sum M). The weights of a
// sample sum to 1 over the reservoirs that could have drawn it, so the
// result is unbiased, and a sample another surface could hardly have
// drawn (its W large there) is weighted down as much here: no fireflies.
// Each other reservoir costs three evaluations, not k + 1.
// q̂ is p̂ without the surface's factor (the luminance of
// light_point's light): what the weights compare surfaces by.
struct Pairwise {
    // The canonical reservoir (finished: w holds W), its q̂ and p̂ at c.
    canon: Reservoir,
    canon_light: Light,
    canon_q: f32,
    // Its weight so far (before the common 1 / (M_c + sum M)).
    canon_weight: f32,
    k: f32,
    // The result: weights summed in w, M summed in m.
    r: Reservoir,
}

fn pairwise_begin(c: Surface, canon: Reservoir, k: u32) -> Pairwise {
    var q = 0.0;
    var p = 0.0;
    let light = load_light(select(0u, canon.light, canon.light != NO_SAMPLE));
    if canon.light != NO_SAMPLE {
        let lp = light_point_of(c, light, canon.oct);
        q = luminance(lp.light);
        p = p_hat_of(c, lp);
    }
    var cr = canon;
    cr.p_hat = p;
    var r = empty_reservoir();
    r.m = canon.m;
    return Pairwise(cr, light, q, select(canon.m, 0.0, k > 0u), f32(max(k, 1u)), r);
}

// One of the k others: reservoir `ri` built at surface `si`, or none (a
// neighbour that failed the similarity test: its pair is all c's).
fn pairwise_add(pw: ptr<function, Pairwise>, c: Surface, si: Surface, ri: Reservoir, taken: bool, rng: ptr<function, Rng>) {
    let mc = (*pw).canon.m / (*pw).k;
    if !taken || ri.m <= 0.0 {
        (*pw).canon_weight += mc;
        return;
    }
    let pair = ri.m + mc;
    (*pw).r.m += ri.m;
    // The canonical sample's share in this pair.
    if (*pw).canon.light != NO_SAMPLE {
        let qi = ri.m * luminance(light_point_of(si, (*pw).canon_light, (*pw).canon.oct).light);
        let qc = mc * (*pw).canon_q;
        (*pw).canon_weight += pair * select(1.0, qc / (qi + qc), qi + qc > 0.0);
    }
    if ri.light == NO_SAMPLE || !(ri.w > 0.0) {
        return;
    }
    let light = load_light(ri.light);
    let lp = light_point_of(c, light, ri.oct);
    let p = p_hat_of(c, lp);
    let qi = ri.m * luminance(light_point_of(si, light, ri.oct).light);
    let qc = mc * luminance(lp.light);
    let b = select(0.0, qi / (qi + qc), qi + qc > 0.0);
    // (Through a local: naga cannot pass a pointer to a struct member.)
    var r = (*pw).r;
    stream(&r, ri.light, ri.oct, p, pair * b * p * ri.w, 0.0, rand_f32(rng));
    (*pw).r = r;
}

// The resampled reservoir (w: W = sum of weights / ((M_c + sum M) p̂(y))).
fn pairwise_end(pw: ptr<function, Pairwise>, rng: ptr<function, Rng>) -> Reservoir {
    let c = (*pw).canon;
    var r = (*pw).r;
    if c.light != NO_SAMPLE && c.w > 0.0 {
        stream(&r, c.light, c.oct, c.p_hat, (*pw).canon_weight * c.p_hat * c.w, 0.0, rand_f32(rng));
    }
    let ok = r.light != NO_SAMPLE && r.p_hat > 0.0 && r.m > 0.0;
    r.w = select(0.0, r.w / (r.m * r.p_hat), ok);
    if !ok {
        r.light = NO_SAMPLE;
    }
    return r;
}

// The light `r` (finished: w holds W) brings to surface `s`: its sample
// shaded with one shadow ray, times W.
fn shade_reservoir(s: Surface, r: Reservoir) -> vec3f {
    if !s.valid || r.light == NO_SAMPLE || !(r.w > 0.0) {
        return vec3f(0.0);
    }
    let lp = light_point(s, r.light, r.oct);
    if max3(lp.light) <= 0.0 || trace_shadow(r.light, s.o, lp.dir, lp.shadow_tmax) {
        return vec3f(0.0);
    }
    return finite_or_zero(s.weight * lp.light * r.w);
}
