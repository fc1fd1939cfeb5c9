// Sampling and frame helpers (mirrored in src/sampling.rs).
#import finite

const PI: f32 = 3.14159265358979;

// An orthonormal basis around n (Duff et al. 2017).
fn basis(n: vec3f) -> mat3x3f {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = vec3f(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let bt = vec3f(b, s + n.y * n.y * a, -n.y);
    return mat3x3f(t, bt, n);
}

// Cosine-weighted direction around n; pdf = cos(theta) / pi.
fn sample_cosine(n: vec3f, u: vec2f) -> vec3f {
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    let local = vec3f(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u.x)));
    return normalize(basis(n) * local);
}

// The path tracer's glossy lobe: the mirror direction r blended toward a
// cosine-distributed direction around n by `roughness` (in (0, 1]). Its
// pdf has no simple closed form: src/sampling.rs derives it by a change of
// variables (glossy_pdf) and src/chi2.rs tests this sampler against it.
fn sample_glossy(r: vec3f, n: vec3f, roughness: f32, u: vec2f) -> vec3f {
    return normalize(mix(r, sample_cosine(n, u), roughness));
}

// Cones are given by 1 - cos(half-angle), not the cosine: for a small or
// far light the cosine rounds to 1 in f32 and 1 - cos_max cancels to 0
// (a light of radius 1 at distance 1e4 has 1 - cos_max = 5e-9).

// Uniform direction in the cone around `axis` whose half-angle has
// 1 - cos = `one_minus_cos`; pdf = cone_pdf(one_minus_cos).
fn sample_cone(axis: vec3f, one_minus_cos: f32, u: vec2f) -> vec3f {
    let a = u.x * one_minus_cos; // 1 - cos(theta)
    let cos_t = 1.0 - a;
    let sin_t = sqrt(max(0.0, a * (2.0 - a)));
    let phi = 2.0 * PI * u.y;
    let local = vec3f(sin_t * cos(phi), sin_t * sin(phi), cos_t);
    return normalize(basis(axis) * local);
}

// cos of the half-angle a sphere of radius r at distance d subtends (d > r).
fn sphere_cos_max(d: f32, r: f32) -> f32 {
    let s = r / d;
    return sqrt(max(0.0, 1.0 - s * s));
}

// 1 - sphere_cos_max(d, r), without the cancellation: s^2 / (1 + cos).
fn sphere_one_minus_cos(d: f32, r: f32) -> f32 {
    let s = r / d;
    return s * s / (1.0 + sqrt(max(0.0, 1.0 - s * s)));
}

// 1 / (2 pi (1 - cos_max)); the floor only keeps an underflowed cone (a
// light smaller than f32 can tell from a point) finite.
fn cone_pdf(one_minus_cos: f32) -> f32 {
    return 1.0 / (2.0 * PI * max(one_minus_cos, 1e-37));
}

fn max3(v: vec3f) -> f32 {
    return max(v.x, max(v.y, v.z));
}

// Replaces NaN/Inf with zero so one bad sample cannot poison an average.
fn finite_or_zero(v: vec3f) -> vec3f {
    return select(vec3f(0.0), v, all_finite(v));
}

// Multiple importance sampling's power heuristic (Veach),
// a^2 / (a^2 + b^2) for pdfs a, b >= 0, written with their ratio: squaring
// the pdf of a light too small for f32 (about 1e36 at the cone_pdf floor)
// overflowed to inf / inf = NaN, and the path sample was dropped.
fn power_heuristic(a: f32, b: f32) -> f32 {
    if !(a > 0.0) {
        return 0.0;
    }
    let r = b / a;
    return 1.0 / (1.0 + r * r);
}
