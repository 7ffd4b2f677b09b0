//! The serialisable result of a diagnosis.

use serde::{Deserialize, Serialize};

/// A chi-square consistency test.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChiSquareTest {
    /// The statistic `gᵀ S⁻¹ g` (after any fitted terms).
    pub chi2: f64,
    /// Its expected value if the model is right (the number of data less what the white floor
    /// of the metric absorbs, less the fitted parameters).
    pub dof: f64,
    /// Probability of a value at least this large if the model is right.
    pub p_value: f64,
    /// True when `p_value` is above the configured level.
    pub consistent: bool,
}

/// How a candidate enters the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CandidateModel {
    /// A deterministic term: regression columns, GLS magnitudes.
    Regression,
    /// A random process: an added noise term whose intensity is fitted by maximum likelihood.
    NoiseTerm,
}

/// One magnitude component of a candidate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ComponentEstimate {
    /// Component label (`x`, `y`, `z`, or `ax.y` ... for the size effect).
    pub label: String,
    /// Fitted value in the candidate's unit (0 when not retained).
    pub value: f64,
    /// Its 1-sigma (`None` when the data cannot identify it).
    pub sigma: Option<f64>,
    /// Kept in the final model of this candidate.
    pub retained: bool,
    /// Magnitude detected with 90 % probability at the configured significance when this
    /// component is the only effect (unit; `None` for unidentifiable ones; for noise terms the
    /// likelihood's one-sigma of the intensity stands in for the resolution near zero).
    pub detectable: Option<f64>,
}

/// The evidence for one candidate effect.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CandidateReport {
    /// Effect kind name (`sins_imu::EffectKind::name`).
    pub kind: String,
    /// One line of physics.
    pub description: String,
    /// Unit of the magnitudes (paper style).
    pub unit: String,
    /// Regression term or noise term.
    pub model: CandidateModel,
    /// Per-component estimates.
    pub components: Vec<ComponentEstimate>,
    /// Drop of the chi-square (2 × log-likelihood ratio) against the twin alone.
    pub dchi2: f64,
    /// Parameters used (retained components).
    pub dof: usize,
    /// Tail probability of `dchi2`, multiplied by the number of components tried
    /// (Bonferroni over the catalogue).
    pub p_value: f64,
    /// Bayesian information criterion improvement `dchi2 - dof ln n` (positive favours it).
    pub delta_bic: f64,
    /// Penalty of physically implausible magnitudes: `Σ (value / (K · typical))²` over the
    /// retained components, K = `rank::PRIOR_TIMES_TYPICAL` (a Gaussian prior with a
    /// standard deviation of K times the kind's typical navigation-grade magnitude).
    #[serde(default)]
    pub plausibility_penalty: f64,
    /// The ranking figure: `Δχ² / r − k ln n − penalty`, where `r ≥ 1` is the best candidate's
    /// residual chi-square over its expectation (quasi-likelihood: when even the best model
    /// leaves an inconsistent residual, the misfit inflates every Δχ² by about `r`).
    #[serde(default)]
    pub evidence: f64,
    /// Passes the significance level and has positive BIC improvement and evidence.
    pub passes: bool,
    /// Consistency of what is left once this candidate is added.
    pub residual: ChiSquareTest,
    /// Noise terms: whether the fitted walk's smoothed increments look like a walk's
    /// (`None` for regression terms and for a walk fitted at zero intensity).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub whiteness: Option<WhitenessTest>,
    /// The winner (the best passing regression term): whether one magnitude fits every run
    /// (`crate::constancy`; `None` for the other candidates and for a single run).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub constancy: Option<ConstancyTest>,
}

/// Constancy of a candidate's magnitude across runs: one magnitude per run against one for all.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConstancyTest {
    /// Chi-square drop of the per-run fit over the common fit (over the residual's inflation).
    pub dchi2: f64,
    /// Its degrees of freedom: retained components × (runs that see them − 1).
    pub dof: usize,
    /// Tail probability under a common magnitude.
    pub p_value: f64,
    /// True when `p_value` is above the configured level.
    pub consistent: bool,
    /// The strongest retained component fitted on each run with the others (candidate unit).
    pub per_run: Vec<RunEstimate>,
}

/// One run's estimate of a component.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunEstimate {
    /// Run name.
    pub run: String,
    /// Component label.
    pub label: String,
    /// Value (candidate unit; `None` when the run does not see the component).
    pub value: Option<f64>,
    /// Its one-sigma.
    pub sigma: Option<f64>,
}

