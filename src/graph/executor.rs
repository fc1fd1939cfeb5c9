//! Records a compiled `Schedule` as wgpu compute dispatches. Everything is
//! created up front (textures, pipelines, bind groups for both history
//! parities); a frame only writes the frame uniform and records dispatches.

use std::collections::BTreeMap;

use wgpu::util::DeviceExt;

use crate::error::UserError;
use crate::gpu::readback::{read_texture, ImageF32};
use crate::gpu::scene_buffers::SceneBuffers;
use crate::gpu::timing::PassTimer;
use crate::gpu::Gpu;
use crate::graph::desc::TexFormat;
use crate::graph::schedule::*;
use crate::graph::CompiledGraph;
use crate::shader::{BindingKind, SampleType, StorageAccess};

/// How a frame is timed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Timing {
    /// Not timed: submit and go on.
    None,
    /// GPU timestamps around each pass.
    Gpu,
    /// Each pass submitted alone and timed on the CPU clock.
    WallPerPass,
}

impl Timing {
    /// Timestamps on GPUs; per-pass wall time on CPU adapters (lavapipe's
    /// timestamps do not bracket the dispatches' work).
    pub fn for_adapter(gpu: &Gpu) -> Timing {
        if gpu.info.device_type == wgpu::DeviceType::Cpu || !gpu.timestamps {
            Timing::WallPerPass
        } else {
            Timing::Gpu
        }
    }
}

struct PassGpu {
    pipeline: wgpu::ComputePipeline,
    /// (group index, bind group) for parity 0 and 1.
    bind_groups: [Vec<(u32, wgpu::BindGroup)>; 2],
    workgroups: [u32; 3],
    _params: Option<wgpu::Buffer>,
}

pub struct Executor {
    pub schedule: Schedule,
    pub size: (u32, u32),
    textures: Vec<wgpu::Texture>,
    passes: Vec<PassGpu>,
    timer: Option<PassTimer>,
    parity: u8,
}

pub fn wgpu_format(f: TexFormat) -> wgpu::TextureFormat {
    match f {
        TexFormat::R32Float => wgpu::TextureFormat::R32Float,
        TexFormat::Rg32Float => wgpu::TextureFormat::Rg32Float,
        TexFormat::Rgba32Float => wgpu::TextureFormat::Rgba32Float,
        TexFormat::Rgba16Float => wgpu::TextureFormat::Rgba16Float,
        TexFormat::R32Uint => wgpu::TextureFormat::R32Uint,
        TexFormat::Rg32Uint => wgpu::TextureFormat::Rg32Uint,
        TexFormat::Rgba32Uint => wgpu::TextureFormat::Rgba32Uint,
        TexFormat::Rgba8Unorm => wgpu::TextureFormat::Rgba8Unorm,
    }
}

