//! Early write-back of a large file being written: a helper thread fsyncs the file every
//! [`SYNC_EVERY_BYTES`] so that the disk works while the data is still being produced and the
//! final fsync before the atomic rename is short.

use std::fs::File;
use std::sync::mpsc::{SyncSender, TrySendError, sync_channel};
use std::thread::JoinHandle;

/// Bytes appended between two early syncs.
const SYNC_EVERY_BYTES: u64 = 128 << 20;

/// Handle of the helper thread.
pub(crate) struct EarlySync {
    tx: Option<SyncSender<()>>,
    handle: Option<JoinHandle<std::io::Result<()>>>,
    pending_bytes: u64,
}

impl EarlySync {
    /// Start syncing `file` (a clone of its handle is used); `None` when that is impossible, in
    /// which case everything is synced by the final fsync alone.
    pub fn start(file: &File) -> Option<Self> {
        let f = file.try_clone().ok()?;
        let (tx, rx) = sync_channel::<()>(1);
        let handle = std::thread::Builder::new()
            .name("sins-data-sync".into())
            .spawn(move || {
                for () in rx {
                    f.sync_data()?;
                }
                Ok(())
            })
            .ok()?;
        Some(Self {
            tx: Some(tx),
            handle: Some(handle),
            pending_bytes: 0,
        })
    }

    /// Note that about `bytes` more bytes were written; may request a sync (never blocks).
    pub fn wrote(&mut self, bytes: u64) {
        self.pending_bytes += bytes;
        if self.pending_bytes >= SYNC_EVERY_BYTES
            && let Some(tx) = &self.tx
        {
            match tx.try_send(()) {
                Ok(()) | Err(TrySendError::Full(())) => self.pending_bytes = 0,
                Err(TrySendError::Disconnected(())) => self.tx = None,
            }
        }
    }

    /// Wait for the helper; reports the first sync error.
    pub fn finish(mut self) -> std::io::Result<()> {
        self.tx = None;
        match self.handle.take().map(JoinHandle::join) {
            Some(Ok(r)) => r,
            Some(Err(_)) => Err(std::io::Error::other("the sync thread panicked")),
            None => Ok(()),
        }
    }
}

impl Drop for EarlySync {
    fn drop(&mut self) {
        self.tx = None;
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}
