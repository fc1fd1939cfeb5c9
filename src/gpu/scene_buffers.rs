//! The scene on the GPU: one storage buffer per array of `SceneData`.
//! `update` writes only the arrays that changed and bumps `epoch` when it
//! does, so accumulation can reset.

use bytemuck::Pod;
use wgpu::util::DeviceExt;

use crate::graph::EngineResource;
use crate::scene::SceneData;

pub struct SceneBuffers {
    pub spheres: wgpu::Buffer,
    pub triangles: wgpu::Buffer,
    pub normals: wgpu::Buffer,
    pub meshes: wgpu::Buffer,
    pub materials: wgpu::Buffer,
    pub lights: wgpu::Buffer,
    pub bvh: wgpu::Buffer,
    pub instances: wgpu::Buffer,
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
    pub fn new(device: &wgpu::Device, data: SceneData) -> SceneBuffers {
        SceneBuffers {
            spheres: storage(device, "scene_spheres", &data.spheres),
            triangles: storage(device, "scene_triangles", &data.triangles),
            normals: storage(device, "scene_normals", &data.normals),
            meshes: storage(device, "scene_meshes", &data.meshes),
            materials: storage(device, "scene_materials", &data.materials),
            lights: storage(device, "scene_lights", &data.lights),
            bvh: storage(device, "scene_bvh", &data.bvh),
            instances: storage(device, "scene_instances", &data.instances),
            data,
            epoch: 0,
        }
    }

    /// Uploads what differs from the last upload. The array lengths of one
    /// scene never change (animation moves things, it does not add them).
    pub fn update(&mut self, queue: &wgpu::Queue, data: SceneData) -> bool {
        let mut changed = false;
        fn write<T: Pod + PartialEq>(queue: &wgpu::Queue, buf: &wgpu::Buffer, old: &[T], new: &[T], changed: &mut bool) {
            if old != new && old.len() == new.len() && !new.is_empty() {
                queue.write_buffer(buf, 0, bytemuck::cast_slice(new));
                *changed = true;
            }
        }
        write(queue, &self.spheres, &self.data.spheres, &data.spheres, &mut changed);
        write(queue, &self.triangles, &self.data.triangles, &data.triangles, &mut changed);
        write(queue, &self.normals, &self.data.normals, &data.normals, &mut changed);
        write(queue, &self.meshes, &self.data.meshes, &data.meshes, &mut changed);
        write(queue, &self.materials, &self.data.materials, &data.materials, &mut changed);
        write(queue, &self.lights, &self.data.lights, &data.lights, &mut changed);
        write(queue, &self.bvh, &self.data.bvh, &data.bvh, &mut changed);
        write(queue, &self.instances, &self.data.instances, &data.instances, &mut changed);
        changed |= self.data.background != data.background;
        if changed {
            self.epoch = self.epoch.wrapping_add(1);
            self.data = data;
        }
        changed
    }

    pub fn buffer(&self, e: EngineResource) -> Option<&wgpu::Buffer> {
        match e {
            EngineResource::Frame => None,
            EngineResource::Spheres => Some(&self.spheres),
            EngineResource::Triangles => Some(&self.triangles),
            EngineResource::Normals => Some(&self.normals),
            EngineResource::Meshes => Some(&self.meshes),
            EngineResource::Materials => Some(&self.materials),
            EngineResource::Lights => Some(&self.lights),
            EngineResource::Bvh => Some(&self.bvh),
            EngineResource::Instances => Some(&self.instances),
        }
    }
}
