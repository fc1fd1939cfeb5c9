//! The pipeline cache. A compute pipeline is keyed by the content of its
//! shader's import closure (the expanded source: the pass file and every
//! file it imports, directly or not), the entry point and the override
//! constants. An edit of a file therefore misses the cache for exactly the
//! pipelines whose closure contains it; everything else is reused as is.
//!
//! Building needs only the device, so a rebuild can run on another thread
//! (the viewer keeps presenting meanwhile); every pipeline is created inside
//! a validation error scope, so a driver that refuses one is an error that
//! names the pass, not a panic.

use std::collections::hash_map::DefaultHasher;
use std::collections::{BTreeMap, HashMap};
use std::hash::{Hash, Hasher};
use std::sync::Arc;

use crate::error::UserError;
use crate::format::TexFormat;
use crate::gpu::pipeline_cache::DiskPipelineCache;
use crate::graph::schedule::{ResolvedBinding, ScheduledPass};
use crate::graph::frame_kind::{self, Declared, FrameKind, FRAME_CONSTANTS};
use crate::graph::CompiledGraph;
use crate::shader::{BindingKind, SampleType, Shader, StorageAccess};

/// What identifies a cached pipeline (see the module docs).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    shader: String,
    /// Hash of the expanded source (the whole import closure's content).
    source: u64,
    entry: String,
    listed: Option<String>,
    /// Override constants, sorted by name, values as bits.
    constants: Vec<(String, u64)>,
}

/// A pipeline and the bind group layouts it was made with.
pub struct CachedPipeline {
    /// The pass's entry point.
    pub pipeline: wgpu::ComputePipeline,
    /// The pass's `listed` entry, with the same layout.
    pub listed: Option<wgpu::ComputePipeline>,
    /// Which per-frame constants the shader declares (frame_kind.rs).
    pub declared: Declared,
    /// Both again per kind of frame the shader tells apart
    /// (`FrameKind::variants`).
    pub variants: Vec<(FrameKind, wgpu::ComputePipeline, Option<wgpu::ComputePipeline>)>,
    /// Bind group layouts by group index.
    pub layouts: BTreeMap<u32, wgpu::BindGroupLayout>,
}

impl CachedPipeline {
    /// The entry and listed-entry pipelines for a frame of this kind.
    pub fn for_frame(&self, kind: FrameKind) -> (&wgpu::ComputePipeline, Option<&wgpu::ComputePipeline>) {
        let seen = kind.seen_by(self.declared);
        match self.variants.iter().find(|(k, _, _)| *k == seen) {
            Some((_, entry, listed)) => (entry, listed.as_ref()),
            None => (&self.pipeline, self.listed.as_ref()),
        }
    }

    /// Every pipeline built for the pass: the entry and listed entry,
    /// generic and per kind of frame.
    pub fn all(&self) -> impl Iterator<Item = &wgpu::ComputePipeline> {
        let variants = self.variants.iter().flat_map(|(_, entry, listed)| std::iter::once(entry).chain(listed));
        std::iter::once(&self.pipeline).chain(&self.listed).chain(variants)
    }
}

/// Pipelines by key. Cloning is cheap (shared handles).
#[derive(Clone, Default)]
pub struct PipelineCache {
    entries: HashMap<PipelineKey, Arc<CachedPipeline>>,
}

/// The pipelines of one schedule, in pass order, with what had to be built.
pub struct PipelineSet {
    /// One pipeline per pass of the schedule, in order.
    pub per_pass: Vec<Arc<CachedPipeline>>,
    /// Names of the passes whose pipeline was not in the cache.
    pub built: Vec<String>,
    /// The cache holding exactly these pipelines (entries no pass uses any
    /// more are left out, so replaced pipelines are released).
    pub cache: PipelineCache,
}

/// The wgpu texture format of a graph format.
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
        BindingKind::SampledTextureArray => wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2Array,
            multisampled: false,
        },
        BindingKind::Sampler => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
    };
    wgpu::BindGroupLayoutEntry { binding: b.binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None }
}

/// The constants a pass's pipeline is built with: the graph's, then the
/// engine's defaults for overrides the shader declares and the graph left
/// unset (`FLAT_SCENE`, `ONE_MESH` and the schedule's specialisations, chosen from the
/// scene).
pub fn pass_constants(sp: &ScheduledPass, shader: &Shader, engine: &[(&str, f64)]) -> Vec<(String, f64)> {
    let mut constants = sp.constants.clone();
    for (name, value) in engine {
        let declared = shader.info.overrides.iter().any(|o| o.name == *name);
        if declared && !constants.iter().any(|(k, _)| k == name) {
            constants.push((name.to_string(), *value));
        }
    }
    constants.sort_by(|a, b| a.0.cmp(&b.0));
    constants
}

fn key(sp: &ScheduledPass, shader: &Shader, constants: &[(String, f64)]) -> PipelineKey {
    let mut h = DefaultHasher::new();
    shader.source.text.hash(&mut h);
    PipelineKey {
        shader: sp.shader.clone(),
        source: h.finish(),
        entry: sp.entry.clone(),
        listed: sp.listed.clone(),
        constants: constants.iter().map(|(k, v)| (k.clone(), v.to_bits())).collect(),
    }
}

