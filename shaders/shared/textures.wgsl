// Textured materials (docs/scenes.md, "glTF files"): a material's base
// colour and emission textures, read where a ray met a triangle.
// Every texture is a layer of one of four size classes, sRGB with mips
// (src/scene/texture_classes.rs); the level of detail comes from a ray
// cone (Akenine-Moller et al. 2021): the cone's width at the hit, over the
// cosine there, times the triangle's uv-to-world scale. With
// SCENE_TEXTURES false (no material has a texture) all of it folds away.
#import scene
#import brdf

override SCENE_TEXTURES: bool = true;
// Which texture size classes hold images (src/scene/specialise.rs).
override SCENE_TEXTURES_256: bool = true;
override SCENE_TEXTURES_512: bool = true;
override SCENE_TEXTURES_1024: bool = true;
override SCENE_TEXTURES_2048: bool = true;
// Some texture has a uv transform other than the identity
// (KHR_texture_transform): without one, no transform is read.
override SCENE_TEXTURE_TRANSFORMS: bool = true;
// Some material is alpha-tested (alphaMode MASK): a ray's closest hit on
// one is tested by alpha_passes, and traced again beyond it if it fails.
override SCENE_ALPHA_MASK: bool = true;
// Some triangle has vertex colours (glTF COLOR_0): they multiply the base
// colour as a texture does.
override SCENE_VERTEX_COLORS: bool = true;
// Some normal-mapped triangle has vertex tangents (the file's TANGENT or
// MikkTSpace's): normal textures bend in their frame.
override SCENE_VERTEX_TANGENTS: bool = true;

@group(1) @binding(14) var scene_uvs: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(15) var scene_material_textures: texture_storage_2d<rgba32uint, read>;
@group(1) @binding(16) var scene_images_256: texture_2d_array<f32>;
@group(1) @binding(17) var scene_images_512: texture_2d_array<f32>;
@group(1) @binding(18) var scene_images_1024: texture_2d_array<f32>;
@group(1) @binding(19) var scene_images_2048: texture_2d_array<f32>;
@group(1) @binding(20) var scene_sampler: sampler;

const NO_TEXTURE: u32 = 0xffffffffu;

// A metallic-roughness material's BRDF inputs (shared/brdf.wgsl).
fn as_metal_rough(m: Material) -> MetalRough {
    return MetalRough(m.albedo, m.metallic, m.roughness);
}

// What a surface's mirror reflection is multiplied by, seen at cosine
// cos_v: in the hybrid graphs' reflection passes a thesis material's
// (albedo times its specular share); in the thesis probes' mirror bounces
// also a metallic-roughness one's, its Fresnel reflectance F(n.v)
// (Schlick): white for a dielectric, whose coat reflects untinted, the
// base colour for a metal (the reflection passes draw such a surface's
// rays from its GGX lobe instead: shared/reflect.wgsl). The light passes
// weigh its diffuse lobe by 1 - F(n.v) (shaded_diffuse), so the two add
// up as the smooth BRDF's do.
fn specular_tint(m: Material, cos_v: f32) -> vec3f {
    if is_metal_rough(m) {
        return schlick(mr_f0(as_metal_rough(m)), max(cos_v, 1e-4));
    }
    return m.specular * m.albedo;
}

// The diffuse albedo the light passes shade m with at normal n, seen from
// v: a metallic-roughness surface's as its BRDF weighs it, by what the
// coat lets through toward the viewer, (1 - F(n.v)) c_diff; a thesis
// material's, its albedo less its specular share.
fn shaded_diffuse(m: Material, n: vec3f, v: vec3f) -> vec3f {
    if is_metal_rough(m) {
        let mr = as_metal_rough(m);
        return (vec3f(1.0) - schlick(mr_f0(mr), mr_view_cos(n, v))) * mr_c_diff(mr);
    }
    return diffuse_albedo(m);
}

// Texels of `scene_uvs` a triangle (src/scene/gpu_types.rs, TriangleUvGpu):
// uv0 uv1 | uv2 tangent0 tangent1 | tangent2 colour0 colour1 colour2.
const UV_TEXELS: u32 = 3u;

// The spread angle of a camera ray's cone (its width per unit of
// distance): the angle one pixel spans, narrowed as samples add up
// (frame.cone_scale), since the pixel's jittered samples average over
// the pixel themselves.
fn pixel_spread() -> f32 {
    return 2.0 * frame.camera.tan_half_fov / f32(frame.size.y) * frame.cone_scale;
}

