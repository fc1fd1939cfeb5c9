// The probe maps and grid of shared/probes.wgsl on the GPU, for
// tests/probes_gpu.rs to hold against src/probes/: per column i, a test
// direction and a test point (both computed the same way in the test);
// row 0: the direction's hemisphere texel for S = 5 (x, y: the tile's
// column, row); row 1: its octahedral encoding and the round trip's error;
// row 2: the point's cell (base probe); row 3: its position in the cell.
#import probes

@group(0) @binding(0) var probe_test: texture_storage_2d<rgba32float, write>;

const DIRS: u32 = 26u;

// Directions: the 26 axes and diagonals of the cube, then a spiral.
fn test_dir(i: u32, count: u32) -> vec3f {
    if i < DIRS {
        let k = select(i, i + 1u, i >= 13u); // skip (0, 0, 0)
        return normalize(vec3f(f32(k % 3u) - 1.0, f32((k / 3u) % 3u) - 1.0, f32(k / 9u) - 1.0));
    }
    let j = i - DIRS;
    let n = count - DIRS;
    let z = 1.0 - (2.0 * f32(j) + 1.0) / f32(n);
    let r = sqrt(max(0.0, 1.0 - z * z));
    let phi = f32(j) * 2.39996322972865;
    return vec3f(r * cos(phi), r * sin(phi), z);
}

// Points: column 0 is NaN, the others sweep a box twice the grid's size.
fn test_point(i: u32, count: u32) -> vec3f {
    if i == 0u {
        return vec3f(bitcast<f32>(0x7fc00000u));
    }
    let t = f32(i) / f32(count);
    let lo = frame.probe_origin - frame.probe_spacing * f32(frame.probe_n);
    let span = 3.0 * frame.probe_spacing * f32(frame.probe_n);
    return lo + span * fract(vec3f(t, t * 7.0, t * 13.0));
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let count = textureDimensions(probe_test).x;
    if id.x >= count {
        return;
    }
    let d = test_dir(id.x, count);
    let t = hemisphere_texel(d, 5u);
    textureStore(probe_test, vec2u(id.x, 0u), vec4f(f32(t.x), f32(t.y), 0.0, 1.0));
    let e = oct_encode(d);
    textureStore(probe_test, vec2u(id.x, 1u), vec4f(e, length(oct_decode(e) - d), 1.0));
    let c = probe_cell(test_point(id.x, count));
    textureStore(probe_test, vec2u(id.x, 2u), vec4f(vec3f(c.base), 1.0));
    textureStore(probe_test, vec2u(id.x, 3u), vec4f(c.f, 1.0));
}
