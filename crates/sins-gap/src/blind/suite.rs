//! Running the blind suite: seal, then per case simulate the "real" IMU, calibrate it, write its
//! navigation datasets, diagnose them blind, and finally open the manifests and grade.

use super::grade::{Grades, grade, render_grades};
use super::plan::{CALIBRATION_RUN, CaseAnswer, SuiteShape, draw_cases};
use super::seal::{SealIndex, open, seal};
use crate::GapError;
use crate::run::{DiagnoseRequest, diagnose_datasets, diagnose_datasets_identifying};
use sins_config::load_experiment;
use sins_config::markdown::Table;
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
    /// The navigation experiment of the "different histories" cases (those whose answer names
    /// it: [`CaseAnswer::navigation_experiment`], checked against its `name`); the same runs
    /// by name, with other chamber histories.
    pub histories_experiment: PathBuf,
    /// Which of its runs (by name); empty = all.
    pub navigation_runs: Vec<String>,
    /// Keep each case's datasets (about 0.6 GB per 15 h run) instead of deleting them.
    pub keep_datasets: bool,
    /// Run only these cases of the draw (names such as `case07`; empty = all). The draw and
    /// the seal are those of the whole suite; the grades cover the cases run.
    pub only: Vec<String>,
    /// Diagnosis settings.
    pub diagnose: DiagnoseConfig,
    /// The twin's noise identified from each case's own datasets (their stationary
    /// segments, `sins_noiseid`) instead of the navigation experiment's noise file.
    pub identified_noise: bool,
}

impl SuiteConfig {
    /// Whether `case` is run: every case, or only those named in [`SuiteConfig::only`].
    pub fn selects(&self, case: &str) -> bool {
        self.only.is_empty() || self.only.iter().any(|c| c == case)
    }
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
    // The case's own navigation experiment (the "different histories" cases), else the suite's.
    let nav_exp = match &answer.navigation_experiment {
        None => load_experiment(&cfg.navigation_experiment)?,
        Some(name) => {
            let e = load_experiment(&cfg.histories_experiment)?;
            if &e.name != name {
                return Err(GapError::Invalid(format!(
                    "{}: the case records the runs of navigation experiment '{name}', {} is '{}'",
                    answer.case,
                    cfg.histories_experiment.display(),
                    e.name
                )));
            }
            e
        }
    };
    let effect = answer.spec();
    let mut cal = cal_exp
        .scenarios
        .first()
        .cloned()
        .ok_or_else(|| GapError::Invalid("the calibration experiment has no run".into()))?;
    cal.seed = answer.seed;
    // The calibration run is `cal` here (`HiddenEffect::acts_on` also takes `calibration`):
    // an effect of every run, or of the calibration run only, is injected into it; one of a
    // navigation run, or of every navigation run, is not.
    let acts_on = |run: &str| answer.hidden.as_ref().is_none_or(|h| h.acts_on(run));
    if acts_on(CALIBRATION_RUN) {
        cal.effects.extend(effect.clone());
    }
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
        filter.push_batch(samples, None).map_err(cal_err)?;
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
        if acts_on(&sc.name) {
            sc.effects.extend(effect.clone());
        }
        let file = dir.join(format!("{}.parquet", sc.name));
        simulate_to_dataset(&nav_exp.name, &sc, &file, progress)?;
        datasets.push((sc.name.clone(), file));
    }
    Ok((datasets, result))
}

/// A drawn and sealed suite: every case's answer (for generating its data only) and the seal
/// whose hashes are fixed before any diagnosis runs.
#[derive(Clone, Debug)]
pub struct SealedSuite {
    /// The drawn cases, in order (`case01`, `case02`, ...).
    pub answers: Vec<CaseAnswer>,
    /// The seal.
    pub index: SealIndex,
}

/// Draw the cases and seal their answers under `cfg.out/sealed/`; checks `cfg.only`.
pub fn seal_suite(cfg: &SuiteConfig) -> Result<SealedSuite, GapError> {
    std::fs::create_dir_all(&cfg.out).map_err(|e| GapError::io(&cfg.out, e))?;
    let answers = draw_cases(&cfg.shape, cfg.suite_seed);
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
    let index = seal(&cfg.out, cfg.suite_seed, &answers)?;
    Ok(SealedSuite { answers, index })
}

/// The twin's noise model of every case: the navigation experiment's `[imu.noise]`.
pub fn twin_noise(cfg: &SuiteConfig) -> Result<NoiseSpec, GapError> {
    Ok(NoiseSpec::from(
        &load_experiment(&cfg.navigation_experiment)?
            .scenarios
            .first()
            .ok_or_else(|| GapError::Invalid("the navigation experiment has no run".into()))?
            .noise,
    ))
}

