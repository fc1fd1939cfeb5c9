//! Step 7: the schedule.

use super::versions::{is_history, Group, Versions};
use super::PassPlan;
use super::Bound;
use crate::graph::desc::{FrameGraph, ResourceDesc, TextureDesc};
use crate::format::TexFormat;
use crate::graph::schedule::*;
use crate::scene::SceneFeatures;
use crate::shader::{BindingInfo, BindingKind};

#[allow(clippy::too_many_arguments)]
pub(super) fn emit_schedule(
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
                Bound::Run => Target::Run,
                Bound::WorkList => Target::WorkList,
                Bound::TilePool => Target::TilePool,
            };
            bindings.push(ResolvedBinding { name: b.name.clone(), group: b.group, binding: b.binding, kind: b.kind.clone(), target });
        }
        let mut inputs_from: Vec<usize> = vs
            .list
            .iter()
            .filter(|v| v.readers.contains(&pi))
            .filter_map(|v| v.producer)
            .filter(|&p| p != pi)
            .map(|p| order.iter().position(|&o| o == p).expect("producers are scheduled"))
            .collect();
        inputs_from.sort_unstable();
        inputs_from.dedup();
        passes.push(ScheduledPass {
            name: plan.desc.name.clone(),
            shader: plan.desc.shader.clone(),
            entry: plan.entry.name.clone(),
            workgroup_size: plan.entry.workgroup_size,
            listed: plan.listed.map(|e| e.name.clone()),
            params: plan.params.clone(),
            constants: plan.constants.clone(),
            bindings,
            dispatch: plan.desc.dispatch.or(dispatch).unwrap_or_default(),
            texels_per_invocation: plan.desc.texels_per_invocation.unwrap_or(1),
            run: plan.desc.run,
            inputs_from,
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
        probes: desc.probes,
        specialisations: Vec::new(),
        specialise: false,
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
