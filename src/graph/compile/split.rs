//! Step 0: sample loops split across dispatches.
//!
//! A shader loop over samples runs inside one invocation, and drivers bound
//! what one invocation may do: lavapipe ends *every* loop of an invocation
//! once 65535 iterations have run in all (three loops of 40000 in one
//! shader count 40000, 25534 and 1), so `pathtrace.spp = 600` came out 41%
//! too dark; a GPU would instead run one dispatch for as long as it takes.
//!
//! The convention: a pass whose `params` has a u32 `X` and a u32 `X_done`
//! takes `X` samples, `X_done` of which are already in its output. When
//! the graph asks for more than `SAMPLES_PER_DISPATCH`, the pass becomes
//! several: the first runs as written with its share of the samples and
//! `X_done = 0`; each later one, named `NAME#k`, runs the shader's entry
//! point `ENTRY_more` with the next share and the count done so far, and
//! blends into the output in place: its read_write binding `Y_acc` is bound
//! to whatever the first pass binds `Y` to. `X_done` is the engine's to set.
//!
//! A pass with `texels_per_invocation` n > 1 takes n texels' samples in one
//! invocation, so its first dispatch takes at most budget / n samples per
//! texel, n capped at the budget: SAMPLES_PER_DISPATCH, or
//! FLAT_SAMPLES_PER_DISPATCH for a flat scene, whose traces loop far less.
//! The later ones run `ENTRY_more` one texel per invocation, at most
//! SAMPLES_PER_DISPATCH each.

use std::collections::BTreeMap;

use super::{err, ErrorKind};
use super::CompileError;
use crate::graph::desc::{FrameGraph, ParamValue, PassDesc};
use crate::scene::{SceneFeatures, FLAT_LIMIT};
use crate::shader::{ScalarType, ShaderInfo};

/// The most samples one dispatch takes: with 15 traces per path sample and
/// 200 BVH steps per trace, 8 samples stay under lavapipe's 65535.
pub const SAMPLES_PER_DISPATCH: u32 = 8;

/// The same budget where the scene is flat (`SceneFeatures::flat`): a flat
/// trace loops over at most its spheres and its triangles (or a light's
/// occluders), 2 x FLAT_LIMIT = 64 trips, and the sweeps written out slot
/// by slot loop not at all; with 15 traces per path sample, 32 samples
/// stay under 65535 (30720). The path tracer renders 32 texels per
/// invocation there: a SIMD group waits for its slowest lane's paths, and
/// over 32 texels the lanes' path lengths even out more than over 8
/// (pathtrace pass 0.90x the time on the Cornell box at 1280x720).
pub const FLAT_SAMPLES_PER_DISPATCH: u32 = 32;
const _: () = assert!(15 * 2 * FLAT_LIMIT as u32 * FLAT_SAMPLES_PER_DISPATCH < 65535);

/// The samples one dispatch may take for a scene with these features.
fn samples_per_dispatch(features: &SceneFeatures) -> u32 {
    if features.flat {
        FLAT_SAMPLES_PER_DISPATCH
    } else {
        SAMPLES_PER_DISPATCH
    }
}

/// The most dispatches one pass may become (8192 samples a frame).
const MAX_DISPATCHES: u64 = 1024;

