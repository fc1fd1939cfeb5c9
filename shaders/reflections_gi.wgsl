// Reflections (reflections.wgsl) whose shaded hits also get diffuse
// indirect light from the DDGI volume (hybrid-gi.ron).
#import reflect
#import ddgi_volume

@compute @workgroup_size(128, 1)
fn main(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    reflect_select(id);
}

// Over the texels `main` listed (the graph's `listed:` entry).
@compute @workgroup_size(64)
fn listed(@builtin(global_invocation_id) gid: vec3u) {
    let id = work_list_id(gid.x);
    if id.z != 0u {
        return;
    }
    var r = reflect_begin(id);
    while reflect_next(&r) {
        reflect_shade(&r, ddgi_irradiance_at(r.hit_p, r.hit_n, -r.dir));
    }
    reflect_end(id, r);
}
