//! Step 1: names, formats, access, params and constants.

use std::collections::{BTreeMap, BTreeSet};

use super::{err, err_at, names, Bound, CompileError, ErrorKind, PassPlan};
use crate::graph::desc::{FrameGraph, PassDesc, ResourceDesc, RunMode, SizeDesc, TextureDesc, MAX_TEXELS_PER_INVOCATION};
use crate::graph::params::{ParamError, PassParams};
use crate::graph::schedule::{EngineKind, EngineResource, TILE_POOL, WORK_LIST, WORK_LIST_GROUP};
use crate::format::TexFormat;
use crate::shader::{BindingInfo, BindingKind, EntryInfo, SampleType, ScalarType, ShaderInfo, StorageAccess};

pub(super) fn validate<'a>(
    desc: &'a FrameGraph,
    shaders: &'a BTreeMap<String, ShaderInfo>,
) -> Result<Vec<PassPlan<'a>>, CompileError> {
    let mut seen = BTreeSet::new();
    let mut plans = Vec::new();
    for pass in &desc.passes {
        let name = pass.name.as_str();
        if !seen.insert(name) {
            return Err(err(ErrorKind::DuplicatePass, Some(name), "two passes have this name; names must be unique"));
        }
        let shader = shaders.get(&pass.shader).ok_or_else(|| {
            if crate::shader::source::is_inside(&pass.shader) {
                err(ErrorKind::UnknownShader, Some(name), format!("shader `{}` not found in shaders/", pass.shader))
            } else {
                err(ErrorKind::UnknownShader, Some(name), format!("shader `{}` is outside the shader folder: name a shader by its path inside it (no absolute paths, no `..`)", pass.shader))
            }
        })?;
        let listed = pick_listed(pass, shader)?;
        let entry = pick_entry(pass, shader)?;
        // Both entries share one layout: the bindings of either.
        let mut used: Vec<&BindingInfo> = entry.bindings.iter().collect();
        for b in listed.iter().flat_map(|l| &l.bindings) {
            if !used.iter().any(|u| (u.group, u.binding) == (b.group, b.binding)) {
                used.push(b);
            }
        }
        for var in pass.bind.keys() {
            if !used.iter().any(|b| &b.name == var) {
                return Err(err(
                    ErrorKind::UnknownBinding,
                    Some(name),
                    format!(
                        "`bind` maps `{var}`, but entry point `{}` of {} uses no binding of that name; it uses: {}",
                        entry.name,
                        shader.name,
                        names(used.iter().map(|b| &b.name))
                    ),
                ));
            }
        }
        let mut bindings = Vec::new();
        for b in used {
            let target = pass.bind.get(&b.name).unwrap_or(&b.name);
            bindings.push((b, bind_one(desc, name, b, target)?));
        }
        check_work_list(pass, entry, &bindings)?;
        check_texels_per_invocation(pass)?;
        check_tile_pool(desc, pass, &bindings)?;
        check_pass_writes(name, &bindings)?;
        check_run(desc, pass, &bindings)?;
        // An entry point that does not use `params` (another entry of the
        // shader may) takes none.
        let params = if shader.params.is_none() || bindings.iter().any(|(b, _)| b.name == "params") {
            pack_params(pass, shader)?
        } else if let Some(k) = pass.params.keys().next() {
            return Err(err(ErrorKind::UnknownParam, Some(name), format!("param `{k}` given, but entry point `{}` of {} uses no `params`", entry.name, shader.name)));
        } else {
            None
        };
        let constants = check_constants(pass, shader, &desc.constants)?;
        plans.push(PassPlan { desc: pass, entry, listed, bindings, params, constants });
    }
    check_thinned_readers(desc, &plans)?;
    check_graph_constants(desc, shaders)?;
    Ok(plans)
}

