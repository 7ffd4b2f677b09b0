//! What every kind of campaign provides: a fixed list of independent jobs, each run on its own
//! into a serialisable outcome, and a reduce that turns all outcomes (in job order) into the
//! campaign's `summary.json` and `report.md`.

use crate::CampaignError;
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::path::Path;

/// The work of a campaign.
pub trait Work: Sync {
    /// Number of jobs (fixed by the campaign file alone).
    fn jobs(&self) -> usize;
    /// Everything a job's result depends on besides the campaign file, as text (hashed into
    /// the manifest: an edited experiment file is then caught before it mixes results).
    fn fingerprint(&self) -> String;
    /// Work done once when the campaign is planned (e.g. sealing a blind suite's answers).
    fn prepare(&self, _dir: &Path) -> Result<(), CampaignError> {
        Ok(())
    }
    /// A short name of job `job` for messages (`case07`, `seed 2024`, `replica 3`).
    fn job_label(&self, job: usize) -> String;
    /// Checks a stored outcome of job `job` before anything uses it (it parses, its arrays
    /// have the lengths the reduce indexes, it is this job's); the error says what is wrong.
    fn check_outcome(&self, job: usize, outcome: &serde_json::Value) -> Result<(), String> {
        let _ = (job, outcome);
        Ok(())
    }
    /// Runs job `job`; files it writes go under `dir`. Its outcome is what the reduce gets.
    fn run_job(&self, job: usize, dir: &Path) -> Result<serde_json::Value, CampaignError>;
    /// Writes `summary.json`, `report.md` (and any figures) into `out` from every job's
    /// outcome in job order, reading anything else it needs from the campaign directory `dir`
    /// (`out` is a staging directory that is moved into `dir` afterwards); returns the names of
    /// the files written. The bytes depend only on the outcomes, never on timing or on the
    /// directories' paths.
    fn reduce(
        &self,
        outcomes: Vec<serde_json::Value>,
        dir: &Path,
        out: &Path,
    ) -> Result<Vec<String>, CampaignError>;
}

/// A job's error as a [`CampaignError`].
pub(crate) fn job_error(job: usize, e: impl std::fmt::Display) -> CampaignError {
    CampaignError::Job {
        job,
        message: e.to_string(),
    }
}

/// An outcome as JSON.
pub(crate) fn to_value<T: Serialize>(
    job: usize,
    v: &T,
) -> Result<serde_json::Value, CampaignError> {
    serde_json::to_value(v).map_err(|e| job_error(job, format!("cannot serialise: {e}")))
}

/// Outcomes from JSON, naming the job that does not parse.
pub(crate) fn from_values<T: DeserializeOwned>(
    values: Vec<serde_json::Value>,
) -> Result<Vec<T>, CampaignError> {
    values
        .into_iter()
        .enumerate()
        .map(|(k, v)| {
            serde_json::from_value(v)
                .map_err(|e| job_error(k, format!("outcome does not parse: {e}")))
        })
        .collect()
}

/// Writes `text` to `dir/name` atomically.
pub(crate) fn write_text(dir: &Path, name: &str, text: &str) -> Result<(), CampaignError> {
    let path = dir.join(name);
    sins_files::write_file_atomically(&path, text.as_bytes())
        .map_err(|e| CampaignError::io(&path, e))
}

/// Pretty JSON with one trailing newline.
pub(crate) fn pretty<T: Serialize>(v: &T) -> Result<String, CampaignError> {
    serde_json::to_string_pretty(v)
        .map(|s| s + "\n")
        .map_err(|e| job_error(0, format!("cannot serialise the summary: {e}")))
}

/// Progress of a job run inside a shard: not shown (the campaign's bar counts jobs).
pub(crate) struct Quiet;

impl sins_report::Progress for Quiet {
    fn begin(&mut self, _: &str, _: u64) {}
    fn advance(&mut self, _: u64) {}
    fn end(&mut self) {}
}
