//! `replica-uq`: the replica of Table 5 as a prediction (one job per Monte Carlo sample, in
//! `replica-uq`'s fixed job order), reduced to the same summary, Markdown and figures.

use crate::CampaignError;
use crate::kinds::parse;
use crate::kinds::shape::{check_len, replica_uq};
use crate::spec::{Campaign, Kind};
use crate::work::{Work, from_values, job_error, to_value};
use sins_report::{UqStudy, load_uq_study, write_uq_outputs};
use sins_uq::sample::{Job, SampleOutcome, all_jobs, run_job, study_name};
use std::path::Path;

/// The replica's Monte Carlo as campaign work.
pub struct UqWork {
    study: UqStudy,
    jobs: Vec<Job>,
}

impl UqWork {
    /// Loads the assumptions file of a `replica-uq` campaign and applies its sizes and seed.
    pub fn new(c: &Campaign) -> Result<Self, CampaignError> {
        let Kind::ReplicaUq {
            assumptions,
            samples,
            candidate_samples,
            pick_freeze,
        } = &c.kind
        else {
            return Err(job_error(0, "not a replica-uq campaign"));
        };
        let mut study = load_uq_study(assumptions).map_err(|e| job_error(0, e))?;
        let set = &mut study.set;
        if let Some(n) = samples {
            set.samples = *n;
        }
        if let Some(n) = candidate_samples {
            set.candidates.iter_mut().for_each(|c| c.samples = *n);
        }
        if let Some(n) = pick_freeze {
            set.pick_freeze_samples = *n;
        }
        if let Some(s) = c.seed {
            set.seed = s;
        }
        set.validate().map_err(|e| CampaignError::Spec {
            path: assumptions.clone(),
            message: format!("with the campaign's [replica_uq] sizes: {e}"),
        })?;
        let jobs = all_jobs(&study.set);
        Ok(Self { study, jobs })
    }
}

impl Work for UqWork {
    fn jobs(&self) -> usize {
        self.jobs.len()
    }
    fn fingerprint(&self) -> String {
        format!(
            "{:?}\n{:?}\n{:?}",
            self.study.set, self.study.base, self.study.paper
        )
    }
    fn job_label(&self, job: usize) -> String {
        self.jobs.get(job).map_or_else(String::new, |j| {
            format!("{} {}", study_name(&self.study.set, *j), j.index())
        })
    }
    fn check_outcome(&self, job: usize, outcome: &serde_json::Value) -> Result<(), String> {
        let o: SampleOutcome = parse(outcome)?;
        replica_uq(&o)?;
        let j = self.jobs.get(job).ok_or("is beyond the study's jobs")?;
        let study = study_name(&self.study.set, *j);
        if (o.study.as_str(), o.index) != (study.as_str(), j.index()) {
            return Err(format!(
                "it is the outcome of {} {}, where {study} {} belongs",
                o.study,
                o.index,
                j.index()
            ));
        }
        check_len(
            "values",
            o.values.len(),
            self.study.set.assumptions.len(),
            "the assumptions file",
        )?;
        let runs = self.study.base.navigation.len();
        check_len(
            "max_horizontal_m",
            o.max_horizontal_m.len(),
            runs,
            "the replica",
        )
    }
    fn run_job(&self, job: usize, _dir: &Path) -> Result<serde_json::Value, CampaignError> {
        let j = *self
            .jobs
            .get(job)
            .ok_or_else(|| job_error(job, "out of range"))?;
        let o = run_job(&self.study.base, &self.study.set, j, &|_| {})
            .map_err(|e| job_error(job, e))?;
        to_value(job, &o)
    }
    fn reduce(
        &self,
        outcomes: Vec<serde_json::Value>,
        _dir: &Path,
        out: &Path,
    ) -> Result<Vec<String>, CampaignError> {
        let outcomes: Vec<SampleOutcome> = from_values(outcomes)?;
        let summary = sins_uq::summary::summarize(&self.study.set, &outcomes, &self.study.paper)
            .map_err(|e| job_error(0, e))?;
        write_uq_outputs(out, &summary).map_err(|e| job_error(0, e))
    }
}
