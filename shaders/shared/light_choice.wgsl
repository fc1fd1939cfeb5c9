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

// Whether the scene's lights are in clusters (src/scene/light_clusters.rs:
// more than 64 lights): a choice then weighs the clusters, picks one, and
// weighs its lights, about 2 sqrt(n) weights where one pass weighs n
// (realtime.ron's frame took 1.12x with 64 lights against one, and 1.52x
// with 256, where each light was weighed). Off where the scene has few
// lights (src/scene/specialise.rs): a CPU driver runs both choices' loops
// under lane masks otherwise.
override SCENE_LIGHT_CLUSTERS: bool = true;

// One of the scene's lights for the shading point p (normal n), drawn
// with the uniform number u: `pick` with probability pick_weight / sum.
// `sum` is what light_choice_prob needs of the choice (the weights' sum,
// over the clusters where the lights are in clusters). pick_weight 0: no
// light can reach p (sum may still be above 0, where the cluster picked
// can bring nothing though another could); `pick` is then light 0.
fn choose_light(p: vec3f, n: vec3f, u: f32) -> LightChoice {
    if SCENE_LIGHT_CLUSTERS && frame.n_light_clusters > 0u {
        return choose_clustered(p, n, u);
    }
    var c = LightChoice(0u, 0.0, 0.0, u);
    for (var i = 0u; i < light_count(); i++) {
        c = light_choice_step(c, i, light_choice_weight(load_light(i), p, n));
    }
    return c;
}

// The probability that choose_light at p (normal n), whose `sum` this
// was, chose light `i` (`l` its record); `sum` below 0: every light was
// sampled (1).
fn light_choice_prob(i: u32, l: Light, p: vec3f, n: vec3f, sum: f32) -> f32 {
    if sum < 0.0 {
        return 1.0;
    }
    if !(sum > 0.0) {
        return 0.0;
    }
    if SCENE_LIGHT_CLUSTERS && frame.n_light_clusters > 0u {
        return clustered_prob(i, p, n, sum);
    }
    return light_choice_weight(l, p, n) / sum;
}

// The clusters' texels follow the lights' three each in scene_lights
// (src/scene/light_clusters.rs): two per cluster, then the member list
// and each light's cluster, four indices a texel.
fn cluster_texel(t: u32) -> vec4u {
    return scene_texel(scene_lights, 3u * frame.n_lights + t);
}

// Entry k of a list of indices that starts at cluster texel `base`.
fn cluster_list(base: u32, k: u32) -> u32 {
    return cluster_texel(base + (k >> 2u))[k & 3u];
}

// A cluster: an estimate of what its lights could bring to p (their
// power over the squared distance to its centre, times the largest cosine
// a point of its bounding sphere can make with n), and its span of the
// member list.
struct ClusterWeight {
    w: f32,
    first: u32,
    count: u32,
}

fn cluster_weight(k: u32, p: vec3f, n: vec3f) -> ClusterWeight {
    let a = bitcast<vec4f>(cluster_texel(2u * k));
    let b = cluster_texel(2u * k + 1u);
    let power = bitcast<f32>(b.x);
    // A cluster of one light (a directional light, the environment)
    // takes that light's own weight.
    if b.z == 1u {
        let i = cluster_list(2u * frame.n_light_clusters, b.y);
        return ClusterWeight(light_choice_weight(load_light(i), p, n), b.y, 1u);
    }
    let v = a.xyz - p;
    let d2 = dot(v, v);
    let r2 = a.w * a.w;
    var tilt = 1.0;
    if d2 > r2 {
        // As a sphere light's: no direction into the sphere makes a
        // smaller angle with n than (centre's - half-angle).
        let sin2 = r2 / d2;
        tilt = clamp(dot(n, v) * inverseSqrt(d2) * sqrt(1.0 - sin2) + sqrt(sin2), 0.0, 1.0);
    }
    // Above 0 wherever a light of the cluster is (the bound must leave
    // none out), and finite.
    let w = power * tilt / max(max(d2, r2), 1e-30);
    return ClusterWeight(select(0.0, clamp(w, 1e-30, 1e30), power > 0.0 && tilt > 0.0), b.y, b.z);
}

// choose_light through the clusters: a cluster by its bound, then one of
// its lights by its weight. pick_weight / sum is the product of the two
// chances; sum is the clusters' sum.
fn choose_clustered(p: vec3f, n: vec3f, u: f32) -> LightChoice {
    let clusters = frame.n_light_clusters;
    var c = LightChoice(0u, 0.0, 0.0, u);
    for (var k = 0u; k < clusters; k++) {
        c = light_choice_step(c, k, cluster_weight(k, p, n).w);
    }
    if !(c.sum > 0.0) {
        return LightChoice(0u, 0.0, 0.0, c.u);
    }
    // The picked cluster's span of the member list.
    let span = cluster_texel(2u * c.pick + 1u);
    let first = span.y;
    let count = span.z;
    let list = 2u * clusters;
    var m = LightChoice(0u, 0.0, 0.0, c.u);
    for (var j = 0u; j < count; j++) {
        let i = cluster_list(list, first + j);
        m = light_choice_step(m, i, light_choice_weight(load_light(i), p, n));
    }
    // (The cluster's share times the light's within it: each at most 1.)
    let within = select(0.0, m.pick_weight / m.sum, m.sum > 0.0);
    return LightChoice(m.pick, c.pick_weight * within, c.sum, m.u);
}

// light_choice_prob through the clusters: light i's cluster's chance
// times its chance within the cluster, the cluster's lights weighed in
// the order choose_clustered weighs them (so the sums agree to the bit).
fn clustered_prob(i: u32, p: vec3f, n: vec3f, sum: f32) -> f32 {
    let clusters = frame.n_light_clusters;
    let list = 2u * clusters;
    let k = cluster_list(list + (frame.n_lights + 3u) / 4u, i);
    let cw = cluster_weight(k, p, n);
    // (Light i is one of them: its own weight is taken on the way.)
    var s = 0.0;
    var w = 0.0;
    for (var j = 0u; j < cw.count; j++) {
        let m = cluster_list(list, cw.first + j);
        let wm = light_choice_weight(load_light(m), p, n);
        if wm > 0.0 {
            s += wm;
        }
        if m == i {
            w = wm;
        }
    }
    return select(0.0, (cw.w / sum) * (w / s), s > 0.0 && w > 0.0);
}
