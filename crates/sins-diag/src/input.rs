//! What a diagnosis takes: the real runs, the calibrated parameter set with its uncertainty,
//! the noise model of the twin, and the settings.

use crate::noise::NoiseSpec;
use crate::replay::ReplaySetup;
use crate::source::SampleSource;
use crate::temperature::TemperatureSeries;
use serde::{Deserialize, Serialize};
use sins_imu::{EffectKind, ImuErrorParams};
use sins_nav::Geodetic;
use sins_replay::ErrorPoint;

/// One real run: its samples (re-readable, never held whole), where it was recorded, its
/// segment labels and its real error track (the replay with the calibrated parameters).
pub struct RunData {
    /// Name used in reports.
    pub name: String,
    /// The raw samples.
    pub source: Box<dyn SampleSource>,
    /// Turntable site.
    pub site: Geodetic,
    /// Segment labels (the source's segment indices point into this list).
    pub segment_labels: Vec<String>,
    /// Real error track: 1 Hz error points of the replay with the calibrated parameter set,
    /// self-aligned as [`DiagnoseConfig::replay`] says.
    pub track: Vec<ErrorPoint>,
    /// Per-second temperature means and rates (`None`: computed by an extra pass).
    pub temperatures: Option<TemperatureSeries>,
    /// The twin's mean error track (`None`: zero, i.e. the error-free floor of the algorithm,
    /// 0.3 m over 15 h, is neglected).
    pub twin_mean: Option<Vec<ErrorPoint>>,
}

/// Everything a diagnosis needs.
pub struct DiagnosisInput {
    /// The real runs (a calibration run and/or navigation runs of the same IMU).
    pub runs: Vec<RunData>,
    /// The calibrated parameter set (what the real replay compensated with).
    pub params: ImuErrorParams,
    /// One-sigma of each calibrated coefficient (SI, same layout), if known, treated as
    /// independent. Its effect is common to all runs.
    pub param_sigma: Option<ImuErrorParams>,
    /// Full covariance of the coefficients the model uses (SI, row-major, eq 8 state order,
    /// 21 × 21 or 33 × 33: the calibration filter's `param_covariance`); takes precedence over
    /// `param_sigma`.
    pub param_covariance: Option<Vec<f64>>,
    /// Sensor noise of the twin.
    pub noise: NoiseSpec,
    /// The run (by name) the parameter set was calibrated from, if it is among `runs`: the
    /// candidates then also act through the coefficients the calibration absorbed them into
    /// (see [`crate::absorb`]).
    pub calibration_run: Option<String>,
}

/// Settings of a diagnosis.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct DiagnoseConfig {
    /// How the real pipeline replays runs (alignment, algorithm): must match the tracks.
    #[serde(skip)]
    pub replay: ReplaySetup,
    /// Output grid of the sensitivities, envelope and series (whole seconds).
    pub output_interval_s: usize,
    /// Fit grid (whole seconds, a multiple of the output interval).
    pub fit_interval_s: usize,
    /// White error added to every fit datum of the metric, a tolerance for what the twin does
    /// not model: the algorithm's floor and the linearisation (m).
    pub floor_sigma_m: f64,
    /// How much of that floor the chi-square tests expect the data to carry (m): the tests'
    /// null distributions count a white floor of this size, not `floor_sigma_m` (counting the
    /// whole tolerance as noise would make them blind; counting none would flag the
    /// algorithm's own 0.3 m).
    pub floor_expected_sigma_m: f64,
    /// Family-wise significance level of the candidate tests.
    pub alpha: f64,
    /// Level of the chi-square consistency tests (null and residual).
    pub null_alpha: f64,
    /// Components of a candidate whose |z| falls below this are dropped from its model.
    pub z_keep: f64,
    /// Two candidates whose fitted signatures explain each other to this fraction (in the
    /// twin's metric)...
    pub separability_r2: f64,
    /// ...and whose chi-square drops differ by less than this are reported as not separable.
    pub separability_dchi2: f64,
    /// Lumping interval of the random-walk noise terms (s).
    pub walk_step_s: usize,
    /// Candidate kinds by name (empty: the whole catalogue, `EffectKind::catalogue()`).
    pub candidates: Vec<String>,
    /// Kinds refined whenever they are among the leading candidates, even when their linear
    /// fit is consistent: their perturbation is a strong function of the increments it
    /// perturbs, so that their columns, evaluated on data that carry them, are biased at
    /// first order in the magnitude (the time offset: about 7 % per ms).
    pub refine: Vec<String>,
    /// How many of the leading passing deterministic candidates may be refined (those whose
    /// linear residual is inconsistent, or whose kind is in `refine`); 0 turns the
    /// refinement off. Each costs a corrected replay and a sensitivity pass per run and step.
    pub refine_top: usize,
    /// Gauss-Newton steps at most per refined candidate.
    pub refine_steps: usize,
    /// A refinement stops after the step whose predicted residual chi-square exceeds this many
    /// times the best residual so far (linear or refined, over the deterministic candidates):
    /// such a candidate cannot come close to the leader, so further steps only cost time.
    pub refine_competitive: f64,
    /// Only candidates whose linear residual chi-square is within this factor of the best
    /// linear residual are refined (a candidate a hundred times worse than another before
    /// refinement is not a rival of the leader; each refinement costs passes over every run).
    pub refine_within: f64,
    /// Worker threads (runs are processed in parallel; results do not depend on it).
    pub threads: usize,
    /// The scan for effects local in time (steps, ramps, transients).
    pub events: crate::events::EventScanConfig,
}

impl Default for DiagnoseConfig {
    fn default() -> Self {
        Self {
            replay: ReplaySetup::default(),
            output_interval_s: 10,
            fit_interval_s: 120,
            floor_sigma_m: 1.0,
            floor_expected_sigma_m: 0.2,
            alpha: 1e-3,
            null_alpha: 1e-3,
            z_keep: 2.0,
            separability_r2: 0.9,
            separability_dchi2: 10.0,
            walk_step_s: 1200,
            candidates: Vec::new(),
            refine: vec![EffectKind::AccelTimeOffset.name().to_string()],
            refine_top: 3,
            refine_steps: 3,
            refine_competitive: 10.0,
            refine_within: 100.0,
            threads: 2,
            events: crate::events::EventScanConfig::default(),
        }
    }
}

impl DiagnoseConfig {
    /// The kinds of [`Self::refine`] (unknown names ignored).
    pub fn refine_kinds(&self) -> Vec<EffectKind> {
        self.refine
            .iter()
            .filter_map(|n| EffectKind::from_name(n))
            .collect()
    }

    /// The candidate kinds to try.
    pub fn candidate_kinds(&self) -> Result<Vec<EffectKind>, String> {
        if self.candidates.is_empty() {
            return Ok(EffectKind::catalogue());
        }
        self.candidates
            .iter()
            .map(|n| EffectKind::from_name(n).ok_or_else(|| format!("unknown effect kind '{n}'")))
            .collect()
    }
}