impl PipelineCache {
    /// Pipelines held.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the cache holds no pipeline.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Looks up or builds the pipeline of every pass of `graph`. Does not
    /// change `self`: the result carries the cache to swap in. The
    /// pipelines not in the cache are built in parallel (a driver compiles
    /// each on the calling thread; lavapipe's LLVM takes 150-250 ms each),
    /// through the driver's pipeline cache where there is one (`disk`),
    /// which is saved when pipelines were built.
    pub fn build(&self, device: &wgpu::Device, disk: Option<&DiskPipelineCache>, graph: &CompiledGraph, engine: &[(&str, f64)]) -> Result<PipelineSet, UserError> {
        let mut engine = engine.to_vec();
        engine.extend(graph.schedule.specialisations.iter().map(|s| s.as_constant()));
        // Each pass's key; the passes whose key is new, once per key.
        let mut keys = Vec::new();
        let mut missing: Vec<(usize, Vec<(String, f64)>)> = Vec::new();
        for (i, sp) in graph.schedule.passes.iter().enumerate() {
            let shader = graph
                .shaders
                .get(&sp.shader)
                .ok_or_else(|| UserError::new(format!("pass `{}`: shader {} was not loaded", sp.name, sp.shader)))?;
            let constants = pass_constants(sp, shader, &engine);
            let k = key(sp, shader, &constants);
            if !self.entries.contains_key(&k) && !keys[..i].contains(&k) {
                missing.push((i, constants));
            }
            keys.push(k);
        }
        let passes = &graph.schedule.passes;
        let made = in_parallel(&missing, |(i, constants)| {
            let sp = &passes[*i];
            // Looked up above: every pass's shader is loaded.
            let shader = &graph.shaders[&sp.shader];
            create_guarded(device, disk.map(DiskPipelineCache::cache), sp, shader, constants)
        });
        let mut cache = PipelineCache::default();
        let mut built = Vec::new();
        for ((i, _), p) in missing.iter().zip(made) {
            let p = p.ok_or_else(|| UserError::new(format!("pass `{}`: building its pipeline stopped without a result", passes[*i].name)))?;
            cache.entries.insert(keys[*i].clone(), Arc::new(p?));
            built.push(passes[*i].name.clone());
        }
        let mut per_pass = Vec::new();
        for k in &keys {
            let p = match cache.entries.get(k).or_else(|| self.entries.get(k)) {
                Some(p) => Arc::clone(p),
                None => return Err(UserError::new("internal: a pipeline was neither cached nor built")),
            };
            cache.entries.insert(k.clone(), Arc::clone(&p));
            per_pass.push(p);
        }
        if let (Some(disk), false) = (disk, built.is_empty()) {
            disk.save();
        }
        Ok(PipelineSet { per_pass, built, cache })
    }
}

/// `f` over `items` on up to as many threads as the machine has cores, the
/// results in `items`' order (None where a thread panicked: a bug, as
/// create_guarded catches the compiler's panics).
fn in_parallel<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<Option<R>> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(items.len());
    if threads <= 1 {
        return items.iter().map(|x| Some(f(x))).collect();
    }
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut results: Vec<(usize, R)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(item) = items.get(i) else { return mine };
                        mine.push((i, f(item)));
                    }
                })
            })
            .collect();
        workers.into_iter().flat_map(|w| w.join().unwrap_or_default()).collect()
    });
    results.sort_by_key(|(i, _)| *i);
    let mut results = results.into_iter().peekable();
    (0..items.len()).map(|i| results.next_if(|(j, _)| *j == i).map(|(_, r)| r)).collect()
}

/// `create`, with a panic in the shader compiler turned into an error that
/// names the pass and its shader. naga validates some WGSL its SPIR-V
/// writer then cannot handle and panics on (a pointer to a struct member
/// passed to a function, `f(&s.field)`: "Expression [n] is not cached!"); a
/// shader is user input, and a running viewer keeps its last good state.
/// The error scope `create` pushed is popped as its guard unwinds.
fn create_guarded(device: &wgpu::Device, disk: Option<&wgpu::PipelineCache>, sp: &ScheduledPass, shader: &Shader, constants: &[(String, f64)]) -> Result<CachedPipeline, UserError> {
    quiet_compiler_panics();
    COMPILING.set(true);
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| create(device, disk, sp, shader, constants)));
    COMPILING.set(false);
    match outcome {
        Ok(result) => result,
        Err(payload) => {
            let what = payload.downcast_ref::<String>().map(String::as_str).or_else(|| payload.downcast_ref::<&str>().copied()).unwrap_or("a panic");
            Err(UserError::new(format!(
                "pass `{}` ({}): the shader compiler failed on this shader: {what} (naga is known to fail so on a pointer to a struct member passed to a function, `f(&s.field)`: pass a pointer to a whole variable)",
                sp.name,
                shader_location(sp, shader)
            )))
        }
    }
}

