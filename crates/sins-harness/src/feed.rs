//! The simulator on a thread of its own, feeding its batches to consumers on threads of their
//! own: a run's simulation, replays and filters overlap instead of taking turns on one core.
//! Every consumer sees the same batches in the same order as on one thread, so no result
//! depends on the thread count.

use crate::HarnessError;
use sins_sim::{SimBatch, Simulator};
use std::sync::Arc;
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::thread::{Scope, ScopedJoinHandle};

/// Batches simulated ahead of the slowest consumer (each about 1.6 MB at 16,384 samples).
const BATCHES_AHEAD: usize = 2;

/// One consumer of a run's batches, called once per batch, in order.
pub type Consumer<'a> = Box<dyn FnMut(&SimBatch) -> Result<(), HarnessError> + Send + 'a>;

/// Run `sim` in batches of `batch_len` samples and hand every batch, in order, to each of
/// `consumers`. With `threads` ≥ 2 the simulator and every consumer but the first run on
/// threads of their own (the first runs on the calling thread); with 1 everything runs on the
/// calling thread, batch by batch. `progress(samples)` runs on the calling thread once the
/// first consumer has taken a batch. On failure the first consumer's error in order is
/// returned and the others' work is dropped.
pub fn feed(
    sim: &mut Simulator,
    batch_len: usize,
    threads: usize,
    consumers: &mut [Consumer<'_>],
    progress: &mut dyn FnMut(u64),
) -> Result<(), HarnessError> {
    if threads < 2 || consumers.is_empty() {
        return sim.run(batch_len, |b| {
            for c in consumers.iter_mut() {
                c(b)?;
            }
            progress(b.len() as u64);
            Ok(())
        });
    }
    let Some((first, rest)) = consumers.split_first_mut() else {
        return Ok(());
    };
    let (senders, mut receivers): (Vec<_>, Vec<_>) = (0..=rest.len())
        .map(|_| sync_channel::<Arc<SimBatch>>(BATCHES_AHEAD))
        .unzip();
    let first_rx = receivers.remove(0);
    // Returning early drops the receivers, which stops the producer before the scope joins it.
    std::thread::scope(|s| {
        let producer = spawn(s, "simulator".into(), move || {
            produce(sim, batch_len, &senders)
        })?;
        let others = rest
            .iter_mut()
            .zip(receivers)
            .enumerate()
            .map(|(k, (c, rx))| {
                spawn(s, format!("consumer {}", k + 1), move || {
                    consume(c, &rx, &mut |_| {})
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        // A consumer that stops early drops its receiver, which stops the producer, whose end
        // ends every other consumer.
        let first_result = consume(first, &first_rx, progress);
        drop(first_rx);
        join(producer);
        first_result?;
        others.into_iter().try_for_each(join)
    })
}

/// `f` on a named thread of scope `s`.
fn spawn<'scope, T: Send + 'scope>(
    s: &'scope Scope<'scope, '_>,
    name: String,
    f: impl FnOnce() -> T + Send + 'scope,
) -> Result<ScopedJoinHandle<'scope, T>, HarnessError> {
    std::thread::Builder::new()
        .name(name)
        .spawn_scoped(s, f)
        .map_err(HarnessError::Thread)
}

/// The producer: every batch, shared, to every consumer, until the run ends or one hangs up
/// (that consumer reports its own error).
fn produce(sim: &mut Simulator, batch_len: usize, senders: &[SyncSender<Arc<SimBatch>>]) {
    struct HungUp;
    let _: Result<(), HungUp> = sim.run(batch_len, |b| {
        let shared = Arc::new(b.clone());
        senders
            .iter()
            .try_for_each(|tx| tx.send(Arc::clone(&shared)).map_err(|_| HungUp))
    });
}

/// A consumer's loop over the batches until the producer ends or the consumer fails.
fn consume(
    c: &mut Consumer<'_>,
    rx: &Receiver<Arc<SimBatch>>,
    progress: &mut dyn FnMut(u64),
) -> Result<(), HarnessError> {
    for b in rx {
        c(&b)?;
        progress(b.len() as u64);
    }
    Ok(())
}

/// The thread's result; a panic on it goes on in the caller.
fn join<T>(h: ScopedJoinHandle<'_, T>) -> T {
    h.join().unwrap_or_else(|p| std::panic::resume_unwind(p))
}
