//! The Table 1 Monte Carlo as independent jobs: one 42-state calibration per seed plus the
//! noise-free run of the same scenario, each computed on its own (a campaign shard, another
//! machine) and assembled into the same [`Table1Study`] that [`crate::run_study`] builds.

use crate::error::StudyError;
use crate::montecarlo::{McRunOutcome, Table1Study, mc_seeds};
use crate::reference::{TABLE1_FILE, Table1, load_table1};
use crate::run::{CalibrationRun, calibrate_scenario, config_for_scenario, truncate_motion};
use sins_config::load_experiment;
use sins_imu::ParamModel;
use sins_kf::FilterNoise;
use sins_sim::{NoiseModel, Scenario};
use std::path::Path;

/// The Monte Carlo of Table 1: the first run of an experiment calibrated under `seeds` noise
/// seeds, and once without any noise (the method's own floor).
#[derive(Clone, Debug)]
pub struct Table1MonteCarlo {
    experiment: String,
    base: Scenario,
    seeds: Vec<u64>,
    table1: Table1,
}

impl Table1MonteCarlo {
    /// Loads the experiment (its first run) and the paper's Table 1 from `reference_dir`;
    /// `seeds` Monte Carlo seeds starting at `first_seed` (default: the run's own seed); the
    /// motion cut after `max_duration_s` when given (shortened studies, as
    /// [`crate::StudyConfig::max_duration_s`]).
    pub fn load(
        experiment: &Path,
        reference_dir: &Path,
        seeds: usize,
        first_seed: Option<u64>,
        max_duration_s: Option<f64>,
    ) -> Result<Self, StudyError> {
        if seeds == 0 {
            return Err(StudyError::Setup(
                "the Monte Carlo needs at least one seed".into(),
            ));
        }
        let exp = load_experiment(experiment)?;
        let mut base =
            exp.scenarios.first().cloned().ok_or_else(|| {
                StudyError::Setup(format!("experiment `{}` has no run", exp.name))
            })?;
        if let Some(d) = max_duration_s {
            truncate_motion(&mut base, d);
        }
        Ok(Self {
            experiment: format!("{} / {}", exp.name, base.name),
            seeds: mc_seeds(first_seed.unwrap_or(base.seed), seeds),
            base,
            table1: load_table1(reference_dir.join(TABLE1_FILE))?,
        })
    }

    /// Number of jobs: one per seed, then the noise-free run.
    pub fn jobs(&self) -> usize {
        self.seeds.len() + 1
    }

    /// The seeds, in job order.
    pub fn seeds(&self) -> &[u64] {
        &self.seeds
    }

    /// The calibrated run (its motion cut when asked), with the run's own seed.
    pub fn base(&self) -> &Scenario {
        &self.base
    }

    /// `experiment / run`, as Table 1's study names it.
    pub fn experiment(&self) -> &str {
        &self.experiment
    }

    /// The paper's Table 1.
    pub fn table1(&self) -> &Table1 {
        &self.table1
    }

    /// The 42-state calibration of Monte Carlo seed number `k` (`k < seeds`).
    pub fn seed_run(&self, k: usize) -> Result<CalibrationRun, StudyError> {
        let mut sc = self.base.clone();
        sc.seed = *self.seeds.get(k).ok_or_else(|| {
            StudyError::Setup(format!(
                "seed number {k} is out of range: the Monte Carlo has {} seeds",
                self.seeds.len()
            ))
        })?;
        calibrate_scenario(&sc, config_for_scenario(&sc, ParamModel::States42))
    }

    /// Everything a job's result depends on, as text (for a campaign's manifest hash).
    pub fn fingerprint(&self) -> String {
        format!("{:?}\n{:?}\n{:?}", self.base, self.seeds, self.table1)
    }

    /// Runs job `k`: seed `k`'s calibration, or (k = seeds) the noise-free run.
    pub fn run_job(&self, k: usize) -> Result<McRunOutcome, StudyError> {
        match self.seeds.get(k) {
            Some(&seed) => Ok(McRunOutcome::new(
                seed,
                &self.seed_run(k)?,
                &self.base.truth,
            )),
            None if k == self.seeds.len() => {
                let run = noise_free_run(&self.base)?;
                Ok(McRunOutcome::new(self.base.seed, &run, &self.base.truth))
            }
            None => Err(StudyError::Setup(format!(
                "job {k} is out of range: the Monte Carlo has {} jobs",
                self.jobs()
            ))),
        }
    }

    /// Assembles every job's outcome (in job order) into Table 1 over the Monte Carlo.
    pub fn assemble(&self, outcomes: &[McRunOutcome]) -> Result<Table1Study, StudyError> {
        if outcomes.len() != self.jobs() {
            return Err(StudyError::Setup(format!(
                "{} outcomes for a Monte Carlo of {} jobs",
                outcomes.len(),
                self.jobs()
            )));
        }
        let (per_seed, free) = outcomes.split_at(self.seeds.len());
        for (o, s) in per_seed.iter().zip(&self.seeds) {
            if o.outcome.seed != *s {
                return Err(StudyError::Setup(format!(
                    "outcome of seed {} where seed {s} belongs",
                    o.outcome.seed
                )));
            }
        }
        Ok(Table1Study::from_outcomes(
            self.experiment.clone(),
            per_seed.iter().map(|o| o.outcome.clone()).collect(),
            &per_seed[0].observability(),
            &free[0].estimate_si,
            &self.base.truth,
            &self.table1,
        ))
    }
}

/// The scenario calibrated without any sensor or thermometer noise, by a filter that assumes
/// none: the method's own floor (linearisation, discretisation, numerics).
pub fn noise_free_run(base: &Scenario) -> Result<CalibrationRun, StudyError> {
    let mut sc = base.clone();
    sc.noise = NoiseModel::default();
    sc.thermal.thermometer_noise_degc = 0.0;
    let mut c = config_for_scenario(&sc, ParamModel::States42);
    c.noise = FilterNoise::none();
    calibrate_scenario(&sc, c)
}
