//! The sensitivities and the twin's noise covariance of one run, from one pass over its samples.

use crate::align::AlignmentReplica;
use crate::bank::ColumnBank;
use crate::columns::{ColumnEval, slots_of};
use crate::error::DiagError;
use crate::model::{ErrorModel, Vec7};
use crate::noise::{NoiseProp, NoiseSpec};
use crate::pass::{Grid, PassInput, PassTimes, run_pass};
use crate::replay::ReplaySetup;
use crate::source::SampleSource;
use crate::temperature::TemperatureSeries;
use nalgebra::DMatrix;
use sins_imu::effects::Sensor;
use sins_imu::effects::time_local::{BiasEvent, EventShape};
use sins_imu::{EffectKind, EffectSpec, ImuErrorParams, Linearity};
use sins_nav::{Geodetic, Vec3};
use sins_replay::ErrorPoint;

/// Indices (into `columns::PARAM_SLOTS`) of the six bias coefficients, whose full responses carry the
/// random-walk candidates: gyro x, y, z then accelerometer x, y, z.
pub const BIAS_SLOTS: [usize; 6] = [0, 1, 2, 3, 4, 5];

/// One column's identity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColumnId {
    /// Component `1` of catalogue kind `0` (1 SI unit).
    Effect(EffectKind, usize),
    /// A paper coefficient (index into `columns::PARAM_SLOTS`, 1 SI unit).
    Param(usize),
}

/// Everything the fit needs from one run.
#[derive(Clone, Debug)]
pub struct RunSensitivity {
    /// Run name.
    pub run: String,
    /// Output and fit times.
    pub times: PassTimes,
    /// Column identities, in the order of `north_m` / `east_m`.
    pub ids: Vec<ColumnId>,
    /// North position response of each column at each output time (m per SI unit).
    pub north_m: Vec<Vec<f64>>,
    /// East position response (m per SI unit).
    pub east_m: Vec<Vec<f64>>,
    /// Full error states of the six bias columns ([`BIAS_SLOTS`]) at each output time.
    pub bias_states: Vec<Vec<Vec7>>,
    /// Full error states of the six bias columns at the start of navigation.
    pub bias_states_at_nav_start: Vec<Vec7>,
    /// Time constants of the turn-on transient columns (s).
    pub turn_on_taus_s: Vec<f64>,
    /// Full state at the first output time of a unit bias `e^{-(t - t0)/τ}` from the first
    /// sample (`t0` = `PassTimes::start_s`) on each bias axis (gyro x, y, z, accelerometer
    /// x, y, z; rad/s or m/s²), through the alignment: `[axis][τ index]`.
    pub turn_on_states: Vec<Vec<Vec7>>,
    /// Twin noise: position covariance `[var N, var E, cov NE]` at each output time (m²).
    pub envelope: Vec<[f64; 3]>,
    /// Twin noise: covariance of `[N_0, E_0, N_1, ...]` at the fit times (m²).
    pub fit_covariance: DMatrix<f64>,
    /// Error model at the site (for the random-walk responses).
    pub model: ErrorModel,
}

impl RunSensitivity {
    /// Index of column `id`, if computed.
    pub fn column(&self, id: ColumnId) -> Option<usize> {
        self.ids.iter().position(|&c| c == id)
    }
}

/// Settings of a sensitivity pass.
pub struct SensitivitySetup<'a> {
    /// Calibrated parameter set (compensation; the thermal lag's coefficients).
    pub params: &'a ImuErrorParams,
    /// Twin noise.
    pub noise: &'a NoiseSpec,
    /// How the real pipeline replays (alignment, algorithm).
    pub replay: &'a ReplaySetup,
    /// Candidate kinds (random processes get no column: they use the bias columns).
    pub candidates: &'a [EffectKind],
    /// Grids.
    pub grid: Grid,
    /// Refinement pass: only the columns of this kind (no calibration columns), evaluated with
    /// the kind's own fitted perturbation (SI magnitudes) removed from the increments.
    pub refine: Option<(EffectKind, Vec<f64>)>,
    /// Time constants (s) of the turn-on bias transients propagated through the alignment to
    /// the first output time (see [`RunSensitivity::turn_on_states`]).
    pub turn_on_taus_s: &'a [f64],
}

