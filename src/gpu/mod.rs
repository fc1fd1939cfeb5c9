//! The wgpu context: instance, adapter, device and queue, headless by
//! default. Also texture readback and timestamp queries. Knows nothing of
//! graphs or scenes (docs/ARCHITECTURE.md, "Layers").

pub mod pipeline_cache;
pub mod readback;
pub mod timing;

use std::sync::{Arc, Mutex};

use crate::error::UserError;

/// Exit code for "no usable GPU adapter" and other user-fixable problems.
pub const EXIT_USER_ERROR: i32 = 2;

/// Everything here is a cheap handle (wgpu objects are reference counted),
/// so a rebuild on another thread takes its own clone.
#[derive(Clone)]
pub struct Gpu {
    /// The wgpu instance the adapter came from.
    pub instance: wgpu::Instance,
    /// The chosen adapter.
    pub adapter: wgpu::Adapter,
    /// The device, with the features and limits glint asked for.
    pub device: wgpu::Device,
    /// The device's queue.
    pub queue: wgpu::Queue,
    /// The adapter's name, backend and device type.
    pub info: wgpu::AdapterInfo,
    /// Timestamp queries available (per-pass GPU timings).
    pub timestamps: bool,
    /// Errors no error scope caught (wgpu's default handler would panic):
    /// logged once each and kept here for the viewer's overlay.
    pub uncaptured: Arc<Mutex<Vec<String>>>,
    /// Compiled pipelines kept across runs, where the adapter keeps them
    /// and `GLINT_PIPELINE_CACHE` is not `off` (pipeline_cache.rs).
    pub pipeline_cache: Option<Arc<pipeline_cache::DiskPipelineCache>>,
}

/// How long glint waits for the GPU to finish submitted work before it
/// gives up with an error: `GLINT_GPU_TIMEOUT_S`, 120 s by default (a
/// value that is not a usable number of seconds is refused when the GPU
/// context is made, `check_gpu_timeout`).
pub fn gpu_timeout() -> std::time::Duration {
    parse_gpu_timeout(std::env::var("GLINT_GPU_TIMEOUT_S").ok().as_deref()).unwrap_or(std::time::Duration::from_secs(120))
}

/// The most seconds `GLINT_GPU_TIMEOUT_S` may give (about 11.5 days).
const MAX_GPU_TIMEOUT_S: f64 = 1e6;

/// `GLINT_GPU_TIMEOUT_S` read: None when unset, else a positive finite
/// number of seconds up to MAX_GPU_TIMEOUT_S, or what is wrong with it.
pub fn parse_gpu_timeout(value: Option<&str>) -> Result<std::time::Duration, String> {
    let Some(v) = value else { return Ok(std::time::Duration::from_secs(120)) };
    let refuse = |what: String| format!("GLINT_GPU_TIMEOUT_S{what}: give the seconds glint waits for the GPU before giving up, above 0 and at most {MAX_GPU_TIMEOUT_S} (unset: 120)");
    let secs = match v.trim().parse::<f64>() {
        Ok(secs) if secs.is_finite() && secs > 0.0 && secs <= MAX_GPU_TIMEOUT_S => secs,
        Ok(_) => return Err(refuse(format!("=`{v}`"))),
        Err(_) if v.trim().is_empty() => return Err(refuse(" is empty".into())),
        Err(_) => return Err(refuse(format!("=`{v}` is not a number"))),
    };
    Ok(std::time::Duration::from_secs_f64(secs))
}

/// Refuses a `GLINT_GPU_TIMEOUT_S` that is not a usable number of seconds.
fn check_gpu_timeout() -> Result<(), UserError> {
    parse_gpu_timeout(std::env::var("GLINT_GPU_TIMEOUT_S").ok().as_deref()).map(|_| ()).map_err(UserError::new)
}

const NO_ADAPTER_HELP: &str = "no GPU adapter found. glint needs Vulkan, Metal or DX12; on a machine \
without a GPU, install Mesa's CPU driver (Debian/Ubuntu: `apt-get install -y mesa-vulkan-drivers`) \
and run with WGPU_BACKEND=vulkan. WGPU_ADAPTER_NAME=<substring> picks an adapter by name.";

impl Gpu {
    /// Creates a headless context. The adapter comes from `WGPU_BACKEND`
    /// (vulkan, metal, dx12, gl) and `WGPU_ADAPTER_NAME`, else the best one.
    pub fn new() -> Result<Gpu, UserError> {
        pollster::block_on(Self::new_async())
    }

    /// A context on `instance` whose adapter can present to `surface`
    /// (the viewer's window).
    pub fn for_surface(instance: wgpu::Instance, surface: &wgpu::Surface<'_>) -> Result<Gpu, UserError> {
        pollster::block_on(Self::with_instance(instance, Some(surface)))
    }

