// Textured materials (docs/scenes.md, "glTF files"): a material's base
// colour and emission textures, read where a ray met a triangle.
// Every texture is a layer of one of four size classes, sRGB with mips
// (src/scene/texture_classes.rs); the level of detail comes from a ray
// cone (Akenine-Moller et al. 2021): the cone's width at the hit, over the
// cosine there, times the triangle's uv-to-world scale. With
// SCENE_TEXTURES false (no material has a texture) all of it folds away.
#import scene

override SCENE_TEXTURES: bool = true;
// Some material is alpha-tested (alphaMode MASK): traversal asks
// alpha_passes of each triangle it would take.
override SCENE_ALPHA_MASK: bool = true;

@group(1) @binding(14) var scene_uvs: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(15) var scene_material_textures: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(16) var scene_images_256: texture_2d_array<f32>;
@group(1) @binding(17) var scene_images_512: texture_2d_array<f32>;
@group(1) @binding(18) var scene_images_1024: texture_2d_array<f32>;
@group(1) @binding(19) var scene_images_2048: texture_2d_array<f32>;
@group(1) @binding(20) var scene_sampler: sampler;

const NO_TEXTURE: u32 = 0xffffffffu;

// The angle one pixel spans (the width of a camera ray's cone per unit
// of distance).
fn pixel_spread() -> f32 {
    return 2.0 * frame.camera.tan_half_fov / f32(frame.size.y);
}

// Texture `slot` (class << 16 | layer) at uv, `lod_uv` the log2 of the
// footprint's width in uv units; `wrap` 0 repeat (the sampler's), 1 clamp,
// 2 mirror (done here on the uv, kept between the edge texels' centres of
// the coarser mip level read, so the repeating sampler does not blend in
// the far edge).
fn sample_slot(slot: u32, uv_in: vec2f, wrap: vec2u, lod_uv: f32) -> vec4f {
    let side_log2 = 8.0 + f32(min(slot >> 16u, 3u));
    let edge = 0.5 * exp2(ceil(clamp(lod_uv, -side_log2, 0.0)));
    var uv = uv_in;
    uv = select(uv, 1.0 - abs(fract(uv * 0.5) * 2.0 - 1.0), wrap == vec2u(2u));
    uv = select(uv, clamp(uv, vec2f(edge), vec2f(1.0 - edge)), wrap != vec2u(0u));
    let layer = i32(slot & 0xffffu);
    switch slot >> 16u {
        case 0u: {
            return textureSampleLevel(scene_images_256, scene_sampler, uv, layer, lod_uv + 8.0);
        }
        case 1u: {
            return textureSampleLevel(scene_images_512, scene_sampler, uv, layer, lod_uv + 9.0);
        }
        case 2u: {
            return textureSampleLevel(scene_images_1024, scene_sampler, uv, layer, lod_uv + 10.0);
        }
        default: {
            return textureSampleLevel(scene_images_2048, scene_sampler, uv, layer, lod_uv + 11.0);
        }
    }
}

// uv' = (row u . (uv, 1), row v . (uv, 1)) and the log2 of how it scales
// widths.
fn transform_uv(u: vec4f, v: vec4f, uv: vec2f) -> vec3f {
    let det = abs(u.x * v.y - u.y * v.x);
    return vec3f(dot(u.xyz, vec3f(uv, 1.0)), dot(v.xyz, vec3f(uv, 1.0)), 0.5 * log2(max(det, 1e-30)));
}

