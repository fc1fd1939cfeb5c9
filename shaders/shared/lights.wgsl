// Light sampling shared by the lights pass and the path tracer.
#import intersect
#import sampling

struct LightSample {
    dir: vec3f,
    // Distance to the sampled point on the light (shadow ray length).
    dist: f32,
    // Radiance / pdf (sphere light) or intensity / d^2 (point light).
    weight: vec3f,
    // Solid-angle pdf; 0 for a point light (a delta).
    pdf: f32,
    valid: bool,
}

// One sample of light `l` seen from point p: a direction in the cone the
// sphere subtends (uniform cone sampling), or the direction to a point light.
fn sample_light(l: Light, p: vec3f, u: vec2f) -> LightSample {
    var s = LightSample(vec3f(0.0, 1.0, 0.0), 0.0, vec3f(0.0), 0.0, false);
    let to = l.position - p;
    let d = length(to);
    if !(d > 0.0) {
        return s;
    }
    let axis = to / d;
    if l.kind == LIGHT_POINT {
        s.dir = axis;
        s.dist = d;
        s.weight = l.color / (d * d);
        s.valid = true;
        return s;
    }
    if d <= l.radius * 1.0001 {
        return s; // inside the light: it lights nothing from here
    }
    let cos_max = sphere_cos_max(d, l.radius);
    s.dir = sample_cone(axis, cos_max, u);
    var t = ray_sphere(p, s.dir, l.position, l.radius, 0.0, 3.0e38);
    if t <= 0.0 {
        t = d * cos_max; // grazing the silhouette: the tangent distance
    }
    s.dist = t;
    s.pdf = cone_pdf(cos_max);
    s.weight = l.color / s.pdf;
    s.valid = true;
    return s;
}

// The solid-angle pdf `sample_light` would give direction-independent
// sphere light `l` from point p (0 if p is inside it).
fn light_pdf(l: Light, p: vec3f) -> f32 {
    let d = length(l.position - p);
    if l.kind != LIGHT_SPHERE || d <= l.radius * 1.0001 {
        return 0.0;
    }
    return cone_pdf(sphere_cos_max(d, l.radius));
}

// Whether the light sample is visible from the offset origin `o`.
fn light_visible(o: vec3f, s: LightSample) -> bool {
    return !trace_any(o, s.dir, s.dist * (1.0 - 1e-4));
}
