//! The scene on the GPU: one binding per array of `SceneData` (triangles
//! and BVH nodes share `scene_geometry`).
//! `update` writes only the arrays that changed and bumps `epoch` when it
//! does, so accumulation can reset.
//!
//! What traversal reads at every step (triangles and BVH nodes, in one
//! texture; spheres; instances) lives in `rgba32uint` textures bound as
//! read-only storage
//! textures, one texel per 16 bytes of a record, `SCENE_TEXTURE_WIDTH`
//! texels to a row (`shaders/shared/scene.wgsl` and `bvh.wgsl` read them
//! back with `textureLoad`). Texel fetches are what every GPU is built for,
//! and on CPU drivers they are far cheaper than storage-buffer loads:
//! lavapipe loads a storage buffer one lane and one component at a time,
//! round-tripping the vector through memory each time (17.2 ns per vec4 per
//! invocation, against 2.8 ns for a sampled texel and 2.2 ns for a storage
//! texel, which has no mip level to resolve; AMD EPYC, Mesa 22.3:
//! `cargo run --release --example load_cost`). Rows also lift the
//! one-binding size limit of storage buffers (128 MiB on lavapipe).
//! Shading normals are textures too (so no per-triangle array is bound by
//! the storage-binding limit), and so are materials and lights, which
//! every shading pass reads at every pixel (moving them out of storage
//! buffers took the albedo pass from 15 to 10 ms at 1280x720); meshes stay
//! in a storage buffer.

use bytemuck::Pod;
use wgpu::util::DeviceExt;

use glam::Vec3;

use crate::bvh::entry::{camera_cut, camera_entries, entry_texels, CameraEntriesGpu};
use crate::bvh::tiles::{tile_table, PixelCamera, TileTable, MAX_TILES, TILE_TEXELS};
use crate::scene::flat_uniform::flat_uniform;
use crate::scene::origins::{origin_table, Viewpoints};
use crate::scene::SceneData;


/// Texels per row of a scene texture (every adapter takes 8192).
pub const SCENE_TEXTURE_WIDTH: u32 = 4096;

/// Bytes in one texel of a scene texture (`rgba32uint`).
const TEXEL_BYTES: usize = 16;

/// Rows a scene texture needs for `bytes` of records (at least one).
pub fn scene_texture_rows(bytes: usize) -> u64 {
    let texels = bytes.div_ceil(TEXEL_BYTES) as u64;
    texels.div_ceil(u64::from(SCENE_TEXTURE_WIDTH)).max(1)
}

/// An array of 16-byte-multiple records in an `rgba32uint` texture.
pub struct SceneTexture {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
}

impl SceneTexture {
    /// The view shaders bind (`texture_storage_2d<rgba32uint, read>`).
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    fn new<T: Pod>(device: &wgpu::Device, queue: &wgpu::Queue, label: &str, items: &[T]) -> SceneTexture {
        debug_assert_eq!(std::mem::size_of::<T>() % TEXEL_BYTES, 0);
        Self::from_bytes(device, queue, label, bytemuck::cast_slice(items))
    }

    fn from_bytes(device: &wgpu::Device, queue: &wgpu::Queue, label: &str, bytes: &[u8]) -> SceneTexture {
        let rows = scene_texture_rows(bytes.len()) as u32;
        let texture = device.create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width: SCENE_TEXTURE_WIDTH, height: rows, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba32Uint,
                usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &padded_rows(bytes, rows),
        );
        let view = texture.create_view(&Default::default());
        SceneTexture { texture, view }
    }

    /// Writes the texels of `new` that differ from `old` (the same array
    /// before), which start at texel `base` of the texture: one span, from
    /// the first differing texel to the last. A moving light rewrites the
    /// few TLAS nodes it moved, not the whole geometry. True if any differed.
    fn write_changes(&self, queue: &wgpu::Queue, base: usize, old: &[u8], new: &[u8]) -> bool {
        // The arrays of one scene keep their lengths (SceneBvh pads the TLAS).
        debug_assert_eq!(old.len(), new.len());
        if old.len() != new.len() {
            return false;
        }
        let texels = || old.chunks_exact(TEXEL_BYTES).zip(new.chunks_exact(TEXEL_BYTES));
        let Some(first) = texels().position(|(a, b)| a != b) else { return false };
        let last = texels().rposition(|(a, b)| a != b).unwrap_or(first);
        self.write_texels(queue, base + first, &new[first * TEXEL_BYTES..(last + 1) * TEXEL_BYTES]);
        true
    }

    /// Writes `bytes` (whole texels) from texel `first` on.
    fn write_texels(&self, queue: &wgpu::Queue, first: usize, bytes: &[u8]) {
        let mut rest = bytes;
        for span in texel_spans(first, bytes.len() / TEXEL_BYTES) {
            let (now, later) = rest.split_at(span.width * span.height * TEXEL_BYTES);
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &self.texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d { x: span.x as u32, y: span.y as u32, z: 0 },
                    aspect: wgpu::TextureAspect::All,
                },
                now,
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some((span.width * TEXEL_BYTES) as u32), rows_per_image: None },
                wgpu::Extent3d { width: span.width as u32, height: span.height as u32, depth_or_array_layers: 1 },
            );
            rest = later;
        }
    }
}

