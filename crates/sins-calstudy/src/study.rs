//! The whole calibration study: settings, the jobs (Monte Carlo of Table 1, the 30-state run,
//! the four least-squares points, the proposed run on the Table 3 truth), run in parallel and
//! collected by index, and the result structures.

use crate::baseline::{LsStudy, stable_chamber_degc};
use crate::error::StudyError;
use crate::montecarlo::{SeedOutcome, Table1Study};
use crate::reference::{TABLE3_FILE, load_table3};
use crate::run::{CalibrationRun, calibrate_scenario, config_for_scenario, truncate_motion};
use crate::table1mc::Table1MonteCarlo;
use crate::table3::Table3Study;
use crate::thirty::ThirtyStateStudy;
use serde::Serialize;
use sins_config::{load_experiment, motion_duration_s};
use sins_harness::parallel::map_indexed;
use sins_imu::ParamModel;
use sins_nav::{ARCSEC, DEG_PER_H, UG};
use sins_sim::Scenario;
use sins_sim::noise::GM_ALLAN_PEAK_RATIO;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What to run.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyConfig {
    /// The Table 1 simulation (`experiments/paper_calibration.toml`); its first run's seed starts
    /// the Monte Carlo.
    pub table1_experiment: PathBuf,
    /// The proposed calibration of the Table 3 truth (`experiments/paper_truth_calibration.toml`).
    pub truth_experiment: PathBuf,
    /// The least-squares baseline's temperature points (`experiments/paper_ls_baseline.toml`).
    pub ls_experiment: PathBuf,
    /// Directory of the paper's tables (`experiments/reference`).
    pub reference_dir: PathBuf,
    /// Monte Carlo seeds (the paper study: 10).
    pub seeds: usize,
    /// Worker threads (results do not depend on it).
    pub threads: usize,
    /// Settling time before each least-squares point (h, not simulated): the paper needs "more
    /// than 3 h" per point, 4 × (4.2 h + 3 h) = 28.8 h.
    pub settling_h: f64,
    /// Cut every scenario's motion after this many seconds (shortened studies, tests).
    pub max_duration_s: Option<f64>,
}

impl StudyConfig {
    /// The paper study on the files of an `experiments/` directory: 10 seeds, 2 threads, 3 h
    /// settling, full length.
    pub fn paper(experiments_dir: impl AsRef<Path>) -> Self {
        let d = experiments_dir.as_ref();
        Self {
            table1_experiment: d.join("paper_calibration.toml"),
            truth_experiment: d.join("paper_truth_calibration.toml"),
            ls_experiment: d.join("paper_ls_baseline.toml"),
            reference_dir: d.join("reference"),
            seeds: 10,
            threads: 2,
            settling_h: 3.0,
            max_duration_s: None,
        }
    }
}

/// The sensor noise of the Table 1 experiment in its file units (the filter assumes the same).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NoiseFigures {
    /// Gyro angle random walk (deg/sqrt(h)).
    pub gyro_arw_deg_per_sqrt_h: f64,
    /// Gyro bias instability, Allan figure (deg/h).
    pub gyro_bias_instability_deg_per_h: f64,
    /// Its correlation time (s).
    pub gyro_bias_correlation_s: f64,
    /// Gyro quantum (arcsec).
    pub gyro_quantum_arcsec: f64,
    /// Accelerometer velocity random walk (ug/sqrt(Hz)).
    pub accel_vrw_ug_per_sqrt_hz: f64,
    /// Accelerometer bias instability, Allan figure (ug).
    pub accel_bias_instability_ug: f64,
    /// Its correlation time (s).
    pub accel_bias_correlation_s: f64,
    /// Thermometer noise (degC).
    pub thermometer_noise_degc: f64,
}

