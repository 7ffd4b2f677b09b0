//! Diagnosing datasets: replay each with the calibrated parameter set (the "real" error
//! track), then compare it with the twin (`sins_diag::diagnose`).

use crate::{DatasetSource, GapError};
use serde::Serialize;
use sins_diag::diagnose;
use sins_diag::input::{DiagnoseConfig, DiagnosisInput, RunData};
use sins_diag::noise::NoiseSpec;
use sins_diag::replay::replay_run;
use sins_diag::report::Diagnosis;
use sins_harness::pipeline::NamedParams;
use sins_imu::ImuErrorParams;
use std::path::PathBuf;
use std::time::Instant;

/// What to diagnose.
#[derive(Clone, Debug)]
pub struct DiagnoseRequest {
    /// The real runs (name, dataset): a calibration run and/or navigation runs of one IMU on a
    /// turntable at the site in each file's metadata.
    pub datasets: Vec<(String, PathBuf)>,
    /// The calibrated parameter set (what the real replay compensates with).
    pub params: ImuErrorParams,
    /// Its one-sigma per coefficient, when the parameter file carries it.
    pub param_sigma: Option<ImuErrorParams>,
    /// Its full covariance (row-major, eq-8 order, SI) when known (a calibration run in
    /// memory); wins over `param_sigma`.
    pub param_covariance: Option<Vec<f64>>,
    /// The twin's sensor noise.
    pub noise: NoiseSpec,
    /// The dataset (by name) the parameter set was calibrated from, when it is among
    /// `datasets`: its recalibration with each candidate added tells how the calibration
    /// absorbed the candidate (see `sins_diag::absorb`).
    pub calibration_run: Option<String>,
    /// Diagnosis settings.
    pub config: DiagnoseConfig,
}

/// One replayed run, as the report describes it.
#[derive(Clone, Debug, Serialize)]
pub struct RunInfo {
    /// Run name.
    pub name: String,
    /// The dataset.
    pub path: PathBuf,
    /// Length of the data (h).
    pub duration_h: f64,
    /// Largest horizontal error of the real replay (m).
    pub max_horizontal_m: f64,
    /// Segment labels of the dataset.
    pub segment_labels: Vec<String>,
}

/// A diagnosis with what it ran on.
#[derive(Clone, Debug, Serialize)]
pub struct DiagnosisOutcome {
    /// The result.
    pub diagnosis: Diagnosis,
    /// The runs.
    pub runs: Vec<RunInfo>,
    /// Wall time of the replays and of the diagnosis (s).
    pub replay_s: f64,
    /// Wall time of the diagnosis proper (s).
    pub diagnose_s: f64,
}

/// Replay every dataset and diagnose the gap.
pub fn diagnose_datasets(req: &DiagnoseRequest) -> Result<DiagnosisOutcome, GapError> {
    if req.datasets.is_empty() {
        return Err(GapError::Invalid("no dataset to diagnose".into()));
    }
    let started = Instant::now();
    let mut runs = Vec::new();
    let mut infos = Vec::new();
    for (name, path) in &req.datasets {
        let mut source = DatasetSource::open(path, name)?;
        let info = source.info().clone();
        let set = NamedParams {
            key: "calibrated".into(),
            params: req.params,
        };
        sins_report::require_temperatures(path, &info, &[set])?;
        let site = info.meta.site;
        let real = replay_run(name, &mut source, &req.params, &site, &req.config.replay)?;
        let max_horizontal_m = real.summary.as_ref().map_or(0.0, |s| s.max_horizontal_m);
        infos.push(RunInfo {
            name: name.clone(),
            path: path.clone(),
            duration_h: info.n_rows as f64 * info.meta.sample_interval_s() / 3600.0,
            max_horizontal_m,
            segment_labels: info.segment_labels.clone(),
        });
        runs.push(RunData {
            name: name.clone(),
            source: Box::new(source),
            site,
            segment_labels: info.segment_labels.clone(),
            track: real.points,
            temperatures: Some(real.temperatures),
            twin_mean: None,
        });
    }
    let replay_s = started.elapsed().as_secs_f64();
    let mut input = DiagnosisInput {
        runs,
        params: req.params,
        param_sigma: req.param_sigma,
        param_covariance: req.param_covariance.clone(),
        noise: req.noise,
        calibration_run: req.calibration_run.clone(),
    };
    let t = Instant::now();
    let diagnosis = diagnose(&mut input, &req.config)?;
    Ok(DiagnosisOutcome {
        diagnosis,
        runs: infos,
        replay_s,
        diagnose_s: t.elapsed().as_secs_f64(),
    })
}
