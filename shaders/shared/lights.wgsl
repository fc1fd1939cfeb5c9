// Light sampling shared by the lights pass and the path tracer.
#import flat
#import rng
#import sampling
#import environment

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
    if SCENE_ENVIRONMENT && l.kind == LIGHT_ENVIRONMENT {
        // A direction drawn from the map; shadow rays go as far as rays go.
        let e = env_sample(l, u);
        s.dir = e.dir;
        s.dist = 3.0e38;
        s.pdf = e.pdf;
        s.weight = select(vec3f(0.0), e.radiance / e.pdf, e.pdf > 0.0);
        s.valid = e.pdf > 0.0;
        return s;
    }
    if SCENE_DIRECTIONAL_LIGHTS && l.kind == LIGHT_DIRECTIONAL {
        // A delta direction; shadow rays go as far as rays go.
        s.dir = l.position;
        s.dist = 3.0e38;
        s.weight = l.color;
        s.valid = true;
        return s;
    }
    let to = l.position - p;
    let d = length(to);
    if !(d > 0.0) {
        return s;
    }
    let axis = to / d;
    if l.kind == LIGHT_POINT {
        // A sphere light shaded as a point (radius > 0) must not shadow
        // itself: the shadow ray ends at its surface.
        if d <= l.radius {
            return s;
        }
        s.dir = axis;
        s.dist = d - l.radius;
        s.weight = l.color * spot_factor(l, -axis) / (d * d);
        s.valid = true;
        return s;
    }
    // On the light's own surface (or anywhere inside it, where no sphere
    // light can hold a shading point: SCENE_INSIDE_LIGHTS).
    if d <= l.radius * 1.0001 && (!SCENE_INSIDE_LIGHTS || d >= l.radius * 0.9999) {
        return s;
    }
    // Inside the light (a sphere light around the camera and the scene):
    // every direction meets it, so a uniform direction (a cone of every
    // direction, pdf 1 / (4 pi)), as far as the sphere.
    let inside = SCENE_INSIDE_LIGHTS && d < l.radius;
    let one_minus_cos = select(sphere_one_minus_cos(d, l.radius), 2.0, inside);
    s.dir = sample_cone(axis, one_minus_cos, u);
    var t = ray_sphere(p, s.dir, l.position, l.radius, 0.0, 3.0e38);
    if t <= 0.0 && inside {
        return s;
    }
    if t <= 0.0 {
        t = d * sphere_cos_max(d, l.radius); // grazing the silhouette: the tangent distance
    }
    s.dist = t;
    s.pdf = cone_pdf(one_minus_cos);
    s.weight = l.color / s.pdf;
    s.valid = true;
    return s;
}

// The solid-angle pdf `sample_light` would give direction-independent
// sphere light `l` from point p (1 / (4 pi) inside it, 0 on its surface).
fn light_pdf(l: Light, p: vec3f) -> f32 {
    let d = length(l.position - p);
    if l.kind != LIGHT_SPHERE || (d <= l.radius * 1.0001 && (!SCENE_INSIDE_LIGHTS || d >= l.radius * 0.9999)) {
        return 0.0;
    }
    return cone_pdf(select(sphere_one_minus_cos(d, l.radius), 2.0, SCENE_INSIDE_LIGHTS && d < l.radius));
}

// Whether reflected rays can meet light l: a sphere's surface, the sky.
// The hybrid graphs' light passes give a glossy lobe the other lights
// (points, spots, directional), the reflection passes these.
fn rays_meet(l: Light) -> bool {
    return l.kind == LIGHT_SPHERE || l.kind == LIGHT_ENVIRONMENT;
}

// The direction from o toward a point, spot or directional light l.
fn toward_light(l: Light, o: vec3f) -> vec3f {
    return select(normalize(l.position - o), l.position, l.kind == LIGHT_DIRECTIONAL);
}

// Whether sample `s` of light `i` is visible from the offset origin `o`.
fn light_visible(i: u32, o: vec3f, s: LightSample) -> bool {
    return !trace_shadow(i, o, s.dir, shadow_ray_length(s));
}

// How far a shadow ray toward the sample goes: just short of the light.
fn shadow_ray_length(s: LightSample) -> f32 {
    return s.dist * (1.0 - 1e-4);
}

// Replaces the physical 1/d^2 with the thesis's exponential when falloff
// is 1: exp(-k d) in its place.
fn falloff_scale(falloff: u32, k: f32, d: f32) -> f32 {
    if falloff == 1u {
        return d * d * exp(-k * d);
    }
    return 1.0;
}

// What a visible sample `s` of light `l` gives surface point p facing it
// at cos_n: L cos / pdf (or I cos / d^2), times the falloff's scale.
fn sample_irradiance(l: Light, p: vec3f, s: LightSample, cos_n: f32, falloff: u32, falloff_k: f32) -> vec3f {
    // (A directional or environment light has no distance to fall off over.)
    let far = (SCENE_DIRECTIONAL_LIGHTS && l.kind == LIGHT_DIRECTIONAL) || (SCENE_ENVIRONMENT && l.kind == LIGHT_ENVIRONMENT);
    let scale = select(falloff_scale(falloff, falloff_k, length(l.position - p)), 1.0, far);
    return s.weight * cos_n * scale;
}

// Sphere light `l` as the far-field point light the raster-style point
// mode shades: intensity L pi r^2 at its centre.
fn sphere_as_point(l: Light) -> Light {
    return Light(l.position, l.radius, l.color * PI * l.radius * l.radius, LIGHT_POINT, vec4f(0.0, 0.0, 0.0, 1.0));
}

// The mean over `count` samples (0 counts as 1) of L cos / pdf (or
// I cos / d^2) from light l (index i) at surface point p with normal n; o is p
// offset off the surface.
fn light_irradiance(i: u32, l: Light, p: vec3f, n: vec3f, o: vec3f, count: u32, falloff: u32, falloff_k: f32, rng: ptr<function, Rng>) -> vec3f {
    var sum = vec3f(0.0);
    // Tested at the bottom (see brute_force): lights_area 0.86x the time.
    var k = 0u;
    loop {
        let s = sample_light(l, o, rand2(rng));
        let cos_n = dot(n, s.dir);
        let unlit = !s.valid || cos_n <= 0.0 || !light_visible(i, o, s);
        if !unlit {
            sum += sample_irradiance(l, p, s, cos_n, falloff, falloff_k);
        }
        continuing {
            k++;
            break if k >= count;
        }
    }
    return sum / f32(max(count, 1u));
}