/// A rectangle of a scene texture, in texels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct TexelSpan {
    x: usize,
    y: usize,
    width: usize,
    height: usize,
}

/// The rectangles that hold `count` texels from texel `first` on, in order:
/// the rest of the first row, the whole rows, the start of the last.
fn texel_spans(first: usize, count: usize) -> Vec<TexelSpan> {
    let width = SCENE_TEXTURE_WIDTH as usize;
    let (mut texel, mut left) = (first, count);
    let mut spans = Vec::new();
    while left > 0 {
        let (x, y) = (texel % width, texel / width);
        let span = if x == 0 && left >= width {
            TexelSpan { x, y, width, height: left / width }
        } else {
            TexelSpan { x, y, width: (width - x).min(left), height: 1 }
        };
        texel += span.width * span.height;
        left -= span.width * span.height;
        spans.push(span);
    }
    spans
}

/// The records' bytes, zero-padded to whole rows.
fn padded_rows(bytes: &[u8], rows: u32) -> Vec<u8> {
    let mut padded = bytes.to_vec();
    padded.resize(rows as usize * SCENE_TEXTURE_WIDTH as usize * TEXEL_BYTES, 0);
    padded
}

/// `scene_lights`: the lights, then their clusters (src/scene/light_clusters.rs).
fn lights_bytes(data: &SceneData) -> Vec<u8> {
    let mut bytes = bytemuck::cast_slice(&data.lights).to_vec();
    bytes.extend_from_slice(bytemuck::cast_slice(&data.light_clusters.texels));
    bytes
}

/// `scene_geometry`: the triangles (three texels each), then the BVH nodes
/// (two texels each, from texel 3 * triangle count).
pub fn geometry_bytes(data: &SceneData) -> Vec<u8> {
    let mut bytes = bytemuck::cast_slice::<_, u8>(&data.triangles).to_vec();
    bytes.extend_from_slice(bytemuck::cast_slice(&data.bvh));
    bytes
}

/// The scene's GPU arrays, one per `EngineResource` it provides.
pub struct SceneBuffers {
    /// `scene_spheres`
    pub spheres: SceneTexture,
    /// `scene_geometry`: the triangles, then the BVH nodes.
    pub geometry: SceneTexture,
    /// `scene_normals`
    pub normals: SceneTexture,
    /// `scene_meshes`, a storage buffer.
    pub meshes: wgpu::Buffer,
    /// `scene_materials`
    pub materials: SceneTexture,
    /// `scene_lights`
    pub lights: SceneTexture,
    /// `scene_instances`: the TLAS instances.
    pub instances: SceneTexture,
    /// The flat scene seen from the camera and light 0, and each light's
    /// occluders (`origins`).
    pub origins: SceneTexture,
    /// A flat scene's primitives as a uniform (`flat_uniform`), and the
    /// bytes last written to it.
    pub flat: wgpu::Buffer,
    flat_bytes: Vec<u8>,
    origin_table: Vec<[u32; 4]>,
    /// Where the camera's rays enter a one-mesh scene's BLAS
    /// (`crate::bvh::entry`), and what was last written to it.
    pub entries: wgpu::Buffer,
    entries_gpu: CameraEntriesGpu,
    /// Where the camera rays of each screen tile enter a one-mesh scene's
    /// BLAS (`crate::bvh::tiles`; its size and row length go in
    /// `entries`), what was last written to it, and for which camera and
    /// scene epoch.
    pub tiles: SceneTexture,
    tile_texels: Vec<[u32; 4]>,
    tiles_for: Option<(PixelCamera, u32)>,
    /// The table's tile size (log2; 0: no table) and tiles across.
    tile_grid: [u32; 2],
    /// Whether the occluder lists leave out the triangles that cannot
    /// shadow their light (tests turn it off to compare).
    pub cull_occluders: bool,
    /// Blue-noise ranks (`crate::blue_noise`), the same for every scene.
    pub blue_noise: SceneTexture,
    /// Texture coordinates, parallel to the triangles (a scene with
    /// textures; one zero texel otherwise).
    pub uvs: SceneTexture,
    /// Each material's texture slots (a scene with textures).
    pub material_textures: SceneTexture,
    /// The environment light's map and tables (`SceneData::environment`),
    /// written once: animation does not change it.
    pub environment: SceneTexture,
    /// The arrays as last uploaded.
    pub data: SceneData,
    /// Bumped whenever anything visible changed.
    pub epoch: u32,
}

