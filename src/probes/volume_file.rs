//! A baked irradiance volume on disk (`glint bake --out`, `glint render
//! --volume`): a first line `glint-volume 1`, a RON header line naming the
//! scene (a hash of its geometry, materials and lights as loaded), the
//! probe grid, the bake's settings and the textures that follow, then the
//! textures' texels as little-endian f32 RGBA. A volume whose scene or grid
//! differs from what it is loaded for is refused with what differs, never
//! used silently.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::UserError;

const MAGIC: &str = "glint-volume 1";

/// The header line: what the volume was baked for and what it holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VolumeHeader {
    /// The scene file it was baked for (for messages).
    pub scene: String,
    /// `Scene::content_hash` of that scene as loaded.
    pub scene_hash: u64,
    /// "thesis" or "ddgi".
    pub mode: String,
    /// The grid's probe level L ((L+1)^3 probes).
    pub level: u32,
    /// The grid's padding (share of the extent left free on each side).
    pub padding: f32,
    /// The bake's settings (paths, bounces, samples per axis...), as text.
    pub settings: Vec<(String, String)>,
    /// Graph resources stored, with their sizes (Rgba32Float).
    pub textures: Vec<StoredTexture>,
}

/// One texture of the volume: a graph resource and its size.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StoredTexture {
    /// The graph resource it fills.
    pub resource: String,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
}

/// A header and each texture's texels (RGBA, row by row).
#[derive(Debug, Clone, PartialEq)]
pub struct VolumeFile {
    /// What the volume is.
    pub header: VolumeHeader,
    /// Each texture's texels, in header order.
    pub texels: Vec<Vec<[f32; 4]>>,
}

impl VolumeFile {
    /// The file's bytes; an error where a texture's texel count does not match its size.
    pub fn to_bytes(&self) -> Result<Vec<u8>, String> {
        for (t, data) in self.header.textures.iter().zip(&self.texels) {
            if data.len() != (t.width as usize) * (t.height as usize) {
                return Err(format!("texture `{}` has {} texels, not {}x{}", t.resource, data.len(), t.width, t.height));
            }
        }
        let header = ron::to_string(&self.header).map_err(|e| e.to_string())?;
        let mut out = format!("{MAGIC}\n{header}\n").into_bytes();
        for data in &self.texels {
            out.extend_from_slice(bytemuck::cast_slice(data));
        }
        Ok(out)
    }

    /// Parses a volume file's bytes; an error says what is wrong with them.
    pub fn from_bytes(bytes: &[u8]) -> Result<VolumeFile, String> {
        let first = bytes.iter().position(|&b| b == b'\n').ok_or("not a glint volume (no header line)")?;
        if &bytes[..first] != MAGIC.as_bytes() {
            return Err(format!("not a glint volume: the first line is not `{MAGIC}`"));
        }
        let rest = &bytes[first + 1..];
        let second = rest.iter().position(|&b| b == b'\n').ok_or("the header line is not finished")?;
        let text = std::str::from_utf8(&rest[..second]).map_err(|_| "the header is not UTF-8".to_string())?;
        let header: VolumeHeader = ron::from_str(text).map_err(|e| format!("the header does not parse: {e}"))?;
        let mut payload = &rest[second + 1..];
        let mut texels = Vec::new();
        for t in &header.textures {
            let count = (t.width as usize).checked_mul(t.height as usize).ok_or("texture size overflows")?;
            let bytes = count.checked_mul(16).ok_or("texture size overflows")?;
            if payload.len() < bytes {
                return Err(format!("texture `{}` ({}x{}) is cut short: {} of {bytes} bytes", t.resource, t.width, t.height, payload.len()));
            }
            let data: Vec<[f32; 4]> = payload[..bytes].chunks_exact(16).map(|c| std::array::from_fn(|i| f32::from_le_bytes([c[4 * i], c[4 * i + 1], c[4 * i + 2], c[4 * i + 3]]))).collect();
            texels.push(data);
            payload = &payload[bytes..];
        }
        if !payload.is_empty() {
            return Err(format!("{} bytes follow the last texture", payload.len()));
        }
        Ok(VolumeFile { header, texels })
    }

    /// Writes the volume to `path`.
    pub fn save(&self, path: &Path) -> Result<(), UserError> {
        let bytes = self.to_bytes().map_err(|e| UserError::in_file(path, e))?;
        std::fs::write(path, bytes).map_err(|e| UserError::in_file(path, format!("cannot write the volume: {e}")))
    }

