//! A parallel map over independent items that keeps their order: the diagnosis's stages hand
//! it runs, or runs and axes, and get results identical for any thread count.

use crate::error::DiagError;

/// `f` on every item, on up to `threads` workers that each take the next item not yet started
/// (in the order given); results in item order, identical for any thread count (each item is
/// processed alone).
pub(crate) fn par_map<I: Send, T: Send>(
    items: Vec<I>,
    threads: usize,
    f: impl Fn(I) -> T + Sync,
) -> Result<Vec<T>, DiagError> {
    let n = items.len();
    let mut queue: Vec<(usize, I)> = items.into_iter().enumerate().collect();
    queue.reverse(); // popped from the back
    let queue = std::sync::Mutex::new(queue);
    let results = std::sync::Mutex::new((0..n).map(|_| None).collect::<Vec<Option<T>>>());
    let work = || {
        loop {
            let next = queue.lock().ok().and_then(|mut q| q.pop());
            let Some((i, item)) = next else { break };
            let out = f(item);
            if let Ok(mut r) = results.lock() {
                r[i] = Some(out);
            }
        }
    };
    let panicked = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads.clamp(1, n.max(1)))
            .map(|_| s.spawn(work))
            .collect();
        workers.into_iter().any(|w| w.join().is_err())
    });
    let lost = || DiagError::Numerical("a worker thread panicked".into());
    if panicked {
        return Err(lost());
    }
    results
        .into_inner()
        .map_err(|_| lost())?
        .into_iter()
        .map(|r| r.ok_or_else(lost))
        .collect()
}
