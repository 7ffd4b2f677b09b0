//! `calibration-mc`: the Table 1 Monte Carlo of the 42-state calibration (one job per seed,
//! then the noise-free run), reduced to the same Table 1 study as `calibration-report`.

use crate::CampaignError;
use crate::kinds::parse;
use crate::kinds::shape::calibration_mc;
use crate::spec::{Campaign, Kind};
use crate::work::{Work, from_values, job_error, pretty, to_value, write_text};
use sins_calstudy::{McRunOutcome, Table1MonteCarlo, render_table1_markdown};
use std::path::Path;

/// The Table 1 Monte Carlo as campaign work.
pub struct CalMcWork {
    mc: Table1MonteCarlo,
}

impl CalMcWork {
    /// Loads the experiment and Table 1 of a `calibration-mc` campaign.
    pub fn new(c: &Campaign) -> Result<Self, CampaignError> {
        let Kind::CalibrationMc {
            seeds,
            experiment,
            reference_dir,
            max_duration_s,
        } = &c.kind
        else {
            return Err(job_error(0, "not a calibration-mc campaign"));
        };
        let mc = Table1MonteCarlo::load(experiment, reference_dir, *seeds, c.seed, *max_duration_s)
            .map_err(|e| job_error(0, e))?;
        Ok(Self { mc })
    }
}

impl Work for CalMcWork {
    fn jobs(&self) -> usize {
        self.mc.jobs()
    }
    fn fingerprint(&self) -> String {
        self.mc.fingerprint()
    }
    fn job_label(&self, job: usize) -> String {
        self.mc
            .seeds()
            .get(job)
            .map_or_else(|| "noise-free run".into(), |s| format!("seed {s}"))
    }
    fn check_outcome(&self, job: usize, outcome: &serde_json::Value) -> Result<(), String> {
        let o: McRunOutcome = parse(outcome)?;
        calibration_mc(&o)?;
        let seed = self
            .mc
            .seeds()
            .get(job)
            .copied()
            .unwrap_or(self.mc.base().seed);
        if o.outcome.seed != seed {
            return Err(format!(
                "it is the outcome of seed {}, where {} belongs",
                o.outcome.seed,
                self.job_label(job)
            ));
        }
        Ok(())
    }
    fn run_job(&self, job: usize, _dir: &Path) -> Result<serde_json::Value, CampaignError> {
        let o = self.mc.run_job(job).map_err(|e| job_error(job, e))?;
        to_value(job, &o)
    }
    fn reduce(
        &self,
        outcomes: Vec<serde_json::Value>,
        _dir: &Path,
        out: &Path,
    ) -> Result<Vec<String>, CampaignError> {
        let outcomes: Vec<McRunOutcome> = from_values(outcomes)?;
        let study = self.mc.assemble(&outcomes).map_err(|e| job_error(0, e))?;
        write_text(out, "summary.json", &pretty(&study)?)?;
        write_text(out, "report.md", &render_table1_markdown(&study))?;
        Ok(vec!["summary.json".into(), "report.md".into()])
    }
}
