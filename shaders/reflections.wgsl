// Reflections: mirror bounces from specular surfaces, up to max_depth,
// with screen-space reuse (shared/reflect.wgsl). `main` lists the texels
// whose surface reflects; `listed` (the graph's `listed:` entry) traces
// only those.
#import reflect

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    reflect_select(id);
}

@compute @workgroup_size(64)
fn listed(@builtin(global_invocation_id) gid: vec3u) {
    let id = work_list_id(gid.x);
    if id.z != 0u {
        return;
    }
    var r = reflect_begin(id);
    while reflect_next(&r) {
        reflect_shade(&r, vec3f(0.0));
    }
    reflect_end(id, r);
}
