//! Versions: a write makes a new version; a read sees the newest version
//! written earlier in file order, or the previous frame's (history), or the
//! first one written later (a forward reference: ordering then follows data).

use std::collections::{BTreeMap, BTreeSet};

use super::{err, CompileError, ErrorKind, PassPlan};
use crate::graph::desc::{FrameGraph, ResourceDesc, TextureDesc};
use crate::graph::schedule::{CullReason, CulledPass};

#[derive(Debug, Clone)]
pub(super) struct Version {
    pub(super) resource: String,
    pub(super) number: u32,
    /// Plan index of the producer; None for a history resource's version 0.
    pub(super) producer: Option<usize>,
    pub(super) in_place: bool,
    pub(super) readers: Vec<usize>,
    /// Physical group (filled by `assign_groups`).
    pub(super) group: usize,
}

#[derive(Debug, Default)]
pub(super) struct Versions {
    pub(super) list: Vec<Version>,
    pub(super) by_key: BTreeMap<(String, u32), usize>,
}

impl Versions {
    pub(super) fn get(&self, resource: &str, number: u32) -> Option<usize> {
        self.by_key.get(&(resource.to_string(), number)).copied()
    }
    pub(super) fn push(&mut self, v: Version) -> usize {
        self.by_key.insert((v.resource.clone(), v.number), self.list.len());
        self.list.push(v);
        self.list.len() - 1
    }
    pub(super) fn latest(&self, resource: &str) -> Option<usize> {
        self.list.iter().enumerate().filter(|(_, v)| v.resource == resource).max_by_key(|(_, v)| v.number).map(|(i, _)| i)
    }
}

/// Whether `r` survives across frames: a history resource (two textures)
/// or a persistent one (one). Either has a version 0 (what the last frame
/// left) and is a culling root.
pub(super) fn is_history(desc: &FrameGraph, r: &str) -> bool {
    matches!(desc.resources.get(r), Some(ResourceDesc::Texture(TextureDesc { history: true, .. } | TextureDesc { persistent: true, .. })))
}

pub(super) fn is_persistent(desc: &FrameGraph, r: &str) -> bool {
    matches!(desc.resources.get(r), Some(ResourceDesc::Texture(TextureDesc { persistent: true, .. })))
}

pub(super) fn assign_versions(desc: &FrameGraph, plans: &[PassPlan], writers: &Writers, culled: &[CulledPass]) -> Result<Versions, CompileError> {
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
pub(super) type Writers = BTreeMap<String, Vec<String>>;

pub(super) fn writers_of(plans: &[PassPlan]) -> Writers {
    let mut w = Writers::new();
    for p in plans {
        for (r, _) in p.writes() {
            w.entry(r.to_string()).or_default().push(p.desc.name.clone());
        }
    }
    w
}

pub(super) fn culled_writers(writers: &Writers, culled: &[CulledPass], r: &str) -> String {
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

pub(super) fn check_output_written(writers: &Writers, vs: &Versions, culled: &[CulledPass], output: &str) -> Result<(), CompileError> {
    match vs.latest(output) {
        Some(v) if vs.list[v].producer.is_some() => Ok(()),
        _ => Err(err(
            ErrorKind::UnwrittenRead,
            None,
            format!("output `{output}` is written by no pass{}", culled_writers(writers, culled, output)),
        )),
    }
}

// Physical groups: versions that must share one texture (in-place writes,
// history slots). Pooling later may put several groups in one texture.

#[derive(Debug, Clone)]
pub(super) struct Group {
    pub(super) resource: String,
    pub(super) history_slot: Option<u8>,
    pub(super) versions: Vec<usize>,
}

pub(super) fn assign_groups(desc: &FrameGraph, vs: &mut Versions) -> Vec<Group> {
    let mut groups: Vec<Group> = Vec::new();
    let mut order: Vec<usize> = (0..vs.list.len()).collect();
    order.sort_by(|&a, &b| (&vs.list[a].resource, vs.list[a].number).cmp(&(&vs.list[b].resource, vs.list[b].number)));
    let mut prev: Option<usize> = None;
    for i in order {
        let (resource, in_place) = (vs.list[i].resource.clone(), vs.list[i].in_place);
        let prev_same = prev.filter(|&p| vs.list[p].resource == resource);
        let group = if is_history(desc, &resource) {
            let slot = match prev_same {
                // A persistent resource is one texture: every version in slot 0.
                _ if is_persistent(desc, &resource) => 0,
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

