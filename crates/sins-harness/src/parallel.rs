//! One deterministic work pool for the harness and the crates above it: jobs are taken in any
//! order by scoped threads and their results are stored by job index, so no output depends on
//! the thread count (each job is computed alone, from its own inputs and seeds).

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;

/// `f(0), f(1), …, f(n − 1)` computed on up to `threads` scoped threads (at least 1), returned in
/// index order. A panicking job propagates the panic to the caller.
pub fn map_indexed<R: Send>(n: usize, threads: usize, f: impl Fn(usize) -> R + Sync) -> Vec<R> {
    map_with_progress(n, threads, |i, _| f(i), &mut |_| {})
}

/// [`map_indexed`] for long jobs that report progress: job `i` runs as `f(i, done)` and calls
/// `done(units)` as it advances; `on_progress(units)` runs on the calling thread (which draws
/// the bar and computes nothing), so the callback need not be `Send`.
pub fn map_with_progress<R: Send>(
    n: usize,
    threads: usize,
    f: impl Fn(usize, &dyn Fn(u64)) -> R + Sync,
    on_progress: &mut dyn FnMut(u64),
) -> Vec<R> {
    let next = AtomicUsize::new(0);
    let slots: Vec<Mutex<Option<R>>> = (0..n).map(|_| Mutex::new(None)).collect();
    let (tx, rx) = mpsc::channel::<u64>();
    let (next, slots, f) = (&next, &slots, &f);
    std::thread::scope(|s| {
        for _ in 0..threads.clamp(1, n.max(1)) {
            let tx = tx.clone();
            s.spawn(move || {
                let done = |units: u64| {
                    // The receiver lives until every worker has ended.
                    let _ = tx.send(units);
                };
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= n {
                        break;
                    }
                    let r = f(i, &done);
                    if let Ok(mut slot) = slots[i].lock() {
                        *slot = Some(r);
                    }
                }
            });
        }
        drop(tx);
        for units in rx {
            on_progress(units);
        }
    });
    slots
        .iter()
        .filter_map(|m| m.lock().ok().and_then(|mut v| v.take()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_back_in_index_order_for_any_thread_count() {
        for threads in [1, 2, 5] {
            let v = map_indexed(17, threads, |i| i * i);
            assert_eq!(v, (0..17).map(|i| i * i).collect::<Vec<_>>());
        }
    }

    #[test]
    fn every_unit_of_progress_reaches_the_calling_thread() {
        for threads in [1, 3] {
            let mut total = 0u64;
            let v = map_with_progress(
                6,
                threads,
                |i, done| {
                    for _ in 0..=i {
                        done(10);
                    }
                    i
                },
                &mut |u| total += u,
            );
            assert_eq!(v, (0..6).collect::<Vec<_>>());
            // 10 units for each of 1 + 2 + … + 6 calls.
            assert_eq!(total, 210);
        }
    }
}
