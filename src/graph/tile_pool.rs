//! The tile pool (shaders/shared/tile_pool.wgsl): a pass that binds
//! `tile_pool` takes its texels from one counter, a chunk at a time, in
//! invocations that loop until the pool is empty, so a device's threads
//! share out the image as they run instead of in fixed parts.
//!
//! lavapipe gives each of its threads an equal, contiguous share of a
//! dispatch's workgroups up front: with one texel per invocation one
//! thread draws the top half of the image and the other the bottom half,
//! and where one half costs more, or another tenant slows one core, the
//! other thread waits. Here a CPU driver gets POOL_CHUNKS_CPU chunks an
//! invocation and a quarter more invocations than the image needs, so a
//! faster thread can take up to 62% of the image (of two); a GPU, which
//! schedules its workgroups as they free up anyway, one chunk an
//! invocation and no more invocations than that.

/// The pool's buffer: its counter, then the indirect dispatch (x, y, z)
/// over the chunks its invocations left (see `Fixup`).
pub const BYTES: u64 = 16;
/// Texels a chunk holds per lane (`POOL_STEPS` in shared/tile_pool.wgsl).
pub const STEPS: u32 = 8;
/// Lanes whose chunks lie side by side in a strip (`POOL_LANES`).
pub const LANES: u32 = 8;
/// The override constant that bounds the chunks an invocation takes.
pub const CHUNKS_CONSTANT: &str = "POOL_CHUNKS";
/// Chunks an invocation takes at most on a CPU driver. Fewer cost more:
/// each invocation that finds the pool empty still runs its loop body
/// once under an empty lane mask, and each chunk is one atomic per lane.
pub const POOL_CHUNKS_CPU: u32 = 8;
/// Invocations dispatched on a CPU driver, as a multiple of what the
/// image needs at POOL_CHUNKS_CPU chunks each: the slack that lets one
/// thread take more than its share.
pub const CPU_SLACK: f64 = 1.25;

/// Chunks an invocation takes at most on this kind of device.
pub fn chunks(device: wgpu::DeviceType) -> u32 {
    if device == wgpu::DeviceType::Cpu {
        POOL_CHUNKS_CPU
    } else {
        1
    }
}

/// The engine's constant for pipelines on this kind of device.
pub fn constant(device: wgpu::DeviceType) -> (&'static str, f64) {
    (CHUNKS_CONSTANT, f64::from(chunks(device)))
}

/// The dispatch of a pass that takes its texels from the pool, with
/// workgroups of `workgroup_size`: enough invocations (with CPU_SLACK on a
/// CPU) that their chunks cover the render size (the pool hands out the
/// texels of `frame.size`), as workgroups along x.
pub fn workgroups(device: wgpu::DeviceType, workgroup_size: [u32; 3], (w, h): (u32, u32)) -> [u32; 3] {
    let texels = u64::from(w) * u64::from(h);
    let per_invocation = u64::from(STEPS * chunks(device));
    let mut invocations = texels.div_ceil(per_invocation);
    if device == wgpu::DeviceType::Cpu {
        invocations = (invocations as f64 * CPU_SLACK).ceil() as u64;
    }
    let per_group = u64::from(workgroup_size.iter().product::<u32>().max(1));
    // Within every device's limit on one dimension (wgpu's default): the
    // invocations dispatched take the chunks of any left out.
    [u32::try_from(invocations.div_ceil(per_group)).unwrap_or(u32::MAX).clamp(1, 65535), 1, 1]
}

/// The chunks the pool holds for a render size: as shared/tile_pool.wgsl
/// cuts it, strips of LANES x STEPS texels along each row (the last one
/// of a row running past the edge), LANES chunks a strip.
pub fn total_chunks((w, h): (u32, u32)) -> u32 {
    let per_row = w.div_ceil(LANES * STEPS);
    per_row.saturating_mul(h).saturating_mul(LANES)
}

/// Why a second dispatch: lavapipe ends every loop of a SIMD group's run
/// of a shader once 65535 iterations have run in all
/// (src/graph/compile/split.rs), so a lane stops taking chunks once its
/// traversals have looped POOL_TRIP_BUDGET times, and the invocations may
/// then leave chunks the dispatch counted on them taking. This one
/// invocation writes the group count of a second, indirect dispatch of
/// the same pass over what is left (none, where nothing stopped early):
/// each of its invocations takes at least one chunk.
const FIXUP_WGSL: &str = "
@group(0) @binding(0) var<storage, read_write> pool: array<u32, 4>;
// x: the chunks the pool holds; y: invocations a workgroup.
@group(0) @binding(1) var<uniform> shape: vec4u;

