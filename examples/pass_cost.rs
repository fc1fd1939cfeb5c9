//! What the fixed parts of a full-screen pass cost on this adapter: an
//! invocation that only stores, texel loads and stores of each format the
//! graphs use, workgroup shapes, and a uniform read. Each variant is one
//! 1280x720 dispatch (every workgroup shape divides it), median of 7. This
//! is the floor under every per-pixel pass (albedo, accumulate, sobel,
//! blur): what a pass costs beyond it is its own work.
//!
//! The HEAVY variants put 800 integer operations behind a condition. On
//! lavapipe (Mesa 22.3) they show that a branch skips nothing: an `if` no
//! lane takes, one on a uniform, one on `subgroupAny` or on a
//! `workgroupUniformLoad` all cost what the straight code costs, and a loop
//! runs at least one trip however few lanes enter it (small known-bound
//! loops are unrolled into ifs first). Only a shorter dispatch saves the
//! work, which is why sparse passes list their texels (shared/work_list.wgsl).
//!
//! Texel loads cost what their cache misses cost: four loads of one
//! texture around the pixel cost about one load, four far apart about
//! four. The workgroup's shape decides how well the driver's row-by-row
//! walk streams through memory: with 8x8 workgroups an 8-lane SIMD group
//! reads 8 texels of each of 8 rows (8 pages apart at 1280 texels a row),
//! with 64x1 one run of 64 texels, and four loads from four textures cost
//! a third as much. A wider run also pays the driver's fixed cost per
//! workgroup less often (an empty dispatch: 8x8 4.8 ms, 64x1 2.7, 256x1
//! 2.1). Hence screen passes are @workgroup_size(128, 1), which divides
//! the usual widths (shared/frame.wgsl).
//!
//! The "13 prims" variants read a small scene's primitives (three texels
//! each, the same index in every lane, as the flat-scene loop does) from a
//! storage texture, from a uniform array and from workgroup memory filled
//! once per workgroup: the texture is the cheapest (about 19, 27 and 60 ms
//! here), so scene data stays in textures.
//!
//!   WGPU_BACKEND=vulkan cargo run --release --example pass_cost
//!   PASS_COST_ONLY=loads ...    only the variants whose name has "loads"

const SIZE: (u32, u32) = (1280, 720);

struct Variant {
    name: &'static str,
    workgroup: (u32, u32),
    body: &'static str,
}

// Four rgba32float loads from four textures, stored: timed per workgroup shape.
const FOUR_LOADS: &str = "textureStore(o32, id.xy, textureLoad(t32, id.xy, 0) + textureLoad(t32b, id.xy, 0) + textureLoad(t32c, id.xy, 0) + textureLoad(t32d, id.xy, 0));";

