// Which light a bounce samples when it samples one (the path's NEE_ONE):
// each light with probability proportional to what it could bring to the
// shading point, unshadowed: an estimate of its irradiance there, which
// a surface facing away from it gets none of. A uniform choice spent half
// of thesis-env2's light samples on its small light and most of
// thesis-env3-16-lights' on the fifteen lamps in the far corners
// (docs/realtime.md, "Lights chosen by what they bring").
//
// Unbiased as long as a light that can bring something has a weight above
// 0: a light is given none only where it lies wholly below the surface's
// horizon, where sampling it would bring nothing either. Multiple
// importance sampling weighs a light a bounce ray meets by the same
// probability (light_choice_prob), from the weights' sum kept with the
// path.
#import scene
#import sampling

// Scenes with more lights choose uniformly. The choice weighs every light
// at every bounce: realtime.ron's frame took 1.12x with 64 lights and
// 1.52x with 256, which the better choice still pays for there
// (docs/realtime.md, "Lights chosen by what they bring").
const LIGHT_CHOICE_MAX_LIGHTS: u32 = 256u;

// The weight of light `l` at point p with shading normal n (facing the
// ray that arrived): its luminance times the solid angle it fills, times
// the most any of it can be tilted toward n (for a sphere light, whose
// part above the horizon may be beside its centre; for a point light,
// the cosine itself, and a spot's cone). A directional light's is its
// irradiance at normal incidence, the environment's pi times its mean
// radiance (`color` of its record, src/scene/environment.rs).
fn light_choice_weight(l: Light, p: vec3f, n: vec3f) -> f32 {
    // Held finite and not NaN, so that a sum of weights stays finite:
    // a light of radiance near f32's largest, or a point light at a
    // distance whose square underflows, gets 1e30.
    let w = irradiance_bound(l, p, n);
    return select(0.0, min(w, 1e30), w > 0.0);
}

fn irradiance_bound(l: Light, p: vec3f, n: vec3f) -> f32 {
    let lum = dot(l.color, vec3f(0.2126, 0.7152, 0.0722));
    if l.kind == LIGHT_ENVIRONMENT {
        return PI * lum;
    }
    if l.kind == LIGHT_DIRECTIONAL {
        return lum * max(dot(n, l.position), 0.0);
    }
    let v = l.position - p;
    let d2 = dot(v, v);
    if !(d2 > 0.0) {
        return 0.0;
    }
    let cos_centre = dot(n, v) * inverseSqrt(d2);
    if l.kind == LIGHT_POINT {
        return lum * spot_factor(l, -v * inverseSqrt(d2)) * max(cos_centre, 0.0) / d2;
    }
    let r2 = l.radius * l.radius;
    if d2 <= r2 {
        // Inside the light (or on it): it fills the whole sphere of
        // directions.
        return PI * lum;
    }
    // The cone the sphere fills has half-angle a, sin^2 a = r^2 / d^2; a
    // direction of it makes at least the angle (centre's - a) with n, so
    // its cosine is at most cos(centre - a) <= cos_centre cos a + sin a.
    let sin2 = r2 / d2;
    let tilt = clamp(cos_centre * sqrt(1.0 - sin2) + sqrt(sin2), 0.0, 1.0);
    return lum * (PI * sin2 * tilt);
}

// A choice in progress over the lights, made in one pass with one uniform
// number: after each light, `pick` is each light so far with probability
// its weight over `sum`. `u` is what is left of the number, still uniform
// in [0, 1) (rescaled at each step, so no second number is drawn).
struct LightChoice {
    pick: u32,
    pick_weight: f32,
    sum: f32,
    u: f32,
}

// Light i, of weight w, offered to the choice.
fn light_choice_step(c_in: LightChoice, i: u32, w: f32) -> LightChoice {
    var c = c_in;
    if !(w > 0.0) {
        return c;
    }
    c.sum += w;
    let q = w / c.sum;
    if c.u < q {
        c.pick = i;
        c.pick_weight = w;
        c.u = c.u / q;
    } else {
        c.u = (c.u - q) / (1.0 - q);
    }
    // (Rounding could leave u at 1.)
    c.u = min(c.u, 0.99999994);
    return c;
}

// One of the scene's lights for the shading point p (normal n), drawn
// with the uniform number u. `sum` 0: no light can reach p; `pick` is
// then light 0, and its weight 0.
fn choose_light(p: vec3f, n: vec3f, u: f32) -> LightChoice {
    var c = LightChoice(0u, 0.0, 0.0, u);
    let count = light_count();
    if count > LIGHT_CHOICE_MAX_LIGHTS {
        // Every light of weight 1.
        return LightChoice(min(u32(u * f32(count)), count - 1u), 1.0, f32(count), 0.0);
    }
    for (var i = 0u; i < count; i++) {
        c = light_choice_step(c, i, light_choice_weight(load_light(i), p, n));
    }
    return c;
}

// The probability that choose_light at p (normal n), whose weights summed
// to `sum`, chose light `l`; `sum` below 0: every light was sampled (1).
fn light_choice_prob(l: Light, p: vec3f, n: vec3f, sum: f32) -> f32 {
    if sum < 0.0 {
        return 1.0;
    }
    if !(sum > 0.0) {
        return 0.0;
    }
    if light_count() > LIGHT_CHOICE_MAX_LIGHTS {
        return 1.0 / sum;
    }
    return light_choice_weight(l, p, n) / sum;
}
