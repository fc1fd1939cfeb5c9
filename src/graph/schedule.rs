//! The output of `compile`: everything the executor needs, with every name
//! already resolved to an index.

use crate::format::TexFormat;
use crate::graph::desc::{ProbesDesc, RunMode, SizeDesc};
use crate::scene::{Feature, SceneFeatures};
use crate::shader::BindingKind;

/// The binding through which a pass lists texels for its `listed` entry.
pub const WORK_LIST: &str = "work_list";
/// The listed entry's workgroup size (`WORK_GROUP` in shared/work_list.wgsl).
pub const WORK_LIST_GROUP: u32 = 64;
/// The binding through which a pass takes its texels from a pool in
/// chunks (shared/tile_pool.wgsl): one counter, zeroed before each dispatch.
pub const TILE_POOL: &str = "tile_pool";
/// Bytes before the work list's items: the count, then the indirect
/// dispatch's (x, y, z) groups.
pub const WORK_LIST_HEADER: u64 = 16;

/// Buffers the engine provides, bound by name like graph resources.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EngineResource {
    /// `var<uniform> frame: Frame` (camera, previous camera, frame index, seed, counts).
    Frame,
    Spheres,
    /// Triangles, then the two-level BVH's nodes (one array, so traversal
    /// fetches a node pair or a triangle from the same place).
    Geometry,
    /// Shading normals, parallel to the triangles.
    Normals,
    Meshes,
    Materials,
    Lights,
    /// The TLAS instances.
    Instances,
    /// A flat scene's triangles seen from the camera and light 0
    /// (`crate::scene::origins`).
    Origins,
    /// A flat scene's triangles and spheres in a uniform buffer
    /// (`crate::scene::flat_uniform`).
    Flat,
    /// Where the camera's rays enter a one-mesh scene's BLAS, a uniform
    /// (`crate::bvh::entry`).
    Entries,
    /// Where the camera rays of each screen tile enter it
    /// (`crate::bvh::tiles`).
    Tiles,
}

impl EngineResource {
    pub const ALL: [EngineResource; 12] = [
        EngineResource::Frame,
        EngineResource::Spheres,
        EngineResource::Geometry,
        EngineResource::Normals,
        EngineResource::Meshes,
        EngineResource::Materials,
        EngineResource::Lights,
        EngineResource::Instances,
        EngineResource::Origins,
        EngineResource::Flat,
        EngineResource::Entries,
        EngineResource::Tiles,
    ];

    pub fn name(self) -> &'static str {
        match self {
            EngineResource::Frame => "frame",
            EngineResource::Spheres => "scene_spheres",
            EngineResource::Geometry => "scene_geometry",
            EngineResource::Normals => "scene_normals",
            EngineResource::Meshes => "scene_meshes",
            EngineResource::Materials => "scene_materials",
            EngineResource::Lights => "scene_lights",
            EngineResource::Instances => "scene_instances",
            EngineResource::Origins => "scene_origins",
            EngineResource::Flat => "scene_flat",
            EngineResource::Entries => "scene_entries",
            EngineResource::Tiles => "scene_tiles",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|e| e.name() == name)
    }

    /// How shaders declare it. The per-primitive and per-node arrays are
    /// textures (`src/scene/buffers.rs` says why).
    pub fn kind(self) -> EngineKind {
        match self {
            EngineResource::Frame | EngineResource::Flat | EngineResource::Entries => EngineKind::Uniform,
            EngineResource::Spheres
            | EngineResource::Geometry
            | EngineResource::Normals
            | EngineResource::Instances
            | EngineResource::Origins
            | EngineResource::Tiles
            | EngineResource::Materials
            | EngineResource::Lights => EngineKind::Texture,
            EngineResource::Meshes => EngineKind::Storage,
        }
    }
}

/// The binding type of an engine resource.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EngineKind {
    /// `var<uniform>`
    Uniform,
    /// `var<storage, read>`
    Storage,
    /// `texture_storage_2d<rgba32uint, read>` (records of 16-byte texels)
    Texture,
}

impl EngineKind {
    pub fn wgsl(self) -> &'static str {
        match self {
            EngineKind::Uniform => "var<uniform>",
            EngineKind::Storage => "var<storage, read>",
            EngineKind::Texture => "texture_storage_2d<rgba32uint, read>",
        }
    }
}

/// A texture reference that may alternate between two physical textures
/// from frame to frame (history resources written out of place).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TexRef {
    Fixed(usize),
    /// `textures[slot ^ parity]` where the parity flips each frame when
    /// `flips` (the resource's last write of a frame lands in slot 1).
    PingPong { textures: [usize; 2], slot: u8, flips: bool },
}

