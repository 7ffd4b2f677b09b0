//! Table 1 over a Monte Carlo of seeds: per-coefficient errors against the truth and the filter's
//! own 1-sigma, the paper's residuals, the NEES of the 33-coefficient block and the observability
//! of all 42 states.

use crate::reference::Table1;
use crate::run::CalibrationRun;
use crate::stats::{median, nees, nees_mean_interval};
use crate::units::{PARAMS, to_paper, vec_to_paper};
use serde::{Deserialize, Serialize};
use sins_imu::{ImuErrorParams, ParamModel};
use sins_kf::{ObservabilityReport, params_to_vec};

/// The Monte Carlo seeds of an experiment run: the run's own seed first, then the next ones
/// (`run_seed + i`, wrapping; the simulator expands each seed into an unrelated ChaCha key).
pub fn mc_seeds(run_seed: u64, n: usize) -> Vec<u64> {
    (0..n as u64).map(|i| run_seed.wrapping_add(i)).collect()
}

/// One Monte Carlo seed of the 42-state filter, coefficients in paper units (eq-8 order).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeedOutcome {
    /// Simulation seed.
    pub seed: u64,
    /// Estimate of the 33 coefficients.
    pub estimate: Vec<f64>,
    /// Estimate minus truth.
    pub error: Vec<f64>,
    /// The filter's 1-sigma.
    pub sigma: Vec<f64>,
    /// NEES of the 33-coefficient block with the filter's full covariance (χ²(33) if consistent).
    pub nees: f64,
    /// Final over initial 1-sigma of each of the 42 states.
    pub sigma_ratio: Vec<f64>,
    /// Largest normalised horizontal velocity innovation of the run (χ²(2) per update).
    pub max_normalized_innovation: f64,
}

impl SeedOutcome {
    /// Evaluate one calibration run against the truth (a 42-state parameter set).
    pub fn new(seed: u64, run: &CalibrationRun, truth: &ImuErrorParams) -> Self {
        let r = &run.result;
        let est = params_to_vec(&r.params, ParamModel::States42);
        let err: Vec<f64> = est
            .iter()
            .zip(params_to_vec(truth, ParamModel::States42))
            .map(|(e, t)| e - t)
            .collect();
        Self {
            seed,
            estimate: vec_to_paper(&est),
            error: vec_to_paper(&err),
            sigma: vec_to_paper(&params_to_vec(&r.sigma, ParamModel::States42)),
            nees: nees(&err, &r.param_covariance).unwrap_or(f64::NAN),
            sigma_ratio: r.observability.states.iter().map(|s| s.ratio).collect(),
            max_normalized_innovation: r.max_normalized_innovation,
        }
    }
}

/// What Table 1 needs of one calibration run, serialisable so that the runs of a Monte Carlo can
/// be computed apart (campaign shards) and assembled later: the per-seed outcome, the initial
/// and final 1-sigma of all 42 states (SI, state order) and the estimate (SI, 33 coefficients).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct McRunOutcome {
    /// The seed's outcome against the truth.
    pub outcome: SeedOutcome,
    /// 1-sigma of every state when the filter started (SI, state order, 42 values).
    pub initial_sigma_si: Vec<f64>,
    /// 1-sigma of every state at the end (SI, state order, 42 values).
    pub final_sigma_si: Vec<f64>,
    /// Estimate of the 33 coefficients (SI, state order).
    pub estimate_si: Vec<f64>,
}

impl McRunOutcome {
    /// Evaluate one 42-state calibration run of seed `seed` against the truth.
    pub fn new(seed: u64, run: &CalibrationRun, truth: &ImuErrorParams) -> Self {
        let states = &run.result.observability.states;
        Self {
            outcome: SeedOutcome::new(seed, run, truth),
            initial_sigma_si: states.iter().map(|s| s.initial_sigma).collect(),
            final_sigma_si: states.iter().map(|s| s.final_sigma).collect(),
            estimate_si: params_to_vec(&run.result.params, ParamModel::States42),
        }
    }

    /// The run's observability report (final over initial 1-sigma of every state).
    pub fn observability(&self) -> ObservabilityReport {
        ObservabilityReport::new(&self.initial_sigma_si, &self.final_sigma_si, 0.1)
    }
}

