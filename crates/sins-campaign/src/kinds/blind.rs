//! `blind`: the blind validation suite of the gap diagnosis, one job per case. The plan draws
//! and seals the answers (their hashes fixed before any diagnosis runs); each job generates its
//! case's data and diagnoses the files blind; the reduce opens the seal and grades.

use crate::CampaignError;
use crate::spec::{Campaign, Kind};
use crate::work::{Quiet, Work, from_values, job_error, pretty, to_value, write_text};
use serde::Serialize;
use sins_diag::input::DiagnoseConfig;
use sins_diag::noise::NoiseSpec;
use sins_diag::report::Diagnosis;
use sins_gap::blind::grade::Grades;
use sins_gap::blind::plan::{CaseAnswer, SuiteShape, draw_cases};
use sins_gap::blind::seal::{SealIndex, sealed_dir};
use sins_gap::blind::suite::{SuiteConfig, grade_suite, run_case, seal_suite, twin_noise};
use std::path::{Path, PathBuf};

/// The blind suite as campaign work.
pub struct BlindWork {
    /// The suite; its `out` is set to the campaign directory of each call ([`Self::suite`]).
    cfg: SuiteConfig,
    answers: Vec<CaseAnswer>,
    noise: NoiseSpec,
    fingerprint: String,
}

/// What the reduce writes to `summary.json`.
#[derive(Serialize)]
struct BlindSummary<'a> {
    suite_seed: u64,
    suite_sha256: &'a str,
    grades: &'a Grades,
}

impl BlindWork {
    /// The suite of a `blind` campaign.
    pub fn new(c: &Campaign) -> Result<Self, CampaignError> {
        let Kind::Blind {
            cases,
            null,
            outside,
            time_local,
            wide_time_local,
            different_histories,
            histories_experiment,
            identified_noise,
            runs,
            calibration_experiment,
            navigation_experiment,
        } = &c.kind
        else {
            return Err(job_error(0, "not a blind campaign"));
        };
        let cfg = SuiteConfig {
            out: PathBuf::new(),
            suite_seed: c.seed.unwrap_or(1),
            shape: SuiteShape {
                cases: *cases,
                null_cases: *null,
                out_of_catalogue: *outside,
                time_local: *time_local,
                time_local_runs: runs.clone(),
                wide_time_local: *wide_time_local,
                different_histories: *different_histories,
                ..SuiteShape::default()
            },
            calibration_experiment: calibration_experiment.clone(),
            navigation_experiment: navigation_experiment.clone(),
            histories_experiment: histories_experiment.clone(),
            navigation_runs: runs.clone(),
            keep_datasets: false,
            only: Vec::new(),
            diagnose: DiagnoseConfig::default(),
            identified_noise: *identified_noise,
        };
        let load = |p: &Path| sins_config::load_experiment(p).map_err(|e| job_error(0, e));
        let fingerprint = format!(
            "{:?}\n{:?}\n{:?}\n{:?}\n{:?}{}{}",
            cfg.suite_seed,
            cfg.shape,
            cfg.navigation_runs,
            load(&cfg.calibration_experiment)?,
            load(&cfg.navigation_experiment)?,
            // Only when set: the fingerprints of the campaigns planned before it existed hold.
            if cfg.identified_noise {
                "\nidentified noise"
            } else {
                ""
            },
            // Likewise the experiment of the "different histories" cases, when they are drawn
            // (the shape's Debug shows the new sections only when they draw cases).
            if cfg.shape.different_histories > 0 {
                format!("\n{:?}", load(&cfg.histories_experiment)?)
            } else {
                String::new()
            }
        );
        let answers = draw_cases(&cfg.shape, cfg.suite_seed);
        let noise = twin_noise(&cfg).map_err(|e| job_error(0, e))?;
        Ok(Self {
            cfg,
            answers,
            noise,
            fingerprint,
        })
    }

    /// The suite run in campaign directory `dir` (sealed answers, case directories).
    fn suite(&self, dir: &Path) -> SuiteConfig {
        SuiteConfig {
            out: dir.to_owned(),
            ..self.cfg.clone()
        }
    }

    fn read_index(dir: &Path) -> Result<SealIndex, CampaignError> {
        let path = sealed_dir(dir).join("index.json");
        let text = std::fs::read_to_string(&path).map_err(|e| CampaignError::io(&path, e))?;
        serde_json::from_str(&text).map_err(|e| CampaignError::Manifest {
            path,
            message: format!("not a seal index: {e}"),
        })
    }
}

impl Work for BlindWork {
    fn jobs(&self) -> usize {
        self.answers.len()
    }
    fn fingerprint(&self) -> String {
        self.fingerprint.clone()
    }
    fn prepare(&self, dir: &Path) -> Result<(), CampaignError> {
        seal_suite(&self.suite(dir)).map_err(|e| job_error(0, e))?;
        Ok(())
    }
    fn job_label(&self, job: usize) -> String {
        self.answers
            .get(job)
            .map_or_else(String::new, |a| a.case.clone())
    }
    fn run_job(&self, job: usize, dir: &Path) -> Result<serde_json::Value, CampaignError> {
        let answer = self
            .answers
            .get(job)
            .ok_or_else(|| job_error(job, "out of range"))?;
        let (mut diagnosis, _) = run_case(&self.suite(dir), answer, self.noise, &mut Quiet)
            .map_err(|e| job_error(job, e))?;
        // The plots' series stay in the case's own diagnosis directory; grading needs none.
        diagnosis.series.clear();
        to_value(job, &diagnosis)
    }
    fn reduce(
        &self,
        outcomes: Vec<serde_json::Value>,
        dir: &Path,
        out: &Path,
    ) -> Result<Vec<String>, CampaignError> {
        let diagnoses: Vec<Diagnosis> = from_values(outcomes)?;
        let index = Self::read_index(dir)?;
        let named = self
            .answers
            .iter()
            .map(|a| a.case.clone())
            .zip(diagnoses)
            .collect();
        let (grades, markdown) =
            grade_suite(&self.suite(dir), &index, named).map_err(|e| job_error(0, e))?;
        let summary = BlindSummary {
            suite_seed: index.suite_seed,
            suite_sha256: &index.suite_sha256,
            grades: &grades,
        };
        write_text(out, "summary.json", &pretty(&summary)?)?;
        write_text(out, "report.md", &markdown)?;
        Ok(vec!["summary.json".into(), "report.md".into()])
    }
}
