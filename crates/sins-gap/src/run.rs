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

/// Replay every dataset and diagnose the gap against a twin with sensor noise `noise`.
pub fn diagnose_datasets(
    req: &DiagnoseRequest,
    noise: NoiseSpec,
) -> Result<DiagnosisOutcome, GapError> {
    diagnose_replayed(replay_datasets(req)?, req, noise)
}

/// [`diagnose_datasets`] with the twin's noise from `identify` (it returns the noise and
/// whatever else its caller wants, e.g. notes). With two or more worker threads
/// (`req.config.threads`) it runs on a second thread while the datasets are replayed: the
/// identification and the replays read the files independently, so the results are those of
/// running one after the other, in about the time of the longer of the two. An error of
/// `identify` wins over one of the replays: it is what running the identification first
/// reports.
pub fn diagnose_datasets_identifying<T: Send, E: Send + From<GapError>>(
    req: &DiagnoseRequest,
    identify: impl FnOnce() -> Result<(NoiseSpec, T), E> + Send,
) -> Result<(DiagnosisOutcome, T), E> {
    if req.config.threads < 2 {
        let (noise, extra) = identify()?;
        return Ok((diagnose_datasets(req, noise)?, extra));
    }
    let (identified, replayed) = std::thread::scope(|scope| {
        let worker = scope.spawn(identify);
        let replayed = replay_datasets(req);
        (worker.join(), replayed)
    });
    let (noise, extra) = identified.map_err(|_| {
        GapError::Invalid("the noise identification stopped unexpectedly (a panic)".into())
    })??;
    Ok((diagnose_replayed(replayed?, req, noise)?, extra))
}

/// The datasets replayed: the runs as the diagnosis takes them, what the report says of each,
/// and the replays' wall time.
struct Replayed {
    runs: Vec<RunData>,
    infos: Vec<RunInfo>,
    replay_s: f64,
}

/// Replay every dataset of `req` with its parameter set (the real error tracks).
fn replay_datasets(req: &DiagnoseRequest) -> Result<Replayed, GapError> {
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
    Ok(Replayed {
        runs,
        infos,
        replay_s: started.elapsed().as_secs_f64(),
    })
}

/// Diagnose the replayed runs against the twin with sensor noise `noise`.
fn diagnose_replayed(
    replayed: Replayed,
    req: &DiagnoseRequest,
    noise: NoiseSpec,
) -> Result<DiagnosisOutcome, GapError> {
    let mut input = DiagnosisInput {
        runs: replayed.runs,
        params: req.params,
        param_sigma: req.param_sigma,
        param_covariance: req.param_covariance.clone(),
        noise,
        calibration_run: req.calibration_run.clone(),
    };
    let t = Instant::now();
    let diagnosis = diagnose(&mut input, &req.config)?;
    Ok(DiagnosisOutcome {
        diagnosis,
        runs: replayed.infos,
        replay_s: replayed.replay_s,
        diagnose_s: t.elapsed().as_secs_f64(),
    })
}