/// One case: generate the "real" IMU's data from its answer under `cfg.out/cases/<case>/data`
/// (removed afterwards unless `keep_datasets`), diagnose the files blind (against `noise`, or
/// the noise identified from the case's own datasets with `cfg.identified_noise`) and write the
/// diagnosis to `cfg.out/cases/<case>/diagnosis/`. Data a killed earlier attempt left is
/// replaced.
pub fn run_case(
    cfg: &SuiteConfig,
    answer: &CaseAnswer,
    noise: NoiseSpec,
    progress: &mut dyn Progress,
) -> Result<(Diagnosis, CaseTiming), GapError> {
    let case_dir = cfg.out.join("cases").join(&answer.case);
    let data = case_dir.join("data");
    if data.exists() {
        std::fs::remove_dir_all(&data).map_err(|e| GapError::io(&data, e))?;
    }
    let t = Instant::now();
    let (datasets, cal) = generate(cfg, answer, &data, progress)?;
    let generate_s = t.elapsed().as_secs_f64();
    // From here on the diagnosis sees only files and the calibrated parameter set.
    let t = Instant::now();
    let request = DiagnoseRequest {
        datasets,
        params: cal.params,
        param_sigma: Some(cal.sigma),
        param_covariance: Some(cal.param_covariance.clone()),
        calibration_run: Some(CALIBRATION_RUN.to_string()),
        config: cfg.diagnose.clone(),
    };
    let (mut outcome, noise_notes) = if cfg.identified_noise {
        let labels = sins_noiseid::NoiseIdConfig::default().labels;
        let (datasets, params) = (&request.datasets, &cal.params);
        diagnose_datasets_identifying(&request, || {
            let id = crate::identify_datasets(datasets, &labels, Some(params))?;
            Ok::<_, GapError>((id.to_noise_spec(), id.diagnosis_notes()))
        })?
    } else {
        (diagnose_datasets(&request, noise)?, Vec::new())
    };
    outcome.diagnosis.notes.splice(0..0, noise_notes);
    crate::write_diagnosis(&case_dir, "diagnosis", &outcome)?;
    let timing = CaseTiming {
        case: answer.case.clone(),
        generate_s,
        diagnose_s: t.elapsed().as_secs_f64(),
    };
    if !cfg.keep_datasets {
        std::fs::remove_dir_all(&data).map_err(|e| GapError::io(&data, e))?;
    }
    Ok((outcome.diagnosis, timing))
}

/// Open the sealed manifests (hash-checked) and grade the diagnoses of the cases run (in case
/// order; all of them, or those of `cfg.only`). The Markdown holds no timing, so that the same
/// diagnoses always give the same bytes.
pub fn grade_suite(
    cfg: &SuiteConfig,
    index: &SealIndex,
    diagnoses: Vec<(String, Diagnosis)>,
) -> Result<(Grades, String), GapError> {
    let opened: Vec<CaseAnswer> = open(&cfg.out, index)?
        .into_iter()
        .filter(|a| cfg.selects(&a.case))
        .collect();
    if opened.len() != diagnoses.len()
        || opened
            .iter()
            .zip(&diagnoses)
            .any(|(a, (c, _))| &a.case != c)
    {
        return Err(GapError::Invalid(format!(
            "{} diagnoses for {} sealed cases, or not in case order",
            diagnoses.len(),
            opened.len()
        )));
    }
    let pairs: Vec<(CaseAnswer, Diagnosis)> = opened
        .into_iter()
        .zip(diagnoses)
        .map(|(a, (_, d))| (a, d))
        .collect();
    let grades = grade(&pairs);
    let markdown = render_grades(&grades, &index.suite_sha256);
    Ok((grades, markdown))
}

/// The per-case timing as a Markdown table.
pub fn timing_markdown(timing: &[CaseTiming]) -> String {
    let mut table = Table::new(["case", "generate", "diagnose"]);
    for t in timing {
        table.row([
            t.case.clone(),
            format!("{:.1}", t.generate_s),
            format!("{:.1}", t.diagnose_s),
        ]);
    }
    format!("\n## Time per case (s)\n\n{table}")
}

/// Run the suite: draw and seal, generate and diagnose every case, open and grade.
pub fn run_suite(cfg: &SuiteConfig, progress: &mut dyn Progress) -> Result<SuiteResult, GapError> {
    let sealed = seal_suite(cfg)?;
    let noise = twin_noise(cfg)?;
    let mut diagnoses: Vec<(String, Diagnosis)> = Vec::new();
    let mut timing = Vec::new();
    for answer in sealed.answers.iter().filter(|a| cfg.selects(&a.case)) {
        let (diagnosis, t) = run_case(cfg, answer, noise, progress)?;
        timing.push(t);
        diagnoses.push((answer.case.clone(), diagnosis));
    }
    // Only now: open the sealed manifests (hash-checked) and grade.
    let (grades, mut markdown) = grade_suite(cfg, &sealed.index, diagnoses)?;
    markdown.push_str(&timing_markdown(&timing));
    Ok(SuiteResult {
        index: sealed.index,
        grades,
        timing,
        markdown,
    })
}