/// One coefficient of the Table 1 comparison (paper units).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Table1Entry {
    /// Coefficient name (eq 8).
    pub name: String,
    /// Paper unit.
    pub unit: String,
    /// Truth (the experiment's truth IMU; Table 1's preset).
    pub truth: f64,
    /// Our estimate on the first seed.
    pub first_estimate: f64,
    /// Our signed residual on the first seed (estimate − truth).
    pub first_residual: f64,
    /// Our 1-sigma on the first seed.
    pub first_sigma: f64,
    /// Median over the seeds of |estimate − truth|.
    pub median_abs_error: f64,
    /// Median over the seeds of the filter's 1-sigma.
    pub median_sigma: f64,
    /// Seeds whose |error| ≤ 3 × their own 1-sigma.
    pub seeds_within_3sigma: usize,
    /// The paper's estimate.
    pub paper_estimate: f64,
    /// The paper's residual.
    pub paper_residual: f64,
    /// The paper's print resolution (its residual is rounded to this).
    pub paper_resolution: f64,
    /// `median_abs_error ≤ paper_residual`.
    pub at_or_below_paper: bool,
    /// The same with our median rounded to the paper's resolution.
    pub at_or_below_paper_rounded: bool,
    /// `median_sigma / paper_residual`: above 1 the filter's own uncertainty (the sigma floor
    /// of this noise level) exceeds the paper's residual (infinite when that is 0; JSON has no
    /// infinity, so `null` there).
    pub sigma_over_paper: f64,
    /// Signed residual of the same run without any sensor or thermometer noise (the method's
    /// own floor: linearisation, discretisation, numerics).
    pub noise_free_residual: f64,
    /// `|noise_free_residual|` rounded to the paper's resolution is at or below its residual.
    pub noise_free_at_or_below_paper: bool,
}

/// Final/initial 1-sigma of one state.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ObservabilityEntry {
    /// State name (eq 8).
    pub name: String,
    /// Unit of the sigmas (SI for the navigation states, paper units for the coefficients).
    pub unit: String,
    /// Initial 1-sigma (first seed).
    pub initial_sigma: f64,
    /// Final 1-sigma (first seed).
    pub final_sigma: f64,
    /// Final / initial (first seed).
    pub ratio: f64,
    /// Largest ratio over all seeds.
    pub worst_ratio: f64,
    /// The worst ratio is ≤ 0.1 (the sigma fell at least tenfold in every seed).
    pub fell_tenfold: bool,
}

/// Table 1 reproduced over a Monte Carlo of seeds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Table1Study {
    /// Experiment name and run.
    pub experiment: String,
    /// The seeds, first = the run's own seed.
    pub seeds: Vec<u64>,
    /// One entry per coefficient in the paper's printed order.
    pub entries: Vec<Table1Entry>,
    /// Coefficients whose median |error| is at or below the paper's residual.
    pub count_at_or_below_paper: usize,
    /// The same after rounding our median to the paper's print resolution.
    pub count_at_or_below_paper_rounded: usize,
    /// Coefficients whose noise-free residual (rounded to the paper's resolution) is at or below
    /// the paper's residual.
    pub count_noise_free_at_or_below_paper: usize,
    /// Seeds needed within 3 sigma per coefficient (9 of 10: ⌈0.9 N⌉).
    pub required_within_3sigma: usize,
    /// Coefficients that have at least that many.
    pub count_meeting_3sigma: usize,
    /// Degrees of freedom of each NEES (33).
    pub nees_dim: usize,
    /// NEES of each seed.
    pub nees: Vec<f64>,
    /// Mean NEES over the seeds.
    pub nees_mean: f64,
    /// Two-sided 95 % interval of the mean NEES of a consistent filter (χ²(33 N)/N).
    pub nees_interval_95: [f64; 2],
    /// The mean lies inside the interval.
    pub nees_consistent: bool,
    /// All 42 states.
    pub observability: Vec<ObservabilityEntry>,
    /// Every state's sigma fell at least tenfold in every seed.
    pub all_fell_tenfold: bool,
    /// The state with the largest (worst) final/initial ratio and that ratio.
    pub weakest_state: (String, f64),
    /// Per-seed detail.
    pub per_seed: Vec<SeedOutcome>,
}

impl Table1Study {
    /// Build from the per-seed outcomes (first = the run's own seed), the first seed's run (for
    /// the initial/final sigmas), the noise-free run of the same scenario, the truth and the
    /// paper's Table 1.
    pub fn new(
        experiment: String,
        per_seed: Vec<SeedOutcome>,
        first: &CalibrationRun,
        noise_free: &CalibrationRun,
        truth: &ImuErrorParams,
        table1: &Table1,
    ) -> Self {
        let free = params_to_vec(&noise_free.result.params, ParamModel::States42);
        Self::from_outcomes(
            experiment,
            per_seed,
            &first.result.observability,
            &free,
            truth,
            table1,
        )
    }

