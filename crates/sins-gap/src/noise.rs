//! The twin's noise identified from datasets (their stationary segments), for `diagnose`
//! without a noise file and for the blind suite's identified-noise twin.

use crate::GapError;
use crate::source::DatasetSource;
use sins_diag::source::SampleSource;
use sins_imu::ImuErrorParams;
use sins_noiseid::{IdentifiedNoise, NoiseIdConfig, RunStationary};
use std::path::PathBuf;

/// Open `datasets` (`(name, path)`) and identify their noise from the segments labelled
/// `labels` (one pass over each), the accelerometer increments compensated with
/// `compensation` when given (see [`RunStationary::compensation`]).
pub fn identify_datasets(
    datasets: &[(String, PathBuf)],
    labels: &[String],
    compensation: Option<&ImuErrorParams>,
) -> Result<IdentifiedNoise, GapError> {
    let cfg = NoiseIdConfig {
        labels: labels.to_vec(),
        ..NoiseIdConfig::default()
    };
    identify_datasets_with(datasets, &cfg, compensation)
}

/// [`identify_datasets`] with every setting of the identification given.
pub fn identify_datasets_with(
    datasets: &[(String, PathBuf)],
    cfg: &NoiseIdConfig,
    compensation: Option<&ImuErrorParams>,
) -> Result<IdentifiedNoise, GapError> {
    let mut sources = Vec::new();
    for (name, path) in datasets {
        sources.push((name.clone(), DatasetSource::open(path, name)?));
    }
    let mut runs: Vec<RunStationary<'_>> = sources
        .iter_mut()
        .map(|(name, s)| {
            let segment_labels = s.info().segment_labels.clone();
            let site = s.info().meta.site;
            RunStationary {
                name: name.clone(),
                source: s as &mut dyn SampleSource,
                segment_labels,
                site,
                compensation: compensation.copied(),
            }
        })
        .collect();
    sins_noiseid::identify_noise(&mut runs, cfg).map_err(|e| {
        let files: Vec<String> = datasets
            .iter()
            .map(|(_, p)| p.display().to_string())
            .collect();
        GapError::Invalid(format!(
            "identifying the noise of {}: {e}",
            files.join(", ")
        ))
    })
}
