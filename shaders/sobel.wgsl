// Noise detection (thesis 4.2.2): a Sobel filter on the luminance of the
// noisy lit image, augmented so that real edges do not count: a neighbour
// contributes only when its normal is aligned with the centre's
// (cos >= normal_cos) and neither it nor the centre is an emitter or a
// miss; otherwise it stands in with the centre's own value.
#import scene

struct Params {
    normal_cos: f32, // ui: 0..1 "normal cos"
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var lit: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var gbuf_normal: texture_storage_2d<rgba16float, read>;
@group(0) @binding(3) var gbuf_id: texture_storage_2d<rgba32uint, read>;
@group(0) @binding(4) var edges: texture_storage_2d<r32float, write>;

fn luminance(c: vec3f) -> f32 {
    return dot(c, vec3f(0.2126, 0.7152, 0.0722));
}

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let ids = textureLoad(gbuf_id, id.xy);
    if !is_lit_surface(ids) {
        textureStore(edges, id.xy, vec4f(0.0));
        return;
    }
    let n = textureLoad(gbuf_normal, id.xy).xyz;
    let centre = luminance(textureLoad(lit, id.xy).rgb);
    var v: array<f32, 9>;
    for (var j = 0; j < 3; j++) {
        for (var i = 0; i < 3; i++) {
            let q = clamp(vec2i(id.xy) + vec2i(i - 1, j - 1), vec2i(0), vec2i(frame.size) - 1);
            let nq = textureLoad(gbuf_normal, q).xyz;
            let ok = is_lit_surface(textureLoad(gbuf_id, q)) && dot(n, nq) >= params.normal_cos;
            v[j * 3 + i] = select(centre, luminance(textureLoad(lit, q).rgb), ok);
        }
    }
    let gx = (v[2] + 2.0 * v[5] + v[8]) - (v[0] + 2.0 * v[3] + v[6]);
    let gy = (v[6] + 2.0 * v[7] + v[8]) - (v[0] + 2.0 * v[1] + v[2]);
    textureStore(edges, id.xy, vec4f(sqrt(gx * gx + gy * gy), 0.0, 0.0, 1.0));
}