/// Settings the study ran with.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StudySettings {
    /// Monte Carlo seeds.
    pub seeds: usize,
    /// Sample rate of the data (Hz).
    pub sample_rate_hz: f64,
    /// Strapdown update rate of the filter's navigation (two-sample updates, Hz).
    pub navigation_rate_hz: f64,
    /// Kalman propagation and measurement-update interval (s).
    pub update_interval_s: f64,
    /// Length of the Table 1 calibration (h, alignment included).
    pub calibration_h: f64,
    /// Alignment before the filter (s).
    pub alignment_s: f64,
    /// Sensor noise of the experiment (and of the filter).
    pub noise: NoiseFigures,
    /// Motion cut (s) for shortened studies; `None` for the full runs.
    pub max_duration_s: Option<f64>,
}

/// Wall-clock figures (the only part of a [`Study`] that differs between runs).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Timing {
    /// One 42-state calibration (Monte Carlo seed 1) run alone: simulation + filter (s).
    pub single_42_state_wall_s: f64,
    /// Of which inside the filter (s).
    pub single_42_state_filter_s: f64,
    /// Samples of that run.
    pub single_42_state_samples: usize,
    /// The whole study (s).
    pub study_wall_s: f64,
    /// Worker threads.
    pub threads: usize,
    /// Calibrations run.
    pub calibrations: usize,
}

/// The whole study. Every field except `timing` is bit-identical for any thread count.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Study {
    /// Settings.
    pub settings: StudySettings,
    /// Table 1 over the Monte Carlo (consistency, NEES, observability, paper comparison).
    pub table1: Table1Study,
    /// The 30-state filter on the Table 1 data.
    pub thirty_state: ThirtyStateStudy,
    /// The least-squares baseline.
    pub ls_baseline: LsStudy,
    /// Table 3 comparison.
    pub table3: Table3Study,
    /// Wall times.
    pub timing: Timing,
}

enum Job {
    Mc(usize),
    NoiseFree,
    Thirty,
    Ls(usize),
    Proposed,
}

fn scenarios(path: &Path, cut: Option<f64>) -> Result<(String, Vec<Scenario>), StudyError> {
    let exp = load_experiment(path)?;
    let mut v = exp.scenarios;
    if let Some(d) = cut {
        v.iter_mut().for_each(|s| truncate_motion(s, d));
    }
    Ok((exp.name, v))
}

fn first(name: &str, v: &[Scenario]) -> Result<Scenario, StudyError> {
    v.first()
        .cloned()
        .ok_or_else(|| StudyError::Setup(format!("experiment `{name}` has no run")))
}

fn hours(sc: &Scenario) -> f64 {
    motion_duration_s(&sc.motion) / 3600.0
}

