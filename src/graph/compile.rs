//! `compile`: a pure function of (graph, shader reflections, scene features)
//! to a `Schedule`. Each step of DESIGN.md section 3 is a named function.

use std::collections::{BTreeMap, BTreeSet};

use crate::error::Location;
use crate::graph::desc::{FrameGraph, ParamValue, PassDesc, ResourceDesc, SizeDesc, TexFormat, TextureDesc};
use crate::graph::edit::GraphEdits;
use crate::graph::schedule::*;
use crate::scene::SceneFeatures;
use crate::shader::{BindingInfo, BindingKind, EntryInfo, SampleType, ScalarType, ShaderInfo, StorageAccess};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    DuplicatePass,
    UnknownShader,
    UnknownEntry,
    UnknownBinding,
    UnknownResource,
    FormatMismatch,
    WrongAccess,
    DuplicateWriter,
    UnwrittenRead,
    UnknownOutput,
    Cycle,
    MissingParam,
    UnknownParam,
    BadParam,
    MissingConstant,
    UnknownConstant,
    BadEdit,
}

/// A graph compile error. `pass` and `shader_location` say where; the caller
/// adds the graph file's line (see `graph::locate`).
#[derive(Debug, Clone, PartialEq)]
pub struct CompileError {
    pub kind: ErrorKind,
    pub pass: Option<String>,
    pub shader_location: Option<Location>,
    pub message: String,
}

impl std::fmt::Display for CompileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some(p) = &self.pass {
            write!(f, "pass `{p}`: ")?;
        }
        write!(f, "{}", self.message)?;
        if let Some(loc) = &self.shader_location {
            write!(f, " (declared at {loc})")?;
        }
        Ok(())
    }
}

fn err(kind: ErrorKind, pass: Option<&str>, message: impl Into<String>) -> CompileError {
    CompileError { kind, pass: pass.map(str::to_string), shader_location: None, message: message.into() }
}

fn err_at(kind: ErrorKind, pass: &str, b: &BindingInfo, message: impl Into<String>) -> CompileError {
    CompileError {
        kind,
        pass: Some(pass.to_string()),
        shader_location: Some(b.location.clone()),
        message: message.into(),
    }
}

#[derive(Debug, Clone, Default)]
pub struct CompileOptions {
    /// Render this resource instead of the graph's `output` (debug views,
    /// per-pass golden images).
    pub output: Option<String>,
    /// `--set`, `--skip`, `--stop-after` (see graph::edit).
    pub edits: GraphEdits,
    /// Resources whose final version is kept (not pooled) until the frame
    /// ends, so the engine can read it back for stats. Absent or unwritten
    /// ones are ignored.
    pub keep: Vec<String>,
}

/// What one binding of a validated pass refers to.
#[derive(Debug, Clone, PartialEq)]
enum Bound {
    Read(String),
    Write { resource: String, in_place: bool },
    Engine(EngineResource),
    Params,
}

#[derive(Debug, Clone)]
struct PassPlan<'a> {
    desc: &'a PassDesc,
    entry: &'a EntryInfo,
    bindings: Vec<(&'a BindingInfo, Bound)>,
    params: Option<Vec<u8>>,
    constants: Vec<(String, f64)>,
}

impl PassPlan<'_> {
    fn reads(&self) -> impl Iterator<Item = &str> {
        self.bindings.iter().filter_map(|(_, b)| match b {
            Bound::Read(r) => Some(r.as_str()),
            Bound::Write { resource, in_place: true } => Some(resource.as_str()),
            _ => None,
        })
    }
    fn writes(&self) -> impl Iterator<Item = (&str, bool)> {
        self.bindings.iter().filter_map(|(_, b)| match b {
            Bound::Write { resource, in_place } => Some((resource.as_str(), *in_place)),
            _ => None,
        })
    }
}

