// The engine's per-frame uniform (mirrors FrameGpu in src/session/frame_uniform.rs).

struct Camera {
    origin: vec3f,
    tan_half_fov: f32,
    right: vec3f,
    aspect: f32,
    up: vec3f,
    _pad0: f32,
    forward: vec3f,
    _pad1: f32,
}

struct Frame {
    camera: Camera,
    prev_camera: Camera,
    size: vec2u,
    frame_index: u32,
    accum_count: u32,
    time: f32,
    seed: u32,
    scene_epoch: u32,
    n_spheres: u32,
    n_instances: u32,
    n_triangles: u32,
    n_lights: u32,
    // The noise-mask threshold from the PID controller (threshold.wgsl).
    mask_threshold: f32,
    background: vec3f,
    // Frames since the scene last changed (0: all history is stale);
    // unlike accum_count, camera motion does not reset it.
    epoch_frames: u32,
    // 1.0, which the shader compiler cannot know: multiplying by it keeps
    // compensated (Kahan) arithmetic from being folded away (Mesa's NIR,
    // for one, treats float ops as reassociable; see shared/mean.wgsl).
    exact_one: f32,
    // The grid the origin is rebased on (a power of two near half the
    // scene's extent); ray offsets take each hit's own error bound instead
    // (offset_ray, src/bvh/offset.rs).
    offset_scale: f32,
    // Frames since history was last dropped (a new session, a restart, a
    // reset): 0 = no history texture holds anything yet. Camera motion
    // and scene changes do not reset it (see epoch_frames for those).
    history_frames: u32,
    // What camera-ray cones are narrowed by as samples add up (textures.wgsl,
    // pixel_spread; cone_scale in src/session/frame_uniform.rs).
    cone_scale: f32,
    // The graph's probe grid (`probes:` in a graph), relative to the scene
    // origin: probe (0,0,0), the spacing, probes per axis (0: no probes).
    probe_origin: vec3f,
    probe_n: u32,
    probe_spacing: vec3f,
    // Last frame's cone_scale (for a pass that traces its paths again).
    prev_cone_scale: f32,
    // How many clusters the lights are in (0: few lights; light_choice.wgsl).
    n_light_clusters: u32,
    _pad_c0: u32,
    _pad_c1: u32,
    _pad_c2: u32,
}

@group(1) @binding(0) var<uniform> frame: Frame;

// Direction through pixel `pixel` at sub-pixel offset `jitter` in [0,1)^2.
// Pixel (0,0) is top-left; the camera looks along `forward`.
fn camera_dir(cam: Camera, pixel: vec2u, jitter: vec2f) -> vec3f {
    let size = vec2f(frame.size);
    let p = vec2f(pixel) + jitter;
    let sx = (2.0 * p.x / size.x - 1.0) * cam.aspect * cam.tan_half_fov;
    let sy = (1.0 - 2.0 * p.y / size.y) * cam.tan_half_fov;
    return normalize(cam.forward + sx * cam.right + sy * cam.up);
}

// Where world point `p` lands on `cam`'s image, in pixels (continuous:
// pixel (i, j) spans [i, i+1) x [j, j+1)); the inverse of camera_dir.
// z <= 0 (behind the camera) returns a negative depth in .z.
// The point a miss's direction `dir` stands for, seen from camera `cam`:
// far enough along it that adding it to the camera's position keeps it
// (a camera 4.4e7 from the origin rounds a unit step away: its misses then
// projected behind it and lost their history where a camera near the
// origin kept it), and 1 for a camera within 1024 of the origin.
fn miss_point(cam: Camera, dir: vec3f) -> vec3f {
    let a = abs(cam.origin);
    let far = max(1.0, max(a.x, max(a.y, a.z)) * (1.0 / 1024.0));
    return cam.origin + far * dir;
}

fn project(cam: Camera, p: vec3f) -> vec3f {
    let d = p - cam.origin;
    let z = dot(d, cam.forward);
    let size = vec2f(frame.size);
    let sx = dot(d, cam.right) / (z * cam.aspect * cam.tan_half_fov);
    let sy = dot(d, cam.up) / (z * cam.tan_half_fov);
    return vec3f((sx + 1.0) * 0.5 * size.x, (1.0 - sy) * 0.5 * size.y, z);
}

// Screen passes run @workgroup_size(128, 1): one run along a row, which a
// CPU driver streams through memory (an 8x8 tile touches eight rows apart
// and its texel loads cost up to three times as much), and lavapipe's
// fixed cost per workgroup paid half as often as with 64 (an empty
// 1280x720 dispatch: 2.7 ms in 64x1 groups, 2.1 in 256x1; `cargo run
// --release --example pass_cost`). 128 divides the usual widths (640,
// 1280, 1920): 256 left half a workgroup idle at the end of each row of
// 640 and took hybrid-point to 1.15x the frame at 640x360, where 128
// takes 1.00x of 64 there and 0.98x at 1280x720 (`glint bench frames`). Entries that stride by their
// dispatch or take texels from a pool (pathtrace's main, the ray bench's
// query and primary, DDGI's gather phases) and work-list entries
// (WORK_GROUP) keep 64.
fn in_frame(id: vec3u) -> bool {
    return id.x < frame.size.x && id.y < frame.size.y;
}