/// The graph with every splittable pass expanded (None: nothing to do).
pub(super) fn split_sample_loops(desc: &FrameGraph, shaders: &BTreeMap<String, ShaderInfo>, features: &SceneFeatures) -> Result<Option<FrameGraph>, CompileError> {
    let budget = u64::from(samples_per_dispatch(features));
    let mut out = desc.clone();
    let mut changed = false;
    out.passes.clear();
    for pass in &desc.passes {
        let Some(param) = sample_param(pass, shaders) else {
            out.passes.push(pass.clone());
            continue;
        };
        changed = true;
        let done = format!("{param}_done");
        if pass.params.contains_key(&done) {
            return Err(err(ErrorKind::BadParam, Some(&pass.name), format!("`{done}` is set by the engine (it splits `{param}` across dispatches); leave it out")));
        }
        let total = match pass.params.get(param.as_str()) {
            Some(ParamValue::Int(n)) if *n >= 1 && *n <= i64::from(u32::MAX) => *n as u64,
            // The packer reports a missing or malformed value.
            _ => {
                let mut p = pass.clone();
                p.params.insert(done, ParamValue::Int(0));
                out.passes.push(p);
                continue;
            }
        };
        // As many texels as the graph asks, up to the budget: one
        // invocation may not loop over more samples than drivers allow
        // (0 stays 0: validate names it).
        let capped = pass.texels_per_invocation.map(|n| u64::from(n).min(budget) as u32);
        let texels = u64::from(capped.unwrap_or(1).max(1));
        let shares = if texels == 1 {
            equal_shares(total)
        } else {
            let first = total.min(budget / texels);
            std::iter::once(first).chain(equal_shares(total - first)).collect()
        };
        let chunks = shares.len() as u64;
        if chunks > MAX_DISPATCHES {
            return Err(err(
                ErrorKind::BadParam,
                Some(&pass.name),
                format!(
                    "`{param}` = {total} would take {chunks} dispatches of at most {SAMPLES_PER_DISPATCH} samples a frame; at most {} samples a frame ({MAX_DISPATCHES} dispatches): accumulate frames for more",
                    MAX_DISPATCHES * u64::from(SAMPLES_PER_DISPATCH)
                ),
            ));
        }
        let mut so_far = 0u64;
        for (k, &share) in shares.iter().enumerate() {
            let mut p = pass.clone();
            p.texels_per_invocation = capped;
            p.params.insert(param.clone(), ParamValue::Int(share as i64));
            p.params.insert(done.clone(), ParamValue::Int(so_far as i64));
            if k > 0 {
                p.name = format!("{}#{}", pass.name, k + 1);
                let entry = format!("{}_more", pass.entry.clone().unwrap_or_else(|| "main".to_string()));
                let more = shaders.get(&pass.shader).and_then(|s| s.entry_points.iter().find(|e| e.name == entry));
                let Some(more) = more else {
                    return Err(err(
                        ErrorKind::UnknownEntry,
                        Some(&pass.name),
                        format!("`{param}` = {total} is split across {chunks} dispatches of at most {SAMPLES_PER_DISPATCH}, which needs the entry point `{entry}` in {}", pass.shader),
                    ));
                };
                for b in &more.bindings {
                    if let Some(y) = b.name.strip_suffix("_acc") {
                        let target = pass.bind.get(y).cloned().unwrap_or_else(|| y.to_string());
                        p.bind.insert(b.name.clone(), target);
                    }
                }
                p.entry = Some(entry);
                p.texels_per_invocation = None;
            }
            so_far += share;
            out.passes.push(p);
        }
    }
    Ok(changed.then_some(out))
}

/// `total` samples in dispatches of at most SAMPLES_PER_DISPATCH, shares as
/// equal as can be (the first total % chunks take one more); none for 0.
fn equal_shares(total: u64) -> Vec<u64> {
    let chunks = total.div_ceil(u64::from(SAMPLES_PER_DISPATCH));
    (0..chunks).map(|k| total / chunks + u64::from(k < total % chunks)).collect()
}

/// The name `X` of a pass's splittable sample count: its shader's params
/// have u32 members `X` and `X_done`.
fn sample_param(pass: &PassDesc, shaders: &BTreeMap<String, ShaderInfo>) -> Option<String> {
    let layout = shaders.get(&pass.shader)?.params.as_ref()?;
    let is_u32 = |name: &str| layout.members.iter().any(|m| m.name == name && m.scalar == ScalarType::U32 && m.components == 1);
    layout
        .members
        .iter()
        .filter_map(|m| m.name.strip_suffix("_done"))
        .find(|x| is_u32(x) && is_u32(&format!("{x}_done")))
        .map(str::to_string)
}
