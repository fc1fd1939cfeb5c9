//! Lights in clusters, so that a path can choose one light among hundreds
//! without weighing every one of them (shaders/shared/light_choice.wgsl).
//!
//! A scene with more than `CLUSTERED_ABOVE` light records gets its local
//! lights (sphere and point lights) split into spatial clusters of about
//! sqrt(n) lights each, by halving the set along its longest axis at the
//! median; a directional light and the environment each make a cluster of
//! their own. A choice then weighs every cluster by an estimate of what its
//! lights could bring to the shading point (their power over the squared
//! distance, times the largest cosine any point of the cluster's bounding
//! sphere can make with the normal), picks one, and then weighs that
//! cluster's lights one by one: about 2 sqrt(n) weights instead of n.
//!
//! The clusters are texels appended to `scene_lights` after the lights'
//! own (three a light), at texel 3 n:
//! - per cluster two texels: its bounding sphere (centre, radius: f32
//!   bits), then its power (f32 bits), the first of its members in the
//!   member list, and how many it has;
//! - the member list: light indices, four a texel, cluster after cluster;
//! - each light's cluster, four a texel, by light index.
//!
//! Built again whenever the scene is packed (lights move), with the same
//! counts: the texture keeps its size while the scene animates.

use super::gpu_types::{LightGpu, LIGHT_DIRECTIONAL, LIGHT_ENVIRONMENT, LIGHT_SPHERE};

/// Scenes with at most this many light records weigh every light at every
/// choice (realtime.ron's frame took 1.12x with 64 lights against one);
/// beyond, they choose a cluster first.
pub const CLUSTERED_ABOVE: usize = 64;

/// Whether a scene with `records` light records (the environment's
/// included) chooses its lights through clusters.
pub fn clustered(records: usize) -> bool {
    records > CLUSTERED_ABOVE
}

/// A scene's light clusters as the texels that follow its lights in
/// `scene_lights` (none for a scene that is not `clustered`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LightClusters {
    /// How many clusters (`frame.n_light_clusters`; 0: none).
    pub count: u32,
    /// Their records, member list and each light's cluster.
    pub texels: Vec<[u32; 4]>,
}

/// What one cluster holds, before packing.
#[derive(Debug, Clone, PartialEq)]
struct Cluster {
    centre: [f32; 3],
    radius: f32,
    power: f32,
    members: Vec<u32>,
}

/// Luminance, as the shaders weigh a light (shared/light_choice.wgsl).
fn luminance(c: [f32; 3]) -> f64 {
    0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2])
}

/// Light `l`'s power as the cluster bound counts it: what it brings at
/// unit distance facing it (a sphere light's luminance times pi r^2, a
/// point light's intensity).
fn power(l: &LightGpu) -> f64 {
    let lum = luminance(l.color).max(0.0);
    if l.kind == LIGHT_SPHERE {
        let r = f64::from(l.radius);
        lum * std::f64::consts::PI * r * r
    } else {
        lum
    }
}

/// The clusters of `lights`, or none where the scene has too few lights
/// to need them.
pub fn light_clusters(lights: &[LightGpu]) -> LightClusters {
    if !clustered(lights.len()) {
        return LightClusters::default();
    }
    let (global, local): (Vec<u32>, Vec<u32>) =
        (0..lights.len() as u32).partition(|&i| matches!(lights[i as usize].kind, LIGHT_DIRECTIONAL | LIGHT_ENVIRONMENT));
    let size = ((local.len() as f64).sqrt().ceil() as usize).max(1);
    let mut groups = Vec::new();
    split(lights, local, size, &mut groups);
    groups.extend(global.into_iter().map(|i| vec![i]));
    pack(lights, groups.iter().map(|g| cluster(lights, g)).collect())
}