// pixel_spread as last frame's camera rays had it.
fn last_pixel_spread() -> f32 {
    return 2.0 * frame.prev_camera.tan_half_fov / f32(frame.size.y) * frame.prev_cone_scale;
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
    // One read per size class the scene has (SCENE_TEXTURES_<side>): CPU
    // drivers run each under a lane mask for every texel sampled.
    let size_class = slot >> 16u;
    var texel = vec4f(0.0);
    if SCENE_TEXTURES_256 && size_class == 0u {
        texel = textureSampleLevel(scene_images_256, scene_sampler, uv, layer, lod_uv + 8.0);
    }
    if SCENE_TEXTURES_512 && size_class == 1u {
        texel = textureSampleLevel(scene_images_512, scene_sampler, uv, layer, lod_uv + 9.0);
    }
    if SCENE_TEXTURES_1024 && size_class == 2u {
        texel = textureSampleLevel(scene_images_1024, scene_sampler, uv, layer, lod_uv + 10.0);
    }
    if SCENE_TEXTURES_2048 && size_class >= 3u {
        texel = textureSampleLevel(scene_images_2048, scene_sampler, uv, layer, lod_uv + 11.0);
    }
    return texel;
}

// uv' = (row u . (uv, 1), row v . (uv, 1)) and the log2 of how it scales
// widths.
fn transform_uv(u: vec4f, v: vec4f, uv: vec2f) -> vec3f {
    let det = abs(u.x * v.y - u.y * v.x);
    return vec3f(dot(u.xyz, vec3f(uv, 1.0)), dot(v.xyz, vec3f(uv, 1.0)), 0.5 * log2(max(det, 1e-30)));
}

// Where point p of triangle `prim` lies in its texture space: its uv, the
// log2 of a ray cone's footprint there in uv units (the cone `width`
// wide at p, met along rd), and the triangle's edges in world and in uv
// space (for a tangent frame).
struct SurfaceUv {
    uv: vec2f,
    lod_uv: f32,
    e1: vec3f,
    e2: vec3f,
    du1: vec2f,
    du2: vec2f,
    // The triangle and p's barycentrics there (vertex attributes).
    prim: u32,
    bary: vec2f,
}

fn surface_uv(prim: u32, p: vec3f, rd: vec3f, width: f32) -> SurfaceUv {
    let p0 = load_triangle_vertex(prim, 0u);
    let e1 = load_triangle_vertex(prim, 1u) - p0;
    let e2 = load_triangle_vertex(prim, 2u) - p0;
    let t01 = bitcast<vec4f>(scene_texel(scene_uvs, UV_TEXELS * prim));
    let t2 = bitcast<vec4f>(scene_texel(scene_uvs, UV_TEXELS * prim + 1u)).xy;
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
    return SurfaceUv(uv, lod_uv, e1, e2, du1, du2, prim, vec2f(b1, b2));
}

// A colour packed as 1 - c in unorm 11-11-10 (gpu_types.rs, pack_color):
// zero, what a scene without vertex colours holds, is white.
fn unpack_color(v: u32) -> vec3f {
    return 1.0 - vec3f(f32(v & 0x7ffu) / 2047.0, f32((v >> 11u) & 0x7ffu) / 2047.0, f32(v >> 22u) / 1023.0);
}

// The vertex colour at s, interpolated.
fn vertex_color(s: SurfaceUv) -> vec3f {
    let c = scene_texel(scene_uvs, UV_TEXELS * s.prim + 2u).yzw;
    return (1.0 - s.bary.x - s.bary.y) * unpack_color(c.x) + s.bary.x * unpack_color(c.y) + s.bary.y * unpack_color(c.z);
}

// A tangent packed as snorm 10-10-10 and a sign bit (gpu_types.rs,
// pack_tangent): xyz and the bitangent's sign.
fn unpack_tangent(v: u32) -> vec4f {
    let i = bitcast<i32>(v);
    let xyz = vec3f(f32(extractBits(i, 0u, 10u)), f32(extractBits(i, 10u, 10u)), f32(extractBits(i, 20u, 10u))) / 511.0;
    return vec4f(xyz, select(1.0, -1.0, (v & 0x40000000u) != 0u));
}

// Material record texels (src/scene/gpu_types.rs, MaterialTexturesGpu).
const MATERIAL_TEXTURE_TEXELS: u32 = 10u;

fn material_texel(id: u32, k: u32) -> vec4u {
    return scene_texel(scene_material_textures, MATERIAL_TEXTURE_TEXELS * id + k);
}

