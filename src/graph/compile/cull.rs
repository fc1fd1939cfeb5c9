//! Steps 2 and 3: cull passes whose `requires` the scene lacks, then
//! passes that reach neither the output nor a history write (nor a
//! resource the options ask for, `CompileOptions::also_compute`).

use super::versions::{is_history, Versions};
use super::PassPlan;
use crate::graph::desc::{FrameGraph, ProbeMode};
use crate::graph::schedule::{CullReason, CulledPass};
use crate::scene::{Feature, SceneFeatures};

/// `probes` is the graph's probe mode, which decides `ThesisProbes` and
/// `DdgiProbes`; the scene decides the other features.
pub(super) fn cull_by_requires<'a>(plans: Vec<PassPlan<'a>>, features: &SceneFeatures, probes: Option<ProbeMode>) -> (Vec<PassPlan<'a>>, Vec<CulledPass>) {
    let has = |f: Feature| match f {
        Feature::ThesisProbes => probes == Some(ProbeMode::Thesis),
        Feature::DdgiProbes => probes == Some(ProbeMode::Ddgi),
        other => features.has(other),
    };
    let mut kept = Vec::new();
    let mut culled = Vec::new();
    for p in plans {
        let missing: Vec<_> = p.desc.requires.iter().copied().filter(|f| !has(*f)).collect();
        if missing.is_empty() {
            kept.push(p);
        } else {
            culled.push(CulledPass { name: p.desc.name.clone(), reason: CullReason::Requires(missing) });
        }
    }
    (kept, culled)
}

// Step 3.

pub(super) fn cull_unreachable<'a>(
    desc: &FrameGraph,
    plans: Vec<PassPlan<'a>>,
    vs: &mut Versions,
    output: &str,
    also: &[String],
) -> (Vec<PassPlan<'a>>, Vec<CulledPass>) {
    let mut roots: Vec<usize> = Vec::new();
    for r in desc.resources.keys() {
        if r == output || is_history(desc, r) || also.contains(r) {
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
    // A history or persistent resource no kept pass touches gets no texture
    // (a probe volume of the mode the graph does not use).
    let untouched: Vec<String> = vs
        .list
        .iter()
        .filter(|v| v.number == 0 && v.readers.is_empty())
        .filter(|v| !vs.list.iter().any(|o| o.resource == v.resource && o.number > 0))
        .map(|v| v.resource.clone())
        .collect();
    if !untouched.is_empty() {
        let old = std::mem::take(vs);
        for v in old.list.into_iter().filter(|v| !untouched.contains(&v.resource)) {
            vs.push(v);
        }
    }
    (kept, culled)
}

