#import reflect

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    var r = reflect_begin(id);
    while reflect_next(&r) {
        reflect_shade(&r, vec3f(0.0));
    }
    reflect_end(id, r);
}