    /// Reads a volume from `path` (without checking it fits: see `VolumeHeader::mismatch`).
    pub fn load(path: &Path) -> Result<VolumeFile, UserError> {
        let bytes = crate::error::read_user_file(path, "volume")?;
        Self::from_bytes(&bytes).map_err(|e| UserError::in_file(path, e))
    }
}

impl VolumeHeader {
    /// Why this volume does not fit `expected` (the scene and grid it is
    /// loaded for), or None when it does. Settings are not compared: a
    /// volume baked with more paths is the same volume, better.
    pub fn mismatch(&self, expected: &VolumeHeader) -> Option<String> {
        if self.scene_hash != expected.scene_hash {
            return Some(format!(
                "it was baked for {} (scene hash {:016x}), but {} hashes {:016x}: its geometry, materials or lights changed; bake it again",
                self.scene, self.scene_hash, expected.scene, expected.scene_hash
            ));
        }
        if self.mode != expected.mode || self.level != expected.level || self.padding != expected.padding {
            return Some(format!(
                "it is a {} volume at level {} (padding {}), but the graph wants {} at level {} (padding {})",
                self.mode, self.level, self.padding, expected.mode, expected.level, expected.padding
            ));
        }
        for t in &expected.textures {
            match self.textures.iter().find(|s| s.resource == t.resource) {
                None => return Some(format!("it has no `{}`", t.resource)),
                Some(s) if (s.width, s.height) != (t.width, t.height) => {
                    return Some(format!("its `{}` is {}x{}, the graph's is {}x{}", t.resource, s.width, s.height, t.width, t.height));
                }
                _ => {}
            }
        }
        None
    }
}

/// FNV-1a over bytes: a stable hash (std's is not promised to be).
pub fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}

/// FNV-1a's offset basis: the `h` to start `fnv1a` with.
pub const FNV_START: u64 = 0xcbf29ce484222325;

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> VolumeFile {
        VolumeFile {
            header: VolumeHeader {
                scene: "scenes/cornell.ron".into(),
                scene_hash: 0x1234_5678_9abc_def0,
                mode: "thesis".into(),
                level: 1,
                padding: 0.1,
                settings: vec![("paths".into(), "16".into())],
                textures: vec![StoredTexture { resource: "thesis_irradiance".into(), width: 2, height: 1 }],
            },
            texels: vec![vec![[1.0, 2.0, 3.0, 4.0], [f32::MAX, -0.0, 1e-30, 0.5]]],
        }
    }

    #[test]
    fn a_volume_round_trips_bit_for_bit() {
        let v = sample();
        let back = VolumeFile::from_bytes(&v.to_bytes().unwrap()).unwrap();
        assert_eq!(back.header, v.header);
        let bits = |t: &Vec<Vec<[f32; 4]>>| t.iter().flatten().flatten().map(|f| f.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back.texels), bits(&v.texels));
    }

    #[test]
    fn broken_files_say_what_is_wrong() {
        let good = sample().to_bytes().unwrap();
        assert!(VolumeFile::from_bytes(b"PNG\n").unwrap_err().contains("not a glint volume"));
        assert!(VolumeFile::from_bytes(&good[..good.len() - 4]).unwrap_err().contains("cut short"));
        let mut long = good.clone();
        long.extend_from_slice(&[0; 8]);
        assert!(VolumeFile::from_bytes(&long).unwrap_err().contains("8 bytes follow"));
        let mut bad = sample();
        bad.texels[0].pop();
        assert!(bad.to_bytes().unwrap_err().contains("has 1 texels"));
    }

    #[test]
    fn a_stale_volume_is_refused_with_the_reason() {
        let v = sample().header;
        assert_eq!(v.mismatch(&v), None);
        let mut other = v.clone();
        other.scene_hash ^= 1;
        assert!(v.mismatch(&other).unwrap().contains("geometry, materials or lights changed"));
        let mut other = v.clone();
        other.level = 2;
        assert!(v.mismatch(&other).unwrap().contains("level 1"));
        let mut other = v.clone();
        other.textures[0].width = 4;
        assert!(v.mismatch(&other).unwrap().contains("is 2x1, the graph's is 4x1"));
        // More paths is the same volume.
        let mut other = v.clone();
        other.settings[0].1 = "1024".into();
        assert_eq!(v.mismatch(&other), None);
    }
}