/// Every graph-wide constant is declared by some pass's shader (else it
/// is a misspelling, which would otherwise change nothing).
fn check_graph_constants(desc: &FrameGraph, shaders: &BTreeMap<String, ShaderInfo>) -> Result<(), CompileError> {
    let declared = |k: &str| desc.passes.iter().filter_map(|p| shaders.get(&p.shader)).any(|s| s.overrides.iter().any(|o| o.name == k));
    if let Some(k) = desc.constants.keys().find(|k| !declared(k)) {
        return Err(err(ErrorKind::UnknownConstant, None, format!("graph constant `{k}`: no pass's shader declares `override {k}`")));
    }
    Ok(())
}

fn pick_entry<'a>(pass: &PassDesc, shader: &'a ShaderInfo) -> Result<&'a EntryInfo, CompileError> {
    // The `listed` entry is not a candidate for the pass's own.
    let candidates: Vec<&EntryInfo> = shader.entry_points.iter().filter(|ep| Some(&ep.name) != pass.listed.as_ref()).collect();
    let found = match &pass.entry {
        Some(e) => candidates.iter().copied().find(|ep| &ep.name == e),
        None if candidates.len() == 1 => candidates.first().copied(),
        None => None,
    };
    found.ok_or_else(|| {
        err(
            ErrorKind::UnknownEntry,
            Some(&pass.name),
            format!(
                "{} has compute entry points [{}]; {}",
                shader.name,
                names(shader.entry_points.iter().map(|e| &e.name)),
                match &pass.entry {
                    Some(e) => format!("`{e}` is not one of them"),
                    None => "name one with `entry:`".to_string(),
                }
            ),
        )
    })
}

/// The `listed` entry: another compute entry of the shader, with the work
/// list's workgroup size.
fn pick_listed<'a>(pass: &PassDesc, shader: &'a ShaderInfo) -> Result<Option<&'a EntryInfo>, CompileError> {
    let Some(name) = &pass.listed else { return Ok(None) };
    let found = shader.entry_points.iter().find(|ep| &ep.name == name);
    let Some(listed) = found.filter(|_| pass.entry.as_ref() != Some(name)) else {
        return Err(err(
            ErrorKind::UnknownEntry,
            Some(&pass.name),
            format!(
                "`listed: \"{name}\"` must name another compute entry point of {} than the pass's own; it has [{}]",
                shader.name,
                names(shader.entry_points.iter().map(|e| &e.name)),
            ),
        ));
    };
    if listed.workgroup_size != [WORK_LIST_GROUP, 1, 1] {
        let [x, y, z] = listed.workgroup_size;
        return Err(err(
            ErrorKind::UnknownEntry,
            Some(&pass.name),
            format!("listed entry `{name}` has @workgroup_size({x}, {y}, {z}); an entry run over a work list takes @workgroup_size({WORK_LIST_GROUP}) (its indirect dispatch counts groups of {WORK_LIST_GROUP})"),
        ));
    }
    Ok(Some(listed))
}

/// A work list needs both halves: the pass's entry fills it, a `listed`
/// entry runs over it.
/// `texels_per_invocation` within 1..=MAX_TEXELS_PER_INVOCATION, and not on
/// a pass with a work list (whose list holds one entry per invocation).
fn check_texels_per_invocation(pass: &PassDesc) -> Result<(), CompileError> {
    let Some(n) = pass.texels_per_invocation else {
        return Ok(());
    };
    if !(1..=MAX_TEXELS_PER_INVOCATION).contains(&n) {
        return Err(err(ErrorKind::BadSize, Some(&pass.name), format!("`texels_per_invocation` is {n}; give 1 to {MAX_TEXELS_PER_INVOCATION}")));
    }
    if n > 1 && pass.listed.is_some() {
        return Err(err(ErrorKind::BadSize, Some(&pass.name), "`texels_per_invocation` above 1 and `listed` do not go together: a work list has one entry per texel"));
    }
    Ok(())
}