/// Whiteness test of a random-walk candidate (`crate::walk`): its smoothed increments,
/// standardised under the fitted walk, should hold no outlier (a step) and no lag-one
/// correlation (an oscillation, a smooth drift).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WhitenessTest {
    /// Largest |z| of a standardised increment.
    pub max_abs_z: f64,
    /// Increments tested.
    pub increments: usize,
    /// Standardised lag-one correlation sum of neighbouring increments.
    pub lag1_z: f64,
    /// Stationarity of the increments' variance, first half against second half (z).
    #[serde(default)]
    pub stationarity_z: f64,
    /// Largest cross-run alignment of the increments at the same time since turn-on (z).
    #[serde(default)]
    pub aligned_z: f64,
    /// Tail probability of the most extreme statistic under the walk (Bonferroni).
    pub p_value: f64,
    /// True when `p_value` is above the configured level: the fit looks like a walk (and its
    /// evidence does not vanish once the time-local events are removed).
    pub consistent: bool,
    /// The walk's chi-square drop refitted on the gap less the time-local events, when there
    /// were events and the walk led.
    #[serde(default)]
    pub without_events_dchi2: Option<f64>,
}

/// The conclusion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "verdict", rename_all = "snake_case")]
pub enum Verdict {
    /// The real tracks are consistent with the twin and no candidate is significant.
    NoSignificantGap,
    /// One candidate explains the gap: significant, the residual is consistent, and one
    /// magnitude fits every run.
    Explained {
        /// Kind name.
        by: String,
    },
    /// The best candidate is significant but the residual is still inconsistent with the twin,
    /// or the magnitude it needs differs from run to run (see [`ConstancyTest`]).
    PartlyExplained {
        /// Kind name.
        by: String,
    },
    /// The gap is significant and no candidate of the catalogue explains it.
    Unexplained,
    /// The best candidates leave signatures the data cannot tell apart.
    NotSeparable {
        /// Catalogue kind names, best first.
        candidates: Vec<String>,
        /// Time courses outside the catalogue that explain the same gap as well (a catalogue
        /// effect driven by one chamber history and a time course common to every run look
        /// alike; see [`crate::rival`]).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        time_local: Vec<TimeCourseAlternative>,
    },
}

/// A time course outside the catalogue that explains the gap as well as a catalogue verdict:
/// one signal of the rival fit (see [`crate::rival`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimeCourseAlternative {
    /// The time-local kind it is reported as (`accel_bias_ramp`, `gyro_bias_step` ...).
    pub kind: String,
    /// Channel: `gyro x` ... `accel z` (body axes).
    pub channel: String,
    /// The run it acts in, or `all runs` (one time course on every run's time axis).
    pub runs: String,
    /// `step`, `ramp`, `transient`, `turn-on transient`, `pulse`, `plateau` or `oscillation`.
    pub shape: String,
    /// Onset (s on the run's time axis; navigation start for an oscillation).
    pub onset_s: f64,
    /// Time constant of a transient, duration of a pulse, rise time of a plateau, or period of
    /// an oscillation (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_s: Option<f64>,
    /// Size in `unit` (a step's jump, a ramp's rate, a transient's value at onset, a pulse's or
    /// a plateau's level, an oscillation's amplitude of its sine or cosine part).
    pub size: f64,
    /// Unit of the size.
    pub unit: String,
    /// Its chi-square drop when it was added to the rival fit (one degree of freedom).
    pub dchi2: f64,
}

/// One segment and channel of a run's gap.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SegmentGap {
    /// Segment label.
    pub segment: String,
    /// `north` or `east`.
    pub channel: String,
    /// Largest |gap| in the segment (m).
    pub max_abs_m: f64,
    /// RMS gap in the segment (m).
    pub rms_m: f64,
    /// Largest |gap| / twin sigma.
    pub max_sigmas: f64,
    /// Output points in the segment.
    pub points: usize,
}

/// Share of a channel's gap energy on one time-scale basis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TimeScaleShare {
    /// `north` or `east`.
    pub channel: String,
    /// `secular`, `foucault_24h`, `schuler_84min`, `segment_steps` or `residual`.
    pub basis: String,
    /// Fraction of the gap's energy (sum of squares) on this basis after the previous ones
    /// (nested in the order listed; the shares of a channel add up to one).
    pub share: f64,
    /// Fraction that only this basis explains: the full model's explained energy less that of
    /// the model without this basis (0 for the residual). A step at a segment start that a
    /// slow quadratic also roughly follows gets its nested share under `secular` but its unique
    /// share here.
    pub unique: f64,
}

