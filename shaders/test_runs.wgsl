// Counters for tests/run_modes.rs: `count` adds one to its persistent
// texel per dispatch and records the `run` uniform; `gather` copies four
// counters into one row, every frame.
#import run

@group(0) @binding(0) var counter: texture_storage_2d<rgba32float, read_write>;

@compute @workgroup_size(1)
fn count() {
    let c = textureLoad(counter, vec2u(0u));
    // x: dispatches seen; y: this dispatch's iteration; z: since_change;
    // w: dispatches in this frame.
    textureStore(counter, vec2u(0u), vec4f(c.x + 1.0, f32(run.iteration), f32(run.since_change), f32(run.count)));
}

@group(0) @binding(1) var a: texture_storage_2d<rgba32float, read>;
@group(0) @binding(2) var b: texture_storage_2d<rgba32float, read>;
@group(0) @binding(3) var c: texture_storage_2d<rgba32float, read>;
@group(0) @binding(4) var d: texture_storage_2d<rgba32float, read>;
@group(0) @binding(5) var row: texture_storage_2d<rgba32float, write>;

@compute @workgroup_size(4)
fn gather(@builtin(global_invocation_id) id: vec3u) {
    var v = vec4f(0.0);
    switch id.x {
        case 0u: { v = textureLoad(a, vec2u(0u)); }
        case 1u: { v = textureLoad(b, vec2u(0u)); }
        case 2u: { v = textureLoad(c, vec2u(0u)); }
        default: { v = textureLoad(d, vec2u(0u)); }
    }
    textureStore(row, vec2u(id.x, 0u), v);
}