// Texture `slot` of material `id`, its transform at texels k, k + 1 and
// its wrap bits at `shift` of `wrap_bits`, read at s.
fn sample_material(id: u32, slot: u32, k: u32, wrap_bits: u32, shift: u32, s: SurfaceUv) -> vec4f {
    var t = vec3f(s.uv, 0.0);
    if SCENE_TEXTURE_TRANSFORMS {
        t = transform_uv(bitcast<vec4f>(material_texel(id, k)), bitcast<vec4f>(material_texel(id, k + 1u)), s.uv);
    }
    let wrap = vec2u((wrap_bits >> shift) & 3u, (wrap_bits >> (shift + 2u)) & 3u);
    return sample_slot(slot, t.xy, wrap, s.lod_uv + t.z);
}

// Material `id` at point p of triangle `prim` (NO_OBJECT: a sphere, or
// nothing was hit), reached along rd by a ray cone `width` wide there:
// base colour, emission and (metallic-roughness materials) metalness and
// roughness textures applied.
fn material_at(id: u32, prim: u32, p: vec3f, rd: vec3f, width: f32) -> Material {
    let m = load_material(id);
    if !SCENE_TEXTURES || prim == NO_OBJECT {
        return m;
    }
    let slots = material_texel(id, 0u);
    var mr_slot = NO_TEXTURE;
    if is_metal_rough(m) {
        mr_slot = material_texel(id, 5u).x;
    }
    if slots.x == NO_TEXTURE && slots.y == NO_TEXTURE && mr_slot == NO_TEXTURE && !SCENE_VERTEX_COLORS {
        return m;
    }
    return textured(m, id, slots, mr_slot, surface_uv(prim, p, rd, width));
}

// What a hit's textures multiply its material by: the base colour, the
// emission and (metallic-roughness materials) the roughness and
// metalness; 1 where the material has no such texture.
struct TextureFactors {
    base: vec3f,
    emission: vec3f,
    rough_metal: vec2f,
}

const NO_FACTORS = TextureFactors(vec3f(1.0), vec3f(1.0), vec2f(1.0));

// `m` (material `id`) with its textures applied at s: `slots` its record's
// first texel, `mr_slot` its metallic-roughness texture (NO_TEXTURE: none
// read).
fn textured(m: Material, id: u32, slots: vec4u, mr_slot: u32, s: SurfaceUv) -> Material {
    return with_factors(m, texture_factors(id, slots, mr_slot, s));
}

// The factors of material `id`'s textures at s (as `textured`).
fn texture_factors(id: u32, slots: vec4u, mr_slot: u32, s: SurfaceUv) -> TextureFactors {
    var f = NO_FACTORS;
    if slots.x != NO_TEXTURE {
        f.base = sample_material(id, slots.x, 1u, slots.z, 0u, s).rgb;
    }
    if slots.y != NO_TEXTURE {
        f.emission = sample_material(id, slots.y, 3u, slots.z, 4u, s).rgb;
    }
    if mr_slot != NO_TEXTURE {
        // glTF: green is roughness, blue metalness (linear data).
        f.rough_metal = sample_material(id, mr_slot, 6u, slots.z, 8u, s).gb;
    }
    if SCENE_VERTEX_COLORS {
        f.base *= vertex_color(s);
    }
    return f;
}

// `m` times its texture factors f; a metallic-roughness material's
// specular share follows its metalness.
fn with_factors(m_in: Material, f: TextureFactors) -> Material {
    var m = m_in;
    m.albedo *= f.base;
    m.emission *= f.emission;
    if is_metal_rough(m) && any(f.rough_metal != vec2f(1.0)) {
        m.roughness *= f.rough_metal.x;
        m.metallic *= f.rough_metal.y;
        m.specular = m.metallic + DIELECTRIC_F0 * (1.0 - m.metallic);
    }
    return m;
}

// A hit's bent shading normal and texture factors: material `id` (loaded:
// m) at point p of triangle `prim`, reached along rd by a ray cone `width`
// wide there, `n` its interpolated normal (n and NO_FACTORS for a sphere,
// a miss or an untextured material); the triangle's uvs read once.
struct SurfaceFactors {
    n: vec3f,
    factors: TextureFactors,
}