fn storage<T: Pod>(device: &wgpu::Device, label: &str, items: &[T]) -> wgpu::Buffer {
    // Storage bindings cannot be empty: keep one zeroed element.
    let one = [T::zeroed()];
    let items = if items.is_empty() { &one[..] } else { items };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(items),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
    })
}

impl SceneBuffers {
    /// Uploads `data` as a new scene (epoch 0); the per-frame tables start empty.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, data: SceneData) -> SceneBuffers {
        let origin_table = origin_table(&data, &Viewpoints { camera: Vec3::ZERO, probes: None, pixels: None }, true);
        let flat_bytes = flat_uniform(&data);
        let entries_gpu = scene_entries(&data, None);
        // Scenes whose rays never start at one BLAS need no tile table.
        let tile_texels = vec![[0u32; 4]; if !data.is_flat() && is_one_mesh(&data) { MAX_TILES * TILE_TEXELS } else { 1 }];
        SceneBuffers {
            spheres: SceneTexture::new(device, queue, "scene_spheres", &data.spheres),
            geometry: SceneTexture::from_bytes(device, queue, "scene_geometry", &geometry_bytes(&data)),
            normals: SceneTexture::new(device, queue, "scene_normals", &data.normals),
            meshes: storage(device, "scene_meshes", &data.meshes),
            materials: SceneTexture::new(device, queue, "scene_materials", &data.materials),
            lights: SceneTexture::from_bytes(device, queue, "scene_lights", &lights_bytes(&data)),
            instances: SceneTexture::new(device, queue, "scene_instances", &data.instances),
            origins: SceneTexture::new(device, queue, "scene_origins", &origin_table),
            flat: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("scene_flat"),
                contents: &flat_bytes,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            }),
            entries: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("scene_entries"),
                contents: bytemuck::bytes_of(&entries_gpu),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            }),
            entries_gpu,
            tiles: SceneTexture::new(device, queue, "scene_tiles", &tile_texels),
            tile_texels,
            blue_noise: SceneTexture::new(device, queue, "blue_noise", crate::blue_noise::texels()),
            uvs: SceneTexture::new(device, queue, "scene_uvs", &data.uvs),
            material_textures: SceneTexture::new(device, queue, "scene_material_textures", &data.material_textures),
            environment: SceneTexture::new(device, queue, "scene_environment", data.environment.as_slice()),
            tiles_for: None,
            tile_grid: [0, 0],
            flat_bytes,
            origin_table,
            cull_occluders: true,
            data,
            epoch: 0,
        }
    }

    /// Uploads what differs from the last upload and bumps `epoch` if
    /// anything did. The array lengths of one scene never change (animation
    /// moves things, it does not add them).
    pub fn update(&mut self, queue: &wgpu::Queue, data: SceneData) -> bool {
        let changed = self.upload(queue, data);
        if changed {
            self.epoch = self.epoch.wrapping_add(1);
        }
        changed
    }

    /// Uploads the same scene relative to a new origin: nothing moved, so
    /// the epoch (and with it the accumulated history) stays.
    pub fn rebase(&mut self, queue: &wgpu::Queue, data: SceneData) {
        self.upload(queue, data);
    }

    fn upload(&mut self, queue: &wgpu::Queue, data: SceneData) -> bool {
        let mut changed = false;
        fn write<T: Pod + PartialEq>(queue: &wgpu::Queue, buf: &wgpu::Buffer, old: &[T], new: &[T], changed: &mut bool) {
            if old != new && old.len() == new.len() && !new.is_empty() {
                queue.write_buffer(buf, 0, bytemuck::cast_slice(new));
                *changed = true;
            }
        }
        fn write_texture<T: Pod>(queue: &wgpu::Queue, tex: &SceneTexture, base: usize, old: &[T], new: &[T], changed: &mut bool) {
            *changed |= tex.write_changes(queue, base, bytemuck::cast_slice(old), bytemuck::cast_slice(new));
        }
        let old = &self.data;
        write_texture(queue, &self.spheres, 0, &old.spheres, &data.spheres, &mut changed);
        write_texture(queue, &self.geometry, 0, &old.triangles, &data.triangles, &mut changed);
        let node_base = std::mem::size_of_val(data.triangles.as_slice()) / TEXEL_BYTES;
        write_texture(queue, &self.geometry, node_base, &old.bvh, &data.bvh, &mut changed);
        write_texture(queue, &self.normals, 0, &old.normals, &data.normals, &mut changed);
        write_texture(queue, &self.uvs, 0, &old.uvs, &data.uvs, &mut changed);
        write(queue, &self.meshes, &old.meshes, &data.meshes, &mut changed);
        write_texture(queue, &self.materials, 0, &old.materials, &data.materials, &mut changed);
        write_texture(queue, &self.lights, 0, &old.lights, &data.lights, &mut changed);
        // The clusters after the lights (src/scene/light_clusters.rs).
        let cluster_base = std::mem::size_of_val(data.lights.as_slice()) / TEXEL_BYTES;
        write_texture(queue, &self.lights, cluster_base, &old.light_clusters.texels, &data.light_clusters.texels, &mut changed);
        write_texture(queue, &self.instances, 0, &old.instances, &data.instances, &mut changed);
        changed |= old.background != data.background;
        let flat = flat_uniform(&data);
        if flat != self.flat_bytes {
            queue.write_buffer(&self.flat, 0, &flat);
            self.flat_bytes = flat;
        }
        if changed {
            self.data = data;
        }
        changed
    }

    /// Rebuilds `scene_origins` for this frame's viewpoints (relative to
    /// the rebasing origin, as in the frame uniform) and the scene as it
    /// is now, and writes what changed: a still camera in a still scene
    /// writes nothing.
    pub fn set_origins(&mut self, queue: &wgpu::Queue, view: &Viewpoints) {
        let table = origin_table(&self.data, view, self.cull_occluders);
        self.origins.write_changes(queue, 0, bytemuck::cast_slice(&self.origin_table), bytemuck::cast_slice(&table));
        self.origin_table = table;
        let mut entries = self.camera_entries(view.camera);
        self.set_tiles(queue, view.pixels, &mut entries);
        if entries != self.entries_gpu {
            queue.write_buffer(&self.entries, 0, bytemuck::bytes_of(&entries));
            self.entries_gpu = entries;
        }
    }

    /// The camera's cut of the BLAS of a one-mesh scene that is not flat
    /// (the scenes whose rays start at that BLAS: `ONE_MESH`); none
    /// elsewhere.
    fn camera_entries(&self, camera: Vec3) -> CameraEntriesGpu {
        scene_entries(&self.data, Some(camera))
    }

    /// Rebuilds the tile table for `pixels` where the camera or the scene
    /// changed (a Sponza-sized BLAS takes about 8 ms at 1280x720), and
    /// gives `entries` its tile size and row length (none: size 0).
    fn set_tiles(&mut self, queue: &wgpu::Queue, pixels: Option<PixelCamera>, entries: &mut CameraEntriesGpu) {
        let d = &self.data;
        let Some(pixels) = pixels.filter(|_| self.takes_tiles()) else {
            return;
        };
        let key = Some((pixels, self.epoch));
        if self.tiles_for != key {
            self.tiles_for = key;
            let table = tile_table(&d.bvh, d.instances[0].index, &pixels);
            let (grid, texels) = match table {
                Some(t) => ([t.log2, t.tiles_x], t.texels),
                None => ([0, 0], vec![[0u32; 4]; self.tile_texels.len()]),
            };
            self.tiles.write_changes(queue, 0, bytemuck::cast_slice(&self.tile_texels), bytemuck::cast_slice(&texels));
            self.tile_texels = texels;
            self.tile_grid = grid;
        }
        entries.count[1] = self.tile_grid[0];
        entries.count[2] = self.tile_grid[1];
    }

    /// The tile table for the camera the last frame drew, built again
    /// (what a camera move costs the CPU: `glint bench rays` times it);
    /// None where the scene takes no table or no frame was drawn yet.
    pub fn rebuild_tile_table(&self) -> Option<TileTable> {
        let (pixels, _) = self.tiles_for?;
        if !self.takes_tiles() {
            return None;
        }
        tile_table(&self.data.bvh, self.data.instances[0].index, &pixels)
    }

    /// Whether the scene's camera rays start from a tile table: one mesh,
    /// not flat (the table's texture was made full size only then).
    fn takes_tiles(&self) -> bool {
        self.tile_texels.len() == MAX_TILES * TILE_TEXELS && is_one_mesh(&self.data)
    }

    /// Whether rays test every primitive instead of walking the BVH (the
    /// `FLAT_SCENE` override the executor gives the shaders).
    pub fn is_flat(&self) -> bool {
        self.data.is_flat()
    }

    /// Whether the TLAS holds exactly one instance and it is a mesh (the
    /// `ONE_MESH` override: traversal starts at that mesh's BLAS). Motion
    /// moves instances but never adds or removes one.
    pub fn is_one_mesh(&self) -> bool {
        is_one_mesh(&self.data)
    }
}