    async fn new_async() -> Result<Gpu, UserError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        Self::with_instance(instance, None).await
    }

    /// Another device on the same adapter, with its own queue: work on
    /// one does not wait for work on the other (the viewer renders the
    /// scene on one and its window on the other). It comes from an instance
    /// of its own: lavapipe's devices on one instance share its screen, and
    /// a window frame waited for a scene frame on the other device.
    pub fn second_device(&self) -> Result<Gpu, UserError> {
        pollster::block_on(async {
            let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
            let same = |a: &wgpu::Adapter| {
                let i = a.get_info();
                (i.name == self.info.name && i.backend == self.info.backend && i.device_type == self.info.device_type)
                    && (i.vendor, i.device) == (self.info.vendor, self.info.device)
            };
            let found = instance.enumerate_adapters(wgpu::Backends::from(self.info.backend)).await.into_iter().find(same);
            match found {
                Some(adapter) => Self::with_adapter(instance, adapter).await,
                None => Self::with_adapter(self.instance.clone(), self.adapter.clone()).await,
            }
        })
    }

    async fn with_instance(instance: wgpu::Instance, surface: Option<&wgpu::Surface<'_>>) -> Result<Gpu, UserError> {
        let adapter = pick_adapter(&instance, surface).await?;
        Self::with_adapter(instance, adapter).await
    }

    async fn with_adapter(instance: wgpu::Instance, adapter: wgpu::Adapter) -> Result<Gpu, UserError> {
        let info = adapter.get_info();
        let wanted = wgpu::Features::TIMESTAMP_QUERY
            | wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES
            | wgpu::Features::SUBGROUP
            | wgpu::Features::PIPELINE_CACHE;
        let features = adapter.features() & wanted;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("glint"),
                required_features: features,
                required_limits: adapter.limits(),
                ..Default::default()
            })
            .await
            .map_err(|e| UserError::new(format!("the adapter `{}` refused a device: {e}", info.name)))?;
        let uncaptured = Arc::new(Mutex::new(Vec::new()));
        let log = Arc::clone(&uncaptured);
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            let message = e.to_string();
            eprintln!("glint: GPU error outside an error scope: {message}");
            if let Ok(mut l) = log.lock() {
                l.push(message);
            }
        }));
        let pipeline_cache = pipeline_cache::cache_dir(|name| std::env::var(name).ok())
            .and_then(|dir| pipeline_cache::DiskPipelineCache::open(&device, &info, &dir))
            .map(Arc::new);
        Ok(Gpu {
            uncaptured,
            pipeline_cache,
            timestamps: features.contains(wgpu::Features::TIMESTAMP_QUERY),
            instance,
            adapter,
            device,
            queue,
            info,
        })
    }

    /// The adapter, its kind and backend, and the driver's own version
    /// where it gives one (lavapipe: the Mesa release, which the adapter's
    /// name leaves out).
    pub fn describe(&self) -> String {
        let driver = self.info.driver_info.trim();
        let driver = if driver.is_empty() { String::new() } else { format!(", {driver}") };
        format!("{} ({:?}, {:?}{driver})", self.info.name, self.info.device_type, self.info.backend)
    }

    /// Largest 2D texture side this device takes.
    pub fn max_texture_side(&self) -> u32 {
        self.device.limits().max_texture_dimension_2d
    }

    /// Counts of live wgpu objects (textures, buffers, pipelines, bind
    /// groups...), from wgpu's own registry report: how tests see that
    /// rebuilds release what they replace.
    pub fn live_objects(&self) -> Option<LiveObjects> {
        let r = self.instance.generate_report()?;
        let h = r.hub_report();
        // wgpu does not re-export the report's types; read fields by name.
        macro_rules! n {
            ($f:ident) => {
                h.$f.num_allocated
            };
        }
        Some(LiveObjects {
            textures: n!(textures),
            texture_views: n!(texture_views),
            buffers: n!(buffers),
            bind_groups: n!(bind_groups),
            bind_group_layouts: n!(bind_group_layouts),
            pipeline_layouts: n!(pipeline_layouts),
            compute_pipelines: n!(compute_pipelines),
            shader_modules: n!(shader_modules),
            query_sets: n!(query_sets),
        })
    }

    /// Waits for all submitted work, at most `gpu_timeout()` (a watchdog:
    /// on a GPU a runaway pass would otherwise keep the frame forever).
    /// False when it timed out.
    pub fn wait(&self) -> bool {
        let poll = self.device.poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(gpu_timeout()) });
        if let Err(wgpu::PollError::Timeout) = poll {
            eprintln!("glint: the GPU did not finish its work within {} s (GLINT_GPU_TIMEOUT_S sets the limit)", gpu_timeout().as_secs_f64());
            return false;
        }
        true
    }
}

