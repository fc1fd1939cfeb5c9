// Sampling and frame helpers (mirrored in src/sampling.rs).

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

// Uniform direction in the cone around `axis` with half-angle acos(cos_max);
// pdf = 1 / (2 pi (1 - cos_max)).
fn sample_cone(axis: vec3f, cos_max: f32, u: vec2f) -> vec3f {
    let cos_t = 1.0 - u.x * (1.0 - cos_max);
    let sin_t = sqrt(max(0.0, 1.0 - cos_t * cos_t));
    let phi = 2.0 * PI * u.y;
    let local = vec3f(sin_t * cos(phi), sin_t * sin(phi), cos_t);
    return normalize(basis(axis) * local);
}

// cos of the half-angle a sphere of radius r at distance d subtends (d > r).
fn sphere_cos_max(d: f32, r: f32) -> f32 {
    let s = r / d;
    return sqrt(max(0.0, 1.0 - s * s));
}

fn cone_pdf(cos_max: f32) -> f32 {
    return 1.0 / (2.0 * PI * max(1.0 - cos_max, 1e-12));
}

fn max3(v: vec3f) -> f32 {
    return max(v.x, max(v.y, v.z));
}

// Replaces NaN/Inf with zero so one bad sample cannot poison an average.
fn finite_or_zero(v: vec3f) -> vec3f {
    let ok = all(v == v) && all(abs(v) < vec3f(3.0e38));
    return select(vec3f(0.0), v, ok);
}