/// Where one run's gap lies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunLocalisation {
    /// Run name.
    pub run: String,
    /// Per segment and channel.
    pub segments: Vec<SegmentGap>,
    /// First time the gap leaves the twin's 3-sigma envelope on either channel (s), if it does.
    pub first_exit_s: Option<f64>,
    /// Channel of that first exit.
    pub first_exit_channel: Option<String>,
    /// Segment of that first exit.
    pub first_exit_segment: Option<String>,
    /// Time-scale decomposition.
    pub time_scales: Vec<TimeScaleShare>,
    /// `gᵀ S⁻¹ g` of this run alone against its number of data.
    pub chi2: ChiSquareTest,
}

/// Gap metrics of one run before and after adding the fitted effect(s).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GapMetrics {
    /// |max horizontal error of the real track - that of the prediction| (m).
    pub max_horizontal_gap_m: f64,
    /// RMS over time of the horizontal gap vector (m).
    pub rms_gap_m: f64,
}

/// Withheld validation of the winning effect.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ValidationReport {
    /// Effect kind name.
    pub kind: String,
    /// The fitting data determined the effect (a retained component at |z| ≥ 3); when false the
    /// prediction is the twin alone and the shrinkage is zero.
    pub informative: bool,
    /// What the fit used (run names joined by `+`, or `<run>[first half]`).
    pub fitted_on: String,
    /// What it was evaluated on.
    pub evaluated_on: String,
    /// Fitted magnitudes (unit of the kind), retained components.
    pub magnitudes: Vec<(String, f64, f64)>,
    /// Before (twin alone).
    pub before: GapMetrics,
    /// After (twin + fitted effect).
    pub after: GapMetrics,
    /// `100 (1 - after/before)` for the RMS gap.
    pub rms_shrinkage_percent: f64,
    /// `100 (1 - after/before)` for the maximum-horizontal-error gap.
    pub max_shrinkage_percent: f64,
    /// Systematic gap before, `√max(0, gᵀ S⁻¹ g - E₀)` on the withheld fit points: the gap
    /// beyond what the twin's noise and calibration uncertainty explain, in the twin's own
    /// metric (dimensionless; 0 when the gap is within the twin's spread on average).
    #[serde(default)]
    pub systematic_before: f64,
    /// Systematic gap after the fitted effect is added.
    #[serde(default)]
    pub systematic_after: f64,
    /// `100 (1 - after/before)` of the systematic gap: the share of the gap the twin cannot
    /// attribute to noise that the effect removes. Unlike the RMS gap it is not diluted by the
    /// noise that the twin already predicts.
    #[serde(default)]
    pub systematic_shrinkage_percent: f64,
}

/// Time series of one run on the output grid, for plots.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunSeries {
    /// Run name.
    pub run: String,
    /// Output times (s).
    pub t_s: Vec<f64>,
    /// Segment label at each time.
    pub segment: Vec<String>,
    /// Gap real - twin mean, north (m).
    pub gap_north_m: Vec<f64>,
    /// Gap, east (m).
    pub gap_east_m: Vec<f64>,
    /// Twin 1-sigma, north (m).
    pub sigma_north_m: Vec<f64>,
    /// Twin 1-sigma, east (m).
    pub sigma_east_m: Vec<f64>,
    /// Prediction of the winning effect fitted to all runs, north (m; zeros if none).
    pub fitted_north_m: Vec<f64>,
    /// Same, east (m).
    pub fitted_east_m: Vec<f64>,
}

