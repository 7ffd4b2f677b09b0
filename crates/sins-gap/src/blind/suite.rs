//! Running the blind suite: seal, then per case simulate the "real" IMU, calibrate it, write its
//! navigation datasets, diagnose them blind, and finally open the manifests and grade.

use super::grade::{Grades, grade, render_grades};
use super::plan::{CaseAnswer, SuiteShape, draw_cases};
use super::seal::{SealIndex, open, seal};
use crate::GapError;
use crate::run::{DiagnoseRequest, diagnose_datasets};
use sins_config::load_experiment;
use sins_diag::input::DiagnoseConfig;
use sins_diag::noise::NoiseSpec;
use sins_diag::report::Diagnosis;
use sins_harness::HarnessError;
use sins_harness::pipeline::{calibration_filter, filter_noise_for};
use sins_imu::ParamModel;
use sins_report::{Progress, simulate_to_dataset, simulate_to_dataset_with};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Settings of a blind suite.
#[derive(Clone, Debug)]
pub struct SuiteConfig {
    /// Output directory (sealed manifests, per-case diagnoses, the graded report).
    pub out: PathBuf,
    /// Seed of the case draw.
    pub suite_seed: u64,
    /// How many cases of each sort.
    pub shape: SuiteShape,
    /// The calibration experiment of the "real" IMU (its first run).
    pub calibration_experiment: PathBuf,
    /// The navigation experiment whose runs each case records.
    pub navigation_experiment: PathBuf,
    /// Which of its runs (by name); empty = all.
    pub navigation_runs: Vec<String>,
    /// Keep each case's datasets (about 0.6 GB per 15 h run) instead of deleting them.
    pub keep_datasets: bool,
    /// Run only these cases of the draw (names such as `case07`; empty = all). The draw and
    /// the seal are those of the whole suite; the grades cover the cases run.
    pub only: Vec<String>,
    /// Diagnosis settings.
    pub diagnose: DiagnoseConfig,
}

/// Per-case progress and timing.
#[derive(Clone, Debug)]
pub struct CaseTiming {
    /// Case.
    pub case: String,
    /// Simulation + calibration + dataset writing (s).
    pub generate_s: f64,
    /// Replays + diagnosis (s).
    pub diagnose_s: f64,
}

/// The whole suite's result.
#[derive(Clone, Debug)]
pub struct SuiteResult {
    /// The seal.
    pub index: SealIndex,
    /// The grades.
    pub grades: Grades,
    /// Per-case timing.
    pub timing: Vec<CaseTiming>,
    /// `report.md` of the suite.
    pub markdown: String,
}

/// Name of each case's calibration run among its datasets.
const CALIBRATION_RUN: &str = "cal";

/// Generate one case's data from its (sealed) answer: calibrate the real IMU, write its
/// calibration run and its navigation runs; returns the dataset list and the calibrated
/// parameter set.
fn generate(
    cfg: &SuiteConfig,
    answer: &CaseAnswer,
    dir: &Path,
    progress: &mut dyn Progress,
) -> Result<(Vec<(String, PathBuf)>, sins_kf::CalibrationResult), GapError> {
    let cal_exp = load_experiment(&cfg.calibration_experiment)?;
    let nav_exp = load_experiment(&cfg.navigation_experiment)?;
    let effect = answer.spec();
    let mut cal = cal_exp
        .scenarios
        .first()
        .cloned()
        .ok_or_else(|| GapError::Invalid("the calibration experiment has no run".into()))?;
    cal.seed = answer.seed;
    cal.effects.extend(effect.clone());
    std::fs::create_dir_all(dir).map_err(|e| GapError::io(dir, e))?;
    // The calibration run, simulated once: written as a file (the diagnosis replays it and
    // measures from it how the calibration absorbed the effect) and fed to the 42-state filter.
    let model = ParamModel::States42;
    let cal_err = |source| HarnessError::Calibration {
        run: cal.name.clone(),
        states: model.n_states(),
        source,
    };
    let mut filter = calibration_filter(
        model,
        1.0 / cal.rate_hz,
        cal.site,
        filter_noise_for(&cal.noise),
        cal.truth.reference_temperature_degc,
    )
    .map_err(cal_err)?;
    let cal_file = dir.join(format!("{CALIBRATION_RUN}.parquet"));
    simulate_to_dataset_with(&cal_exp.name, &cal, &cal_file, progress, &mut |samples| {
        for s in samples {
            filter.push(s).map_err(cal_err)?;
        }
        Ok(())
    })?;
    let result = filter.finish().map_err(cal_err)?;
    let mut datasets = vec![(CALIBRATION_RUN.to_string(), cal_file)];
    for (i, sc) in nav_exp.scenarios.iter().enumerate() {
        if !cfg.navigation_runs.is_empty() && !cfg.navigation_runs.contains(&sc.name) {
            continue;
        }
        let mut sc = sc.clone();
        sc.seed = answer.seed.wrapping_add(100 + i as u64);
        sc.effects.extend(effect.clone());
        let file = dir.join(format!("{}.parquet", sc.name));
        simulate_to_dataset(&nav_exp.name, &sc, &file, progress)?;
        datasets.push((sc.name.clone(), file));
    }
    Ok((datasets, result))
}