/// `members` halved along the longest axis of their centres' bounds,
/// at the median, until each part has at most `size` lights.
fn split(lights: &[LightGpu], mut members: Vec<u32>, size: usize, out: &mut Vec<Vec<u32>>) {
    if members.len() <= size {
        if !members.is_empty() {
            out.push(members);
        }
        return;
    }
    let at = |i: u32| lights[i as usize].position.map(f64::from);
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for &i in &members {
        for (k, v) in at(i).into_iter().enumerate() {
            lo[k] = lo[k].min(v);
            hi[k] = hi[k].max(v);
        }
    }
    let axis = (0..3).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b]))).unwrap_or(0);
    members.sort_by(|&a, &b| at(a)[axis].total_cmp(&at(b)[axis]).then(a.cmp(&b)));
    let rest = members.split_off(members.len() / 2);
    split(lights, members, size, out);
    split(lights, rest, size, out);
}

/// The bounding sphere and power of the lights `members`. The radius is
/// rounded up, so that the sphere as stored (centre rounded to f32) still
/// holds every light whole: the bound must leave no light out.
fn cluster(lights: &[LightGpu], members: &[u32]) -> Cluster {
    let ls = || members.iter().map(|&i| &lights[i as usize]);
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for l in ls() {
        let r = f64::from(l.radius.max(0.0));
        for k in 0..3 {
            lo[k] = lo[k].min(f64::from(l.position[k]) - r);
            hi[k] = hi[k].max(f64::from(l.position[k]) + r);
        }
    }
    let centre = [0, 1, 2].map(|k| (0.5 * (lo[k] + hi[k])) as f32);
    let radius = ls()
        .map(|l| {
            let d: f64 = (0..3).map(|k| (f64::from(l.position[k]) - f64::from(centre[k])).powi(2)).sum();
            d.sqrt() + f64::from(l.radius.max(0.0))
        })
        .fold(0.0, f64::max);
    let power: f64 = ls().map(power).sum();
    Cluster { centre, radius: round_up(radius * (1.0 + 1e-6)), power: round_up(power).min(f32::MAX), members: members.to_vec() }
}

/// `x` as the nearest f32 at least as large (0 stays 0).
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) < x { f.next_up() } else { f }
}

