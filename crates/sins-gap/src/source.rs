//! A dataset file as a [`SampleSource`]: every pass opens the file again and reads it in
//! bounded batches, so a 15 h dataset never sits in memory whole.

use sins_data::{DatasetInfo, DatasetReader};
use sins_diag::DiagError;
use sins_diag::source::{BatchSink, SampleSource};
use std::path::PathBuf;

/// A dataset in the project's format (Parquet or CSV).
#[derive(Clone)]
pub struct DatasetSource {
    path: PathBuf,
    info: DatasetInfo,
    name: String,
}

impl DatasetSource {
    /// Open `path` (validates its header and metadata) for the run called `name`.
    pub fn open(path: impl Into<PathBuf>, name: &str) -> Result<Self, sins_data::DataError> {
        let path = path.into();
        let info = DatasetReader::open(&path)?.info().clone();
        Ok(Self {
            path,
            info,
            name: name.to_string(),
        })
    }

    /// The dataset's description (site, rate, labels, columns).
    pub fn info(&self) -> &DatasetInfo {
        &self.info
    }
}

impl SampleSource for DatasetSource {
    fn sample_interval_s(&self) -> f64 {
        self.info.meta.sample_interval_s()
    }

    fn visit(&mut self, sink: &mut BatchSink<'_>) -> Result<(), DiagError> {
        let fail = |e: sins_data::DataError| DiagError::Source {
            run: self.name.clone(),
            reason: e.to_string(),
        };
        let mut reader = DatasetReader::open(&self.path).map_err(fail)?;
        let mut zeros: Vec<u16> = Vec::new();
        while let Some(batch) = reader.next_batch().map_err(fail)? {
            match &batch.segment_index {
                Some(seg) => sink(&batch.samples, seg)?,
                None => {
                    zeros.resize(batch.samples.len(), 0);
                    sink(&batch.samples, &zeros)?
                }
            }
        }
        Ok(())
    }

    fn try_clone(&self) -> Option<Box<dyn SampleSource>> {
        Some(Box::new(self.clone()))
    }
}