/// Run the suite: draw and seal, generate and diagnose every case, open and grade.
pub fn run_suite(cfg: &SuiteConfig, progress: &mut dyn Progress) -> Result<SuiteResult, GapError> {
    std::fs::create_dir_all(&cfg.out).map_err(|e| GapError::io(&cfg.out, e))?;
    let answers = draw_cases(&cfg.shape, cfg.suite_seed);
    let index = seal(&cfg.out, cfg.suite_seed, &answers)?;
    let noise = NoiseSpec::from(
        &load_experiment(&cfg.navigation_experiment)?
            .scenarios
            .first()
            .ok_or_else(|| GapError::Invalid("the navigation experiment has no run".into()))?
            .noise,
    );
    if let Some(unknown) = cfg
        .only
        .iter()
        .find(|c| !answers.iter().any(|a| &a.case == *c))
    {
        return Err(GapError::Invalid(format!(
            "--only: no case named '{unknown}' in a suite of {} cases (case01 ... case{:02})",
            answers.len(),
            answers.len()
        )));
    }
    let selected = |case: &str| cfg.only.is_empty() || cfg.only.iter().any(|c| c == case);
    let mut diagnoses: Vec<(String, Diagnosis)> = Vec::new();
    let mut timing = Vec::new();
    for answer in answers.iter().filter(|a| selected(&a.case)) {
        let case_dir = cfg.out.join("cases").join(&answer.case);
        let t = Instant::now();
        let (datasets, cal) = generate(cfg, answer, &case_dir.join("data"), progress)?;
        let generate_s = t.elapsed().as_secs_f64();
        // From here on the diagnosis sees only files and the calibrated parameter set.
        let t = Instant::now();
        let request = DiagnoseRequest {
            datasets: datasets.clone(),
            params: cal.params,
            param_sigma: Some(cal.sigma),
            param_covariance: Some(cal.param_covariance.clone()),
            noise,
            calibration_run: Some(CALIBRATION_RUN.to_string()),
            config: cfg.diagnose.clone(),
        };
        let outcome = diagnose_datasets(&request)?;
        crate::write_diagnosis(&case_dir, "diagnosis", &outcome)?;
        timing.push(CaseTiming {
            case: answer.case.clone(),
            generate_s,
            diagnose_s: t.elapsed().as_secs_f64(),
        });
        if !cfg.keep_datasets {
            let data = case_dir.join("data");
            std::fs::remove_dir_all(&data).map_err(|e| GapError::io(&data, e))?;
        }
        diagnoses.push((answer.case.clone(), outcome.diagnosis));
    }
    // Only now: open the sealed manifests (hash-checked) and grade.
    let opened = open(&cfg.out, &index)?;
    let pairs: Vec<(CaseAnswer, Diagnosis)> = opened
        .into_iter()
        .filter(|a| selected(&a.case))
        .zip(diagnoses)
        .map(|(a, (case, d))| {
            debug_assert_eq!(a.case, case);
            (a, d)
        })
        .collect();
    let grades = grade(&pairs);
    let mut markdown = render_grades(&grades, &index.suite_sha256);
    markdown.push_str("\n## Time per case (s)\n\n| case | generate | diagnose |\n|---|---|---|\n");
    for t in &timing {
        markdown.push_str(&format!(
            "| {} | {:.1} | {:.1} |\n",
            t.case, t.generate_s, t.diagnose_s
        ));
    }
    Ok(SuiteResult {
        index,
        grades,
        timing,
        markdown,
    })
}
