// Ground truth (thesis 2.4): Monte Carlo path tracing with Lambertian
// diffuse and a specular lobe chosen with probability `specular` (mirror
// direction blended toward a diffuse one by `roughness`). Next-event
// estimation on the diffuse lobe, combined with BSDF sampling by the power
// heuristic, so the image converges to the same answer as plain path
// tracing. Russian roulette after `rr_depth` bounces.
// The first hit is not stored (a graph whose accumulation never
// reprojects, passes/pathtrace.ron, runs it with FIRST_HIT 0):
// pathtrace_gbuffer.wgsl is the same tracer writing a G-buffer too.
#import path_render

// The sample, and the first hit nowhere (shared/path_render.wgsl).
fn store_sample(pixel: vec2u, radiance_in: vec3f, pos: vec4f, normal: vec4f, ids: vec4u) {
    textureStore(radiance, pixel, vec4f(radiance_in, 1.0));
}