fn surface_factors(m: Material, id: u32, prim: u32, p: vec3f, rd: vec3f, width: f32, n: vec3f) -> SurfaceFactors {
    if !SCENE_TEXTURES || prim == NO_OBJECT {
        return SurfaceFactors(n, NO_FACTORS);
    }
    let slots = material_texel(id, 0u);
    let more = material_texel(id, 5u);
    let mr_slot = select(NO_TEXTURE, more.x, is_metal_rough(m));
    if slots.x == NO_TEXTURE && slots.y == NO_TEXTURE && mr_slot == NO_TEXTURE && more.y == NO_TEXTURE && !SCENE_VERTEX_COLORS {
        return SurfaceFactors(n, NO_FACTORS);
    }
    let s = surface_uv(prim, p, rd, width);
    var out = SurfaceFactors(n, texture_factors(id, slots, mr_slot, s));
    if more.y != NO_TEXTURE {
        out.n = bent_normal(id, more.y, bitcast<f32>(more.z), slots.z, s, n);
    }
    return out;
}

// Texture factors as gbuf_material holds them: eight unorm16 values (the
// textures' own texels are 8-bit; 1 stays exactly 1).
fn pack_factors(f: TextureFactors) -> vec4u {
    return vec4u(pack2x16unorm(f.base.rg), pack2x16unorm(vec2f(f.base.b, f.emission.r)), pack2x16unorm(f.emission.gb), pack2x16unorm(f.rough_metal));
}

fn unpack_factors(v: vec4u) -> TextureFactors {
    let b = unpack2x16unorm(v.y);
    let e = unpack2x16unorm(v.z);
    return TextureFactors(vec3f(unpack2x16unorm(v.x), b.x), vec3f(b.y, e), unpack2x16unorm(v.w));
}

// The material a G-buffer pixel shows, its texture factors read from
// gbuf_material (`packed`) rather than sampled again: CPU drivers run the
// sampling code under a lane mask for every pixel, textured or not, so
// each pass that sampled it paid for it everywhere. ids as gbuffer.wgsl
// writes them.
fn stored_material(ids: vec4u, packed: vec4u) -> Material {
    if !SCENE_TEXTURES || ids.y == NO_OBJECT {
        return load_material(select(ids.x, 0u, ids.y == NO_OBJECT));
    }
    return with_factors(load_material(ids.x), unpack_factors(packed));
}

// `n` bent by normal texture `slot` of material `id` (x and y times
// `scale`; `wrap_bits` the record's wrap modes) at s, in the tangent frame
// of the triangle's vertex tangents where it has them (glTF's bitangent
// cross(n, t) w), else of its uvs (+x along u, +y toward the image's top,
// as glTF's normal textures are written); the tangent made orthogonal to n
// (Gram-Schmidt); n itself where neither frame exists.
fn bent_normal(id: u32, slot: u32, scale: f32, wrap_bits: u32, s: SurfaceUv, n: vec3f) -> vec3f {
    var frame = vertex_frame(s, n);
    if !frame.ok {
        frame = uv_frame(s, n);
    }
    if !frame.ok {
        return n;
    }
    let c = sample_material(id, slot, 8u, wrap_bits, 12u, s).xyz * 2.0 - 1.0;
    let bent = frame.t * (c.x * scale) + frame.b * (c.y * scale) + n * c.z;
    return select(n, normalize(bent), dot(bent, bent) > 0.0);
}

// The frame of the triangle's vertex tangents at s around n (none where it
// has none, or SCENE_VERTEX_TANGENTS is false).
fn vertex_frame(s: SurfaceUv, n: vec3f) -> TangentFrame {
    if !SCENE_VERTEX_TANGENTS {
        return NO_FRAME;
    }
    let t01 = scene_texel(scene_uvs, UV_TEXELS * s.prim + 1u).zw;
    let t2 = scene_texel(scene_uvs, UV_TEXELS * s.prim + 2u).x;
    if t01.x == 0u || t01.y == 0u || t2 == 0u {
        return NO_FRAME;
    }
    let a = unpack_tangent(t01.x);
    let t = (1.0 - s.bary.x - s.bary.y) * a.xyz + s.bary.x * unpack_tangent(t01.y).xyz + s.bary.y * unpack_tangent(t2).xyz;
    let tu = t - n * dot(n, t);
    if dot(tu, tu) <= 1e-12 {
        return NO_FRAME;
    }
    let tn = normalize(tu);
    return TangentFrame(tn, cross(n, tn) * a.w, true);
}

// A tangent, a bitangent toward the normal texture's +y, and whether they
// exist.
struct TangentFrame {
    t: vec3f,
    b: vec3f,
    ok: bool,
}

const NO_FRAME = TangentFrame(vec3f(0.0), vec3f(0.0), false);

