//! Independent work spread over every core a batch at a time: each batch's
//! results are handed back, in order, before the next batch starts, so at
//! most a batch of them is held at once (a scene's decoded images and mip
//! chains run to hundreds of MiB).

/// Calls `work` on each of `items` on its own thread, `cores` items at a
/// time, and hands each item and its result to `each`, in the items'
/// order. A panic in `work` is passed on.
pub fn in_batches<T: Sync, R: Send>(items: &[T], work: impl Fn(&T) -> R + Sync, mut each: impl FnMut(&T, R)) {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    for batch in items.chunks(cores) {
        let results: Vec<R> = std::thread::scope(|s| {
            let work = &work;
            let handles: Vec<_> = batch.iter().map(|item| s.spawn(move || work(item))).collect();
            handles.into_iter().map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e))).collect()
        });
        for (item, r) in batch.iter().zip(results) {
            each(item, r);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_item_is_worked_and_handed_back_in_order() {
        let items: Vec<u32> = (0..37).collect();
        let mut seen = Vec::new();
        in_batches(&items, |&x| x * x, |&x, sq| seen.push((x, sq)));
        assert_eq!(seen, items.iter().map(|&x| (x, x * x)).collect::<Vec<_>>());
        in_batches(&[] as &[u32], |&x| x, |_, _| panic!("no items"));
    }
}