/// The whole diagnosis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Diagnosis {
    /// Total data used by the fits (two channels per fit time per run).
    pub n_data: usize,
    /// `gᵀ S⁻¹ g` of all runs together: is the gap consistent with the twin?
    pub null_test: ChiSquareTest,
    /// Candidates, best first (by BIC improvement).
    pub candidates: Vec<CandidateReport>,
    /// The conclusion.
    pub verdict: Verdict,
    /// Where the gap lies, per run.
    pub localisation: Vec<RunLocalisation>,
    /// Withheld validation of the winner (empty without a deterministic winner).
    pub validation: Vec<ValidationReport>,
    /// Series for plots.
    pub series: Vec<RunSeries>,
    /// Notes on assumptions, decisions and anything skipped, typed (see [`Note`]).
    pub notes: Vec<Note>,
    /// The time-local scan: events (steps, ramps, transients with their onset) and the
    /// detectable levels through each run.
    #[serde(default)]
    pub events: crate::events::EventScan,
    /// Why the twin's noise model cannot be trusted (empty when it can): the noise
    /// identification found its model inconsistent with the data it came from. The verdict
    /// then stands on a twin whose spread may be wrong, and says so.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub noise_untrusted: Vec<String>,
    /// Time courses outside the catalogue that explain the gap in place of the catalogue
    /// (verdict `unexplained`) or as well as it (verdict `not_separable`); see
    /// [`crate::rival`].
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rivals: Vec<TimeCourseAlternative>,
    /// How much of each temperature-driven candidate's information a time course common to
    /// every run takes away: a limit of the data (see [`crate::confound`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub confound: Vec<Confound>,
}

/// The confound of one temperature-driven candidate with a time course common to every run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Confound {
    /// Kind name.
    pub kind: String,
    /// Share of its Fisher information (pooled over components, 0-1) that the common time
    /// course takes away with these runs.
    pub information_lost: f64,
    /// Its component that loses the most.
    pub worst_component: String,
    /// That component's share lost (0-1).
    pub worst_component_lost: f64,
    /// The pooled share with one more run like `like_run`, the chamber held.
    pub with_held_run: f64,
    /// The pooled share with one more run like `like_run`, its temperature excursion reversed.
    pub with_reversed_run: f64,
    /// The run the extra runs are modelled on (the longest).
    pub like_run: String,
}

/// What a [`Note`] of the diagnosis is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NoteKind {
    /// The twin's assumptions: its mean, its spread, the fit grid of a long run.
    Twin,
    /// The calibration run's absorption of the candidates, or its absence.
    CalibrationAbsorption,
    /// The calibration uncertainty (none given).
    CalibrationUncertainty,
    /// Slow noise the identification left open, fitted on the gap and carried by the twin.
    UnresolvedWalks,
    /// A leading candidate refined in its own linearisation, or the refinement's failure.
    Refinement,
    /// The time-local scan: its family, its events, a walk refused for absorbing them, the
    /// catalogue ranked again without them.
    TimeLocal,
    /// The located events leave no significant gap: the catalogue gets no credit.
    NoCredit,
    /// The rival time courses and what the nested tests concluded.
    Rivals,
    /// The calibration run's filter innovations: outliers the paper's model does not explain,
    /// and whether a named cause, removed, accounts for them.
    CalibrationInnovations,
    /// From the noise identification the twin's noise came from (motion left out, bias
    /// changes, a model inconsistent with its data).
    NoiseIdentification,
}

/// A named figure a [`Note`] quotes, in the unit its name carries (`_s`, `chi2`, `p_value`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Figure {
    /// Name, with the unit as a suffix where it has one.
    pub name: String,
    /// Value.
    pub value: f64,
}

/// One note of a diagnosis: its kind, the run and channel it concerns (when one), the figures
/// it quotes, and its text for a reader. The Markdown report prints the text; the JSON keeps
/// the rest for a program.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Note {
    /// What it is about.
    pub kind: NoteKind,
    /// The run it concerns, if one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<String>,
    /// The channel or candidate it concerns, if one (`gyro x`, `gyro_bias_random_walk`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub subject: Option<String>,
    /// The figures the text quotes.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub figures: Vec<Figure>,
    /// The note as a sentence.
    pub text: String,
}

impl Note {
    /// A note of `kind` with `text` and nothing else.
    pub fn new(kind: NoteKind, text: impl Into<String>) -> Self {
        Self {
            kind,
            run: None,
            subject: None,
            figures: Vec::new(),
            text: text.into(),
        }
    }

    /// With the run it concerns.
    pub fn run(mut self, run: impl Into<String>) -> Self {
        self.run = Some(run.into());
        self
    }

    /// With the channel or candidate it concerns.
    pub fn subject(mut self, subject: impl Into<String>) -> Self {
        self.subject = Some(subject.into());
        self
    }

    /// With a figure it quotes.
    pub fn figure(mut self, name: &str, value: f64) -> Self {
        self.figures.push(Figure {
            name: name.to_string(),
            value,
        });
        self
    }
}

impl std::fmt::Display for Note {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}
