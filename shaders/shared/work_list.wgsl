// A pass's work list: the texels its entry point found work for, which its
// `listed` entry (a second entry point, named by `listed:` in the graph)
// then runs over, WORK_GROUP to a workgroup, by an indirect dispatch that
// costs only those texels. The engine empties the list before the pass
// (src/graph/executor.rs; the layout is WORK_LIST_HEADER and
// WORK_LIST_GROUP in src/graph/schedule.rs).
//
// Why: CPU drivers (lavapipe) run a shader's branches under a lane mask,
// taken or not, so a pass where 4% of the pixels need a ray pays for the
// ray on every pixel; a per-texel `if` saves nothing there.

const WORK_GROUP: u32 = 64u;

struct WorkList {
    count: atomic<u32>,
    // The indirect dispatch: groups of WORK_GROUP listed texels (x), 1, 1.
    groups: atomic<u32>,
    groups_y: u32,
    groups_z: u32,
    // (x, y) as x | y << 16.
    items: array<u32>,
}

@group(2) @binding(1) var<storage, read_write> work_list: WorkList;

fn work_list_push(texel: vec2u) {
    let i = atomicAdd(&work_list.count, 1u);
    work_list.items[i] = texel.x | (texel.y << 16u);
    if i % WORK_GROUP == 0u {
        atomicAdd(&work_list.groups, 1u);
    }
}

// Listed invocation `i`'s texel, shaped like the entry's global id
// (x, y, 0), or z = 1 past the end (the last group's spare invocations):
// `let id = work_list_id(gid.x); if id.z != 0u { return; }`.
fn work_list_id(i: u32) -> vec3u {
    if i >= atomicLoad(&work_list.count) {
        return vec3u(0u, 0u, 1u);
    }
    let v = work_list.items[i];
    return vec3u(v & 0xffffu, v >> 16u, 0u);
}