const VARIANTS: &[Variant] = &[
    Variant { name: "return at once", workgroup: (8, 8), body: "if id.x == 99999u { textureStore(o32, id.xy, vec4f(1.0)); }" },
    Variant { name: "return at once 64x1", workgroup: (64, 1), body: "if id.x == 99999u { textureStore(o32, id.xy, vec4f(1.0)); }" },
    Variant { name: "return at once 128x1", workgroup: (128, 1), body: "if id.x == 99999u { textureStore(o32, id.xy, vec4f(1.0)); }" },
    Variant { name: "return at once 256x1", workgroup: (256, 1), body: "if id.x == 99999u { textureStore(o32, id.xy, vec4f(1.0)); }" },
    Variant { name: "store rgba32float", workgroup: (8, 8), body: "textureStore(o32, id.xy, vec4f(f32(id.x)));" },
    Variant { name: "store rgba32float 16x16", workgroup: (16, 16), body: "textureStore(o32, id.xy, vec4f(f32(id.x)));" },
    Variant { name: "store rgba32float 64x1", workgroup: (64, 1), body: "textureStore(o32, id.xy, vec4f(f32(id.x)));" },
    Variant { name: "store rgba32float 8x1", workgroup: (8, 1), body: "textureStore(o32, id.xy, vec4f(f32(id.x)));" },
    Variant { name: "store rgba32float 256x1", workgroup: (256, 1), body: "textureStore(o32, id.xy, vec4f(f32(id.x)));" },
    Variant { name: "store rgba16float", workgroup: (8, 8), body: "textureStore(o16, id.xy, vec4f(f32(id.x)));" },
    Variant { name: "store r32float", workgroup: (8, 8), body: "textureStore(or32, id.xy, vec4f(f32(id.x)));" },
    Variant { name: "store rgba32uint", workgroup: (8, 8), body: "textureStore(ou32, id.xy, vec4u(id.x));" },
    Variant { name: "store to a buffer", workgroup: (8, 8), body: "ob[id.y * 1280u + id.x] = vec4f(f32(id.x));" },
    Variant {
        name: "load rgba32float + store",
        workgroup: (8, 8),
        body: "textureStore(o32, id.xy, textureLoad(t32, id.xy, 0));",
    },
    Variant {
        name: "4 loads rgba32float + store",
        workgroup: (8, 8),
        body: FOUR_LOADS,
    },
    Variant {
        name: "4 loads rgba32float + store 64x1",
        workgroup: (64, 1),
        body: FOUR_LOADS,
    },
    Variant {
        name: "4 loads rgba32float + store 32x2",
        workgroup: (32, 2),
        body: FOUR_LOADS,
    },
    Variant {
        name: "4 loads rgba32float + store 16x4",
        workgroup: (16, 4),
        body: FOUR_LOADS,
    },
    Variant {
        name: "2 loads rgba32float + store",
        workgroup: (8, 8),
        body: "textureStore(o32, id.xy, textureLoad(t32, id.xy, 0) + textureLoad(t32b, id.xy, 0));",
    },
    Variant {
        name: "4 loads of one rgba32float + store",
        workgroup: (8, 8),
        body: "textureStore(o32, id.xy, textureLoad(t32, id.xy, 0) + textureLoad(t32, id.xy + vec2u(1u, 0u), 0) + textureLoad(t32, id.xy + vec2u(0u, 1u), 0) + textureLoad(t32, id.xy + vec2u(1u, 1u), 0));",
    },
    Variant {
        name: "4 far loads of one rgba32float + store",
        workgroup: (8, 8),
        body: "textureStore(o32, id.xy, textureLoad(t32, id.xy, 0) + textureLoad(t32, (id.xy + vec2u(0u, 180u)) % vec2u(1280u, 720u), 0) + textureLoad(t32, (id.xy + vec2u(0u, 360u)) % vec2u(1280u, 720u), 0) + textureLoad(t32, (id.xy + vec2u(0u, 540u)) % vec2u(1280u, 720u), 0));",
    },
    Variant {
        name: "storage-read rgba32float + store",
        workgroup: (8, 8),
        body: "textureStore(o32, id.xy, textureLoad(s32, id.xy));",
    },
    Variant {
        name: "4 storage-reads rgba32float + store",
        workgroup: (8, 8),
        body: "textureStore(o32, id.xy, textureLoad(s32, id.xy) + textureLoad(s32, id.xy + vec2u(1u, 0u)) + textureLoad(s32, id.xy + vec2u(0u, 1u)) + textureLoad(s32, id.xy + vec2u(1u, 1u)));",
    },
    Variant {
        name: "load rgba16float + store",
        workgroup: (8, 8),
        body: "textureStore(o32, id.xy, textureLoad(t16, id.xy, 0));",
    },
    Variant {
        name: "load rgba32uint + store",
        workgroup: (8, 8),
        body: "textureStore(o32, id.xy, vec4f(textureLoad(tu32, id.xy, 0)));",
    },
    Variant {
        name: "3 stores rgba32float",
        workgroup: (8, 8),
        body: "textureStore(o32, id.xy, vec4f(1.0)); textureStore(o32b, id.xy, vec4f(2.0)); textureStore(o32c, id.xy, vec4f(3.0));",
    },
    Variant { name: "HEAVY straight, every lane", workgroup: (8, 8), body: "var h = id.x; HEAVY textureStore(or32, id.xy, vec4f(f32(h)));" },
    Variant { name: "HEAVY in an if no lane takes", workgroup: (8, 8), body: "var h = id.x; if f32(id.x) * u.b.x > 1.0 { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));" },
    Variant {
        name: "HEAVY in a while-once no lane takes",
        workgroup: (8, 8),
        body: "var h = id.x; var go = f32(id.x) * u.b.x > 1.0; while go { HEAVY go = false; } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY in a while-once 1 lane of 8",
        workgroup: (8, 8),
        body: "var h = id.x; var go = (id.x & 7u) == 3u; while go { HEAVY go = false; } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY in a while-once 1 row of 8",
        workgroup: (8, 8),
        body: "var h = id.x; var go = (id.y & 7u) == 3u; while go { HEAVY go = false; } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY if subgroupAny, 1 row of 8",
        workgroup: (8, 8),
        body: "var h = id.x; let go = (id.y & 7u) == 3u; if subgroupAny(go) { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY while subgroupAny, 1 row of 8",
        workgroup: (8, 8),
        body: "var h = id.x; var go = (id.y & 7u) == 3u; while subgroupAny(go) { HEAVY go = false; } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY if uniform false",
        workgroup: (8, 8),
        body: "var h = id.x; if u.b.x > 1.0 { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY if wg-uniform, 1 wg row of 8",
        workgroup: (8, 8),
        body: "var h = id.x; if (id.y & 63u) == 3u { wflag = 1u; } if workgroupUniformLoad(&wflag) != 0u { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY loop-break-first, no lane",
        workgroup: (8, 8),
        body: "var h = id.x; let go = f32(id.x) * u.b.x > 1.0; loop { if !go { break; } HEAVY break; } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY loop-break-first, 1 row of 8",
        workgroup: (8, 8),
        body: "var h = id.x; let go = (id.y & 7u) == 3u; loop { if !go { break; } HEAVY break; } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY for divergent count, no lane",
        workgroup: (8, 8),
        body: "var h = id.x; let n = select(0u, 1u, f32(id.x) * u.b.x > 1.0); for (var i = 0u; i < n; i++) { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY loop u32(uniform false)",
        workgroup: (8, 8),
        body: "var h = id.x; for (var k = 0u; k < u32(u.b.x > 1.0); k++) { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY loop wg-uniform, 1/8 of wgs",
        workgroup: (8, 8),
        body: "var h = id.x; if (id.y & 63u) == 3u { wflag = 1u; } for (var k = 0u; k < workgroupUniformLoad(&wflag); k++) { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY loop wg-uniform, no wg",
        workgroup: (8, 8),
        body: "var h = id.x; if f32(id.x) * u.b.x > 1.0 { wflag = 1u; } for (var k = 0u; k < workgroupUniformLoad(&wflag); k++) { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY loop unknown bound, no lane",
        workgroup: (8, 8),
        body: "var h = id.x; let n = select(0u, 1u + bitcast<u32>(u.b.y), f32(id.x) * u.b.x > 1.0); for (var k = 0u; k < n; k++) { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY loop unknown bound, 1 row of 8",
        workgroup: (8, 8),
        body: "var h = id.x; let n = select(0u, 1u + bitcast<u32>(u.b.y), (id.y & 7u) == 3u); for (var k = 0u; k < n; k++) { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY loop unknown bound, 1 lane of 8",
        workgroup: (8, 8),
        body: "var h = id.x; let n = select(0u, 1u + bitcast<u32>(u.b.y), (id.x & 7u) == 3u); for (var k = 0u; k < n; k++) { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY uniform-loop, false",
        workgroup: (8, 8),
        body: "var h = id.x; for (var k = 0u; k < select(0u, u32(u.a.w + 1.0), u.b.x > 1.0); k++) { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY uniform-loop, true",
        workgroup: (8, 8),
        body: "var h = id.x; for (var k = 0u; k < select(0u, u32(u.a.w + 1.0), u.b.x < 1.0); k++) { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "HEAVY in a loop of 0 trips",
        workgroup: (8, 8),
        body: "var h = id.x; for (var i = 0u; i < bitcast<u32>(u.a.x); i++) { HEAVY } textureStore(or32, id.xy, vec4f(f32(h)));",
    },
    Variant {
        name: "13 prims from a storage texture",
        workgroup: (64, 1),
        body: "var acc = 0.0; for (var i = 0u; i < 13u + u32(u.b.x); i++) { let a = bitcast<vec4f>(textureLoad(sg, vec2u(3u * i + 0u, 0u))); let b = bitcast<vec4f>(textureLoad(sg, vec2u(3u * i + 1u, 0u))); let c = bitcast<vec4f>(textureLoad(sg, vec2u(3u * i + 2u, 0u))); acc += dot(a.xyz - vec3f(f32(id.x)), b.xyz) * c.x; } textureStore(or32, id.xy, vec4f(acc));",
    },
    Variant {
        name: "13 prims from a uniform array",
        workgroup: (64, 1),
        body: "var acc = 0.0; for (var i = 0u; i < 13u + u32(u.b.x); i++) { let a = ua.v[3u * i + 0u]; let b = ua.v[3u * i + 1u]; let c = ua.v[3u * i + 2u]; acc += dot(a.xyz - vec3f(f32(id.x)), b.xyz) * c.x; } textureStore(or32, id.xy, vec4f(acc));",
    },
    Variant {
        name: "13 prims from workgroup memory",
        workgroup: (64, 1),
        body: "for (var k = id.x % 64u; k < 39u; k += 64u) { wprims[k] = bitcast<vec4f>(textureLoad(sg, vec2u(k, 0u))); } workgroupBarrier(); var acc = 0.0; for (var i = 0u; i < 13u + u32(u.b.x); i++) { let a = wprims[3u * i + 0u]; let b = wprims[3u * i + 1u]; let c = wprims[3u * i + 2u]; acc += dot(a.xyz - vec3f(f32(id.x)), b.xyz) * c.x; } textureStore(or32, id.xy, vec4f(acc));",
    },
    Variant {
        name: "uniform read + store",
        workgroup: (8, 8),
        body: "textureStore(o32, id.xy, vec4f(u.a.xyz * f32(id.x), u.b.w));",
    },
];

