//! `reports`: a list of report configurations (many IMUs, many releases), one job per
//! configuration, or with `noise_seeds = N` one job per configuration and sensor-noise seed
//! (K..K+N-1, K = `first_noise_seed`, default 1: the run-to-run spread a release gate compares
//! against). Each job writes its full
//! report under `DIR/reports/<name>/` (`<name>-seed<k>` with noise seeds); the reduce gathers
//! every report's Table 5 cells into one table and its summaries into `summary.json`.

use crate::CampaignError;
use crate::spec::{Campaign, Kind};
use crate::work::{Quiet, Work, from_values, job_error, pretty, to_value, write_text};
use serde::Serialize;
use sins_config::load_report_config;
use sins_config::markdown::Align::{Left, Right};
use sins_config::markdown::Table;
use sins_harness::config::ReportConfig;
use sins_harness::summary::Summary;
use std::fmt::Write as _;
use std::path::Path;

/// A list of reports as campaign work.
pub struct ReportsWork {
    configs: Vec<ReportConfig>,
    /// Noise seeds per configuration (0: the files' own seeds, one job each).
    noise_seeds: u64,
    /// The first noise seed.
    first_noise_seed: u64,
    fingerprint: String,
}

#[derive(Serialize)]
struct ReportsSummary<'a> {
    reports: &'a [Summary],
}

impl ReportsWork {
    /// Loads every configuration of a `reports` campaign; names must differ (each report
    /// has its own directory).
    pub fn new(c: &Campaign) -> Result<Self, CampaignError> {
        let Kind::Reports {
            configs,
            noise_seeds,
            first_noise_seed,
        } = &c.kind
        else {
            return Err(job_error(0, "not a reports campaign"));
        };
        let mut loaded: Vec<ReportConfig> = Vec::new();
        let mut fingerprint = String::new();
        for path in configs {
            let cfg = load_report_config(path).map_err(|e| CampaignError::Spec {
                path: path.clone(),
                message: e.to_string(),
            })?;
            if let Some(prev) = loaded.iter().find(|p| p.name == cfg.name) {
                return Err(CampaignError::Spec {
                    path: path.clone(),
                    message: format!(
                        "report name '{}' is also the name of {}: every report of a campaign needs its own name",
                        cfg.name,
                        prev.source_path.display()
                    ),
                });
            }
            let text = std::fs::read_to_string(path).map_err(|e| CampaignError::io(path, e))?;
            let _ = write!(fingerprint, "{text}\n{cfg:?}\n");
            loaded.push(cfg);
        }
        let noise_seeds = noise_seeds.unwrap_or(0);
        let _ = writeln!(fingerprint, "noise_seeds {noise_seeds}");
        // Left out of the fingerprint at its default, so plans made before the key existed
        // still open.
        if *first_noise_seed != 1 {
            let _ = writeln!(fingerprint, "first_noise_seed {first_noise_seed}");
        }
        Ok(Self {
            configs: loaded,
            noise_seeds,
            first_noise_seed: *first_noise_seed,
            fingerprint,
        })
    }
}

impl ReportsWork {
    /// Job `job`'s configuration, with its noise seed set and its name made its own.
    fn job_config(&self, job: usize) -> Option<ReportConfig> {
        let per = self.noise_seeds.max(1) as usize;
        let mut cfg = self.configs.get(job / per)?.clone();
        if self.noise_seeds > 0 {
            let seed = (job % per) as u64 + self.first_noise_seed;
            cfg.noise_seed = Some(seed);
            cfg.name = format!("{}-seed{seed}", cfg.name);
        }
        Some(cfg)
    }
}

impl Work for ReportsWork {
    fn jobs(&self) -> usize {
        self.configs.len() * self.noise_seeds.max(1) as usize
    }
    fn fingerprint(&self) -> String {
        self.fingerprint.clone()
    }
    fn job_label(&self, job: usize) -> String {
        self.job_config(job)
            .map_or_else(String::new, |c| c.name.clone())
    }
    fn run_job(&self, job: usize, dir: &Path) -> Result<serde_json::Value, CampaignError> {
        let cfg = self
            .job_config(job)
            .ok_or_else(|| job_error(job, "out of range"))?;
        // One thread per report: the campaign already runs its jobs side by side.
        let mut run =
            sins_report::run_report(&cfg, 1, &mut Quiet).map_err(|e| job_error(job, e))?;
        let reports = dir.join("reports");
        std::fs::create_dir_all(&reports).map_err(|e| CampaignError::io(&reports, e))?;
        sins_report::write_report(&reports, &run).map_err(|e| job_error(job, e))?;
        // The summary keeps the configuration's own name: a gate compares reports of one
        // configuration over noise seeds (each seed's report has its own directory).
        if let Some(base) = self.configs.get(job / self.noise_seeds.max(1) as usize) {
            run.summary.name = base.name.clone();
        }
        to_value(job, &run.summary)
    }
    fn reduce(
        &self,
        outcomes: Vec<serde_json::Value>,
        _dir: &Path,
        out: &Path,
    ) -> Result<Vec<String>, CampaignError> {
        let summaries: Vec<Summary> = from_values(outcomes)?;
        write_text(
            out,
            "summary.json",
            &pretty(&ReportsSummary {
                reports: &summaries,
            })?,
        )?;
        write_text(out, "report.md", &markdown(&summaries))?;
        Ok(vec!["summary.json".into(), "report.md".into()])
    }
}

/// One row per report, experiment and parameter set: maximum horizontal error and where.
fn markdown(summaries: &[Summary]) -> String {
    let mut t = Table::new([
        "report",
        "noise seed",
        "experiment",
        "parameter set",
        "max horizontal (nmi)",
        "at (h)",
        "segment",
        "improvement (%)",
    ])
    .align(&[Left, Right, Left, Left, Right, Right, Left, Right]);
    for s in summaries {
        for e in &s.experiments {
            let imp = e
                .improvement_percent
                .map_or_else(|| "-".into(), |v| format!("{v:.1}"));
            for (key, r) in &e.results {
                t.row([
                    s.name.clone(),
                    s.noise_seed.map_or_else(|| "-".into(), |k| k.to_string()),
                    e.name.clone(),
                    key.clone(),
                    format!("{:.3}", r.max_horizontal_nmi),
                    format!("{:.2}", r.t_max_s / 3600.0),
                    r.segment_at_max.clone(),
                    imp.clone(),
                ]);
            }
        }
    }
    format!("# Reports campaign\n\nEvery report's own directory is `reports/<name>/`.\n\n{t}")
}
