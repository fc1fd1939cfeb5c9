//! A session's irradiance volume: whether its bake is still running, and
//! saving it to or loading it from a file (`probes::volume_file`). The
//! volume is every persistent resource of the graph; a loaded one counts
//! as baked for the scene as it is, so its passes run again only when the
//! scene changes.

use std::path::Path;

use crate::error::UserError;
use crate::format::TexFormat;
use crate::graph::desc::ProbeMode;
use crate::probes::volume_file::{StoredTexture, VolumeFile, VolumeHeader};
use crate::session::Session;

impl Session {
    /// Whether a pass that builds persistent resources (a bake) will run in
    /// the next frame.
    pub fn baking(&self) -> bool {
        self.executor.updates_persistent(self.scene.buffers.epoch)
    }

    /// The header a volume of this session has: its scene (by `scene_hash`,
    /// `Scene::content_hash` of the scene as loaded), probe grid and
    /// persistent textures.
    pub fn volume_header(&self, scene_name: &str, scene_hash: u64, settings: Vec<(String, String)>) -> Result<VolumeHeader, UserError> {
        let Some(probes) = self.executor.schedule.probes else {
            return Err(UserError::new(format!("graph `{}` has no probe grid (`probes:`), so no volume", self.executor.schedule.name)));
        };
        let textures: Vec<StoredTexture> = self
            .executor
            .persistent_resources()
            .into_iter()
            .filter(|(_, format, _)| *format == TexFormat::Rgba32Float)
            .map(|(resource, _, (width, height))| StoredTexture { resource, width, height })
            .collect();
        if textures.is_empty() {
            return Err(UserError::new(format!("graph `{}` keeps no volume textures (persistent Rgba32Float resources)", self.executor.schedule.name)));
        }
        Ok(VolumeHeader {
            scene: scene_name.to_string(),
            scene_hash,
            mode: match probes.mode {
                ProbeMode::Thesis => "thesis",
                ProbeMode::Ddgi => "ddgi",
            }
            .to_string(),
            level: probes.level,
            padding: probes.padding,
            settings,
            textures,
        })
    }

    /// Writes the volume (after the frames that baked it).
    pub fn save_volume(&self, path: &Path, header: VolumeHeader) -> Result<(), UserError> {
        let mut texels = Vec::new();
        for t in &header.textures {
            let image = self
                .executor
                .read_persistent(&self.gpu, &t.resource)
                .ok_or_else(|| UserError::new(format!("`{}` is not a persistent resource", t.resource)))??;
            texels.push(image.data);
        }
        VolumeFile { header, texels }.save(path)
    }

    /// Loads a volume into this session's persistent resources, refusing
    /// one baked for another scene or grid (`expected`, from
    /// `volume_header`), and marks the bake done for the scene as it is.
    pub fn load_volume(&mut self, path: &Path, expected: &VolumeHeader) -> Result<(), UserError> {
        let file = VolumeFile::load(path)?;
        if let Some(why) = file.header.mismatch(expected) {
            return Err(UserError::in_file(path, format!("this volume does not fit: {why}")));
        }
        for t in &expected.textures {
            let i = file.header.textures.iter().position(|s| s.resource == t.resource).unwrap_or(usize::MAX);
            let data = file.texels.get(i).ok_or_else(|| UserError::in_file(path, format!("no texels for `{}`", t.resource)))?;
            self.executor.write_persistent(&self.gpu, &t.resource, data)?;
        }
        self.executor.finish_runs(self.scene.buffers.epoch);
        Ok(())
    }
}
