//! Step 5: lifetimes, in schedule positions.

use super::versions::{Group, Versions};

#[derive(Debug, Clone, Copy)]
pub(super) struct Lifetime {
    pub(super) first: usize,
    pub(super) last: usize,
}

pub(super) fn compute_lifetimes(order: &[usize], vs: &mut Versions, groups: &[Group], kept: &[&str]) -> Vec<Lifetime> {
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

