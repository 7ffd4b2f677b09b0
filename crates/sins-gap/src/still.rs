//! Stillness of a dataset file: the windows of the stillness detector over a whole run, its
//! still stretches and motion, for the alignment check of `navigate`.

use crate::GapError;
use sins_noiseid::still::{Stillness, StillnessConfig, Window, WindowBuilder, detect};
use std::path::Path;

/// False alarms per hour of still data when motion refuses an alignment: strict, since a
/// refusal stops the user (a real disturbance exceeds this threshold many times over).
pub const ALIGNMENT_FALSE_ALARMS_PER_HOUR: f64 = 1e-6;

/// A dataset's still stretches and motion.
#[derive(Clone, Debug)]
pub struct DatasetStillness {
    /// The detector's windows.
    pub windows: Vec<Window>,
    /// Its verdict.
    pub stillness: Stillness,
}

impl DatasetStillness {
    /// The still stretches (start, end; s) of at least `min_s`.
    pub fn still_stretches(&self, min_s: f64) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        let mut open: Option<(f64, f64)> = None;
        let step = |w: &Window, next: Option<&Window>| next.map_or(w.start_s + 1.0, |n| n.start_s);
        for (i, w) in self.windows.iter().enumerate() {
            let end = step(w, self.windows.get(i + 1));
            match (self.stillness.still[i], &mut open) {
                (true, Some(o)) => o.1 = end,
                (true, None) => open = Some((w.start_s, end)),
                (false, Some(o)) => {
                    out.push(*o);
                    open = None;
                }
                (false, None) => {}
            }
        }
        out.extend(open);
        out.retain(|(a, b)| b - a >= min_s);
        out
    }
}

/// Run the stillness detector over the dataset at `path` (every sample a candidate), over its
/// first `max_duration_s` when given (the samples after it are not read).
pub fn dataset_stillness(
    path: &Path,
    cfg: &StillnessConfig,
    max_duration_s: Option<f64>,
) -> Result<DatasetStillness, GapError> {
    let mut reader = sins_data::DatasetReader::open(path)?;
    let h = reader.info().meta.sample_interval_s();
    let mut b = WindowBuilder::new(h, cfg);
    let mut until_s: Option<f64> = None;
    'read: while let Some(batch) = reader.next_batch()? {
        for s in &batch.samples {
            let until = *until_s.get_or_insert(s.t_s + max_duration_s.unwrap_or(f64::INFINITY));
            if s.t_s > until {
                break 'read;
            }
            b.push(s.t_s, sins_noiseid::still::rates(s, h), true);
        }
        reader.recycle(batch);
    }
    b.close();
    let name = path
        .file_stem()
        .map_or("run".into(), |s| s.to_string_lossy().into_owned());
    let stillness = detect(&name, &b.windows, cfg);
    Ok(DatasetStillness {
        windows: b.windows,
        stillness,
    })
}