/// `scene_entries` for a one-mesh scene that is not flat: the camera's cut
/// (none without a camera) and the BLAS root's packed reference, where
/// its rays start (`count[3]`: one uniform load instead of an instance
/// and a node from the scene textures for every ray). Zero elsewhere.
fn scene_entries(d: &SceneData, camera: Option<Vec3>) -> CameraEntriesGpu {
    if d.is_flat() || !is_one_mesh(d) {
        return CameraEntriesGpu::default();
    }
    let root = d.instances[0].index;
    let cut = camera.and_then(|c| camera_cut(&d.bvh, root, c));
    let mut gpu = camera_entries(&d.bvh, cut.as_deref());
    gpu.count[3] = d.bvh.get(root as usize).map_or(0, |_| entry_texels(&d.bvh, root)[0][3]);
    gpu
}

fn is_one_mesh(data: &SceneData) -> bool {
    matches!(data.instances.as_slice(), [only] if only.kind == crate::bvh::scene::INSTANCE_MESH)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::FLAT_LIMIT;
    use crate::bvh::BvhNode;
    use crate::scene::TriangleGpu;

    #[test]
    fn rows_cover_the_records() {
        let row = SCENE_TEXTURE_WIDTH as usize * TEXEL_BYTES;
        assert_eq!(scene_texture_rows(0), 1, "an empty array still binds one row");
        assert_eq!(scene_texture_rows(16), 1);
        assert_eq!(scene_texture_rows(row), 1);
        assert_eq!(scene_texture_rows(row + 1), 2);
        assert_eq!(scene_texture_rows(3 * row - 16), 3);
        // 1M triangles (48 bytes) and their nodes fit a 16384-row texture.
        assert!(scene_texture_rows(1_000_000 * 48 + 623_540 * 32) <= 16384);
    }

    #[test]
    fn texel_spans_cover_a_range_in_row_order() {
        let w = SCENE_TEXTURE_WIDTH as usize;
        let span = |x, y, width, height| TexelSpan { x, y, width, height };
        assert_eq!(texel_spans(5, 0), vec![]);
        assert_eq!(texel_spans(5, 10), vec![span(5, 0, 10, 1)]);
        assert_eq!(texel_spans(w - 2, 5), vec![span(w - 2, 0, 2, 1), span(0, 1, 3, 1)]);
        assert_eq!(texel_spans(3 * w, 2 * w), vec![span(0, 3, w, 2)]);
        assert_eq!(
            texel_spans(w + 7, 3 * w),
            vec![span(7, 1, w - 7, 1), span(0, 2, w, 2), span(0, 4, 7, 1)],
        );
        // Every texel once, in order.
        for (first, count) in [(0, 1), (1, w), (w - 1, 2 * w + 1), (12345, 54321)] {
            let covered: usize = texel_spans(first, count).iter().map(|s| s.width * s.height).sum();
            assert_eq!(covered, count);
        }
    }

    #[test]
    fn shaders_use_the_same_row_width() {
        let wgsl = include_str!("../../shaders/shared/scene.wgsl");
        let line = wgsl.lines().find(|l| l.starts_with("const SCENE_TEXTURE_WIDTH_LOG2: u32 =")).expect("scene.wgsl declares SCENE_TEXTURE_WIDTH_LOG2");
        let log2: u32 = line.trim_end_matches(';').rsplit('=').next().unwrap().trim().trim_end_matches('u').parse().unwrap();
        assert_eq!(1u32 << log2, SCENE_TEXTURE_WIDTH);
    }

    #[test]
    fn flat_sweep_writes_out_every_slot() {
        let wgsl = include_str!("../../shaders/shared/flat.wgsl");
        assert!(wgsl.contains(&format!("const FLAT_SLOTS: u32 = {FLAT_LIMIT}u;")), "flat.wgsl has FLAT_LIMIT slots of each kind");
        // Four slots a call, by hand (flat_sweep): a flat scene may be all
        // spheres or all triangles.
        for kind in ["flat_spheres4", "flat_triangles4"] {
            for k in (0..FLAT_LIMIT).step_by(4) {
                assert!(wgsl.contains(&format!("    {kind}(r, {k}u, tmax, &best);")), "flat_sweep skips {kind} slot {k}");
            }
        }
    }

    #[test]
    fn one_mesh_means_a_lone_mesh_instance() {
        use crate::bvh::scene::{InstanceGpu, INSTANCE_MESH, INSTANCE_SPHERE};
        let inst = |kind| InstanceGpu { kind, index: 1, _pad: [0; 2] };
        let with = |instances: Vec<InstanceGpu>| SceneData { instances, ..Default::default() };
        assert!(is_one_mesh(&with(vec![inst(INSTANCE_MESH)])));
        assert!(!is_one_mesh(&with(vec![])), "an empty scene has no BLAS to start at");
        assert!(!is_one_mesh(&with(vec![inst(INSTANCE_SPHERE)])));
        assert!(!is_one_mesh(&with(vec![inst(INSTANCE_MESH), inst(INSTANCE_MESH)])));
        assert!(!is_one_mesh(&with(vec![inst(INSTANCE_MESH), inst(INSTANCE_SPHERE)])));
    }

    #[test]
    fn geometry_is_triangles_then_nodes() {
        let tri = |k: f32| TriangleGpu { p0: [k, 0.0, 0.0], material: 7, p1: [0.0, k, 0.0], object: 9, p2: [0.0, 0.0, k], _pad0: 0 };
        let node = BvhNode { bmin: [-1.0; 3], left_first: 5, bmax: [1.0; 3], count: 2 };
        let data = SceneData { triangles: vec![tri(1.0), tri(2.0)], bvh: vec![node], ..Default::default() };
        let bytes = geometry_bytes(&data);
        // Node 0 starts at texel 3 * triangle count (node_texel_base in bvh.wgsl).
        assert_eq!(bytes.len(), 2 * 3 * TEXEL_BYTES + 2 * TEXEL_BYTES);
        let texel = |i: usize| &bytes[i * TEXEL_BYTES..(i + 1) * TEXEL_BYTES];
        assert_eq!(texel(3), &bytemuck::bytes_of(&tri(2.0))[..TEXEL_BYTES]);
        assert_eq!(texel(2 * 3), &bytemuck::bytes_of(&node)[..TEXEL_BYTES]);
        assert_eq!(texel(2 * 3 + 1), &bytemuck::bytes_of(&node)[TEXEL_BYTES..]);
        // Padded to whole rows for the upload.
        assert_eq!(padded_rows(&bytes, 1).len(), SCENE_TEXTURE_WIDTH as usize * TEXEL_BYTES);
    }
}
