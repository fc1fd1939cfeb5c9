// Diffuse light from the irradiance volume: at each lit surface of the
// G-buffer, albedo / pi times the volume's irradiance for its normal, added
// to `lit`. Entry `thesis` reads chapter 3's maps (probes_thesis.wgsl):
// trilinear over the 8 probes of the point's cell, the normal mapped back
// to its bucket, no filtering within a map (as the thesis did).
// `probe_view` draws each probe as a small sphere showing the irradiance
// its maps hold for the sphere's normal (a debug view).
#import intersect
#import probes
#import sampling

@group(0) @binding(0) var gbuf_pos: texture_2d<f32>;
@group(0) @binding(1) var gbuf_normal: texture_2d<f32>;
@group(0) @binding(2) var gbuf_id: texture_2d<u32>;
@group(0) @binding(3) var albedo: texture_2d<f32>;
@group(0) @binding(4) var lit_in: texture_2d<f32>;
@group(0) @binding(5) var lit: texture_storage_2d<rgba32float, write>;
@group(0) @binding(6) var thesis_irradiance: texture_storage_2d<rgba32float, read>;

// Samples per axis of the thesis maps.
fn thesis_spa() -> u32 {
    return textureDimensions(thesis_irradiance).y / max(frame.probe_n, 1u);
}

// The irradiance probe `probe` holds for normal `n` (its bucket's value).
fn thesis_probe(probe: u32, n: vec3f, s: u32) -> vec3f {
    let corner = probe_tile(probe) * vec2u(2u * s, s);
    return textureLoad(thesis_irradiance, corner + hemisphere_texel(n, s)).rgb;
}

// Trilinear over the 8 probes of `p`'s cell.
fn thesis_at(p: vec3f, n: vec3f) -> vec3f {
    let s = thesis_spa();
    if frame.probe_n < 2u || s == 0u {
        return vec3f(0.0);
    }
    let cell = probe_cell(p);
    var e = vec3f(0.0);
    for (var c = 0u; c < 8u; c++) {
        e += corner_weight(cell, c) * thesis_probe(probe_index(cell_corner(cell, c)), n, s);
    }
    return e;
}

@compute @workgroup_size(8, 8)
fn thesis(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let before = textureLoad(lit_in, id.xy, 0);
    let ids = textureLoad(gbuf_id, id.xy, 0);
    if !is_lit_surface(ids) {
        textureStore(lit, id.xy, before);
        return;
    }
    let p = textureLoad(gbuf_pos, id.xy, 0).xyz;
    let n = normalize(textureLoad(gbuf_normal, id.xy, 0).xyz);
    let base = textureLoad(albedo, id.xy, 0).rgb * (1.0 - scene_materials[ids.x].specular);
    let radiance = finite_or_zero(base / PI * thesis_at(p, n));
    textureStore(lit, id.xy, vec4f(before.rgb + radiance, 1.0));
}

@group(0) @binding(7) var probe_view: texture_storage_2d<rgba32float, write>;

// Radius of a drawn probe: a fifth of the smallest spacing.
fn probe_radius() -> f32 {
    let sp = frame.probe_spacing;
    return 0.2 * min(sp.x, min(sp.y, sp.z));
}

@compute @workgroup_size(8, 8)
fn thesis_view(@builtin(global_invocation_id) id: vec3u) {
    if !in_frame(id) {
        return;
    }
    let s = thesis_spa();
    let n = frame.probe_n;
    let ro = frame.camera.origin;
    let rd = camera_dir(frame.camera, id.xy, vec2f(0.5));
    let r = probe_radius();
    var best = 3.0e38;
    var shown = vec3f(0.0);
    if n >= 2u && s > 0u {
        for (var i = 0u; i < n * n * n; i++) {
            let c = probe_position(probe_coords(i));
            let t = ray_sphere(ro, rd, c, r, 0.0, best);
            if t > 0.0 {
                best = t;
                shown = thesis_probe(i, normalize(ro + rd * t - c), s) / PI;
            }
        }
    }
    textureStore(probe_view, id.xy, vec4f(finite_or_zero(shown), 1.0));
}