/// Compiles a graph. `shaders` maps shader file names to their reflection.
pub fn compile(
    desc: &FrameGraph,
    shaders: &BTreeMap<String, ShaderInfo>,
    features: &SceneFeatures,
    options: &CompileOptions,
) -> Result<Schedule, CompileError> {
    let edited;
    let desc = if options.edits.is_empty() {
        desc
    } else {
        edited = options.edits.apply(desc).map_err(|m| err(ErrorKind::BadEdit, None, m))?;
        &edited
    };
    let plans = validate(desc, shaders)?;
    let output = options.output.clone().unwrap_or_else(|| desc.output.clone());
    if !desc.resources.contains_key(&output) {
        return Err(err(
            ErrorKind::UnknownOutput,
            None,
            format!("output `{output}` is not a declared resource; declared: {}", names(desc.resources.keys())),
        ));
    }
    let writers = writers_of(&plans);
    let (plans, mut culled) = cull_by_requires(plans, features);
    let mut versions = assign_versions(desc, &plans, &writers, &culled)?;
    check_output_written(&writers, &versions, &culled, &output)?;
    let (plans, unreachable) = cull_unreachable(desc, plans, &mut versions, &output);
    culled.extend(unreachable);
    culled.sort_by_key(|c| desc.passes.iter().position(|p| p.name == c.name));
    let groups = assign_groups(desc, &mut versions);
    let order = order_passes(&plans, &versions, &groups)?;
    let mut kept: Vec<&str> = vec![output.as_str()];
    kept.extend(options.keep.iter().map(String::as_str).filter(|r| versions.latest(r).is_some()));
    let lifetimes = compute_lifetimes(&order, &mut versions, &groups, &kept);
    let (textures, group_refs) = assign_textures(desc, &versions, &groups, &lifetimes);
    let mut schedule = emit_schedule(desc, features, &plans, &order, &versions, &groups, &group_refs, textures, culled, &output);
    schedule.kept = kept.iter().map(|r| r.to_string()).collect();
    Ok(schedule)
}

fn names<'a>(it: impl Iterator<Item = &'a String>) -> String {
    let v: Vec<&str> = it.map(String::as_str).collect();
    if v.is_empty() { "(none)".into() } else { v.join(", ") }
}

// ---------------------------------------------------------------------------
// Step 1: names, formats, access, params and constants.

fn validate<'a>(
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
            err(ErrorKind::UnknownShader, Some(name), format!("shader `{}` not found in shaders/", pass.shader))
        })?;
        let entry = pick_entry(pass, shader)?;
        for var in pass.bind.keys() {
            if !entry.bindings.iter().any(|b| &b.name == var) {
                return Err(err(
                    ErrorKind::UnknownBinding,
                    Some(name),
                    format!(
                        "`bind` maps `{var}`, but entry point `{}` of {} uses no binding of that name; it uses: {}",
                        entry.name,
                        shader.name,
                        names(entry.bindings.iter().map(|b| &b.name))
                    ),
                ));
            }
        }
        let mut bindings = Vec::new();
        for b in &entry.bindings {
            let target = pass.bind.get(&b.name).unwrap_or(&b.name);
            bindings.push((b, bind_one(desc, name, b, target)?));
        }
        check_pass_writes(name, &bindings)?;
        let params = pack_params(pass, shader)?;
        let constants = check_constants(pass, shader)?;
        plans.push(PassPlan { desc: pass, entry, bindings, params, constants });
    }
    Ok(plans)
}

