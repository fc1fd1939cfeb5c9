// The GPU side of the watertightness test (tests/watertight_gpu.rs): one
// ray per texel from the camera position in a uniformly random direction,
// traced for the closest hit and for any hit. The camera sits inside a
// closed mesh, so every ray must hit it. Writes (closest found, any found,
// t, w). On a flat scene the camera's and the light's rays also go through
// shared/origins.wgsl: w is 1 when trace_camera hit what trace_closest hit
// (t within 1e-5) and the shadow ray from 2 radii outside back toward
// light 0 (at the camera) was blocked; +2 and +4 flag each failure.
#import origins
#import rng

@group(0) @binding(0) var watertight: texture_storage_2d<rgba32float, write>;

const SALT: u32 = 0x77746967u;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3u) {
    let size = textureDimensions(watertight);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    var rng = rng_for(id.xy, frame.frame_index, SALT, frame.seed);
    let u = rand2(&rng);
    let z = 1.0 - 2.0 * u.x;
    let r = sqrt(max(0.0, 1.0 - z * z));
    let phi = 6.2831853 * u.y;
    let d = vec3f(r * cos(phi), r * sin(phi), z);
    let o = frame.camera.origin;
    let h = trace_closest(o, d, 3.0e38);
    let any = trace_any(o, d, 3.0e38);
    let cam = trace_camera(d, 3.0e38);
    let camera_agrees = cam.object == h.object && abs(cam.t - h.t) <= 1e-5 * h.t;
    let light = load_light(0u).position;
    let outside = light + 2.0 * h.t * d;
    let blocked = trace_any_from_light(light, outside, -d, 2.0 * h.t * (1.0 - 1e-4));
    let w = 1.0 + select(2.0, 0.0, camera_agrees) + select(4.0, 0.0, blocked);
    textureStore(watertight, id.xy, vec4f(select(0.0, 1.0, hit_found(h)), select(0.0, 1.0, any), h.t, w));
}
