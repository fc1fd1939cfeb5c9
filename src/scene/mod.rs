//! The scene: RON schema, hecs world and components, OBJ loading, scene
//! features, and packing into GPU arrays (docs/scenes.md).
//!
//! `load`/`parse` turn a scene file into a [`Scene`]: an hecs world with one
//! entity per object and light, a local-space mesh store and the material
//! table. [`Scene::animate`] moves the `Motion` entities to a time, and
//! [`Scene::pack`] flattens everything into [`SceneData`] for upload.
//!
//! Material ids: the scene's named materials in file order, then the MTL
//! materials of each OBJ (in the order meshes are first met; none for a mesh
//! with a `material:` override), a default white (0.8) the first time a face
//! has no material, then one emissive material per sphere light.

pub mod buffers;
pub mod environment;
pub mod features;
pub mod flat_uniform;
pub mod gpu_types;
pub mod light_clusters;
mod gltf_file;
mod gltf_scene;
mod load;
mod load_gltf;
mod locate;
mod more_lights;
mod obj;
mod obj_scene;
pub mod origins;
mod pack;
mod schema;
pub mod specialise;
pub mod texture_arrays;
pub mod texture_classes;
mod validate;
mod world;

#[cfg(test)]
mod tests;

pub use features::{Feature, SceneFeatures};
pub use gpu_types::*;
pub use load::{load, opens, parse, SCENE_EXTENSIONS};
pub(crate) use load::parse_with;
pub use world::{
    animate, BasePosition, Camera, Light, LightIndex, LocalTriangle, MaterialId, MaterialTextures, MeshData, MeshShape,
    Motion, ObjectId, Scene, SphereShape, SpotCone, TextureImage, TextureSlot, Transform,
};