fn pick_entry<'a>(pass: &PassDesc, shader: &'a ShaderInfo) -> Result<&'a EntryInfo, CompileError> {
    let found = match &pass.entry {
        Some(e) => shader.entry_points.iter().find(|ep| &ep.name == e),
        None if shader.entry_points.len() == 1 => shader.entry_points.first(),
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

fn bind_one(desc: &FrameGraph, pass: &str, b: &BindingInfo, target: &str) -> Result<Bound, CompileError> {
    if b.name == "params" && target == "params" {
        return match b.kind {
            BindingKind::Uniform { .. } => Ok(Bound::Params),
            _ => Err(err_at(ErrorKind::WrongAccess, pass, b, "`params` must be a var<uniform> struct")),
        };
    }
    if let Some(e) = EngineResource::from_name(target) {
        let ok = match &b.kind {
            BindingKind::Uniform { .. } => e.kind() == EngineKind::Uniform,
            BindingKind::Storage { read_only } => e.kind() == EngineKind::Storage && *read_only,
            BindingKind::StorageTexture { format, access } => e.kind() == EngineKind::Texture && *format == TexFormat::Rgba32Uint && *access == StorageAccess::Read,
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

fn pack_params(pass: &PassDesc, shader: &ShaderInfo) -> Result<Option<Vec<u8>>, CompileError> {
    let name = Some(pass.name.as_str());
    let Some(layout) = &shader.params else {
        if let Some(k) = pass.params.keys().next() {
            return Err(err(ErrorKind::UnknownParam, name, format!("param `{k}` given, but {} has no `params` uniform", shader.name)));
        }
        return Ok(None);
    };
    for k in pass.params.keys() {
        if !layout.members.iter().any(|m| &m.name == k) {
            return Err(err(
                ErrorKind::UnknownParam,
                name,
                format!("unknown param `{k}`; {} takes: {}", shader.name, names(layout.members.iter().map(|m| &m.name))),
            ));
        }
    }
    let mut bytes = vec![0u8; layout.size as usize];
    for m in &layout.members {
        let value = pass.params.get(&m.name).ok_or_else(|| {
            err(ErrorKind::MissingParam, name, format!("param `{}` is missing ({} needs every member of `params`)", m.name, shader.name))
        })?;
        let scalars: Vec<f64> = match value {
            ParamValue::Vector(v) => v.clone(),
            ParamValue::Int(i) => vec![*i as f64],
            ParamValue::Float(f) => vec![*f],
            ParamValue::Bool(b) => vec![f64::from(u8::from(*b))],
        };
        let is_int_literal = !matches!(value, ParamValue::Float(_));
        if scalars.len() != m.components as usize {
            return Err(err(
                ErrorKind::BadParam,
                name,
                format!("param `{}` needs {} value(s), got {}", m.name, m.components, scalars.len()),
            ));
        }
        for (c, &x) in scalars.iter().enumerate() {
            let at = m.offset as usize + 4 * c;
            let word: [u8; 4] = match m.scalar {
                ScalarType::F32 if x.is_finite() => (x as f32).to_le_bytes(),
                ScalarType::U32 if is_int_literal && x.fract() == 0.0 && (0.0..=u32::MAX as f64).contains(&x) => (x as u32).to_le_bytes(),
                ScalarType::I32 if is_int_literal && x.fract() == 0.0 && (i32::MIN as f64..=i32::MAX as f64).contains(&x) => (x as i32).to_le_bytes(),
                _ => {
                    return Err(err(
                        ErrorKind::BadParam,
                        name,
                        format!("param `{}` is {:?} in the shader; {x} does not fit (write an integer for u32/i32)", m.name, m.scalar),
                    ))
                }
            };
            bytes[at..at + 4].copy_from_slice(&word);
        }
    }
    Ok(Some(bytes))
}

fn check_constants(pass: &PassDesc, shader: &ShaderInfo) -> Result<Vec<(String, f64)>, CompileError> {
    let name = Some(pass.name.as_str());
    for (k, v) in &pass.constants {
        let Some(o) = shader.overrides.iter().find(|o| &o.name == k) else {
            return Err(err(
                ErrorKind::UnknownConstant,
                name,
                format!("unknown constant `{k}`; {} overrides: {}", shader.name, names(shader.overrides.iter().map(|o| &o.name))),
            ));
        };
        let fits = match o.scalar {
            ScalarType::F32 => v.is_finite(),
            ScalarType::U32 => v.fract() == 0.0 && *v >= 0.0,
            ScalarType::I32 => v.fract() == 0.0,
            ScalarType::Bool => *v == 0.0 || *v == 1.0,
        };
        if !fits {
            return Err(err(ErrorKind::BadParam, name, format!("constant `{k}` is {:?}; {v} does not fit", o.scalar)));
        }
    }
    if let Some(o) = shader.overrides.iter().find(|o| !o.has_default && !pass.constants.contains_key(&o.name)) {
        return Err(err(ErrorKind::MissingConstant, name, format!("override `{}` has no default; give it in `constants`", o.name)));
    }
    Ok(pass.constants.iter().map(|(k, v)| (k.clone(), *v)).collect())
}

// ---------------------------------------------------------------------------
// Step 2: cull by scene features.

fn cull_by_requires<'a>(plans: Vec<PassPlan<'a>>, features: &SceneFeatures) -> (Vec<PassPlan<'a>>, Vec<CulledPass>) {
    let mut kept = Vec::new();
    let mut culled = Vec::new();
    for p in plans {
        let missing: Vec<_> = p.desc.requires.iter().copied().filter(|f| !features.has(*f)).collect();
        if missing.is_empty() {
            kept.push(p);
        } else {
            culled.push(CulledPass { name: p.desc.name.clone(), reason: CullReason::Requires(missing) });
        }
    }
    (kept, culled)
}

// ---------------------------------------------------------------------------
// Versions: a write makes a new version; a read sees the newest version
// written earlier in file order, or the previous frame's (history), or the
// first one written later (a forward reference: ordering then follows data).

#[derive(Debug, Clone)]
struct Version {
    resource: String,
    number: u32,
    /// Plan index of the producer; None for a history resource's version 0.
    producer: Option<usize>,
    in_place: bool,
    readers: Vec<usize>,
    /// Physical group (filled by `assign_groups`).
    group: usize,
}

#[derive(Debug, Default)]
struct Versions {
    list: Vec<Version>,
    by_key: BTreeMap<(String, u32), usize>,
}

impl Versions {
    fn get(&self, resource: &str, number: u32) -> Option<usize> {
        self.by_key.get(&(resource.to_string(), number)).copied()
    }
    fn push(&mut self, v: Version) -> usize {
        self.by_key.insert((v.resource.clone(), v.number), self.list.len());
        self.list.push(v);
        self.list.len() - 1
    }
    fn latest(&self, resource: &str) -> Option<usize> {
        self.list.iter().enumerate().filter(|(_, v)| v.resource == resource).max_by_key(|(_, v)| v.number).map(|(i, _)| i)
    }
}

fn is_history(desc: &FrameGraph, r: &str) -> bool {
    matches!(desc.resources.get(r), Some(ResourceDesc::Texture(TextureDesc { history: true, .. })))
}

fn assign_versions(desc: &FrameGraph, plans: &[PassPlan], writers: &Writers, culled: &[CulledPass]) -> Result<Versions, CompileError> {
    let mut vs = Versions::default();
    for r in desc.resources.keys().filter(|r| is_history(desc, r)) {
        vs.push(Version { resource: r.clone(), number: 0, producer: None, in_place: false, readers: vec![], group: 0 });
    }
    // Writes first, in file order.
    let mut pure_writer: BTreeMap<&str, &str> = BTreeMap::new();
    for (pi, p) in plans.iter().enumerate() {
        let reads: BTreeSet<&str> = p.reads().collect();
        for (r, in_place) in p.writes() {
            let number = vs.latest(r).map(|i| vs.list[i].number + 1).unwrap_or(1);
            if !reads.contains(r) {
                if let Some(first) = pure_writer.get(r) {
                    return Err(err(
                        ErrorKind::DuplicateWriter,
                        Some(&p.desc.name),
                        format!("writes `{r}` without reading it, but pass `{first}` also does: two writers of one version; read it (bind it as an input) or write another resource"),
                    ));
                }
                pure_writer.insert(r, &p.desc.name);
                if number > 1 && !is_history(desc, r) {
                    return Err(err(
                        ErrorKind::DuplicateWriter,
                        Some(&p.desc.name),
                        format!("writes `{r}` without reading it after earlier passes wrote it; their work would be lost"),
                    ));
                }
            } else if number == 1 && !is_history(desc, r) {
                return Err(err(
                    ErrorKind::UnwrittenRead,
                    Some(&p.desc.name),
                    format!("reads and modifies `{r}`, but no earlier pass writes it{}", culled_writers(writers, culled, r)),
                ));
            }
            vs.push(Version { resource: r.to_string(), number, producer: Some(pi), in_place, readers: vec![], group: 0 });
        }
    }
    // Then reads, now that every version is known.
    for (pi, p) in plans.iter().enumerate() {
        for r in p.reads().collect::<BTreeSet<_>>() {
            let earlier = vs
                .list
                .iter()
                .enumerate()
                .filter(|(_, v)| v.resource == r && v.producer.is_some_and(|w| w < pi))
                .max_by_key(|(_, v)| v.number)
                .map(|(i, _)| i);
            let seen = earlier.or_else(|| vs.get(r, 0)).or_else(|| {
                // Forward reference, only for passes that do not also write r.
                if p.writes().any(|(w, _)| w == r) { None } else { vs.get(r, 1) }
            });
            let Some(v) = seen else {
                return Err(err(
                    ErrorKind::UnwrittenRead,
                    Some(&p.desc.name),
                    format!("reads `{r}`, but no pass writes it{}", culled_writers(writers, culled, r)),
                ));
            };
            vs.list[v].readers.push(pi);
        }
    }
    Ok(vs)
}

/// Every pass (before culling) that writes each resource.
type Writers = BTreeMap<String, Vec<String>>;

fn writers_of(plans: &[PassPlan]) -> Writers {
    let mut w = Writers::new();
    for p in plans {
        for (r, _) in p.writes() {
            w.entry(r.to_string()).or_default().push(p.desc.name.clone());
        }
    }
    w
}

fn culled_writers(writers: &Writers, culled: &[CulledPass], r: &str) -> String {
    let names: Vec<String> = culled
        .iter()
        .filter(|c| writers.get(r).is_some_and(|w| w.contains(&c.name)))
        .map(|c| match &c.reason {
            CullReason::Requires(f) => format!("`{}` culled: it requires {f:?}", c.name),
            CullReason::Unreachable => format!("`{}` culled", c.name),
        })
        .collect();
    if names.is_empty() { String::new() } else { format!(" ({})", names.join("; ")) }
}

fn check_output_written(writers: &Writers, vs: &Versions, culled: &[CulledPass], output: &str) -> Result<(), CompileError> {
    match vs.latest(output) {
        Some(v) if vs.list[v].producer.is_some() => Ok(()),
        _ => Err(err(
            ErrorKind::UnwrittenRead,
            None,
            format!("output `{output}` is written by no pass{}", culled_writers(writers, culled, output)),
        )),
    }
}

// ---------------------------------------------------------------------------
// Step 3: cull passes that reach neither the output nor a history write.

fn cull_unreachable<'a>(
    desc: &FrameGraph,
    plans: Vec<PassPlan<'a>>,
    vs: &mut Versions,
    output: &str,
) -> (Vec<PassPlan<'a>>, Vec<CulledPass>) {
    let mut roots: Vec<usize> = Vec::new();
    for r in desc.resources.keys() {
        if r == output || is_history(desc, r) {
            if let Some(v) = vs.latest(r) {
                roots.push(v);
            }
        }
    }
    let mut needed = vec![false; plans.len()];
    let mut stack: Vec<usize> = roots.iter().filter_map(|&v| vs.list[v].producer).collect();
    while let Some(p) = stack.pop() {
        if std::mem::replace(&mut needed[p], true) {
            continue;
        }
        for v in vs.list.iter().filter(|v| v.readers.contains(&p)) {
            stack.extend(v.producer);
        }
    }
    // Renumber plan indices, drop culled passes' versions and reads.
    let mut new_index = vec![usize::MAX; plans.len()];
    let mut kept = Vec::new();
    let mut culled = Vec::new();
    for (i, p) in plans.into_iter().enumerate() {
        if needed[i] {
            new_index[i] = kept.len();
            kept.push(p);
        } else {
            culled.push(CulledPass { name: p.desc.name.clone(), reason: CullReason::Unreachable });
        }
    }
    let old = std::mem::take(vs);
    for mut v in old.list {
        if let Some(p) = v.producer {
            if !needed[p] {
                continue;
            }
            v.producer = Some(new_index[p]);
        }
        v.readers = v.readers.iter().filter(|&&r| needed[r]).map(|&r| new_index[r]).collect();
        vs.push(v);
    }
    (kept, culled)
}

// ---------------------------------------------------------------------------
// Physical groups: versions that must share one texture (in-place writes,
// history slots). Pooling later may put several groups in one texture.

#[derive(Debug, Clone)]
struct Group {
    resource: String,
    history_slot: Option<u8>,
    versions: Vec<usize>,
}

fn assign_groups(desc: &FrameGraph, vs: &mut Versions) -> Vec<Group> {
    let mut groups: Vec<Group> = Vec::new();
    let mut order: Vec<usize> = (0..vs.list.len()).collect();
    order.sort_by(|&a, &b| (&vs.list[a].resource, vs.list[a].number).cmp(&(&vs.list[b].resource, vs.list[b].number)));
    let mut prev: Option<usize> = None;
    for i in order {
        let (resource, in_place) = (vs.list[i].resource.clone(), vs.list[i].in_place);
        let prev_same = prev.filter(|&p| vs.list[p].resource == resource);
        let group = if is_history(desc, &resource) {
            let slot = match prev_same {
                None => 0,
                Some(p) => {
                    let s = groups[vs.list[p].group].history_slot.unwrap_or(0);
                    if in_place { s } else { 1 - s }
                }
            };
            match groups.iter().position(|g| g.resource == resource && g.history_slot == Some(slot)) {
                Some(g) => g,
                None => {
                    groups.push(Group { resource: resource.clone(), history_slot: Some(slot), versions: vec![] });
                    groups.len() - 1
                }
            }
        } else if let (true, Some(p)) = (in_place, prev_same) {
            vs.list[p].group
        } else {
            groups.push(Group { resource: resource.clone(), history_slot: None, versions: vec![] });
            groups.len() - 1
        };
        vs.list[i].group = group;
        groups[group].versions.push(i);
        prev = Some(i);
    }
    groups
}

// ---------------------------------------------------------------------------
// Step 4: topological order, stable by file order.

fn order_passes(plans: &[PassPlan], vs: &Versions, groups: &[Group]) -> Result<Vec<usize>, CompileError> {
    let n = plans.len();
    let mut edges: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); n];
    for v in &vs.list {
        if let Some(p) = v.producer {
            for &r in &v.readers {
                if r != p {
                    edges[p].insert(r);
                }
            }
        }
    }
    // Write-after-read: a version that overwrites the texture of an earlier
    // version of its group waits for that version's readers.
    for g in groups {
        for w in g.versions.windows(2) {
            let (older, newer) = (&vs.list[w[0]], &vs.list[w[1]]);
            if let Some(p) = newer.producer {
                for &r in &older.readers {
                    if r != p {
                        edges[r].insert(p);
                    }
                }
            }
        }
    }
    let mut indegree = vec![0usize; n];
    for e in &edges {
        for &t in e {
            indegree[t] += 1;
        }
    }
    let mut ready: BTreeSet<usize> = (0..n).filter(|&i| indegree[i] == 0).collect();
    let mut order = Vec::with_capacity(n);
    while let Some(p) = ready.pop_first() {
        order.push(p);
        for &t in &edges[p] {
            indegree[t] -= 1;
            if indegree[t] == 0 {
                ready.insert(t);
            }
        }
    }
    if order.len() < n {
        let cycle = find_cycle(&edges, &indegree);
        let names: Vec<&str> = cycle.iter().map(|&i| plans[i].desc.name.as_str()).collect();
        return Err(err(
            ErrorKind::Cycle,
            None,
            format!("passes depend on each other in a cycle: {} -> {}", names.join(" -> "), names[0]),
        ));
    }
    Ok(order)
}