/// Run the study.
pub fn run_study(cfg: &StudyConfig) -> Result<Study, StudyError> {
    let started = Instant::now();
    let mc = Table1MonteCarlo::load(
        &cfg.table1_experiment,
        &cfg.reference_dir,
        cfg.seeds,
        None,
        cfg.max_duration_s,
    )?;
    let table3 = load_table3(cfg.reference_dir.join(TABLE3_FILE))?;
    let (tr_name, tr) = scenarios(&cfg.truth_experiment, cfg.max_duration_s)?;
    let (ls_name, ls) = scenarios(&cfg.ls_experiment, cfg.max_duration_s)?;
    let base = mc.base().clone();
    let proposed_sc = first(&tr_name, &tr)?;
    for sc in &ls {
        stable_chamber_degc(sc)?;
        if sc.truth != proposed_sc.truth {
            return Err(StudyError::Setup(format!(
                "least-squares run `{}` and `{tr_name}` must calibrate the same truth IMU",
                sc.name
            )));
        }
    }
    let mut jobs: Vec<Job> = (1..cfg.seeds).map(Job::Mc).collect();
    jobs.push(Job::NoiseFree);
    jobs.push(Job::Thirty);
    jobs.extend((0..ls.len()).map(Job::Ls));
    jobs.push(Job::Proposed);
    let run = |sc: &Scenario, model| calibrate_scenario(sc, config_for_scenario(sc, model));
    let mc_run = |i: usize| mc.seed_run(i);
    // Seed 1 alone first: its wall time is one calibration without a concurrent worker.
    let first_run = mc_run(0)?;
    let results = map_indexed(jobs.len(), cfg.threads, |i| match jobs[i] {
        Job::Mc(k) => mc_run(k),
        Job::NoiseFree => crate::table1mc::noise_free_run(&base),
        Job::Thirty => run(&base, ParamModel::States30),
        Job::Ls(k) => run(&ls[k], ParamModel::States30),
        Job::Proposed => run(&proposed_sc, ParamModel::States42),
    });
    let mut runs: Vec<CalibrationRun> = Vec::with_capacity(results.len());
    for r in results {
        runs.push(r?);
    }
    let mut it = runs.into_iter();
    let mut mc_runs = vec![first_run];
    mc_runs.extend(it.by_ref().take(cfg.seeds - 1));
    let noise_free_run = it.next();
    let thirty_run = it.next();
    let ls_runs: Vec<CalibrationRun> = it.by_ref().take(ls.len()).collect();
    let proposed_run = it.next();
    let (Some(noise_free_run), Some(thirty_run), Some(proposed_run)) =
        (noise_free_run, thirty_run, proposed_run)
    else {
        return Err(StudyError::Setup(
            "a calibration job returned no result".into(),
        ));
    };
    let per_seed: Vec<SeedOutcome> = mc_runs
        .iter()
        .zip(mc.seeds())
        .map(|(r, s)| SeedOutcome::new(*s, r, &base.truth))
        .collect();
    let m0 = &mc_runs[0];
    let config = config_for_scenario(&base, ParamModel::States42);
    let n = &base.noise;
    let settings = StudySettings {
        seeds: cfg.seeds,
        sample_rate_hz: base.rate_hz,
        navigation_rate_hz: base.rate_hz / 2.0,
        update_interval_s: config.samples_per_update() as f64 / base.rate_hz,
        calibration_h: hours(&base),
        alignment_s: config.alignment.duration_s,
        noise: NoiseFigures {
            gyro_arw_deg_per_sqrt_h: n.gyro_arw_rad_per_sqrt_s / (sins_nav::DEG / 60.0),
            gyro_bias_instability_deg_per_h: n.gyro_bias_instability_radps * GM_ALLAN_PEAK_RATIO
                / DEG_PER_H,
            gyro_bias_correlation_s: n.gyro_bias_correlation_s,
            gyro_quantum_arcsec: n.gyro_quantum_rad / ARCSEC,
            accel_vrw_ug_per_sqrt_hz: n.accel_vrw_mps_per_sqrt_s / UG,
            accel_bias_instability_ug: n.accel_bias_instability_mps2 * GM_ALLAN_PEAK_RATIO / UG,
            accel_bias_correlation_s: n.accel_bias_correlation_s,
            thermometer_noise_degc: base.thermal.thermometer_noise_degc,
        },
        max_duration_s: cfg.max_duration_s,
    };
    let table1_study = Table1Study::new(
        mc.experiment().to_string(),
        per_seed,
        m0,
        &noise_free_run,
        &base.truth,
        mc.table1(),
    );
    let thirty = ThirtyStateStudy::new(base.seed, &thirty_run, m0, &base.truth);
    let calibrated_h: f64 = ls.iter().map(hours).sum();
    let ls_study = LsStudy::new(
        ls_name,
        &ls,
        &ls_runs,
        &proposed_sc.truth,
        calibrated_h,
        cfg.settling_h,
    )?;
    let table3_study = Table3Study::new(
        tr_name,
        proposed_sc.seed,
        &proposed_run,
        hours(&proposed_sc),
        &ls_study,
        &proposed_sc.truth,
        &table3,
    );
    Ok(Study {
        settings,
        table1: table1_study,
        thirty_state: thirty,
        ls_baseline: ls_study,
        table3: table3_study,
        timing: Timing {
            single_42_state_wall_s: m0.wall.as_secs_f64(),
            single_42_state_filter_s: m0.filter.as_secs_f64(),
            single_42_state_samples: m0.samples,
            study_wall_s: started.elapsed().as_secs_f64(),
            threads: cfg.threads,
            calibrations: jobs.len() + 1,
        },
    })
}