impl TexRef {
    pub fn resolve(self, parity: u8) -> usize {
        match self {
            TexRef::Fixed(i) => i,
            TexRef::PingPong { textures, slot, flips } => textures[usize::from(slot ^ (parity & u8::from(flips)))],
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    Texture(TexRef),
    Engine(EngineResource),
    /// The pass's own `params` uniform (see `ScheduledPass::params`).
    Params,
    /// The pass's `run` uniform: which iteration a dispatch is (see
    /// `RunMode`); the executor writes it before each dispatch.
    Run,
    /// The pass's own list of texels for its `listed` entry
    /// (shared/work_list.wgsl): emptied before the pass, filled by its
    /// entry, read by the listed entry and as its indirect dispatch.
    WorkList,
    /// The pass's tile pool (shared/tile_pool.wgsl): a counter zeroed
    /// before each dispatch, from which its invocations take chunks of
    /// texels until none are left.
    TilePool,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedBinding {
    pub name: String,
    pub group: u32,
    pub binding: u32,
    pub kind: BindingKind,
    pub target: Target,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ScheduledPass {
    pub name: String,
    pub shader: String,
    pub entry: String,
    pub workgroup_size: [u32; 3],
    /// The entry dispatched over the texels `entry` lists (`PassDesc::listed`).
    pub listed: Option<String>,
    /// The `params` uniform (layout, values, packed bytes), if the shader has one.
    pub params: Option<crate::graph::params::PassParams>,
    /// `override` constants for the pipeline.
    pub constants: Vec<(String, f64)>,
    pub bindings: Vec<ResolvedBinding>,
    /// One invocation per texel of this size (the graph's `dispatch`, else
    /// the first texture written).
    pub dispatch: SizeDesc,
    /// Texels per invocation (the dispatch's width divided by it).
    pub texels_per_invocation: u32,
    /// When it runs.
    pub run: RunMode,
    /// Schedule indices of the earlier passes whose writes it reads this
    /// frame (for `RunMode::OnInputChange`).
    pub inputs_from: Vec<usize>,
    /// Names of resource versions read and written, for printing (`lit@2`).
    pub reads: Vec<String>,
    pub writes: Vec<String>,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CullReason {
    /// The scene lacks these features.
    Requires(Vec<Feature>),
    /// Nothing it writes reaches the output or a history resource.
    Unreachable,
}

#[derive(Debug, Clone, PartialEq)]
pub struct CulledPass {
    pub name: String,
    pub reason: CullReason,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TexUsage {
    pub sampled: bool,
    pub storage: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub struct PhysicalTexture {
    /// The resources (versions) that live in it, for labels and printing.
    pub label: String,
    pub format: TexFormat,
    pub size: SizeDesc,
    pub usage: TexUsage,
    /// Survives across frames, never pooled (history or persistent).
    pub history: bool,
    /// One texture across frames (not a history ping-pong pair).
    pub persistent: bool,
}

/// One version of one resource and where it lives.
#[derive(Debug, Clone, PartialEq)]
pub struct VersionInfo {
    pub resource: String,
    pub version: u32,
    pub texture: TexRef,
    /// Schedule indices of the producing pass and of the last reader
    /// (None for the previous frame's history version / never read).
    pub first_use: Option<usize>,
    pub last_use: Option<usize>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    pub name: String,
    pub features: SceneFeatures,
    pub passes: Vec<ScheduledPass>,
    pub culled: Vec<CulledPass>,
    pub textures: Vec<PhysicalTexture>,
    pub versions: Vec<VersionInfo>,
    pub output_resource: String,
    pub output: TexRef,
    pub output_format: TexFormat,
    /// Whether the ping-pong parity flips after each frame.
    pub flips_parity: bool,
    /// Resources whose final version survives the frame (the output and
    /// CompileOptions::keep): these can be read back.
    pub kept: Vec<String>,
    /// The graph's probe grid, after edits.
    pub probes: Option<ProbesDesc>,
    /// Override constants from what the scene lacks, given to every shader
    /// that declares them (empty with `--no-specialise`).
    pub specialisations: Vec<crate::scene::specialise::Specialisation>,
    /// False with `--no-specialise`: then neither the scene's constants nor
    /// the per-frame CAMERA_STILL pipelines are used.
    pub specialise: bool,
}

/// Memory figures for a schedule at a given render size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryStats {
    pub textures: usize,
    pub bytes: u64,
    /// Bytes one texture per version would have taken, minus `bytes`.
    pub bytes_saved: u64,
}

impl Schedule {
    pub fn memory(&self, screen: (u32, u32)) -> MemoryStats {
        let bytes_of = |format: TexFormat, size: SizeDesc| {
            let (w, h) = size.resolve(screen);
            u64::from(w) * u64::from(h) * format.bytes_per_pixel()
        };
        let bytes: u64 = self.textures.iter().map(|t| bytes_of(t.format, t.size)).sum();
        // Without pooling or in-place aliasing: one texture per version
        // (history resources keep what they need either way).
        let mut unpooled = 0;
        for v in &self.versions {
            if let TexRef::Fixed(i) = v.texture {
                let t = &self.textures[i];
                if !t.history && v.first_use.is_some() {
                    unpooled += bytes_of(t.format, t.size);
                }
            }
        }
        unpooled += self.textures.iter().filter(|t| t.history).map(|t| bytes_of(t.format, t.size)).sum::<u64>();
        MemoryStats { textures: self.textures.len(), bytes, bytes_saved: unpooled.saturating_sub(bytes) }
    }
}