/// A pass that takes its texels from a tile pool covers the render size
/// (the pool hands out the texels of `frame.size`, src/graph/tile_pool.rs
/// sizes its dispatch), one texel a step: no other dispatch size, no
/// texture of another size written, no `texels_per_invocation`.
fn check_tile_pool(desc: &FrameGraph, pass: &PassDesc, bindings: &[(&BindingInfo, Bound)]) -> Result<(), CompileError> {
    if !bindings.iter().any(|(_, b)| *b == Bound::TilePool) {
        return Ok(());
    }
    let refuse = |what: String| Err(err(ErrorKind::BadSize, Some(&pass.name), format!("{what}, but the shader takes its texels from `{TILE_POOL}`, which covers the render size one texel at a time")));
    if pass.texels_per_invocation.is_some_and(|n| n > 1) {
        return refuse("`texels_per_invocation` is above 1".into());
    }
    if let Some(d) = pass.dispatch.filter(|d| *d != SizeDesc::Screen) {
        return refuse(format!("`dispatch` is {d:?}"));
    }
    for (_, b) in bindings {
        let Bound::Write { resource, .. } = b else { continue };
        if let Some(ResourceDesc::Texture(TextureDesc { size, .. })) = desc.resources.get(resource) {
            if *size != SizeDesc::Screen {
                return refuse(format!("it writes `{resource}`, of size {size:?}"));
            }
        }
    }
    Ok(())
}

fn check_work_list(pass: &PassDesc, entry: &EntryInfo, bindings: &[(&BindingInfo, Bound)]) -> Result<(), CompileError> {
    let declared = bindings.iter().any(|(_, b)| *b == Bound::WorkList);
    let filled = entry.bindings.iter().any(|b| b.name == WORK_LIST);
    let pooled = bindings.iter().any(|(_, b)| *b == Bound::TilePool);
    match &pass.listed {
        Some(_) if pooled => Err(err(
            ErrorKind::WrongAccess,
            Some(&pass.name),
            format!("the shader takes its texels from `{TILE_POOL}`, and a pass with a `listed:` entry takes them from its work list: give it one or the other"),
        )),
        None if declared => Err(err(
            ErrorKind::WrongAccess,
            Some(&pass.name),
            format!("the shader uses `{WORK_LIST}`, but the pass has no `listed:` entry to run over it"),
        )),
        Some(l) if !filled => Err(err(
            ErrorKind::WrongAccess,
            Some(&pass.name),
            format!("`listed: \"{l}\"` runs over the texels entry `{}` pushes to `{WORK_LIST}`, but that entry does not use `{WORK_LIST}` (shared/work_list.wgsl)", entry.name),
        )),
        _ => Ok(()),
    }
}

