//! `reports`: a list of report configurations (many IMUs, many releases), one job per
//! configuration. Each job writes its full report under `DIR/reports/<name>/`; the reduce
//! gathers every configuration's Table 5 cells into one table.

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
        let Kind::Reports { configs } = &c.kind else {
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
        Ok(Self {
            configs: loaded,
            fingerprint,
        })
    }
}

impl Work for ReportsWork {
    fn jobs(&self) -> usize {
        self.configs.len()
    }
    fn fingerprint(&self) -> String {
        self.fingerprint.clone()
    }
    fn job_label(&self, job: usize) -> String {
        self.configs
            .get(job)
            .map_or_else(String::new, |c| c.name.clone())
    }
    fn run_job(&self, job: usize, dir: &Path) -> Result<serde_json::Value, CampaignError> {
        let cfg = self
            .configs
            .get(job)
            .ok_or_else(|| job_error(job, "out of range"))?;
        let run = sins_report::run_report(cfg, &mut Quiet).map_err(|e| job_error(job, e))?;
        let reports = dir.join("reports");
        std::fs::create_dir_all(&reports).map_err(|e| CampaignError::io(&reports, e))?;
        sins_report::write_report(&reports, &run).map_err(|e| job_error(job, e))?;
        to_value(job, &run.summary)
    }
    fn reduce(
        &self,
        outcomes: Vec<serde_json::Value>,
        dir: &Path,
    ) -> Result<Vec<String>, CampaignError> {
        let summaries: Vec<Summary> = from_values(outcomes)?;
        write_text(
            dir,
            "summary.json",
            &pretty(&ReportsSummary {
                reports: &summaries,
            })?,
        )?;
        write_text(dir, "report.md", &markdown(&summaries))?;
        Ok(vec!["summary.json".into(), "report.md".into()])
    }
}

/// One row per report, experiment and parameter set: maximum horizontal error and where.
fn markdown(summaries: &[Summary]) -> String {
    let mut t = Table::new([
        "report",
        "experiment",
        "parameter set",
        "max horizontal (nmi)",
        "at (h)",
        "segment",
        "improvement (%)",
    ])
    .align(&[Left, Left, Left, Right, Right, Left, Right]);
    for s in summaries {
        for e in &s.experiments {
            let imp = e
                .improvement_percent
                .map_or_else(|| "-".into(), |v| format!("{v:.1}"));
            for (key, r) in &e.results {
                t.row([
                    s.name.clone(),
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
