//! Step 4: topological order, stable by file order.

use std::collections::BTreeSet;

use super::versions::{Group, Versions};
use super::{err, CompileError, ErrorKind, PassPlan};

pub(super) fn order_passes(plans: &[PassPlan], vs: &Versions, groups: &[Group]) -> Result<Vec<usize>, CompileError> {
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