thread_local! {
    /// Whether this thread is inside `create_guarded`.
    static COMPILING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Installs, once, a panic hook that stays silent for a panic inside
/// `create_guarded` (its message becomes the error) and hands every other
/// panic to the hook before it.
fn quiet_compiler_panics() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let before = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !COMPILING.get() {
                before(info);
            }
        }));
    });
}

/// The shader's first file, or its name.
fn shader_location(sp: &ScheduledPass, shader: &Shader) -> String {
    shader.source.files.first().map(|f| f.display().to_string()).unwrap_or_else(|| sp.shader.clone())
}

/// The entry's `@workgroup_size` within the adapter's limits, else an
/// error at the attribute's line (the driver's own is a bare "Validation
/// Error").
fn check_workgroup_size(device: &wgpu::Device, sp: &ScheduledPass, shader: &Shader) -> Result<(), UserError> {
    let limits = device.limits();
    let [x, y, z] = sp.workgroup_size;
    let side = [limits.max_compute_workgroup_size_x, limits.max_compute_workgroup_size_y, limits.max_compute_workgroup_size_z];
    let total = u64::from(x) * u64::from(y) * u64::from(z);
    let most = limits.max_compute_invocations_per_workgroup;
    if total <= u64::from(most) && x <= side[0] && y <= side[1] && z <= side[2] {
        return Ok(());
    }
    // The attribute above the entry's `fn`.
    let text = &shader.source.text;
    let at_fn = text.find(&format!("fn {}(", sp.entry)).unwrap_or(text.len());
    let line = text[..at_fn].rfind("@workgroup_size").map_or(0, |i| text[..i].matches('\n').count() + 1);
    let message = format!(
        "`@workgroup_size({x}, {y}, {z})` of `{}` makes {total} invocations a workgroup; this adapter runs at most {most}, and {}, {}, {} a side",
        sp.entry, side[0], side[1], side[2]
    );
    Err(UserError::at(shader.source.original(line, 1), message))
}

fn create(device: &wgpu::Device, disk: Option<&wgpu::PipelineCache>, sp: &ScheduledPass, shader: &Shader, constants: &[(String, f64)]) -> Result<CachedPipeline, UserError> {
    check_workgroup_size(device, sp, shader)?;
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let mut by_group: BTreeMap<u32, Vec<&ResolvedBinding>> = BTreeMap::new();
    for b in &sp.bindings {
        by_group.entry(b.group).or_default().push(b);
    }
    let layouts: BTreeMap<u32, wgpu::BindGroupLayout> = by_group
        .iter()
        .map(|(g, bs)| {
            let entries: Vec<_> = bs.iter().map(|b| layout_entry(b)).collect();
            (*g, device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(&sp.name), entries: &entries }))
        })
        .collect();
    let groups = layouts.keys().max().map(|g| g + 1).unwrap_or(0);
    let layout_refs: Vec<Option<&wgpu::BindGroupLayout>> = (0..groups).map(|g| layouts.get(&g)).collect();
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(&sp.name),
        bind_group_layouts: &layout_refs,
        immediate_size: 0,
    });
    let constants: Vec<(&str, f64)> = constants.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    // Each pipeline gets its own module, specialised for its entry and
    // constants (shader::specialise: the driver never sees the dead code).
    let make = |entry: &str, constants: &[(&str, f64)]| -> Result<wgpu::ComputePipeline, UserError> {
        let module = crate::shader::specialise::specialised_module(shader, entry, constants)
            .map_err(|e| UserError::new(format!("pass `{}` ({}), entry `{entry}`: {e}", sp.name, shader_location(sp, shader))))?;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(&sp.shader),
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
        });
        Ok(device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(&sp.name),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            cache: disk,
        }))
    };
    let declared = frame_kind::declared(shader.info.overrides.iter().map(|o| o.name.as_str()));
    let built = (|| {
        let pipeline = make(&sp.entry, &constants)?;
        let listed = sp.listed.as_deref().map(|e| make(e, &constants)).transpose()?;
        // One more pair per kind of frame the shader tells apart, the
        // per-frame constants set by the engine, never by the graph.
        let generic: Vec<(&str, f64)> = constants.iter().copied().filter(|(k, _)| !FRAME_CONSTANTS.contains(k)).collect();
        let variants = FrameKind::variants(declared)
            .into_iter()
            .map(|kind| {
                let mut c = generic.clone();
                c.extend(kind.constants());
                Ok((kind, make(&sp.entry, &c)?, sp.listed.as_deref().map(|e| make(e, &c)).transpose()?))
            })
            .collect::<Result<Vec<_>, UserError>>()?;
        Ok::<_, UserError>((pipeline, listed, variants))
    })();
    let driver_error = pollster::block_on(scope.pop());
    let (pipeline, listed, variants) = built?;
    if let Some(e) = driver_error {
        return Err(UserError::new(format!("pass `{}` ({}): the GPU driver rejected the pipeline: {e}", sp.name, shader_location(sp, shader))));
    }
    Ok(CachedPipeline { pipeline, listed, declared, variants, layouts })
}
