#![doc = include_str!("../README.md")]

use std::path::Path;

mod allan;
mod nav;
pub use allan::{AllanRecord, write_allan};
pub use nav::{
    Annotation, NavRecording, ScalarSeries, Strip2, TIMELINE, write_navigation, write_timeseries,
};

/// Errors while writing a Rerun recording.
#[derive(Debug, thiserror::Error)]
pub enum VizError {
    /// The recording could not be created or written.
    #[error("{path}: cannot write Rerun recording: {message}")]
    Rerun {
        /// Target file.
        path: String,
        /// What rerun reported.
        message: String,
    },
    /// The encoded recording could not be written to its file.
    #[error("{path}: cannot write Rerun recording: {source}")]
    Write {
        /// Target file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// A recording file does not decode (truncated or not a recording).
    #[error("{path}: not a complete Rerun recording: {message}")]
    Invalid {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
}

/// A recording stream that keeps everything in memory, and its storage.
pub(crate) fn memory_stream(
    builder: rerun::RecordingStreamBuilder,
    path: &Path,
) -> Result<(rerun::RecordingStream, rerun::sink::MemorySinkStorage), VizError> {
    builder.memory().map_err(|e| VizError::Rerun {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}

/// Encodes what `storage` holds and writes it to `path` aside and renamed into place.
pub(crate) fn save_memory(
    storage: &rerun::sink::MemorySinkStorage,
    path: &Path,
) -> Result<(), VizError> {
    let bytes = storage.drain_as_bytes().map_err(|e| VizError::Rerun {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    sins_files::write_file_atomically(path, &bytes).map_err(|source| VizError::Write {
        path: path.display().to_string(),
        source,
    })
}

/// Decodes every message of the recording at `path` and checks that it ends with Rerun's
/// footer (a truncated file fails, however few bytes it lost); returns the number of messages.
pub fn verify_recording(path: &Path) -> Result<usize, VizError> {
    use rerun::external::re_log_encoding::rrd::DecoderApp;
    let invalid = |message: String| VizError::Invalid {
        path: path.display().to_string(),
        message,
    };
    let bytes = std::fs::read(path).map_err(|e| invalid(e.to_string()))?;
    check_stream_footer(&bytes).map_err(invalid)?;
    let mut it = DecoderApp::decode_eager(bytes.as_slice()).map_err(|e| invalid(e.to_string()))?;
    let mut n = 0;
    for msg in it.by_ref() {
        let _msg = msg.map_err(|e| invalid(e.to_string()))?;
        n += 1;
    }
    let manifests = it.rrd_manifests().map_err(|e| invalid(e.to_string()))?;
    if manifests.is_empty() {
        return Err(invalid("no footer (the file is cut short)".into()));
    }
    Ok(n)
}

/// The stream footer Rerun ends a file with, checked byte for byte: the last 32 bytes are the
/// span of the footer payload (start and length, u64 little-endian) and its xxh32 checksum,
/// then `RRF2`, `FOOT` and the number of footers (1). The decoder alone accepts a file that
/// lost up to 32 bytes of it.
fn check_stream_footer(bytes: &[u8]) -> Result<(), String> {
    use rerun::external::re_log_encoding::rrd::{RRD_FOURCC, StreamFooter};
    let n = StreamFooter::ENCODED_SIZE_BYTES;
    let cut = || "no footer (the file is cut short)".to_string();
    let tail = bytes
        .len()
        .checked_sub(n)
        .map(|k| &bytes[k..])
        .ok_or_else(cut)?;
    let word = |at: usize, len: usize| &tail[at..at + len];
    let u64_at = |at: usize| {
        word(at, 8)
            .iter()
            .rev()
            .fold(0u64, |v, &b| v << 8 | b as u64)
    };
    if word(20, 4) != RRD_FOURCC || word(24, 4) != StreamFooter::RRD_IDENTIFIER {
        return Err(cut());
    }
    if word(28, 4) != 1u32.to_le_bytes() {
        return Err("the stream footer does not point at exactly one footer".into());
    }
    let (start, len) = (u64_at(0), u64_at(8));
    let payload = usize::try_from(start)
        .ok()
        .zip(usize::try_from(len).ok())
        .and_then(|(s, l)| bytes.get(s..s.checked_add(l)?))
        .ok_or_else(|| "the stream footer points outside the file".to_string())?;
    if StreamFooter::compute_crc(payload).to_le_bytes() != word(16, 4) {
        return Err("the footer's checksum does not match (the file is damaged)".into());
    }
    Ok(())
}

/// Send one scalar series under `entity` on the duration timeline `timeline` as a single chunk
/// of columns: one call, however many points. Logged one by one through the recording's
/// batcher, `calibrate`'s 92 000 curve points (1392 snapshots of 66 curves) cost 0.30 s and
/// 107 MB of peak memory more (1.19 s and 152 MB for the whole run against 0.89 s and 45 MB).
pub(crate) fn send_scalars(
    stream: &rerun::RecordingStream,
    entity: &str,
    timeline: &'static str,
    times_s: impl Iterator<Item = f64>,
    values: impl Iterator<Item = f64>,
) -> Result<(), String> {
    let times = rerun::TimeColumn::new_duration_secs(timeline, times_s);
    let columns = rerun::Scalars::update_fields()
        .with_scalars(values)
        .columns_of_unit_batches()
        .map_err(|e| e.to_string())?;
    stream
        .send_columns(entity, [times], columns)
        .map_err(|e| e.to_string())
}

/// One named time series: `(t_s, value)` pairs logged as scalars under `entity`.
pub struct Series<'a> {
    /// Entity path, e.g. `calibration/B_gx`.
    pub entity: &'a str,
    /// Samples (time in seconds, value in the series' unit).
    pub points: &'a [(f64, f64)],
}

/// Write scalar time series to an `.rrd` file (aside, then renamed into place) on a `time_s` timeline (application id
/// `sinsbench`, recording named `name`).
pub fn write_series(path: &Path, name: &str, series: &[Series<'_>]) -> Result<(), VizError> {
    let err = |e: &dyn std::fmt::Display| VizError::Rerun {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let (rec, storage) = memory_stream(
        rerun::RecordingStreamBuilder::new("sinsbench").recording_name(name),
        path,
    )?;
    for s in series {
        let times = s.points.iter().map(|p| p.0);
        let values = s.points.iter().map(|p| p.1);
        send_scalars(&rec, s.entity, "time_s", times, values).map_err(|e| err(&e))?;
    }
    save_memory(&storage, path)
}
