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
    /// Spheres, sphere lights' own included (`SphereGpu` records).
    Spheres,
    /// Triangles, then the two-level BVH's nodes (one array, so traversal
    /// fetches a node pair or a triangle from the same place).
    Geometry,
    /// Shading normals, parallel to the triangles.
    Normals,
    /// Per-mesh boxes and triangle ranges (`MeshGpu`), a storage buffer.
    Meshes,
    /// Materials (`MaterialGpu` records).
    Materials,
    /// Lights (`LightGpu` records).
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
    /// Blue-noise ranks, a 64x64 tile of four channels (`crate::blue_noise`).
    BlueNoise,
    /// Each triangle's texture coordinates (parallel to the triangles).
    Uvs,
    /// Each material's texture slots (`crate::scene::texture_classes`).
    MaterialTextures,
    /// The scene's textures of side 256, 512, 1024 and 2048, one
    /// `texture_2d_array` per size class.
    Images256,
    /// See `Images256`.
    Images512,
    /// See `Images256`.
    Images1024,
    /// See `Images256`.
    Images2048,
    /// The sampler the scene's textures are read with (trilinear, repeat).
    Sampler,
    /// The environment light's map and sampling tables
    /// (`crate::scene::environment`; one zero texel without one).
    Environment,
}

impl EngineResource {
    /// Every engine resource.
    pub const ALL: [EngineResource; 21] = [
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
        EngineResource::BlueNoise,
        EngineResource::Uvs,
        EngineResource::MaterialTextures,
        EngineResource::Images256,
        EngineResource::Images512,
        EngineResource::Images1024,
        EngineResource::Images2048,
        EngineResource::Sampler,
        EngineResource::Environment,
    ];

    /// The name a shader binds it by (`frame`, `scene_spheres`, ...).
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
            EngineResource::BlueNoise => "blue_noise",
            EngineResource::Uvs => "scene_uvs",
            EngineResource::MaterialTextures => "scene_material_textures",
            EngineResource::Images256 => "scene_images_256",
            EngineResource::Images512 => "scene_images_512",
            EngineResource::Images1024 => "scene_images_1024",
            EngineResource::Images2048 => "scene_images_2048",
            EngineResource::Sampler => "scene_sampler",
            EngineResource::Environment => "scene_environment",
        }
    }

    /// The engine resource a binding of this name takes, if any.
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
            | EngineResource::BlueNoise
            | EngineResource::Uvs
            | EngineResource::MaterialTextures
            | EngineResource::Materials
            | EngineResource::Lights
            | EngineResource::Environment => EngineKind::Texture,
            EngineResource::Meshes => EngineKind::Storage,
            EngineResource::Images256 | EngineResource::Images512 | EngineResource::Images1024 | EngineResource::Images2048 => EngineKind::TextureArray,
            EngineResource::Sampler => EngineKind::Sampler,
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
    /// `texture_2d_array<f32>`, filterable (the scene's texture classes)
    TextureArray,
    /// `sampler` (filtering)
    Sampler,
}

impl EngineKind {
    /// The declaration as WGSL writes it, for messages.
    pub fn wgsl(self) -> &'static str {
        match self {
            EngineKind::Uniform => "var<uniform>",
            EngineKind::Storage => "var<storage, read>",
            EngineKind::Texture => "texture_storage_2d<rgba32uint, read>",
            EngineKind::TextureArray => "texture_2d_array<f32>",
            EngineKind::Sampler => "sampler",
        }
    }
}

/// A texture reference that may alternate between two physical textures
/// from frame to frame (history resources written out of place).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TexRef {
    /// Always this texture (an index into `Schedule::textures`).
    Fixed(usize),
    /// `textures[slot ^ parity]` where the parity flips each frame when
    /// `flips` (the resource's last write of a frame lands in slot 1).
    PingPong {
        /// The pair, in slot order (indices into `Schedule::textures`).
        textures: [usize; 2],
        /// The slot this version lives in at parity 0.
        slot: u8,
        /// Whether the parity applies at all (else always `slot`).
        flips: bool,
    },
}

impl TexRef {
    /// The texture index at frame parity `parity` (0 or 1).
    pub fn resolve(self, parity: u8) -> usize {
        match self {
            TexRef::Fixed(i) => i,
            TexRef::PingPong { textures, slot, flips } => textures[usize::from(slot ^ (parity & u8::from(flips)))],
        }
    }
}

/// What a binding binds.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// A graph texture: the physical texture of a resource version.
    Texture(TexRef),
    /// A buffer or texture the engine provides.
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

/// One binding of a pass's entry point and what it binds.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedBinding {
    /// The variable's name in the shader.
    pub name: String,
    /// `@group`
    pub group: u32,
    /// `@binding`
    pub binding: u32,
    /// How the shader declares it (from reflection).
    pub kind: BindingKind,
    /// What the executor binds to it.
    pub target: Target,
}