fn find_cycle(edges: &[BTreeSet<usize>], indegree: &[usize]) -> Vec<usize> {
    // Every node Kahn's algorithm left over has a left-over predecessor, but
    // not necessarily a left-over successor (a pass downstream of a cycle):
    // walk backwards until a node repeats, then read the loop forwards,
    // starting from its first pass in file order.
    let remaining = |i: usize| indegree[i] > 0;
    let Some(start) = (0..edges.len()).find(|&i| remaining(i)) else { return vec![] };
    let mut path = vec![start];
    let mut cur = start;
    loop {
        let Some(prev) = (0..edges.len()).find(|&p| remaining(p) && edges[p].contains(&cur)) else { return path };
        if let Some(pos) = path.iter().position(|&p| p == prev) {
            let mut cycle = path[pos..].to_vec();
            cycle.reverse();
            let first = (0..cycle.len()).min_by_key(|&i| cycle[i]).unwrap_or(0);
            cycle.rotate_left(first);
            return cycle;
        }
        path.push(prev);
        cur = prev;
    }
}

// ---------------------------------------------------------------------------
// Step 5: lifetimes, in schedule positions.

#[derive(Debug, Clone, Copy)]
struct Lifetime {
    first: usize,
    last: usize,
}

fn compute_lifetimes(order: &[usize], vs: &mut Versions, groups: &[Group], kept: &[&str]) -> Vec<Lifetime> {
    let mut pos = vec![0usize; order.len()];
    for (i, &p) in order.iter().enumerate() {
        pos[p] = i;
    }
    let kept_versions: Vec<usize> = kept.iter().filter_map(|r| vs.latest(r)).collect();
    groups
        .iter()
        .map(|g| {
            let mut first = usize::MAX;
            let mut last = 0;
            for &v in &g.versions {
                let ver = &vs.list[v];
                for p in ver.producer.iter().chain(ver.readers.iter()) {
                    first = first.min(pos[*p]);
                    last = last.max(pos[*p]);
                }
                if kept_versions.contains(&v) {
                    last = usize::MAX; // read back after the frame
                }
            }
            Lifetime { first, last }
        })
        .collect()
}