fn bind_one(desc: &FrameGraph, pass: &str, b: &BindingInfo, target: &str) -> Result<Bound, CompileError> {
    if b.name == WORK_LIST && target == WORK_LIST {
        return match b.kind {
            BindingKind::Storage { read_only: false } => Ok(Bound::WorkList),
            _ => Err(err_at(ErrorKind::WrongAccess, pass, b, "`work_list` must be a var<storage, read_write> WorkList (shared/work_list.wgsl)")),
        };
    }
    if b.name == TILE_POOL && target == TILE_POOL {
        return match b.kind {
            BindingKind::Storage { read_only: false } => Ok(Bound::TilePool),
            _ => Err(err_at(ErrorKind::WrongAccess, pass, b, "`tile_pool` must be a var<storage, read_write> atomic<u32> (shared/tile_pool.wgsl)")),
        };
    }
    if b.name == "params" && target == "params" {
        return match b.kind {
            BindingKind::Uniform { .. } => Ok(Bound::Params),
            _ => Err(err_at(ErrorKind::WrongAccess, pass, b, "`params` must be a var<uniform> struct")),
        };
    }
    if b.name == "run" && target == "run" {
        return match b.kind {
            BindingKind::Uniform { .. } => Ok(Bound::Run),
            _ => Err(err_at(ErrorKind::WrongAccess, pass, b, "`run` must be a var<uniform> Run (shared/run.wgsl)")),
        };
    }
    if let Some(e) = EngineResource::from_name(target) {
        let ok = match &b.kind {
            BindingKind::Uniform { .. } => e.kind() == EngineKind::Uniform,
            BindingKind::Storage { read_only } => e.kind() == EngineKind::Storage && *read_only,
            BindingKind::StorageTexture { format, access } => e.kind() == EngineKind::Texture && *format == TexFormat::Rgba32Uint && *access == StorageAccess::Read,
            BindingKind::SampledTextureArray => e.kind() == EngineKind::TextureArray,
            BindingKind::Sampler => e.kind() == EngineKind::Sampler,
            _ => false,
        };
        if !ok {
            let want = e.kind().wgsl();
            return Err(err_at(
                ErrorKind::WrongAccess,
                pass,
                b,
                format!("`{}` binds engine resource `{target}`, which is a {want}, but the shader declares {}", b.name, b.kind.describe()),
            ));
        }
        return Ok(Bound::Engine(e));
    }
    let Some(ResourceDesc::Texture(TextureDesc { format, .. })) = desc.resources.get(target) else {
        return Err(err_at(
            ErrorKind::UnknownResource,
            pass,
            b,
            format!(
                "binding `{}` refers to `{target}`, which is neither a graph resource ({}) nor an engine resource ({}); declare it under `resources` or map it with `bind`",
                b.name,
                names(desc.resources.keys()),
                EngineResource::ALL.map(|e| e.name()).join(", ")
            ),
        ));
    };
    match &b.kind {
        BindingKind::SampledTexture { sample } => {
            let want = if format.is_uint() { SampleType::Uint } else { SampleType::Float };
            if *sample != want {
                return Err(err_at(
                    ErrorKind::FormatMismatch,
                    pass,
                    b,
                    format!("`{}` is {}, but `{target}` is {:?}", b.name, b.kind.describe(), format),
                ));
            }
            Ok(Bound::Read(target.to_string()))
        }
        BindingKind::StorageTexture { format: f, access } => {
            if f != format {
                return Err(err_at(
                    ErrorKind::FormatMismatch,
                    pass,
                    b,
                    format!("`{}` is {}, but resource `{target}` is declared {:?}", b.name, b.kind.describe(), format),
                ));
            }
            match access {
                StorageAccess::Read => Ok(Bound::Read(target.to_string())),
                StorageAccess::Write => Ok(Bound::Write { resource: target.to_string(), in_place: false }),
                StorageAccess::ReadWrite => Ok(Bound::Write { resource: target.to_string(), in_place: true }),
            }
        }
        other => Err(err_at(
            ErrorKind::WrongAccess,
            pass,
            b,
            format!("`{}` is declared {}, but `{target}` is a texture; use texture_2d or texture_storage_2d", b.name, other.describe()),
        )),
    }
}

fn check_pass_writes(pass: &str, bindings: &[(&BindingInfo, Bound)]) -> Result<(), CompileError> {
    for (i, (b, bound)) in bindings.iter().enumerate() {
        let Bound::Write { resource, in_place } = bound else { continue };
        for (other, ob) in &bindings[i + 1..] {
            let clash = match ob {
                Bound::Write { resource: r, .. } => r == resource,
                Bound::Read(r) => r == resource && *in_place,
                _ => false,
            };
            if clash {
                return Err(err_at(
                    ErrorKind::WrongAccess,
                    pass,
                    other,
                    format!("`{}` and `{}` both bind `{resource}`, which one dispatch cannot both write and read or write twice", b.name, other.name),
                ));
            }
        }
        for (other, ob) in &bindings[..i] {
            if *in_place && matches!(ob, Bound::Read(r) if r == resource) {
                return Err(err_at(
                    ErrorKind::WrongAccess,
                    pass,
                    other,
                    format!("`{}` reads `{resource}` while `{}` modifies it in place; read it through the read_write binding", other.name, b.name),
                ));
            }
        }
    }
    Ok(())
}