/// One dispatch of the schedule (a split pass gives several, `NAME#k`).
#[derive(Debug, Clone, PartialEq)]
pub struct ScheduledPass {
    /// The pass's name (`NAME#k` for the later dispatches of a split pass).
    pub name: String,
    /// The shader's path as the graph names it, under shaders/.
    pub shader: String,
    /// The entry point dispatched.
    pub entry: String,
    /// The entry's `@workgroup_size`.
    pub workgroup_size: [u32; 3],
    /// The entry dispatched over the texels `entry` lists (`PassDesc::listed`).
    pub listed: Option<String>,
    /// The `params` uniform (layout, values, packed bytes), if the shader has one.
    pub params: Option<crate::graph::params::PassParams>,
    /// `override` constants for the pipeline.
    pub constants: Vec<(String, f64)>,
    /// Every binding of the entry, resolved.
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
    /// Names of resource versions read, for printing (`lit@2`).
    pub reads: Vec<String>,
    /// Names of resource versions written, for printing (`lit@3`).
    pub writes: Vec<String>,
}

impl ScheduledPass {
    /// Workgroups of a plain dispatch at render size `size` (a pass that
    /// takes its texels from the tile pool sizes its own,
    /// `tile_pool::workgroups`), in u64: a graph's `Fixed` dispatch may
    /// ask for more than a u32 holds.
    pub fn workgroups(&self, size: (u32, u32)) -> [u64; 3] {
        let (w, h) = self.dispatch.resolve(size);
        let w = w.div_ceil(self.texels_per_invocation.max(1));
        let wg = self.workgroup_size;
        [u64::from(w).div_ceil(u64::from(wg[0].max(1))), u64::from(h).div_ceil(u64::from(wg[1].max(1))), 1]
    }
}

/// Why compile left a pass out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CullReason {
    /// The scene lacks these features.
    Requires(Vec<Feature>),
    /// Nothing it writes reaches the output or a history resource.
    Unreachable,
}

/// A pass compile left out.
#[derive(Debug, Clone, PartialEq)]
pub struct CulledPass {
    /// The pass's name in the graph.
    pub name: String,
    /// Why it was left out.
    pub reason: CullReason,
}

/// How passes bind a physical texture (its wgpu usages).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TexUsage {
    /// Bound as a sampled texture.
    pub sampled: bool,
    /// Bound as a storage texture.
    pub storage: bool,
}

/// One texture the executor creates; transient versions may share it.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicalTexture {
    /// The resources (versions) that live in it, for labels and printing.
    pub label: String,
    /// Its texel format.
    pub format: TexFormat,
    /// Its size, absolute or relative to the render size.
    pub size: SizeDesc,
    /// How passes bind it.
    pub usage: TexUsage,
    /// Survives across frames, never pooled (history or persistent).
    pub history: bool,
    /// One texture across frames (not a history ping-pong pair).
    pub persistent: bool,
}

/// One version of one resource and where it lives.
#[derive(Debug, Clone, PartialEq)]
pub struct VersionInfo {
    /// The resource's name in the graph.
    pub resource: String,
    /// The version number: 0 is what a history or persistent resource
    /// holds when the frame starts; each write adds one.
    pub version: u32,
    /// The physical texture it lives in.
    pub texture: TexRef,
    /// Schedule index of the producing pass (None for the previous
    /// frame's history version).
    pub first_use: Option<usize>,
    /// Schedule index of the last pass that reads it (None if never read).
    pub last_use: Option<usize>,
}

/// A compiled frame graph: the passes in order, with every resource and
/// binding resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    /// The graph's name.
    pub name: String,
    /// The scene features it was compiled against.
    pub features: SceneFeatures,
    /// The dispatches, in order; a schedule index indexes this.
    pub passes: Vec<ScheduledPass>,
    /// The passes compile left out, with why.
    pub culled: Vec<CulledPass>,
    /// The physical textures, indexed by `TexRef`.
    pub textures: Vec<PhysicalTexture>,
    /// Every resource version, with its texture and lifetime.
    pub versions: Vec<VersionInfo>,
    /// The name of the output resource.
    pub output_resource: String,
    /// The texture that holds the output's final version.
    pub output: TexRef,
    /// The output's format.
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
    /// the per-frame pipelines (graph/frame_kind.rs) are used.
    pub specialise: bool,
}

/// Memory figures for a schedule at a given render size.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MemoryStats {
    /// Physical textures.
    pub textures: usize,
    /// Their total size in bytes.
    pub bytes: u64,
    /// Bytes one texture per version would have taken, minus `bytes`.
    pub bytes_saved: u64,
}

impl Schedule {
    /// Texture count and bytes at render size `screen` (pixels), and what
    /// pooling saved.
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
