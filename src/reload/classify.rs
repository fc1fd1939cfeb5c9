//! Which rebuild a changed file calls for (pure: unit-tested without a
//! file system or a GPU).
//!
//! - a `.wgsl` file under the shader folder: the shaders whose import
//!   closure holds it (the session finds them);
//! - the running graph file: a graph reload;
//! - the scene file, one of its OBJ meshes, or an `.mtl` beside one of
//!   them: a scene reload;
//! - anything else: nothing.

use std::path::{Path, PathBuf};

use crate::session::rebuild::RebuildKind;
pub use crate::session::Sources;

/// The folders to watch, recursively and without duplicates: editors that
/// save by renaming a temporary file over the old one replace the file, so
/// its folder is watched, not the file.
pub fn watch_dirs(s: &Sources) -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = vec![s.shader_dir.clone()];
    let parent = |p: &Path| p.parent().map(Path::to_path_buf);
    dirs.extend(parent(&s.graph));
    dirs.extend(s.scene.as_deref().and_then(parent));
    dirs.extend(s.meshes.iter().filter_map(|m| parent(m)));
    dirs.sort();
    dirs.dedup();
    // A folder inside another watched one adds nothing.
    let all = dirs.clone();
    dirs.retain(|d| !all.iter().any(|o| o != d && d.starts_with(o)));
    dirs
}

/// The rebuilds for a batch of changed files, in the order scene, graph,
/// shaders (a scene or graph rebuild recompiles with the current shaders,
/// so it goes first; shader changes are gathered into one rebuild).
pub fn classify(s: &Sources, changed: &[PathBuf]) -> Vec<RebuildKind> {
    let mut scene = false;
    let mut graph = false;
    let mut shaders = Vec::new();
    for path in changed {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        let scene_file = s.scene.as_deref() == Some(path.as_path()) || s.meshes.iter().any(|m| m == path);
        let material_file = ext.as_deref() == Some("mtl") && s.meshes.iter().any(|m| m.parent() == path.parent());
        if scene_file || material_file {
            scene = true;
        } else if path == &s.graph {
            graph = true;
        } else if ext.as_deref() == Some("wgsl") && path.starts_with(&s.shader_dir) && !shaders.contains(path) {
            shaders.push(path.clone());
        }
    }
    let mut kinds = Vec::new();
    if let (true, Some(p)) = (scene, &s.scene) {
        kinds.push(RebuildKind::Scene(p.clone()));
    }
    if graph {
        kinds.push(RebuildKind::Graph(s.graph.clone()));
    }
    if !shaders.is_empty() {
        kinds.push(RebuildKind::Shaders(shaders));
    }
    kinds
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sources() -> Sources {
        Sources {
            shader_dir: "/p/shaders".into(),
            graph: "/p/passes/hybrid.ron".into(),
            scene: Some("/p/scenes/a.ron".into()),
            meshes: vec!["/p/scenes/meshes/knot.obj".into()],
        }
    }

    fn paths(list: &[&str]) -> Vec<PathBuf> {
        list.iter().map(PathBuf::from).collect()
    }

    #[test]
    fn files_map_to_rebuilds() {
        let s = sources();
        assert_eq!(classify(&s, &paths(&["/p/shaders/lights.wgsl"])), vec![RebuildKind::Shaders(paths(&["/p/shaders/lights.wgsl"]))]);
        assert_eq!(
            classify(&s, &paths(&["/p/shaders/shared/rng.wgsl", "/p/shaders/shared/rng.wgsl"])),
            vec![RebuildKind::Shaders(paths(&["/p/shaders/shared/rng.wgsl"]))]
        );
        assert_eq!(classify(&s, &paths(&["/p/passes/hybrid.ron"])), vec![RebuildKind::Graph("/p/passes/hybrid.ron".into())]);
        assert_eq!(classify(&s, &paths(&["/p/scenes/a.ron"])), vec![RebuildKind::Scene("/p/scenes/a.ron".into())]);
        assert_eq!(classify(&s, &paths(&["/p/scenes/meshes/knot.obj"])), vec![RebuildKind::Scene("/p/scenes/a.ron".into())]);
        assert_eq!(classify(&s, &paths(&["/p/scenes/meshes/knot.mtl"])), vec![RebuildKind::Scene("/p/scenes/a.ron".into())]);
        // Other graphs, scenes, meshes and files are not the session's.
        for other in ["/p/passes/direct.ron", "/p/scenes/b.ron", "/p/scenes/other/x.obj", "/p/shaders/notes.txt", "/p/scenes/x.mtl", "/q/shaders/a.wgsl"] {
            assert!(classify(&s, &paths(&[other])).is_empty(), "{other}");
        }
    }

    #[test]
    fn a_batch_orders_scene_graph_shaders() {
        let s = sources();
        let kinds = classify(&s, &paths(&["/p/shaders/a.wgsl", "/p/passes/hybrid.ron", "/p/scenes/a.ron", "/p/shaders/b.wgsl"]));
        assert_eq!(
            kinds,
            vec![
                RebuildKind::Scene("/p/scenes/a.ron".into()),
                RebuildKind::Graph("/p/passes/hybrid.ron".into()),
                RebuildKind::Shaders(paths(&["/p/shaders/a.wgsl", "/p/shaders/b.wgsl"])),
            ]
        );
    }

    #[test]
    fn nested_folders_are_watched_once() {
        let mut s = sources();
        s.shader_dir = "/p/shaders".into();
        s.meshes.push("/elsewhere/m.obj".into());
        assert_eq!(watch_dirs(&s), paths(&["/elsewhere", "/p/passes", "/p/scenes", "/p/shaders"]));
    }
}
