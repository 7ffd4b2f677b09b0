//! `calibration-mc`: the Table 1 Monte Carlo of the 42-state calibration (one job per seed,
//! then the noise-free run), reduced to the same Table 1 study as `calibration-report`.

use crate::CampaignError;
use crate::kinds::{check_len, parse};
use crate::spec::{Campaign, Kind};
use crate::work::{Work, from_values, job_error, pretty, to_value, write_text};
use sins_calstudy::{McRunOutcome, Table1MonteCarlo, render_table1_markdown};
use std::path::Path;

/// Coefficients of the 42-state filter (eq 8): the length of every per-seed estimate.
const COEFFICIENTS: usize = 33;
/// States of the 42-state filter (9 navigation states and the coefficients).
const STATES: usize = 42;

/// Every array of a seed's outcome has the length of a 42-state calibration's (Table 1's
/// assembly indexes them by state).
pub fn check_shape(o: &McRunOutcome) -> Result<(), String> {
    let what = "a 42-state calibration";
    check_len("estimate", o.outcome.estimate.len(), COEFFICIENTS, what)?;
    check_len("error", o.outcome.error.len(), COEFFICIENTS, what)?;
    check_len("sigma", o.outcome.sigma.len(), COEFFICIENTS, what)?;
    check_len("sigma_ratio", o.outcome.sigma_ratio.len(), STATES, what)?;
    check_len("initial_sigma_si", o.initial_sigma_si.len(), STATES, what)?;
    check_len("final_sigma_si", o.final_sigma_si.len(), STATES, what)?;
    check_len("estimate_si", o.estimate_si.len(), COEFFICIENTS, what)
}

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
        check_shape(&o)?;
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

#[cfg(test)]
mod tests {
    #[test]
    fn the_lengths_are_those_of_the_42_state_filter() {
        assert_eq!(sins_calstudy::units::PARAMS.len(), super::COEFFICIENTS);
    }
}