@compute @workgroup_size(1)
fn main() {
    let left = shape.x - min(pool[0], shape.x);
    pool[1] = (left + shape.y - 1u) / shape.y;
    pool[2] = 1u;
    pool[3] = 1u;
}
";

/// The pipeline that sizes a pool pass's second dispatch (FIXUP_WGSL),
/// one for all passes of an executor.
pub struct Fixup {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl Fixup {
    /// Builds the fixup pipeline.
    pub fn new(device: &wgpu::Device) -> Fixup {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("tile pool fixup"),
            source: wgpu::ShaderSource::Wgsl(FIXUP_WGSL.into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("tile pool fixup"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let layout = pipeline.get_bind_group_layout(0);
        Fixup { pipeline, layout }
    }
}

/// One pass's pool: the counter (bound as `tile_pool`), the buffer its
/// second dispatch reads its size from, and the fixup's bindings.
pub struct PassPool {
    /// The counter, bound as `tile_pool`.
    pub buffer: wgpu::Buffer,
    args: wgpu::Buffer,
    fixup: wgpu::BindGroup,
}

impl PassPool {
    /// For a pass with `per_group` invocations a workgroup at `size`.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, fixup: &Fixup, label: &str, size: (u32, u32), per_group: u32) -> PassPool {
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: BYTES,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        // A buffer bound writable cannot also be a dispatch's indirect
        // buffer: the group count is copied out to this one.
        let args = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: 12,
            usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let shape = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        queue.write_buffer(&shape, 0, bytemuck::cast_slice(&[total_chunks(size), per_group.max(1), 0, 0]));
        let fixup = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &fixup.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: shape.as_entire_binding() },
            ],
        });
        PassPool { buffer, args, fixup }
    }

    /// Fills the pool before the pass's first dispatch.
    pub fn encode_fill(&self, enc: &mut wgpu::CommandEncoder) {
        enc.clear_buffer(&self.buffer, 0, None);
    }

    /// After the first dispatch: sizes the second over what it left.
    pub fn encode_leftover(&self, enc: &mut wgpu::CommandEncoder, fixup: &Fixup) {
        {
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("tile pool fixup"), timestamp_writes: None });
            cp.set_pipeline(&fixup.pipeline);
            cp.set_bind_group(0, &self.fixup, &[]);
            cp.dispatch_workgroups(1, 1, 1);
        }
        enc.copy_buffer_to_buffer(&self.buffer, 4, &self.args, 0, 12);
    }

    /// The second dispatch's size (after `encode_leftover`).
    pub fn args(&self) -> &wgpu::Buffer {
        &self.args
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cpu_dispatch_has_slack_and_gpu_dispatch_covers_the_image() {
        let wg = [64, 1, 1];
        let size = (1280, 720);
        let texels = 1280 * 720;
        let gpu = workgroups(wgpu::DeviceType::DiscreteGpu, wg, size);
        assert_eq!(gpu, [(texels / STEPS).div_ceil(64), 1, 1]);
        let cpu = workgroups(wgpu::DeviceType::Cpu, wg, size);
        let capacity = u64::from(cpu[0]) * 64 * u64::from(STEPS * POOL_CHUNKS_CPU);
        assert!(capacity >= (texels as f64 * CPU_SLACK) as u64, "{cpu:?}");
        assert!(capacity < (texels as f64 * CPU_SLACK) as u64 + 64 * u64::from(STEPS * POOL_CHUNKS_CPU), "{cpu:?}");
        assert_eq!(workgroups(wgpu::DeviceType::Cpu, wg, (1, 1)), [1, 1, 1]);
    }

    #[test]
    fn the_pool_holds_every_texel_once() {
        // Strips of 64 along each row, the last one past the edge.
        assert_eq!(total_chunks((1280, 720)), 20 * 720 * LANES);
        assert_eq!(total_chunks((100, 3)), 2 * 3 * LANES);
        assert_eq!(total_chunks((1, 1)), LANES);
        // Every texel of a row, once, as the shader hands them out: chunk c
        // is strip c / LANES, column c % LANES, then every LANES-th texel.
        let w = 100;
        let mut seen = vec![0u32; w as usize];
        for c in 0..total_chunks((w, 1)) {
            let (strip, lane) = (c / LANES, c % LANES);
            for step in 0..STEPS {
                let x = strip * LANES * STEPS + lane + step * LANES;
                if x < w {
                    seen[x as usize] += 1;
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1), "{seen:?}");
    }
}