    /// Build from the per-seed outcomes (first = the run's own seed), the first seed's
    /// observability report, the noise-free run's estimate (SI, 33 coefficients in state
    /// order), the truth and the paper's Table 1: [`Table1Study::new`] without the runs
    /// themselves (e.g. from [`McRunOutcome`]s computed elsewhere).
    pub fn from_outcomes(
        experiment: String,
        per_seed: Vec<SeedOutcome>,
        first: &ObservabilityReport,
        noise_free_estimate_si: &[f64],
        truth: &ImuErrorParams,
        table1: &Table1,
    ) -> Self {
        let n = per_seed.len();
        let truth_si = params_to_vec(truth, ParamModel::States42);
        let truth_p = vec_to_paper(&truth_si);
        let free = noise_free_estimate_si;
        let required = (9 * n).div_ceil(10);
        let entries: Vec<Table1Entry> = table1
            .rows
            .iter()
            .map(|row| {
                let k = row.state_index;
                let abs: Vec<f64> = per_seed.iter().map(|s| s.error[k].abs()).collect();
                let sig: Vec<f64> = per_seed.iter().map(|s| s.sigma[k]).collect();
                let med = median(&abs);
                let med_sigma = median(&sig);
                let round = |v: f64| (v / row.resolution).round() * row.resolution;
                let at_or_below = |v: f64| round(v) <= row.residual + 1e-9 * row.resolution;
                let free_res = to_paper(k, free[k] - truth_si[k]);
                let s0 = &per_seed[0];
                Table1Entry {
                    name: row.name.clone(),
                    unit: row.unit.clone(),
                    truth: truth_p[k],
                    first_estimate: s0.estimate[k],
                    first_residual: s0.error[k],
                    first_sigma: s0.sigma[k],
                    median_abs_error: med,
                    median_sigma: med_sigma,
                    seeds_within_3sigma: abs
                        .iter()
                        .zip(&sig)
                        .filter(|(e, s)| **e <= 3.0 * **s)
                        .count(),
                    paper_estimate: row.estimate,
                    paper_residual: row.residual,
                    paper_resolution: row.resolution,
                    at_or_below_paper: med <= row.residual,
                    at_or_below_paper_rounded: at_or_below(med),
                    sigma_over_paper: med_sigma / row.residual,
                    noise_free_residual: free_res,
                    noise_free_at_or_below_paper: at_or_below(free_res.abs()),
                }
            })
            .collect();
        let nees_values: Vec<f64> = per_seed.iter().map(|s| s.nees).collect();
        let nees_mean = nees_values.iter().sum::<f64>() / n as f64;
        let interval = nees_mean_interval(33, n, 0.95);
        let observability = observability(first, &per_seed);
        let weakest = observability
            .iter()
            .max_by(|a, b| a.worst_ratio.total_cmp(&b.worst_ratio))
            .map_or((String::new(), f64::NAN), |o| {
                (o.name.clone(), o.worst_ratio)
            });
        Self {
            experiment,
            seeds: per_seed.iter().map(|s| s.seed).collect(),
            count_at_or_below_paper: entries.iter().filter(|e| e.at_or_below_paper).count(),
            count_at_or_below_paper_rounded: entries
                .iter()
                .filter(|e| e.at_or_below_paper_rounded)
                .count(),
            count_noise_free_at_or_below_paper: entries
                .iter()
                .filter(|e| e.noise_free_at_or_below_paper)
                .count(),
            required_within_3sigma: required,
            count_meeting_3sigma: entries
                .iter()
                .filter(|e| e.seeds_within_3sigma >= required)
                .count(),
            entries,
            nees_dim: 33,
            nees_consistent: (interval[0]..=interval[1]).contains(&nees_mean),
            nees: nees_values,
            nees_mean,
            nees_interval_95: interval,
            all_fell_tenfold: observability.iter().all(|o| o.fell_tenfold),
            observability,
            weakest_state: weakest,
            per_seed,
        }
    }
}

fn observability(first: &ObservabilityReport, per_seed: &[SeedOutcome]) -> Vec<ObservabilityEntry> {
    first
        .states
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let worst = per_seed
                .iter()
                .map(|o| o.sigma_ratio.get(i).copied().unwrap_or(f64::NAN))
                .fold(0.0f64, |m, r| {
                    if m.is_nan() || r.is_nan() {
                        f64::NAN
                    } else {
                        m.max(r)
                    }
                });
            let (unit, i0, i1) = match i.checked_sub(9) {
                Some(k) => (
                    PARAMS[k].unit.to_owned(),
                    to_paper(k, s.initial_sigma),
                    to_paper(k, s.final_sigma),
                ),
                None => (s.unit.to_owned(), s.initial_sigma, s.final_sigma),
            };
            ObservabilityEntry {
                name: s.name.to_owned(),
                unit,
                initial_sigma: i0,
                final_sigma: i1,
                ratio: s.ratio,
                worst_ratio: worst,
                fell_tenfold: worst <= 0.1,
            }
        })
        .collect()
}
