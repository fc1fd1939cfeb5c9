// Test pass (tests/samplers_gpu.rs): for each x, draws two numbers from the
// pixel stream (x, row) of frame 0 and writes the sampled direction: row 0
// sample_cosine around NORMAL, row 1 sample_cone around AXIS with
// 1 - cos = ONE_MINUS_COS, row 2 the raw draws, row 3 sample_glossy of
// MIRROR about NORMAL with ROUGHNESS, row 4 mr_sample of MR seen from
// VIEW (a lobe choice, then two numbers), row 5 mr_eval and mr_pdf at row
// 4's direction, row 6 mr_sample_specular's direction (xyz) and the
// luminance of mr_specular_weight (w) from the two numbers after row 4's.
// The test draws the same with the Rust mirrors (src/sampling.rs,
// src/brdf.rs) and compares.
#import frame
#import rng
#import sampling
#import brdf

const NORMAL: vec3f = vec3f(0.26726124, 0.5345225, 0.8017837);
const AXIS: vec3f = vec3f(-0.2, 0.5, 0.84);
const ONE_MINUS_COS: f32 = 0.0012507823;
const MIRROR: vec3f = vec3f(0.6, -0.1, 0.79372539);
const ROUGHNESS: f32 = 0.35;
const SALT: u32 = 0xc41u;
const VIEW: vec3f = vec3f(0.8, 0.1, 0.59160798);

@group(0) @binding(0) var samples: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(8, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let size = textureDimensions(samples);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    if id.y >= 4u {
        var rng = rng_for(vec2u(id.x, 4u), frame.frame_index, SALT, frame.seed);
        let m = MetalRough(vec3f(0.9, 0.6, 0.3), 0.5, 0.4);
        let u_lobe = rand_f32(&rng);
        let l = mr_sample(m, NORMAL, VIEW, u_lobe, rand2(&rng));
        var out = select(vec4f(l, 1.0), vec4f(mr_eval(m, NORMAL, VIEW, l), mr_pdf(m, NORMAL, VIEW, l)), id.y == 5u);
        if id.y == 6u {
            let s = mr_sample_specular(m, NORMAL, VIEW, rand2(&rng));
            out = vec4f(s, mr_luminance(mr_specular_weight(m, NORMAL, VIEW, s)));
        }
        textureStore(samples, id.xy, out);
        return;
    }
    var rng = rng_for(id.xy, frame.frame_index, SALT, frame.seed);
    let u = rand2(&rng);
    var v = vec3f(u, 0.0);
    if id.y == 0u {
        v = sample_cosine(NORMAL, u);
    } else if id.y == 1u {
        v = sample_cone(normalize(AXIS), ONE_MINUS_COS, u);
    } else if id.y == 3u {
        v = sample_glossy(normalize(MIRROR), NORMAL, ROUGHNESS, u);
    }
    textureStore(samples, id.xy, vec4f(v, 1.0));
}
