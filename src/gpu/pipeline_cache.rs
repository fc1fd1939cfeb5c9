//! Compiled pipelines kept across runs: wgpu's `PipelineCache` (Vulkan
//! adapters), loaded from and saved to a file per adapter, so a driver
//! that fills it compiles a pipeline it has compiled before from the
//! cache instead of from its SPIR-V. Where the adapter has none, or the
//! cache is turned off, glint builds pipelines as it did (lavapipe fills
//! it with nothing: Mesa's own disk cache keeps its machine code instead;
//! docs/viewer.md, "Screenshots and reload latency").
//!
//! `GLINT_PIPELINE_CACHE` chooses the folder: unset, `$XDG_CACHE_HOME/glint`
//! or `~/.cache/glint`; `off`, no cache.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The folder the cache files live in, from the environment (`var` reads
/// a variable): None when turned off or when no folder can be named.
pub fn cache_dir(var: impl Fn(&str) -> Option<String>) -> Option<PathBuf> {
    let non_empty = |name: &str| var(name).filter(|v| !v.trim().is_empty());
    match non_empty("GLINT_PIPELINE_CACHE") {
        Some(v) if v.trim().eq_ignore_ascii_case("off") => None,
        Some(v) => Some(PathBuf::from(v)),
        None => non_empty("XDG_CACHE_HOME").map(|d| PathBuf::from(d).join("glint")).or_else(|| non_empty("HOME").map(|h| PathBuf::from(h).join(".cache").join("glint"))),
    }
}

/// A device's pipeline cache and the file it is kept in.
pub struct DiskPipelineCache {
    cache: wgpu::PipelineCache,
    file: PathBuf,
    /// The length of the data last written (or read): a save with nothing
    /// new writes nothing.
    saved: Mutex<usize>,
}

impl DiskPipelineCache {
    /// The cache of `device` in `dir`, with what an earlier run saved there
    /// for this adapter; None where the device has no pipeline cache
    /// (`wgpu::Features::PIPELINE_CACHE` off, or a backend wgpu keeps none
    /// for).
    pub fn open(device: &wgpu::Device, info: &wgpu::AdapterInfo, dir: &Path) -> Option<DiskPipelineCache> {
        if !device.features().contains(wgpu::Features::PIPELINE_CACHE) {
            return None;
        }
        let file = dir.join(wgpu::util::pipeline_cache_key(info)?);
        let data = std::fs::read(&file).ok();
        // SAFETY: the data is what `get_data` returned in an earlier run,
        // written whole (a temporary file renamed over the old one); wgpu
        // and the driver check its header against this adapter and driver,
        // and with `fallback` a cache that fails the check starts empty.
        let cache = unsafe {
            device.create_pipeline_cache(&wgpu::PipelineCacheDescriptor { label: Some("glint pipelines"), data: data.as_deref(), fallback: true })
        };
        Some(DiskPipelineCache { cache, saved: Mutex::new(data.map_or(0, |d| d.len())), file })
    }

    /// The wgpu cache, for pipeline descriptors.
    pub fn cache(&self) -> &wgpu::PipelineCache {
        &self.cache
    }

    /// The file the cache is kept in.
    pub fn file(&self) -> &Path {
        &self.file
    }

    /// Writes the cache's data to its file if it grew since the last save.
    /// A cache is an optimisation: a failure to write is reported, not an
    /// error.
    pub fn save(&self) {
        let Some(data) = self.cache.get_data() else { return };
        let Ok(mut saved) = self.saved.lock() else { return };
        if data.len() == *saved {
            return;
        }
        match write_whole(&self.file, &data) {
            Ok(()) => *saved = data.len(),
            Err(e) => eprintln!("glint: could not save the pipeline cache to {}: {e} (GLINT_PIPELINE_CACHE=off turns it off)", self.file.display()),
        }
    }
}

/// `data` to `file` through a temporary file renamed over it, so a reader
/// never sees half of it.
fn write_whole(file: &Path, data: &[u8]) -> std::io::Result<()> {
    if let Some(dir) = file.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let temp = file.with_extension(format!("{}.tmp", std::process::id()));
    std::fs::write(&temp, data)?;
    std::fs::rename(&temp, file)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vars<'a>(pairs: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| pairs.iter().find(|(k, _)| *k == name).map(|(_, v)| v.to_string())
    }

    #[test]
    fn the_folder_follows_the_environment() {
        assert_eq!(cache_dir(vars(&[("GLINT_PIPELINE_CACHE", "/tmp/x"), ("HOME", "/home/u")])), Some(PathBuf::from("/tmp/x")));
        assert_eq!(cache_dir(vars(&[("GLINT_PIPELINE_CACHE", "off"), ("HOME", "/home/u")])), None);
        assert_eq!(cache_dir(vars(&[("GLINT_PIPELINE_CACHE", " OFF ")])), None);
        assert_eq!(cache_dir(vars(&[("XDG_CACHE_HOME", "/c"), ("HOME", "/home/u")])), Some(PathBuf::from("/c/glint")));
        assert_eq!(cache_dir(vars(&[("XDG_CACHE_HOME", ""), ("HOME", "/home/u")])), Some(PathBuf::from("/home/u/.cache/glint")));
        assert_eq!(cache_dir(vars(&[("GLINT_PIPELINE_CACHE", "")])), None);
    }

    #[test]
    fn a_save_replaces_the_file_whole() {
        let dir = std::env::temp_dir().join(format!("glint-pipeline-cache-{}", std::process::id()));
        let file = dir.join("cache");
        write_whole(&file, b"first").unwrap_or_else(|e| panic!("{e}"));
        write_whole(&file, b"second").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(std::fs::read(&file).unwrap_or_default(), b"second");
        let left: Vec<_> = std::fs::read_dir(&dir).map(|d| d.filter_map(|e| e.ok()).map(|e| e.file_name()).collect()).unwrap_or_default();
        assert_eq!(left.len(), 1, "temporary files left: {left:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