/// Most dispatches of one pass in a frame.
pub const MAX_PER_FRAME: u32 = 64;

/// A pass that does not run every frame writes only persistent resources
/// (anything else would hold another frame's content, or a pooled
/// texture's); a progressive pass runs 1..=64 iterations a frame.
fn check_run(desc: &FrameGraph, pass: &PassDesc, bindings: &[(&BindingInfo, Bound)]) -> Result<(), CompileError> {
    let name = Some(pass.name.as_str());
    if let RunMode::Progressive { per_frame, until } = pass.run {
        if !(1..=MAX_PER_FRAME).contains(&per_frame) {
            return Err(err(ErrorKind::BadRun, name, format!("`Progressive(per_frame: {per_frame})`: between 1 and {MAX_PER_FRAME} iterations a frame")));
        }
        if until == Some(0) {
            return Err(err(ErrorKind::BadRun, name, "`Progressive(until: 0)` never runs; give at least 1 iteration, or leave `until` out to run forever"));
        }
    }
    if let RunMode::ThinWhenStill { every: 0, .. } = pass.run {
        return Err(err(ErrorKind::BadRun, name, "`ThinWhenStill(every: 0)`: give at least 1 (every frame)"));
    }
    if pass.run == RunMode::EveryFrame {
        return Ok(());
    }
    let thinned = matches!(pass.run, RunMode::ThinWhenStill { .. });
    for (b, bound) in bindings {
        if let Bound::Write { resource, .. } = bound {
            let texture = match desc.resources.get(resource) {
                Some(ResourceDesc::Texture(t)) => Some(t),
                _ => None,
            };
            let persistent = texture.is_some_and(|t| t.persistent);
            // A thinned pass's transient is read only by passes that run
            // when it does (check_thinned_readers); the output and a
            // history are kept across frames, so they must persist.
            let transient = texture.is_some_and(|t| !t.history) && *resource != desc.output;
            let allowed = persistent || (thinned && transient);
            if !allowed {
                return Err(err_at(
                    ErrorKind::BadRun,
                    &pass.name,
                    b,
                    format!(
                        "runs {}, but writes `{resource}`, which is not persistent: a pass that skips frames may write only `persistent: true` resources{}",
                        pass.run.describe(),
                        if thinned { " (or, running `ThinWhenStill`, transients other than the output)" } else { "" }
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// A transient that a pass running `ThinWhenStill` writes is read only by
/// passes with the same `run`: in a frame it skips, nothing that runs
/// reads what it did not write.
fn check_thinned_readers(desc: &FrameGraph, plans: &[PassPlan]) -> Result<(), CompileError> {
    for writer in plans.iter().filter(|p| matches!(p.desc.run, RunMode::ThinWhenStill { .. })) {
        for (_, bound) in &writer.bindings {
            let Bound::Write { resource, .. } = bound else { continue };
            if !matches!(desc.resources.get(resource), Some(ResourceDesc::Texture(TextureDesc { persistent: false, history: false, .. }))) {
                continue;
            }
            for reader in plans {
                let read = reader.bindings.iter().find(|(_, b)| match b {
                    Bound::Read(r) => r == resource,
                    Bound::Write { resource: r, in_place } => r == resource && *in_place,
                    _ => false,
                });
                if let Some((b, _)) = read.filter(|_| reader.desc.run != writer.desc.run) {
                    return Err(err_at(
                        ErrorKind::BadRun,
                        &reader.desc.name,
                        b,
                        format!(
                            "reads `{resource}`, which pass `{}` writes running {}, but runs {}: in the frames `{}` skips, `{resource}` would hold nothing of this frame; give both the same `run`, or make `{resource}` persistent",
                            writer.desc.name,
                            writer.desc.run.describe(),
                            reader.desc.run.describe(),
                            writer.desc.name
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

fn pack_params(pass: &PassDesc, shader: &ShaderInfo) -> Result<Option<PassParams>, CompileError> {
    let name = Some(pass.name.as_str());
    let Some(layout) = &shader.params else {
        if let Some(k) = pass.params.keys().next() {
            return Err(err(ErrorKind::UnknownParam, name, format!("param `{k}` given, but {} has no `params` uniform", shader.name)));
        }
        return Ok(None);
    };
    PassParams::new(&shader.name, layout, pass.params.clone()).map(Some).map_err(|e| {
        let kind = match e {
            ParamError::Missing(_) => ErrorKind::MissingParam,
            ParamError::Unknown(_) => ErrorKind::UnknownParam,
            ParamError::Bad(_) => ErrorKind::BadParam,
        };
        err(kind, name, e.message())
    })
}

/// The pass's constants, with the graph's for overrides its shader declares
/// and the pass leaves unset, each checked against the shader.
fn check_constants(pass: &PassDesc, shader: &ShaderInfo, graph: &BTreeMap<String, f64>) -> Result<Vec<(String, f64)>, CompileError> {
    let name = Some(pass.name.as_str());
    let mut constants = pass.constants.clone();
    for (k, v) in graph {
        if shader.overrides.iter().any(|o| &o.name == k) {
            constants.entry(k.clone()).or_insert(*v);
        }
    }
    for (k, v) in &constants {
        let Some(o) = shader.overrides.iter().find(|o| &o.name == k) else {
            return Err(err(
                ErrorKind::UnknownConstant,
                name,
                format!("unknown constant `{k}`; {} overrides: {}", shader.name, names(shader.overrides.iter().map(|o| &o.name))),
            ));
        };
        // A value from the graph's `constants` is named as such: the pass's
        // own list does not hold it.
        let whose = if pass.constants.contains_key(k) { "" } else { " (from the graph's `constants`)" };
        if crate::graph::frame_kind::FRAME_CONSTANTS.contains(&k.as_str()) {
            return Err(err(ErrorKind::BadParam, name, format!("constant `{k}` is set by the engine per frame (each kind of frame picks its pipeline); a graph cannot set it{whose}")));
        }
        // Within the type's range too: the driver refuses a pipeline
        // constant that does not fit with a bare "Validation Error".
        let (fits, range) = match o.scalar {
            ScalarType::F32 => (v.is_finite() && v.abs() <= f64::from(f32::MAX), "a finite number within +-3.4e38"),
            ScalarType::U32 => (v.fract() == 0.0 && (0.0..=f64::from(u32::MAX)).contains(v), "an integer from 0 to 4294967295"),
            ScalarType::I32 => (v.fract() == 0.0 && (f64::from(i32::MIN)..=f64::from(i32::MAX)).contains(v), "an integer from -2147483648 to 2147483647"),
            ScalarType::Bool => (*v == 0.0 || *v == 1.0, "0 or 1 (false or true)"),
        };
        if !fits {
            let ty = match o.scalar {
                ScalarType::F32 => "f32",
                ScalarType::U32 => "u32",
                ScalarType::I32 => "i32",
                ScalarType::Bool => "bool",
            };
            let shown = crate::error::figure(*v);
            return Err(err(ErrorKind::BadParam, name, format!("constant `{k}` = {shown} does not fit the shader's `override {k}: {ty}`: give {range}{whose}")));
        }
    }
    if let Some(o) = shader.overrides.iter().find(|o| !o.has_default && !constants.contains_key(&o.name)) {
        return Err(err(ErrorKind::MissingConstant, name, format!("override `{}` has no default; give it in `constants`", o.name)));
    }
    Ok(constants.into_iter().collect())
}