// ---------------------------------------------------------------------------
// Step 6: physical textures. Transients are pooled by descriptor across
// disjoint lifetimes; history groups get their own textures.

fn assign_textures(desc: &FrameGraph, vs: &Versions, groups: &[Group], life: &[Lifetime]) -> (Vec<PhysicalTexture>, Vec<usize>) {
    let mut textures: Vec<PhysicalTexture> = Vec::new();
    let mut busy_until: Vec<usize> = Vec::new();
    let mut group_tex = vec![usize::MAX; groups.len()];
    let describe = |r: &str| match desc.resources.get(r) {
        Some(ResourceDesc::Texture(TextureDesc { format, size, .. })) => (*format, *size),
        None => (TexFormat::Rgba32Float, SizeDesc::Screen),
    };
    let mut by_first: Vec<usize> = (0..groups.len()).collect();
    by_first.sort_by_key(|&g| (life[g].first, g));
    for g in by_first {
        let group = &groups[g];
        let (format, size) = describe(&group.resource);
        let label = group.versions.iter().map(|&v| format!("{}@{}", vs.list[v].resource, vs.list[v].number)).collect::<Vec<_>>().join(" ");
        let reuse = if group.history_slot.is_some() || life[g].first == usize::MAX {
            None
        } else {
            (0..textures.len()).find(|&t| {
                !textures[t].history && textures[t].format == format && textures[t].size == size && busy_until[t] < life[g].first
            })
        };
        let t = match reuse {
            Some(t) => {
                textures[t].label.push_str(", ");
                textures[t].label.push_str(&label);
                t
            }
            None => {
                textures.push(PhysicalTexture {
                    label,
                    format,
                    size,
                    usage: TexUsage::default(),
                    history: group.history_slot.is_some(),
                });
                busy_until.push(0);
                textures.len() - 1
            }
        };
        busy_until[t] = busy_until[t].max(life[g].last);
        group_tex[g] = t;
    }
    (textures, group_tex)
}