/// The texels of `clusters` (their records, the member list, each light's
/// cluster), in the layout the module's comment gives.
fn pack(lights: &[LightGpu], clusters: Vec<Cluster>) -> LightClusters {
    let n = lights.len();
    let mut texels = Vec::with_capacity(2 * clusters.len() + 2 * n.div_ceil(4));
    let mut list: Vec<u32> = Vec::with_capacity(n);
    let mut cluster_of = vec![0u32; n];
    for (c, cl) in clusters.iter().enumerate() {
        texels.push([cl.centre[0].to_bits(), cl.centre[1].to_bits(), cl.centre[2].to_bits(), cl.radius.to_bits()]);
        texels.push([cl.power.to_bits(), list.len() as u32, cl.members.len() as u32, 0]);
        for &m in &cl.members {
            cluster_of[m as usize] = c as u32;
            list.push(m);
        }
    }
    let fours = |v: &[u32]| -> Vec<[u32; 4]> { v.chunks(4).map(|c| std::array::from_fn(|k| c.get(k).copied().unwrap_or(0))).collect() };
    texels.extend(fours(&list));
    texels.extend(fours(&cluster_of));
    LightClusters { count: clusters.len() as u32, texels }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::gpu_types::LIGHT_POINT;

    fn light(kind: u32, position: [f32; 3], radius: f32, lum: f32) -> LightGpu {
        LightGpu { position, radius, color: [lum; 3], kind, spot: [0.0, 0.0, 0.0, 1.0] }
    }

    /// A grid of `n` lights, sphere and point lights in turn, with a sun
    /// and the environment last.
    fn many(n: usize) -> Vec<LightGpu> {
        let mut v: Vec<LightGpu> = (0..n)
            .map(|i| {
                let p = [(i % 10) as f32 * 0.3, 2.0, (i / 10) as f32 * 0.3 - 1.0];
                if i % 2 == 0 { light(LIGHT_SPHERE, p, 0.05, 10.0) } else { light(LIGHT_POINT, p, 0.0, 1.0 + i as f32) }
            })
            .collect();
        v.push(light(LIGHT_DIRECTIONAL, [0.0, 1.0, 0.0], 0.0, 3.0));
        v.push(light(LIGHT_ENVIRONMENT, [64.0, 32.0, 0.0], 0.0, 0.5));
        v
    }

    /// The packed records read back, and each light's cluster.
    fn unpack(c: &LightClusters, n: usize) -> (Vec<Cluster>, Vec<u32>) {
        let k = c.count as usize;
        let list: Vec<u32> = c.texels[2 * k..2 * k + n.div_ceil(4)].iter().flatten().copied().collect();
        let of: Vec<u32> = c.texels[2 * k + n.div_ceil(4)..].iter().flatten().copied().take(n).collect();
        let records = (0..k)
            .map(|i| {
                let (a, b) = (c.texels[2 * i], c.texels[2 * i + 1]);
                let members = list[b[1] as usize..(b[1] + b[2]) as usize].to_vec();
                Cluster { centre: [a[0], a[1], a[2]].map(f32::from_bits), radius: f32::from_bits(a[3]), power: f32::from_bits(b[0]), members }
            })
            .collect();
        (records, of)
    }

    #[test]
    fn few_lights_have_no_clusters() {
        assert_eq!(light_clusters(&many(CLUSTERED_ABOVE - 2)), LightClusters::default());
        assert!(light_clusters(&many(CLUSTERED_ABOVE - 1)).count > 0, "65 records");
    }

    #[test]
    fn every_light_is_in_one_cluster_that_holds_it_whole() {
        let lights = many(300);
        let c = light_clusters(&lights);
        let (records, of) = unpack(&c, lights.len());
        assert_eq!(c.texels.len(), 2 * records.len() + 2 * lights.len().div_ceil(4));
        let mut seen = vec![0; lights.len()];
        for (k, Cluster { centre, radius, power: stored, members }) in records.iter().enumerate() {
            assert!(!members.is_empty() && members.len() <= 18, "cluster {k}: {} lights (sqrt(300) is about 17.3)", members.len());
            let mut sum = 0.0;
            for &m in members {
                seen[m as usize] += 1;
                assert_eq!(of[m as usize], k as u32, "light {m}'s cluster");
                let l = &lights[m as usize];
                sum += power(l);
                if matches!(l.kind, LIGHT_DIRECTIONAL | LIGHT_ENVIRONMENT) {
                    assert_eq!(members.len(), 1, "a directional light or the environment is a cluster alone");
                    continue;
                }
                let d: f64 = (0..3).map(|i| (f64::from(l.position[i]) - f64::from(centre[i])).powi(2)).sum();
                assert!(d.sqrt() + f64::from(l.radius) <= f64::from(*radius), "light {m} sticks out of cluster {k}");
            }
            assert!(f64::from(*stored) >= sum && f64::from(*stored) <= sum * (1.0 + 1e-6), "cluster {k}'s power {stored} against {sum}");
        }
        assert!(seen.iter().all(|&s| s == 1), "each light once");
    }

    #[test]
    fn clusters_are_the_same_for_the_same_lights() {
        let lights = many(200);
        assert_eq!(light_clusters(&lights), light_clusters(&lights));
        // Moved lights keep the counts, so the texture keeps its size.
        let moved: Vec<LightGpu> = lights.iter().map(|l| LightGpu { position: [l.position[2], l.position[0], l.position[1]], ..*l }).collect();
        let (a, b) = (light_clusters(&lights), light_clusters(&moved));
        assert_eq!((a.count, a.texels.len()), (b.count, b.texels.len()));
    }

    #[test]
    fn a_light_of_no_power_leaves_its_cluster_the_rest() {
        let mut lights = many(100);
        for l in lights.iter_mut().take(50) {
            l.color = [0.0; 3];
        }
        let c = light_clusters(&lights);
        let (records, _) = unpack(&c, lights.len());
        for Cluster { power: stored, members, .. } in records {
            let sum: f64 = members.iter().map(|&m| power(&lights[m as usize])).sum();
            assert_eq!(stored > 0.0, sum > 0.0, "a cluster has power exactly when one of its lights has");
        }
    }
}