// Material `id` at point p of triangle `prim` (NO_OBJECT: a sphere, or
// nothing was hit), reached along rd by a ray cone `width` wide there.
fn material_at(id: u32, prim: u32, p: vec3f, rd: vec3f, width: f32) -> Material {
    var m = load_material(id);
    if !SCENE_TEXTURES || prim == NO_OBJECT {
        return m;
    }
    let slots = scene_texel(scene_material_textures, 5u * id);
    if slots.x == NO_TEXTURE && slots.y == NO_TEXTURE {
        return m;
    }
    let p0 = load_triangle_vertex(prim, 0u);
    let e1 = load_triangle_vertex(prim, 1u) - p0;
    let e2 = load_triangle_vertex(prim, 2u) - p0;
    let t01 = bitcast<vec4f>(scene_texel(scene_uvs, 2u * prim));
    let t2 = bitcast<vec4f>(scene_texel(scene_uvs, 2u * prim + 1u)).xy;
    // Barycentrics of p (projected onto the triangle's plane).
    let q = p - p0;
    let d00 = dot(e1, e1);
    let d01 = dot(e1, e2);
    let d11 = dot(e2, e2);
    let d20 = dot(q, e1);
    let d21 = dot(q, e2);
    let den = d00 * d11 - d01 * d01;
    let b1 = select(0.0, (d11 * d20 - d01 * d21) / den, den > 0.0);
    let b2 = select(0.0, (d00 * d21 - d01 * d20) / den, den > 0.0);
    let uv = (1.0 - b1 - b2) * t01.xy + b1 * t01.zw + b2 * t2;
    // The cone's footprint in uv units: world width over the cosine,
    // times sqrt(uv area / world area).
    let n = cross(e1, e2);
    let world_area = length(n);
    let du1 = t01.zw - t01.xy;
    let du2 = t2 - t01.xy;
    let uv_area = abs(du1.x * du2.y - du1.y * du2.x);
    let cos_t = max(abs(dot(n, rd)) / max(world_area, 1e-30), 0.05);
    let lod_uv = log2(max(width * sqrt(uv_area / max(world_area, 1e-30)) / cos_t, 1e-30));
    let wrap = vec4u(slots.z & 3u, (slots.z >> 2u) & 3u, (slots.z >> 4u) & 3u, (slots.z >> 6u) & 3u);
    if slots.x != NO_TEXTURE {
        let u = bitcast<vec4f>(scene_texel(scene_material_textures, 5u * id + 1u));
        let v = bitcast<vec4f>(scene_texel(scene_material_textures, 5u * id + 2u));
        let t = transform_uv(u, v, uv);
        m.albedo *= sample_slot(slots.x, t.xy, wrap.xy, lod_uv + t.z).rgb;
    }
    if slots.y != NO_TEXTURE {
        let u = bitcast<vec4f>(scene_texel(scene_material_textures, 5u * id + 3u));
        let v = bitcast<vec4f>(scene_texel(scene_material_textures, 5u * id + 4u));
        let t = transform_uv(u, v, uv);
        m.emission *= sample_slot(slots.y, t.xy, wrap.zw, lod_uv + t.z).rgb;
    }
    return m;
}

// The material a G-buffer pixel shows: ids as gbuffer.wgsl writes them
// (material, object, error, triangle), pos its (position, distance).
fn gbuffer_material(ids: vec4u, pos: vec4f) -> Material {
    if !SCENE_TEXTURES || ids.y == NO_OBJECT {
        return load_material(select(ids.x, 0u, ids.y == NO_OBJECT));
    }
    let rd = normalize(pos.xyz - frame.camera.origin);
    return material_at(ids.x, ids.w, pos.xyz, rd, pos.w * pixel_spread());
}

// Whether triangle `prim` of `material` is there at barycentrics `bary`
// (alphaMode MASK): the base colour texture's alpha, read at its finest
// level (traversal has no ray cone), against the material's threshold
// (the cutoff over the factor's alpha; 0 for an opaque material).
fn alpha_passes(material: u32, prim: u32, bary: vec2f) -> bool {
    if !SCENE_ALPHA_MASK {
        return true;
    }
    let slots = scene_texel(scene_material_textures, 5u * material);
    let threshold = bitcast<f32>(slots.w);
    if threshold <= 0.0 {
        return true;
    }
    if slots.x == NO_TEXTURE {
        return threshold <= 1.0;
    }
    let t01 = bitcast<vec4f>(scene_texel(scene_uvs, 2u * prim));
    let t2 = bitcast<vec4f>(scene_texel(scene_uvs, 2u * prim + 1u)).xy;
    let uv = (1.0 - bary.x - bary.y) * t01.xy + bary.x * t01.zw + bary.y * t2;
    let u = bitcast<vec4f>(scene_texel(scene_material_textures, 5u * material + 1u));
    let v = bitcast<vec4f>(scene_texel(scene_material_textures, 5u * material + 2u));
    let t = transform_uv(u, v, uv);
    return sample_slot(slots.x, t.xy, vec2u(slots.z & 3u, (slots.z >> 2u) & 3u), -24.0).a >= threshold;
}
