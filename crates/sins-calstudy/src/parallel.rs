//! A tiny deterministic work pool: jobs are taken in any order by any thread, results are
//! stored by job index, so the output does not depend on the thread count.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// `f(0), f(1), …, f(n − 1)` computed on up to `threads` scoped threads (at least 1), returned in
/// index order. A panicking job propagates the panic to the caller.
pub fn map_indexed<R: Send>(n: usize, threads: usize, f: impl Fn(usize) -> R + Sync) -> Vec<R> {
    let next = AtomicUsize::new(0);
    let slots: Vec<Mutex<Option<R>>> = (0..n).map(|_| Mutex::new(None)).collect();
    let worker = || {
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if i >= n {
                break;
            }
            let r = f(i);
            if let Ok(mut slot) = slots[i].lock() {
                *slot = Some(r);
            }
        }
    };
    let threads = threads.clamp(1, n.max(1));
    std::thread::scope(|s| {
        for _ in 1..threads {
            s.spawn(worker);
        }
        worker();
    });
    slots
        .into_iter()
        .filter_map(|m| m.into_inner().ok().flatten())
        .collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn results_come_back_in_index_order_for_any_thread_count() {
        for threads in [1, 2, 5] {
            let v = super::map_indexed(17, threads, |i| i * i);
            assert_eq!(v, (0..17).map(|i| i * i).collect::<Vec<_>>());
        }
    }
}