/// One pass over `source`: sensitivities of every candidate component and calibration
/// coefficient, and the twin's noise covariance.
pub fn run_sensitivity(
    run: &str,
    source: &mut dyn SampleSource,
    site: &Geodetic,
    track: &[ErrorPoint],
    temperatures: &TemperatureSeries,
    setup: &SensitivitySetup<'_>,
) -> Result<RunSensitivity, DiagError> {
    if track.is_empty() {
        return Err(DiagError::input(run, "the real error track is empty"));
    }
    let h = source.sample_interval_s();
    if !(h.is_finite() && h > 0.0) {
        return Err(DiagError::input(run, format!("bad sample interval {h} s")));
    }
    let model = ErrorModel::new(site);
    let nav = setup.replay.strapdown(h, site);
    let replica = AlignmentReplica::new(&setup.replay.alignment, &nav, site, &model);
    let mut ids = Vec::new();
    let mut evals = Vec::new();
    let only = setup.refine.as_ref().map(|r| r.0);
    for &kind in setup.candidates {
        if kind.linearity() == Linearity::RandomProcess || only.is_some_and(|o| o != kind) {
            continue;
        }
        for c in 0..kind.n_components() {
            ids.push(ColumnId::Effect(kind, c));
            evals.push(ColumnEval::effect(kind, c, setup.params));
        }
    }
    for (i, slot) in slots_of(setup.params.model).filter(|_| only.is_none()) {
        ids.push(ColumnId::Param(i));
        evals.push(ColumnEval::Param(*slot));
    }
    let keep: Vec<usize> = BIAS_SLOTS
        .iter()
        .map(|&b| {
            ids.iter()
                .position(|&c| c == ColumnId::Param(b))
                .unwrap_or(0)
        })
        .collect();
    let start_s = source.start_time_s();
    let turn_on = (0..6)
        .flat_map(|axis| {
            setup
                .turn_on_taus_s
                .iter()
                .map(move |&tau_s| turn_on_column(axis, tau_s, start_s))
        })
        .collect();
    let mut bank = ColumnBank::new(evals, keep).with_turn_on(turn_on);
    let mut noise = NoiseProp::new(*setup.noise);
    let inp = PassInput {
        run,
        params: setup.params,
        track,
        temperatures,
        replica: &replica,
        model: &model,
        grid: setup.grid,
    };
    let mut correction = match &setup.refine {
        Some((kind, values)) => Some(
            EffectSpec::zero(*kind)
                .with_magnitudes_si(values)
                .ok_or_else(|| DiagError::input(run, "refinement magnitudes of the wrong length"))?
                .build(setup.params),
        ),
        None => None,
    };
    let times = run_pass(source, &inp, &mut bank, &mut noise, correction.as_mut())?;
    let n_tau = setup.turn_on_taus_s.len();
    let turn_on_states = (0..6)
        .map(|a| bank.turn_on_at_first_output[a * n_tau..(a + 1) * n_tau].to_vec())
        .collect();
    Ok(RunSensitivity {
        run: run.to_string(),
        fit_covariance: noise.fit_covariance(),
        envelope: noise.envelope,
        ids,
        north_m: bank.north_m,
        east_m: bank.east_m,
        bias_states: bank.full,
        bias_states_at_nav_start: bank.full_at_nav_start,
        turn_on_taus_s: setup.turn_on_taus_s.to_vec(),
        turn_on_states,
        times,
        model,
    })
}

/// The column of a unit bias `e^{-(t - start_s)/τ}` on bias axis `axis` (gyro x, y, z then
/// accelerometer x, y, z; rad/s or m/s²) from the first sample.
fn turn_on_column(axis: usize, tau_s: f64, start_s: f64) -> ColumnEval {
    let mut magnitude = Vec3::zeros();
    magnitude[axis % 3] = 1.0;
    ColumnEval::Effect(Box::new(BiasEvent {
        sensor: if axis < 3 {
            Sensor::Gyro
        } else {
            Sensor::Accel
        },
        magnitude,
        onset_s: start_s,
        shape: EventShape::Transient {
            time_constant_s: tau_s,
        },
    }))
}