fn layout_entry(b: &ResolvedBinding) -> wgpu::BindGroupLayoutEntry {
    let ty = match &b.kind {
        BindingKind::SampledTexture { sample } => wgpu::BindingType::Texture {
            sample_type: match sample {
                SampleType::Float => wgpu::TextureSampleType::Float { filterable: false },
                SampleType::Uint => wgpu::TextureSampleType::Uint,
                SampleType::Sint => wgpu::TextureSampleType::Sint,
            },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        BindingKind::StorageTexture { format, access } => wgpu::BindingType::StorageTexture {
            access: match access {
                StorageAccess::Read => wgpu::StorageTextureAccess::ReadOnly,
                StorageAccess::Write => wgpu::StorageTextureAccess::WriteOnly,
                StorageAccess::ReadWrite => wgpu::StorageTextureAccess::ReadWrite,
            },
            format: wgpu_format(*format),
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        BindingKind::Uniform { .. } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        BindingKind::Storage { read_only } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: *read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
    };
    wgpu::BindGroupLayoutEntry { binding: b.binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None }
}

/// The override in `shaders/shared/intersect.wgsl` the engine sets from the
/// scene (unless a graph sets it): whether rays test every primitive
/// instead of walking the BVH.
const FLAT_SCENE: &str = "FLAT_SCENE";

impl Executor {
    /// Creates textures, pipelines and bind groups. `frame` is the frame
    /// uniform buffer, `scene` the scene buffers.
    pub fn new(
        gpu: &Gpu,
        graph: &CompiledGraph,
        frame: &wgpu::Buffer,
        scene: &SceneBuffers,
        size: (u32, u32),
    ) -> Result<Executor, UserError> {
        let device = &gpu.device;
        let schedule = graph.schedule.clone();
        let max = gpu.max_texture_side();
        let textures: Vec<wgpu::Texture> = schedule
            .textures
            .iter()
            .map(|t| {
                let (w, h) = t.size.resolve(size);
                if w > max || h > max {
                    return Err(UserError::new(format!(
                        "texture `{}` would be {w}x{h}, beyond this adapter's limit of {max}x{max}; render smaller",
                        t.label
                    )));
                }
                let mut usage = wgpu::TextureUsages::COPY_SRC;
                if t.usage.sampled {
                    usage |= wgpu::TextureUsages::TEXTURE_BINDING;
                }
                if t.usage.storage {
                    usage |= wgpu::TextureUsages::STORAGE_BINDING;
                }
                Ok(device.create_texture(&wgpu::TextureDescriptor {
                    label: Some(&t.label),
                    size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: wgpu_format(t.format),
                    usage,
                    view_formats: &[],
                }))
            })
            .collect::<Result<_, _>>()?;
        let views: Vec<wgpu::TextureView> = textures.iter().map(|t| t.create_view(&Default::default())).collect();

        let mut passes = Vec::new();
        for sp in &schedule.passes {
            let shader = graph
                .shaders
                .get(&sp.shader)
                .ok_or_else(|| UserError::new(format!("shader {} was not loaded", sp.shader)))?;
            let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&sp.shader),
                source: wgpu::ShaderSource::Wgsl(shader.source.text.as_str().into()),
            });
            let mut by_group: BTreeMap<u32, Vec<&ResolvedBinding>> = BTreeMap::new();
            for b in &sp.bindings {
                by_group.entry(b.group).or_default().push(b);
            }
            let max_group = by_group.keys().max().map(|g| g + 1).unwrap_or(0);
            let layouts: BTreeMap<u32, wgpu::BindGroupLayout> = by_group
                .iter()
                .map(|(g, bs)| {
                    let entries: Vec<_> = bs.iter().map(|b| layout_entry(b)).collect();
                    (*g, device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(&sp.name), entries: &entries }))
                })
                .collect();
            let layout_refs: Vec<Option<&wgpu::BindGroupLayout>> = (0..max_group).map(|g| layouts.get(&g)).collect();
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&sp.name),
                bind_group_layouts: &layout_refs,
                immediate_size: 0,
            });
            let mut constants: Vec<(&str, f64)> = sp.constants.iter().map(|(k, v)| (k.as_str(), *v)).collect();
            let declares = |name: &str| shader.info.overrides.iter().any(|o| o.name == name);
            if declares(FLAT_SCENE) && !constants.iter().any(|(k, _)| *k == FLAT_SCENE) {
                constants.push((FLAT_SCENE, f64::from(u8::from(scene.is_flat()))));
            }
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&sp.name),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(&sp.entry),
                compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
                cache: None,
            });
            let params = sp.params.as_ref().map(|bytes| {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&sp.name),
                    contents: bytes,
                    usage: wgpu::BufferUsages::UNIFORM,
                })
            });
            let make_groups = |parity: u8| -> Vec<(u32, wgpu::BindGroup)> {
                by_group
                    .iter()
                    .map(|(g, bs)| {
                        let entries: Vec<wgpu::BindGroupEntry> = bs
                            .iter()
                            .map(|b| wgpu::BindGroupEntry {
                                binding: b.binding,
                                resource: match &b.target {
                                    Target::Texture(t) => wgpu::BindingResource::TextureView(&views[t.resolve(parity)]),
                                    Target::Params => params.as_ref().map(|p| p.as_entire_binding()).unwrap_or_else(|| frame.as_entire_binding()),
                                    Target::Engine(EngineResource::Frame) => frame.as_entire_binding(),
                                    Target::Engine(e) => scene.binding(*e).unwrap_or_else(|| frame.as_entire_binding()),
                                },
                            })
                            .collect();
                        (*g, device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(&sp.name), layout: &layouts[g], entries: &entries }))
                    })
                    .collect()
            };
            let bind_groups = [make_groups(0), make_groups(1)];
            if let Some(e) = pollster::block_on(scope.pop()) {
                return Err(UserError::new(format!(
                    "pass `{}` ({}): the GPU driver rejected the pipeline: {e}",
                    sp.name, sp.shader
                )));
            }
            let (w, h) = sp.dispatch.resolve(size);
            let wg = sp.workgroup_size;
            passes.push(PassGpu {
                pipeline,
                bind_groups,
                workgroups: [w.div_ceil(wg[0].max(1)), h.div_ceil(wg[1].max(1)), 1],
                _params: params,
            });
        }
        let timer = gpu.timestamps.then(|| PassTimer::new(device, &gpu.queue, passes.len()));
        Ok(Executor { schedule, size, textures, passes, timer, parity: 0 })
    }

    /// Records one frame's dispatches.
    pub fn encode(&self, enc: &mut wgpu::CommandEncoder) {
        for (i, (p, sp)) in self.passes.iter().zip(&self.schedule.passes).enumerate() {
            self.encode_pass(enc, p, sp, self.timer.as_ref().map(|t| t.writes(i)));
        }
        if let Some(t) = &self.timer {
            t.resolve(enc);
        }
    }

    fn encode_pass(
        &self,
        enc: &mut wgpu::CommandEncoder,
        p: &PassGpu,
        sp: &ScheduledPass,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(&sp.name), timestamp_writes });
        cp.set_pipeline(&p.pipeline);
        for (g, bg) in &p.bind_groups[usize::from(self.parity)] {
            cp.set_bind_group(*g, bg, &[]);
        }
        cp.dispatch_workgroups(p.workgroups[0], p.workgroups[1], p.workgroups[2]);
    }

    /// Records and submits one frame. With `Timing::Gpu`, returns per-pass
    /// GPU milliseconds from timestamps (when the adapter has them); with
    /// `Timing::WallPerPass`, submits each pass alone and times it on the
    /// CPU clock (for CPU adapters, whose timestamps do not bracket the
    /// work). Both wait for the frame.
    pub fn run_frame(&mut self, gpu: &Gpu, timing: Timing) -> Result<Option<Vec<f64>>, UserError> {
        if timing == Timing::WallPerPass {
            let mut ms = Vec::with_capacity(self.passes.len());
            for (p, sp) in self.passes.iter().zip(&self.schedule.passes) {
                let start = std::time::Instant::now();
                let mut enc = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(&sp.name) });
                self.encode_pass(&mut enc, p, sp, None);
                gpu.queue.submit([enc.finish()]);
                gpu.wait();
                ms.push(start.elapsed().as_secs_f64() * 1e3);
            }
            self.end_frame();
            return Ok(Some(ms));
        }
        let mut enc = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        self.encode(&mut enc);
        gpu.queue.submit([enc.finish()]);
        let ms = match (&self.timer, timing) {
            (Some(t), Timing::Gpu) => Some(t.read_ms(&gpu.device)?),
            _ => None,
        };
        self.end_frame();
        Ok(ms)
    }

    /// Flips the history parity after a frame's work was recorded.
    pub fn end_frame(&mut self) {
        if self.schedule.flips_parity {
            self.parity ^= 1;
        }
    }

    /// The texture holding the output of the last frame.
    pub fn output_texture(&self) -> &wgpu::Texture {
        // end_frame already flipped: the last frame used the other parity.
        let last = if self.schedule.flips_parity { self.parity ^ 1 } else { self.parity };
        &self.textures[self.schedule.output.resolve(last)]
    }

    pub fn read_output(&self, gpu: &Gpu) -> Result<ImageF32, UserError> {
        read_texture(&gpu.device, &gpu.queue, self.output_texture(), self.schedule.output_format)
    }

    /// The final version of a kept resource (see Schedule::kept) after the
    /// last frame; None when the resource was not kept.
    pub fn read_resource(&self, gpu: &Gpu, resource: &str) -> Option<Result<ImageF32, UserError>> {
        if !self.schedule.kept.iter().any(|r| r == resource) {
            return None;
        }
        let v = self.schedule.versions.iter().filter(|v| v.resource == resource).max_by_key(|v| v.version)?;
        let last = if self.schedule.flips_parity { self.parity ^ 1 } else { self.parity };
        let index = v.texture.resolve(last);
        let format = self.schedule.textures.get(index)?.format;
        Some(read_texture(&gpu.device, &gpu.queue, &self.textures[index], format))
    }

    pub fn pass_names(&self) -> Vec<&str> {
        self.schedule.passes.iter().map(|p| p.name.as_str()).collect()
    }
}