/// The adapter `WGPU_BACKEND` and `WGPU_ADAPTER_NAME` select, or the best
/// one; when none is found, an error that names the filter that matched
/// nothing and lists the adapters there are.
async fn pick_adapter(instance: &wgpu::Instance, surface: Option<&wgpu::Surface<'_>>) -> Result<wgpu::Adapter, UserError> {
    check_gpu_timeout()?;
    let backend_var = std::env::var("WGPU_BACKEND").ok();
    let backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::all());
    if let (Some(v), true) = (&backend_var, backends.is_empty()) {
        return Err(UserError::new(format!("WGPU_BACKEND=`{v}` names no backend glint knows; use vulkan, metal or dx12 (a comma-separated list picks several)")));
    }
    if backends == wgpu::Backends::GL {
        return Err(UserError::new(
            "WGPU_BACKEND=gl: glint does not run on wgpu's GL backend (its shader translation refuses parts of the path tracer, and its storage \
             textures lack formats glint's passes write); use vulkan, metal or dx12 (on a machine without a GPU: WGPU_BACKEND=vulkan \
             with Mesa's lavapipe)",
        ));
    }
    let mut adapters = instance.enumerate_adapters(backends).await;
    if let Some(s) = surface {
        adapters.retain(|a| a.is_surface_supported(s));
    }
    // wgpu's GL backend cannot run glint's passes: its shader translation
    // refuses some of what the path tracer writes, and its storage
    // textures lack formats the passes write (rg32uint, tried). Its
    // adapters are left out; asked for alone, it is refused in words.
    adapters.retain(|a| a.get_info().backend != wgpu::Backend::Gl);
    let list = |adapters: &[wgpu::Adapter]| {
        let names: Vec<String> = adapters.iter().map(|a| {
            let i = a.get_info();
            format!("`{}` ({:?}, {:?})", i.name, i.device_type, i.backend)
        }).collect();
        names.join(", ")
    };
    if adapters.is_empty() {
        let filter = backend_var.map(|v| format!(" with WGPU_BACKEND=`{v}`")).unwrap_or_default();
        return Err(UserError::new(format!("{NO_ADAPTER_HELP} (none found{filter})")));
    }
    if let Ok(name) = std::env::var("WGPU_ADAPTER_NAME") {
        let wanted = name.to_lowercase();
        let all = list(&adapters);
        return adapters.into_iter().find(|a| a.get_info().name.to_lowercase().contains(&wanted)).ok_or_else(|| {
            UserError::new(format!("WGPU_ADAPTER_NAME=`{name}` matches none of the adapters there are: {all}"))
        });
    }
    // Prefer discrete, then integrated, then anything.
    let rank = |a: &wgpu::Adapter| match a.get_info().device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    };
    adapters.into_iter().min_by_key(rank).ok_or_else(|| UserError::new(NO_ADAPTER_HELP))
}

/// Live wgpu objects by kind (see `Gpu::live_objects`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LiveObjects {
    /// Textures.
    pub textures: usize,
    /// Texture views.
    pub texture_views: usize,
    /// Buffers.
    pub buffers: usize,
    /// Bind groups.
    pub bind_groups: usize,
    /// Bind group layouts.
    pub bind_group_layouts: usize,
    /// Pipeline layouts.
    pub pipeline_layouts: usize,
    /// Compute pipelines.
    pub compute_pipelines: usize,
    /// Shader modules.
    pub shader_modules: usize,
    /// Query sets.
    pub query_sets: usize,
}

impl LiveObjects {
    /// All of them together.
    pub fn total(&self) -> usize {
        self.textures
            + self.texture_views
            + self.buffers
            + self.bind_groups
            + self.bind_group_layouts
            + self.pipeline_layouts
            + self.compute_pipelines
            + self.shader_modules
            + self.query_sets
    }
}

#[cfg(test)]
mod tests {
    use super::parse_gpu_timeout;
    use std::time::Duration;

    #[test]
    fn gpu_timeout_takes_positive_finite_seconds_only() {
        assert_eq!(parse_gpu_timeout(None), Ok(Duration::from_secs(120)));
        assert_eq!(parse_gpu_timeout(Some("2.5")), Ok(Duration::from_secs_f64(2.5)));
        for bad in ["0", "-1", "abc", "inf", "NaN", "", "1e7"] {
            let e = parse_gpu_timeout(Some(bad)).expect_err(bad);
            assert!(e.starts_with("GLINT_GPU_TIMEOUT_S") && e.contains("above 0"), "{bad}: {e}");
        }
        assert!(parse_gpu_timeout(Some("")).unwrap_err().contains("is empty"));
    }
}