const DECLS: &str = "
struct U { a: vec4f, b: vec4f }
var<workgroup> wflag: u32;
var<workgroup> wprims: array<vec4f, 39>;
@group(0) @binding(0) var o32: texture_storage_2d<rgba32float, write>;
@group(0) @binding(1) var o32b: texture_storage_2d<rgba32float, write>;
@group(0) @binding(2) var o32c: texture_storage_2d<rgba32float, write>;
@group(0) @binding(3) var o16: texture_storage_2d<rgba16float, write>;
@group(0) @binding(4) var or32: texture_storage_2d<r32float, write>;
@group(0) @binding(5) var ou32: texture_storage_2d<rgba32uint, write>;
@group(0) @binding(6) var<storage, read_write> ob: array<vec4f>;
@group(0) @binding(7) var t32: texture_2d<f32>;
@group(0) @binding(8) var t32b: texture_2d<f32>;
@group(0) @binding(9) var t32c: texture_2d<f32>;
@group(0) @binding(10) var t32d: texture_2d<f32>;
@group(0) @binding(11) var t16: texture_2d<f32>;
@group(0) @binding(12) var tu32: texture_2d<u32>;
@group(0) @binding(13) var<uniform> u: U;
@group(0) @binding(14) var s32: texture_storage_2d<rgba32float, read>;
@group(0) @binding(15) var sg: texture_storage_2d<rgba32uint, read>;
struct UA { v: array<vec4f, 96> }
@group(0) @binding(16) var<uniform> ua: UA;
";