// ---------------------------------------------------------------------------
// Step 7: the schedule.

#[allow(clippy::too_many_arguments)]
fn emit_schedule(
    desc: &FrameGraph,
    features: &SceneFeatures,
    plans: &[PassPlan],
    order: &[usize],
    vs: &Versions,
    groups: &[Group],
    group_tex: &[usize],
    mut textures: Vec<PhysicalTexture>,
    culled: Vec<CulledPass>,
    output: &str,
) -> Schedule {
    // A history resource flips parity if its final version sits in slot 1.
    let flips = |r: &str| vs.latest(r).is_some_and(|v| groups[vs.list[v].group].history_slot == Some(1));
    let tex_ref = |v: usize| -> TexRef {
        let g = &groups[vs.list[v].group];
        match g.history_slot {
            None => TexRef::Fixed(group_tex[vs.list[v].group]),
            Some(slot) => {
                let other = groups.iter().position(|o| o.resource == g.resource && o.history_slot == Some(1 - slot));
                match other {
                    None => TexRef::Fixed(group_tex[vs.list[v].group]),
                    Some(o) => {
                        let mut pair = [group_tex[vs.list[v].group], group_tex[o]];
                        if slot == 1 {
                            pair.swap(0, 1);
                        }
                        TexRef::PingPong { textures: pair, slot, flips: flips(&g.resource) }
                    }
                }
            }
        }
    };
    let flips_parity = desc.resources.keys().filter(|r| is_history(desc, r)).any(|r| flips(r));
    let mut passes = Vec::new();
    for &pi in order {
        let plan = &plans[pi];
        let read_version = |r: &str| vs.list.iter().position(|v| v.resource == r && v.readers.contains(&pi));
        let written_version = |r: &str| vs.list.iter().position(|v| v.resource == r && v.producer == Some(pi));
        let mut bindings = Vec::new();
        let mut dispatch = None;
        let (mut reads, mut writes) = (Vec::new(), Vec::new());
        for (b, bound) in &plan.bindings {
            let target = match bound {
                Bound::Read(r) => {
                    let v = read_version(r).expect("every read has a version");
                    reads.push(format!("{r}@{}", vs.list[v].number));
                    let t = tex_ref(v);
                    mark_usage(&mut textures, t, b);
                    Target::Texture(t)
                }
                Bound::Write { resource, in_place } => {
                    let v = written_version(resource).expect("every write has a version");
                    if *in_place {
                        if let Some(rv) = read_version(resource) {
                            reads.push(format!("{resource}@{}", vs.list[rv].number));
                        }
                    }
                    writes.push(format!("{resource}@{}", vs.list[v].number));
                    if dispatch.is_none() {
                        if let Some(ResourceDesc::Texture(TextureDesc { size, .. })) = desc.resources.get(resource) {
                            dispatch = Some(*size);
                        }
                    }
                    let t = tex_ref(v);
                    mark_usage(&mut textures, t, b);
                    Target::Texture(t)
                }
                Bound::Engine(e) => Target::Engine(*e),
                Bound::Params => Target::Params,
            };
            bindings.push(ResolvedBinding { name: b.name.clone(), group: b.group, binding: b.binding, kind: b.kind.clone(), target });
        }
        passes.push(ScheduledPass {
            name: plan.desc.name.clone(),
            shader: plan.desc.shader.clone(),
            entry: plan.entry.name.clone(),
            workgroup_size: plan.entry.workgroup_size,
            params: plan.params.clone(),
            constants: plan.constants.clone(),
            bindings,
            dispatch: dispatch.unwrap_or_default(),
            reads,
            writes,
        });
    }
    let mut pos = vec![0usize; order.len()];
    for (i, &p) in order.iter().enumerate() {
        pos[p] = i;
    }
    let versions = vs
        .list
        .iter()
        .enumerate()
        .map(|(i, v)| VersionInfo {
            resource: v.resource.clone(),
            version: v.number,
            texture: tex_ref(i),
            first_use: v.producer.map(|p| pos[p]),
            last_use: v.readers.iter().map(|&r| pos[r]).max(),
        })
        .collect();
    let out_v = vs.latest(output).expect("output checked to exist");
    let output_format = match desc.resources.get(output) {
        Some(ResourceDesc::Texture(TextureDesc { format, .. })) => *format,
        None => TexFormat::Rgba32Float,
    };
    Schedule {
        name: desc.name.clone(),
        features: *features,
        passes,
        culled,
        textures,
        versions,
        output_resource: output.to_string(),
        output: tex_ref(out_v),
        output_format,
        flips_parity,
        kept: Vec::new(),
    }
}

fn mark_usage(textures: &mut [PhysicalTexture], t: TexRef, b: &BindingInfo) {
    let ids = match t {
        TexRef::Fixed(i) => vec![i],
        TexRef::PingPong { textures, .. } => textures.to_vec(),
    };
    for i in ids {
        match b.kind {
            BindingKind::SampledTexture { .. } => textures[i].usage.sampled = true,
            _ => textures[i].usage.storage = true,
        }
    }
}
