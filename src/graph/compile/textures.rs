//! Step 6: physical textures. Transients are pooled by descriptor across
//! disjoint lifetimes; history groups get their own textures.

use super::lifetimes::Lifetime;
use super::versions::{Group, Versions};
use crate::graph::desc::{FrameGraph, ResourceDesc, SizeDesc, TextureDesc};
use crate::format::TexFormat;
use crate::graph::schedule::{PhysicalTexture, TexUsage};

pub(super) fn assign_textures(desc: &FrameGraph, vs: &Versions, groups: &[Group], life: &[Lifetime]) -> (Vec<PhysicalTexture>, Vec<usize>) {
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
                    persistent: super::versions::is_persistent(desc, &group.resource),
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

