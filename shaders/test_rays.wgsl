// The GPU side of the ray robustness tests (tests/rays_gpu.rs): every
// combination of special values (0, -0, NaN, +-Inf, 1, -1, 1e-30) in the
// ray origin and direction, traced against the scene. Each pixel writes
// (closest found, any found, t, w): w is 1 when the traces finished and
// trace_primary and trace_pair found what
// trace_closest and trace_any found, 2 when they did not.
#import flat

@group(0) @binding(0) var ray_result: texture_storage_2d<rgba32float, write>;

fn special(i: u32) -> f32 {
    switch i {
        case 0u: { return 0.0; }
        case 1u: { return bitcast<f32>(0x80000000u); }
        case 2u: { return bitcast<f32>(0x7fc00000u); }
        case 3u: { return bitcast<f32>(0x7f800000u); }
        case 4u: { return bitcast<f32>(0xff800000u); }
        case 5u: { return 1.0; }
        case 6u: { return -1.0; }
        default: { return 1e-30; }
    }
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3u) {
    var flat = scene_flat;
    if id.x >= 512u || id.y >= 512u {
        return;
    }
    let k = id.y * 512u + id.x; // 8^6 combinations
    let o = vec3f(special(k & 7u), special((k >> 3u) & 7u), special((k >> 6u) & 7u));
    let d = vec3f(special((k >> 9u) & 7u), special((k >> 12u) & 7u), special((k >> 15u) & 7u));
    let h = trace_closest(o, d, 3.0e38);
    let any = trace_any(o, d, 3.0e38);
    let p = trace_primary(o, d, 3.0e38);
    // trace_pair along the ray itself: its hit and its shadow verdict.
    let pair = trace_pair(&flat, o, d, true, o, d, 3.0e38, NO_LIGHT);
    // A shadow ray from elsewhere (origin and direction swapped).
    let apart = trace_pair(&flat, o, d, true, d, o, 3.0e38, NO_LIGHT);
    // Wanting no hit and a shadow ray of length 0: neither is traced.
    let none = trace_pair(&flat, o, d, false, o, d, 0.0, NO_LIGHT);
    let agree = bitcast<u32>(p.t) == bitcast<u32>(h.t) && p.object == h.object
        && bitcast<u32>(pair.hit.t) == bitcast<u32>(h.t) && pair.hit.object == h.object && pair.blocked == any
        && bitcast<u32>(apart.hit.t) == bitcast<u32>(h.t) && apart.blocked == trace_any(d, o, 3.0e38)
        && !hit_found(none.hit) && !none.blocked;
    textureStore(ray_result, id.xy, vec4f(select(0.0, 1.0, hit_found(h)), select(0.0, 1.0, any), h.t, select(2.0, 1.0, agree)));
}