fn main() {
    let gpu = match glint::gpu::Gpu::new() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("pass_cost: {e}");
            std::process::exit(2);
        }
    };
    let device = &gpu.device;
    println!("adapter: {}; {}x{} invocations per dispatch", gpu.describe(), SIZE.0, SIZE.1);
    let texture = |format: wgpu::TextureFormat| {
        device
            .create_texture(&wgpu::TextureDescriptor {
                label: None,
                size: wgpu::Extent3d { width: SIZE.0, height: SIZE.1, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING,
                view_formats: &[],
            })
            .create_view(&Default::default())
    };
    use wgpu::TextureFormat as F;
    let views = [
        texture(F::Rgba32Float),
        texture(F::Rgba32Float),
        texture(F::Rgba32Float),
        texture(F::Rgba16Float),
        texture(F::R32Float),
        texture(F::Rgba32Uint),
    ];
    let inputs = [
        texture(F::Rgba32Float),
        texture(F::Rgba32Float),
        texture(F::Rgba32Float),
        texture(F::Rgba32Float),
        texture(F::Rgba16Float),
        texture(F::Rgba32Uint),
    ];
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: u64::from(SIZE.0 * SIZE.1) * 16,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let uniform_array = device.create_buffer(&wgpu::BufferDescriptor { label: None, size: 96 * 16, usage: wgpu::BufferUsages::UNIFORM, mapped_at_creation: false });
    let uniform = device.create_buffer(&wgpu::BufferDescriptor { label: None, size: 32, usage: wgpu::BufferUsages::UNIFORM, mapped_at_creation: false });

    // PASS_COST_ONLY=text runs only the variants whose name contains it.
    let only = std::env::var("PASS_COST_ONLY").unwrap_or_default();
    for v in VARIANTS.iter().filter(|v| v.name.contains(only.as_str())) {
        let src = format!(
            "{DECLS}
@compute @workgroup_size({wx}, {wy})
fn main(@builtin(global_invocation_id) id: vec3u) {{
    {body}
}}",
            wx = v.workgroup.0,
            wy = v.workgroup.1,
            body = v.body.replace("HEAVY", &"h = h * 747796405u + 2891336453u; h ^= h >> 13u; ".repeat(400))
        );
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(v.name), source: wgpu::ShaderSource::Wgsl(src.into()) });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(v.name),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        // `layout: None` keeps only the bindings the shader uses.
        let layout = pipeline.get_bind_group_layout(0);
        let mut entries = Vec::new();
        for (i, view) in views.iter().enumerate() {
            let b = i as u32;
            if v.body.contains(["o32,", "o32b", "o32c", "o16", "or32", "ou32"][i]) {
                entries.push(wgpu::BindGroupEntry { binding: b, resource: wgpu::BindingResource::TextureView(view) });
            }
        }
        if v.body.contains("ob[") {
            entries.push(wgpu::BindGroupEntry { binding: 6, resource: buffer.as_entire_binding() });
        }
        for (i, view) in inputs.iter().enumerate() {
            if v.body.contains(["t32,", "t32b", "t32c", "t32d", "t16", "tu32"][i]) {
                entries.push(wgpu::BindGroupEntry { binding: 7 + i as u32, resource: wgpu::BindingResource::TextureView(view) });
            }
        }
        if v.body.contains("s32,") {
            entries.push(wgpu::BindGroupEntry { binding: 14, resource: wgpu::BindingResource::TextureView(&inputs[1]) });
        }
        if v.body.contains("sg,") {
            entries.push(wgpu::BindGroupEntry { binding: 15, resource: wgpu::BindingResource::TextureView(&inputs[5]) });
        }
        if v.body.contains("ua.v") {
            entries.push(wgpu::BindGroupEntry { binding: 16, resource: uniform_array.as_entire_binding() });
        }
        if v.body.contains("u.a") || v.body.contains("u.b") {
            entries.push(wgpu::BindGroupEntry { binding: 13, resource: uniform.as_entire_binding() });
        }
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &layout, entries: &entries });
        let mut ms: Vec<f64> = (0..8)
            .map(|_| {
                let mut enc = device.create_command_encoder(&Default::default());
                {
                    let mut pass = enc.begin_compute_pass(&Default::default());
                    pass.set_pipeline(&pipeline);
                    pass.set_bind_group(0, &group, &[]);
                    pass.dispatch_workgroups(SIZE.0.div_ceil(v.workgroup.0), SIZE.1.div_ceil(v.workgroup.1), 1);
                }
                let start = std::time::Instant::now();
                gpu.queue.submit([enc.finish()]);
                gpu.wait();
                start.elapsed().as_secs_f64() * 1e3
            })
            .skip(1) // the first dispatch compiles the shader
            .collect();
        ms.sort_by(f64::total_cmp);
        let median = ms[ms.len() / 2];
        let per_pixel_ns = median * 1e6 / f64::from(SIZE.0 * SIZE.1);
        println!("{:32} {median:7.2} ms  {per_pixel_ns:6.2} ns per pixel", v.name);
    }
}
