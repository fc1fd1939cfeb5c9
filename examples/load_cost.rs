//! What one dependent 16-byte load costs a compute shader on this adapter,
//! by where the data lives: a storage buffer (as a vec4, as four u32s, two
//! lanes used), a sampled texture, a read-only storage texture, a uniform
//! buffer, a private array (push and pop), and no load at all. Each
//! invocation of a 1920x1080 dispatch walks K dependent loads through N
//! records (random next pointers). This measurement is why the scene arrays
//! traversal reads live in textures (src/scene/buffers.rs).
//!
//!   WGPU_BACKEND=vulkan cargo run --release --example load_cost [N=65536] [K=64]

use wgpu::util::DeviceExt;

const WIDTH: u32 = 4096;
const SIZE: (u32, u32) = (1920, 1080);

/// (name, declarations and `fn ld(i: u32) -> vec4u`, what binding 0..3 it uses)
const VARIANTS: [(&str, &str, Option<u32>); 8] = [
    ("storage vec4", "@group(0) @binding(0) var<storage, read> b: array<vec4u>;\nfn ld(i: u32) -> vec4u { return b[i]; }", Some(0)),
    (
        "storage 4 x u32",
        "@group(0) @binding(0) var<storage, read> b: array<u32>;\nfn ld(i: u32) -> vec4u { return vec4u(b[4u * i], b[4u * i + 1u], b[4u * i + 2u], b[4u * i + 3u]); }",
        Some(0),
    ),
    ("storage vec4, 2 used", "@group(0) @binding(0) var<storage, read> b: array<vec4u>;\nfn ld(i: u32) -> vec4u { let v = b[i]; return vec4u(v.x, v.w, 0u, 0u); }", Some(0)),
    ("texture_2d", "@group(0) @binding(1) var t: texture_2d<u32>;\nfn ld(i: u32) -> vec4u { return textureLoad(t, vec2u(i & 4095u, i >> 12u), 0); }", Some(1)),
    (
        "storage texture, read",
        "@group(0) @binding(2) var t: texture_storage_2d<rgba32uint, read>;\nfn ld(i: u32) -> vec4u { return textureLoad(t, vec2u(i & 4095u, i >> 12u)); }",
        Some(2),
    ),
    ("uniform (4096 records)", "@group(0) @binding(3) var<uniform> u: array<vec4u, 4096>;\nfn ld(i: u32) -> vec4u { return u[i & 4095u]; }", Some(3)),
    (
        "private array push+pop",
        "var<private> st: array<vec2u, 64>;\nvar<private> sp: u32 = 0u;\nfn ld(i: u32) -> vec4u { st[sp & 63u] = vec2u(i, i * 3u); sp = (sp + 1u + (i & 1u)) & 63u; let v = st[(sp + (i >> 7u)) & 63u]; return vec4u(v.x * 747796405u, v.y ^ 0x9e3779b9u, i + 12345u, v.x * 2891336453u + v.y); }",
        None,
    ),
    ("no load", "fn ld(i: u32) -> vec4u { return vec4u(i * 747796405u, i ^ 0x9e3779b9u, i + 12345u, i * 2891336453u); }", None),
];

fn arg(n: usize, default: u32) -> u32 {
    std::env::args().nth(n).and_then(|s| s.parse().ok()).unwrap_or(default)
}

fn main() {
    let gpu = match glint::gpu::Gpu::new() {
        Ok(g) => g,
        Err(e) => {
            eprintln!("load_cost: {e}");
            std::process::exit(2);
        }
    };
    let device = &gpu.device;
    let n = arg(1, 1 << 16).max(1);
    let k = arg(2, 64).max(1);
    println!("adapter: {}; {} invocations, {k} dependent loads each over {n} records", gpu.describe(), SIZE.0 * SIZE.1);

    // xorshift words: the fourth of each record picks the next record.
    let mut state = 12345u32;
    let rows = n.div_ceil(WIDTH);
    let mut words = vec![0u32; (WIDTH * rows * 4) as usize];
    for w in words.iter_mut().take((n * 4) as usize) {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        *w = state;
    }
    let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&words[..(n * 4) as usize]),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let uniform_words = &words[..4096 * 4];
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(uniform_words),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let texture = device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: None,
            size: wgpu::Extent3d { width: WIDTH, height: rows, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Uint,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&words),
    );
    let view = texture.create_view(&Default::default());
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: u64::from(SIZE.0 * SIZE.1) * 4,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });

    for (name, decl, binding) in VARIANTS {
        let src = format!(
            "{decl}
@group(0) @binding(4) var<storage, read_write> o: array<u32>;
@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3u) {{
    if id.x >= {w}u || id.y >= {h}u {{ return; }}
    var i = (id.x / 8u * 97u + id.y * 13u) % {n}u;
    var acc = 0u;
    for (var s = 0u; s < {k}u; s++) {{
        let v = ld(i);
        acc ^= v.x + v.y + v.z;
        i = (v.w ^ s ^ (id.x & 7u)) % {n}u;
    }}
    o[id.y * {w}u + id.x] = acc;
}}",
            w = SIZE.0,
            h = SIZE.1
        );
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(name), source: wgpu::ShaderSource::Wgsl(src.into()) });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(name),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let mut entries = vec![wgpu::BindGroupEntry { binding: 4, resource: out.as_entire_binding() }];
        match binding {
            Some(0) => entries.push(wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() }),
            Some(3) => entries.push(wgpu::BindGroupEntry { binding: 3, resource: uniform.as_entire_binding() }),
            Some(b) => entries.push(wgpu::BindGroupEntry { binding: b, resource: wgpu::BindingResource::TextureView(&view) }),
            None => {}
        }
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &pipeline.get_bind_group_layout(0), entries: &entries });
        let mut ms: Vec<f64> = (0..5)
            .map(|_| {
                let mut enc = device.create_command_encoder(&Default::default());
                {
                    let mut pass = enc.begin_compute_pass(&Default::default());
                    pass.set_pipeline(&pipeline);
                    pass.set_bind_group(0, &group, &[]);
                    pass.dispatch_workgroups(SIZE.0.div_ceil(8), SIZE.1.div_ceil(8), 1);
                }
                let start = std::time::Instant::now();
                gpu.queue.submit([enc.finish()]);
                gpu.wait();
                start.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        ms.sort_by(f64::total_cmp);
        let median = ms[ms.len() / 2];
        let per_load_ns = median * 1e6 / (f64::from(SIZE.0 * SIZE.1) * f64::from(k));
        println!("{name:24} {median:8.1} ms  {per_load_ns:6.2} ns per load per invocation");
    }
}