// The frame of the triangle's uvs at s around n: +x along u, +y toward the
// image's top (glTF's v runs down it).
fn uv_frame(s: SurfaceUv, n: vec3f) -> TangentFrame {
    let det = s.du1.x * s.du2.y - s.du1.y * s.du2.x;
    if abs(det) < 1e-20 {
        return NO_FRAME;
    }
    let dpdu = (s.e1 * s.du2.y - s.e2 * s.du1.y) / det;
    let dpdv = (s.e2 * s.du1.x - s.e1 * s.du2.x) / det;
    let tu = dpdu - n * dot(n, dpdu);
    if dot(tu, tu) <= 0.0 {
        return NO_FRAME;
    }
    let t = normalize(tu);
    return TangentFrame(t, cross(n, t) * select(1.0, -1.0, dot(cross(n, t), dpdv) > 0.0), true);
}

// A hit's textured material and bent shading normal.
struct ShadedSurface {
    m: Material,
    n: vec3f,
}

// material_at and the bent normal at once (surface_factors; the path
// tracer's hits).
fn shaded_surface_at(id: u32, prim: u32, p: vec3f, rd: vec3f, width: f32, n: vec3f) -> ShadedSurface {
    let m = load_material(id);
    let s = surface_factors(m, id, prim, p, rd, width, n);
    return ShadedSurface(with_factors(m, s.factors), s.n);
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

// The alpha of texture `slot` at uv, wrapped by `wrap`: the nearest texel
// of the finest level, fetched, not filtered (traversal asks for it at
// every candidate hit of an alpha-tested triangle, and a filtered read
// costs lavapipe twice a fetch's time there).
fn alpha_at(slot: u32, uv_in: vec2f, wrap: vec2u) -> f32 {
    let size_class = min(slot >> 16u, 3u);
    let side = 256u << size_class;
    var uv = uv_in;
    uv = select(uv, 1.0 - abs(fract(uv * 0.5) * 2.0 - 1.0), wrap == vec2u(2u));
    uv = select(fract(uv), clamp(uv, vec2f(0.0), vec2f(1.0)), wrap != vec2u(0u));
    let texel = min(vec2u(uv * f32(side)), vec2u(side - 1u));
    let layer = i32(slot & 0xffffu);
    var alpha = 1.0;
    if SCENE_TEXTURES_256 && size_class == 0u {
        alpha = textureLoad(scene_images_256, texel, layer, 0).a;
    }
    if SCENE_TEXTURES_512 && size_class == 1u {
        alpha = textureLoad(scene_images_512, texel, layer, 0).a;
    }
    if SCENE_TEXTURES_1024 && size_class == 2u {
        alpha = textureLoad(scene_images_1024, texel, layer, 0).a;
    }
    if SCENE_TEXTURES_2048 && size_class == 3u {
        alpha = textureLoad(scene_images_2048, texel, layer, 0).a;
    }
    return alpha;
}

// Whether `material` is alpha-tested: traversal stops a shadow ray early
// only at a triangle that is not (intersect.wgsl, traverse_from).
fn alpha_tested(material: u32) -> bool {
    return SCENE_ALPHA_MASK && bitcast<f32>(material_texel(material, 0u).w) > 0.0;
}

// Whether triangle `prim` of `material` is there at barycentrics `bary`
// (alphaMode MASK): the base colour texture's alpha at its finest level
// (traversal has no ray cone), against the material's threshold (the
// cutoff over the factor's alpha; 0 for an opaque material).
fn alpha_passes(material: u32, prim: u32, bary: vec2f) -> bool {
    if !SCENE_ALPHA_MASK {
        return true;
    }
    let slots = material_texel(material, 0u);
    let threshold = bitcast<f32>(slots.w);
    if threshold <= 0.0 {
        return true;
    }
    if slots.x == NO_TEXTURE {
        return threshold <= 1.0;
    }
    let t01 = bitcast<vec4f>(scene_texel(scene_uvs, UV_TEXELS * prim));
    let t2 = bitcast<vec4f>(scene_texel(scene_uvs, UV_TEXELS * prim + 1u)).xy;
    let uv = (1.0 - bary.x - bary.y) * t01.xy + bary.x * t01.zw + bary.y * t2;
    var t = uv;
    if SCENE_TEXTURE_TRANSFORMS {
        t = transform_uv(bitcast<vec4f>(material_texel(material, 1u)), bitcast<vec4f>(material_texel(material, 2u)), uv).xy;
    }
    return alpha_at(slots.x, t, vec2u(slots.z & 3u, (slots.z >> 2u) & 3u)) >= threshold;
}
