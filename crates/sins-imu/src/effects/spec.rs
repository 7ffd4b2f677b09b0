//! [`EffectSpec`]: the data of one extra effect in SI, buildable into the [`ExtraEffect`] the
//! forward model applies, with the constructors the diagnosis uses for its candidate columns.

use super::ExtraEffect;
use super::gyro::{GyroGSensitivity, GyroScaleAsymmetry};
use super::kind::EffectKind;
use super::nonlinearity::{AccelCrossCoupling, AccelQuadratic};
use super::out_of_catalogue::{AccelBiasStep, GyroBiasOscillation};
use super::random_walk::BiasRandomWalk;
use super::size_effect::SizeEffect;
use super::temperature::{
    AccelBiasQuadraticTemp, AccelBiasTempRate, GyroBiasTemp, GyroBiasTempRate,
};
use super::thermal_lag::ThermalLag;
use super::time_local::{BiasEvent, EventShape};
use super::timing::AccelTimeOffset;
use crate::params::ImuErrorParams;
use sins_nav::Vec3;

/// Reference temperature (degC) of the temperature terms built by [`EffectSpec::unit`].
pub const DEFAULT_REFERENCE_DEGC: f64 = 20.0;
/// Period (s) of the gyro bias oscillation built by [`EffectSpec::unit`] (45 min).
pub const DEFAULT_OSCILLATION_PERIOD_S: f64 = 2700.0;
/// Time (s) of the accelerometer bias step built by [`EffectSpec::unit`] (2 h).
pub const DEFAULT_STEP_TIME_S: f64 = 7200.0;
/// Time constant (s) of the bias transients built by [`EffectSpec::unit`] (30 min).
pub const DEFAULT_TRANSIENT_TIME_CONSTANT_S: f64 = 1800.0;
/// Rise time of a ramp to a plateau, duration of a pulse and period of a decaying oscillation
/// built by [`EffectSpec::unit`] (1 h).
pub const DEFAULT_PROFILE_DURATION_S: f64 = 3600.0;
/// Decay time constant of a decaying oscillation built by [`EffectSpec::unit`] (2 h).
pub const DEFAULT_PROFILE_TIME_CONSTANT_S: f64 = 7200.0;

/// A data description of one extra effect (what experiment files name), buildable into the
/// [`ExtraEffect`] the forward model applies. Values in SI. The *magnitude components* (see
/// [`EffectKind::component_labels`], unit [`EffectKind::unit`]) are the fields scaled by
/// [`Self::scaled`]; the other fields (reference temperature, correlation time, seed, period,
/// phase, step time) are auxiliary and never scaled.
#[derive(Clone, Debug, PartialEq)]
pub enum EffectSpec {
    /// See [`AccelBiasQuadraticTemp`].
    AccelBiasQuadraticTemp {
        /// Coefficient per axis (m/s^2/degC^2).
        coeff_mps2_per_degc2: Vec3,
        /// Reference temperature (degC).
        reference_degc: f64,
    },
    /// See [`GyroBiasTemp`].
    GyroBiasTemp {
        /// Coefficient per axis (rad/s/degC).
        coeff_radps_per_degc: Vec3,
        /// Reference temperature (degC).
        reference_degc: f64,
    },
    /// See [`AccelBiasTempRate`].
    AccelBiasTempRate {
        /// Coefficient per axis (m/s^2 per degC/s).
        coeff_mps2_per_degc_per_s: Vec3,
    },
    /// See [`GyroBiasTempRate`].
    GyroBiasTempRate {
        /// Coefficient per axis (rad/s per degC/s).
        coeff_radps_per_degc_per_s: Vec3,
    },
    /// See [`ThermalLag`].
    ThermalLag {
        /// Extra lag time constant of each accelerometer behind its thermometer (s, >= 0).
        tau_s: Vec3,
    },
    /// See [`AccelQuadratic`].
    AccelQuadratic {
        /// K2 per axis ((m/s^2)/(m/s^2)^2 = 1/(m/s^2)).
        k2_per_mps2: Vec3,
    },
    /// See [`SizeEffect`].
    SizeEffect {
        /// Lever arm (m, body axes) of the x, y and z accelerometer from the navigation centre.
        lever_arm_m: [Vec3; 3],
    },
    /// See [`GyroScaleAsymmetry`].
    GyroScaleAsymmetry {
        /// Asymmetry per axis (dimensionless, 1 ppm = 1e-6).
        asymmetry: Vec3,
    },
    /// See [`GyroGSensitivity`].
    GyroGSensitivity {
        /// Diagonal g-sensitivity per axis (rad/s per m/s^2).
        coeff_radps_per_mps2: Vec3,
    },
    /// See [`AccelTimeOffset`].
    AccelTimeOffset {
        /// Delay of each accelerometer behind the gyros (s; negative = ahead).
        delay_s: Vec3,
    },
    /// See [`BiasRandomWalk`] (gyros).
    GyroBiasRandomWalk {
        /// Random-walk intensity per axis (rad/s/sqrt(s)).
        intensity_radps_per_sqrt_s: Vec3,
        /// Correlation time (s); infinite = pure random walk, finite = Gauss-Markov.
        correlation_s: f64,
        /// Seed of the realisation.
        seed: u64,
    },
    /// See [`BiasRandomWalk`] (accelerometers).
    AccelBiasRandomWalk {
        /// Random-walk intensity per axis (m/s^2/sqrt(s)).
        intensity_mps2_per_sqrt_s: Vec3,
        /// Correlation time (s); infinite = pure random walk, finite = Gauss-Markov.
        correlation_s: f64,
        /// Seed of the realisation.
        seed: u64,
    },
    /// See [`GyroBiasOscillation`] (outside the catalogue).
    GyroBiasOscillation {
        /// Amplitude per axis (rad/s).
        amplitude_radps: Vec3,
        /// Period (s, > 0).
        period_s: f64,
        /// Phase at t = 0 (rad).
        phase_rad: f64,
    },
    /// See [`AccelBiasStep`] (outside the catalogue).
    AccelBiasStep {
        /// Step per axis (m/s^2).
        step_mps2: Vec3,
        /// Time of the step (s).
        time_s: f64,
    },
    /// See [`AccelCrossCoupling`] (outside the catalogue).
    AccelCrossCoupling {
        /// Coefficient per axis (1/(m/s^2)).
        coeff_per_mps2: Vec3,
    },
    /// See [`BiasEvent`] (outside the catalogue, time-local): the kinds
    /// [`EffectKind::GyroBiasStep`], [`EffectKind::GyroBiasRamp`], [`EffectKind::AccelBiasRamp`],
    /// [`EffectKind::GyroBiasTransient`] and [`EffectKind::AccelBiasTransient`].
    BiasEvent {
        /// Which of the five kinds.
        kind: EffectKind,
        /// Magnitude per axis (SI: rad/s or m/s², a ramp's per second).
        magnitude_si: Vec3,
        /// Onset (s).
        onset_s: f64,
        /// Time constant of a transient (s, > 0; ignored by steps and ramps).
        time_constant_s: f64,
    },
    /// See [`BiasEvent`] (outside the catalogue, time-local) with the shapes outside the
    /// diagnosis scan's own: the kinds [`EffectKind::GyroBiasPlateau`],
    /// [`EffectKind::AccelBiasPlateau`], [`EffectKind::GyroBiasPulse`],
    /// [`EffectKind::AccelBiasPulse`], [`EffectKind::GyroBiasDecayingOscillation`] and
    /// [`EffectKind::AccelBiasDecayingOscillation`].
    BiasProfile {
        /// Which of the six kinds.
        kind: EffectKind,
        /// Magnitude per axis (SI: rad/s or m/s²; a plateau's level, a pulse's level, an
        /// oscillation's initial amplitude).
        magnitude_si: Vec3,
        /// Onset (s).
        onset_s: f64,
        /// Rise time of a plateau, duration of a pulse, period of an oscillation (s, > 0).
        duration_s: f64,
        /// Decay time constant of an oscillation (s, > 0; ignored by plateaus and pulses).
        time_constant_s: f64,
    },
}

impl EffectSpec {
    /// The kind of this effect.
    pub fn kind(&self) -> EffectKind {
        match self {
            EffectSpec::AccelBiasQuadraticTemp { .. } => EffectKind::AccelBiasQuadraticTemp,
            EffectSpec::GyroBiasTemp { .. } => EffectKind::GyroBiasTemp,
            EffectSpec::AccelBiasTempRate { .. } => EffectKind::AccelBiasTempRate,
            EffectSpec::GyroBiasTempRate { .. } => EffectKind::GyroBiasTempRate,
            EffectSpec::ThermalLag { .. } => EffectKind::ThermalLag,
            EffectSpec::AccelQuadratic { .. } => EffectKind::AccelQuadratic,
            EffectSpec::SizeEffect { .. } => EffectKind::SizeEffect,
            EffectSpec::GyroScaleAsymmetry { .. } => EffectKind::GyroScaleAsymmetry,
            EffectSpec::GyroGSensitivity { .. } => EffectKind::GyroGSensitivity,
            EffectSpec::AccelTimeOffset { .. } => EffectKind::AccelTimeOffset,
            EffectSpec::GyroBiasRandomWalk { .. } => EffectKind::GyroBiasRandomWalk,
            EffectSpec::AccelBiasRandomWalk { .. } => EffectKind::AccelBiasRandomWalk,
            EffectSpec::GyroBiasOscillation { .. } => EffectKind::GyroBiasOscillation,
            EffectSpec::AccelBiasStep { .. } => EffectKind::AccelBiasStep,
            EffectSpec::AccelCrossCoupling { .. } => EffectKind::AccelCrossCoupling,
            EffectSpec::BiasEvent { kind, .. } | EffectSpec::BiasProfile { kind, .. } => *kind,
        }
    }

    /// The effect's stable name (as in files and reports).
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }

    /// True when the diagnosis catalogue contains this kind.
    pub fn in_catalogue(&self) -> bool {
        self.kind().in_catalogue()
    }

    /// True when the perturbation is deterministic and linear in the magnitude components.
    pub fn is_linear(&self) -> bool {
        self.kind().is_linear()
    }

    /// Typical navigation-grade magnitude of one component (SI).
    pub fn typical_magnitude_si(&self) -> f64 {
        self.kind().typical_magnitude_si()
    }

    /// The spec of `kind` with every magnitude component zero and the default auxiliary values
    /// ([`DEFAULT_REFERENCE_DEGC`], infinite correlation time and seed 0,
    /// [`DEFAULT_OSCILLATION_PERIOD_S`] and phase 0, [`DEFAULT_STEP_TIME_S`]).
    pub fn zero(kind: EffectKind) -> EffectSpec {
        let z = Vec3::zeros();
        match kind {
            EffectKind::AccelBiasQuadraticTemp => EffectSpec::AccelBiasQuadraticTemp {
                coeff_mps2_per_degc2: z,
                reference_degc: DEFAULT_REFERENCE_DEGC,
            },
            EffectKind::GyroBiasTemp => EffectSpec::GyroBiasTemp {
                coeff_radps_per_degc: z,
                reference_degc: DEFAULT_REFERENCE_DEGC,
            },
            EffectKind::AccelBiasTempRate => EffectSpec::AccelBiasTempRate {
                coeff_mps2_per_degc_per_s: z,
            },
            EffectKind::GyroBiasTempRate => EffectSpec::GyroBiasTempRate {
                coeff_radps_per_degc_per_s: z,
            },
            EffectKind::ThermalLag => EffectSpec::ThermalLag { tau_s: z },
            EffectKind::AccelQuadratic => EffectSpec::AccelQuadratic { k2_per_mps2: z },
            EffectKind::SizeEffect => EffectSpec::SizeEffect {
                lever_arm_m: [z; 3],
            },
            EffectKind::GyroScaleAsymmetry => EffectSpec::GyroScaleAsymmetry { asymmetry: z },
            EffectKind::GyroGSensitivity => EffectSpec::GyroGSensitivity {
                coeff_radps_per_mps2: z,
            },
            EffectKind::AccelTimeOffset => EffectSpec::AccelTimeOffset { delay_s: z },
            EffectKind::GyroBiasRandomWalk => EffectSpec::GyroBiasRandomWalk {
                intensity_radps_per_sqrt_s: z,
                correlation_s: f64::INFINITY,
                seed: 0,
            },
            EffectKind::AccelBiasRandomWalk => EffectSpec::AccelBiasRandomWalk {
                intensity_mps2_per_sqrt_s: z,
                correlation_s: f64::INFINITY,
                seed: 0,
            },
            EffectKind::GyroBiasOscillation => EffectSpec::GyroBiasOscillation {
                amplitude_radps: z,
                period_s: DEFAULT_OSCILLATION_PERIOD_S,
                phase_rad: 0.0,
            },
            EffectKind::AccelBiasStep => EffectSpec::AccelBiasStep {
                step_mps2: z,
                time_s: DEFAULT_STEP_TIME_S,
            },
            EffectKind::AccelCrossCoupling => EffectSpec::AccelCrossCoupling { coeff_per_mps2: z },
            EffectKind::GyroBiasStep
            | EffectKind::GyroBiasRamp
            | EffectKind::AccelBiasRamp
            | EffectKind::GyroBiasTransient
            | EffectKind::AccelBiasTransient => EffectSpec::BiasEvent {
                kind,
                magnitude_si: z,
                onset_s: DEFAULT_STEP_TIME_S,
                time_constant_s: DEFAULT_TRANSIENT_TIME_CONSTANT_S,
            },
            EffectKind::GyroBiasPlateau
            | EffectKind::AccelBiasPlateau
            | EffectKind::GyroBiasPulse
            | EffectKind::AccelBiasPulse
            | EffectKind::GyroBiasDecayingOscillation
            | EffectKind::AccelBiasDecayingOscillation => EffectSpec::BiasProfile {
                kind,
                magnitude_si: z,
                onset_s: DEFAULT_STEP_TIME_S,
                duration_s: DEFAULT_PROFILE_DURATION_S,
                time_constant_s: DEFAULT_PROFILE_TIME_CONSTANT_S,
            },
        }
    }

    /// The spec of `kind` with magnitude 1 SI unit on component `axis` (0 = x, 1 = y, 2 = z; for
    /// the size effect `3 j + c`, see [`EffectKind::component_labels`]) and 0 elsewhere, auxiliary
    /// values as in [`Self::zero`]. For a [`super::Linearity::Linear`] kind its perturbation is the
    /// regression column of that component.
    ///
    /// # Panics
    /// If `axis >= kind.n_components()`.
    pub fn unit(kind: EffectKind, axis: usize) -> EffectSpec {
        let n = kind.n_components();
        assert!(axis < n, "{kind} has {n} components, asked for {axis}");
        let mut spec = Self::zero(kind);
        spec.for_each_magnitude(|i, m| {
            if i == axis {
                *m = 1.0;
            }
        });
        spec
    }

    /// `unit(kind, axis)` scaled to the kind's typical magnitude.
    pub fn typical(kind: EffectKind, axis: usize) -> EffectSpec {
        Self::unit(kind, axis).scaled(kind.typical_magnitude_si())
    }

    /// This spec with every magnitude component multiplied by `factor` (auxiliary fields kept).
    pub fn scaled(&self, factor: f64) -> EffectSpec {
        let mut spec = self.clone();
        spec.for_each_magnitude(|_, m| *m *= factor);
        spec
    }

    /// The magnitude components in SI, in [`EffectKind::component_labels`] order.
    pub fn magnitudes_si(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.kind().n_components());
        self.clone().for_each_magnitude(|_, m| out.push(*m));
        out
    }

    /// This spec with its magnitude components replaced by `values` (SI, component order);
    /// `None` when `values` has the wrong length.
    pub fn with_magnitudes_si(&self, values: &[f64]) -> Option<EffectSpec> {
        if values.len() != self.kind().n_components() {
            return None;
        }
        let mut spec = self.clone();
        spec.for_each_magnitude(|i, m| *m = values[i]);
        Some(spec)
    }

    /// True when every number of the spec is finite, except a correlation time, which may be
    /// `+inf`; time constants and correlation times must be >= 0 and > 0, a period > 0.
    pub fn is_valid(&self) -> bool {
        let mut ok = true;
        self.clone().for_each_magnitude(|_, m| ok &= m.is_finite());
        ok && match *self {
            EffectSpec::AccelBiasQuadraticTemp { reference_degc, .. }
            | EffectSpec::GyroBiasTemp { reference_degc, .. } => reference_degc.is_finite(),
            EffectSpec::ThermalLag { tau_s } => tau_s.iter().all(|t| *t >= 0.0),
            EffectSpec::GyroBiasRandomWalk { correlation_s, .. }
            | EffectSpec::AccelBiasRandomWalk { correlation_s, .. } => correlation_s > 0.0,
            EffectSpec::GyroBiasOscillation {
                period_s,
                phase_rad,
                ..
            } => period_s.is_finite() && period_s > 0.0 && phase_rad.is_finite(),
            EffectSpec::AccelBiasStep { time_s, .. } => time_s.is_finite(),
            EffectSpec::BiasEvent {
                onset_s,
                time_constant_s,
                ..
            } => onset_s.is_finite() && time_constant_s.is_finite() && time_constant_s > 0.0,
            EffectSpec::BiasProfile {
                onset_s,
                duration_s,
                time_constant_s,
                ..
            } => {
                onset_s.is_finite()
                    && duration_s.is_finite()
                    && duration_s > 0.0
                    && time_constant_s.is_finite()
                    && time_constant_s > 0.0
            }
            _ => true,
        }
    }

    /// The effect, ready for [`crate::ForwardModel::with_effect`]. `truth` is the paper-model
    /// parameter set of the IMU (the thermal lag acts through its TB, TK, TM; the other kinds
    /// ignore it).
    pub fn build(&self, truth: &ImuErrorParams) -> Box<dyn ExtraEffect> {
        match *self {
            EffectSpec::AccelBiasQuadraticTemp {
                coeff_mps2_per_degc2,
                reference_degc,
            } => Box::new(AccelBiasQuadraticTemp {
                coeff_mps2_per_degc2,
                reference_degc,
            }),
            EffectSpec::GyroBiasTemp {
                coeff_radps_per_degc,
                reference_degc,
            } => Box::new(GyroBiasTemp {
                coeff_radps_per_degc,
                reference_degc,
            }),
            EffectSpec::AccelBiasTempRate {
                coeff_mps2_per_degc_per_s,
            } => Box::new(AccelBiasTempRate {
                coeff_mps2_per_degc_per_s,
            }),
            EffectSpec::GyroBiasTempRate {
                coeff_radps_per_degc_per_s,
            } => Box::new(GyroBiasTempRate {
                coeff_radps_per_degc_per_s,
            }),
            EffectSpec::ThermalLag { tau_s } => Box::new(ThermalLag::new(tau_s, truth)),
            EffectSpec::AccelQuadratic { k2_per_mps2 } => Box::new(AccelQuadratic { k2_per_mps2 }),
            EffectSpec::SizeEffect { lever_arm_m } => Box::new(SizeEffect { lever_arm_m }),
            EffectSpec::GyroScaleAsymmetry { asymmetry } => {
                Box::new(GyroScaleAsymmetry { asymmetry })
            }
            EffectSpec::GyroGSensitivity {
                coeff_radps_per_mps2,
            } => Box::new(GyroGSensitivity {
                coeff_radps_per_mps2,
            }),
            EffectSpec::AccelTimeOffset { delay_s } => Box::new(AccelTimeOffset { delay_s }),
            EffectSpec::GyroBiasRandomWalk {
                intensity_radps_per_sqrt_s,
                correlation_s,
                seed,
            } => Box::new(BiasRandomWalk::gyro(
                intensity_radps_per_sqrt_s,
                correlation_s,
                seed,
            )),
            EffectSpec::AccelBiasRandomWalk {
                intensity_mps2_per_sqrt_s,
                correlation_s,
                seed,
            } => Box::new(BiasRandomWalk::accel(
                intensity_mps2_per_sqrt_s,
                correlation_s,
                seed,
            )),
            EffectSpec::GyroBiasOscillation {
                amplitude_radps,
                period_s,
                phase_rad,
            } => Box::new(GyroBiasOscillation {
                amplitude_radps,
                period_s,
                phase_rad,
            }),
            EffectSpec::AccelBiasStep { step_mps2, time_s } => {
                Box::new(AccelBiasStep { step_mps2, time_s })
            }
            EffectSpec::AccelCrossCoupling { coeff_per_mps2 } => {
                Box::new(AccelCrossCoupling { coeff_per_mps2 })
            }
            EffectSpec::BiasEvent {
                kind,
                magnitude_si,
                onset_s,
                time_constant_s,
            } => Box::new(BiasEvent {
                sensor: kind.sensor(),
                magnitude: magnitude_si,
                onset_s,
                shape: event_shape(kind, time_constant_s),
            }),
            EffectSpec::BiasProfile {
                kind,
                magnitude_si,
                onset_s,
                duration_s,
                time_constant_s,
            } => Box::new(BiasEvent {
                sensor: kind.sensor(),
                magnitude: magnitude_si,
                onset_s,
                shape: profile_shape(kind, duration_s, time_constant_s),
            }),
        }
    }

    /// Calls `f(component index, value)` on every magnitude component, in component order.
    fn for_each_magnitude(&mut self, mut f: impl FnMut(usize, &mut f64)) {
        let v: &mut Vec3 = match self {
            EffectSpec::SizeEffect { lever_arm_m } => {
                for (j, arm) in lever_arm_m.iter_mut().enumerate() {
                    for (c, m) in arm.iter_mut().enumerate() {
                        f(3 * j + c, m);
                    }
                }
                return;
            }
            EffectSpec::AccelBiasQuadraticTemp {
                coeff_mps2_per_degc2: v,
                ..
            }
            | EffectSpec::GyroBiasTemp {
                coeff_radps_per_degc: v,
                ..
            }
            | EffectSpec::AccelBiasTempRate {
                coeff_mps2_per_degc_per_s: v,
            }
            | EffectSpec::GyroBiasTempRate {
                coeff_radps_per_degc_per_s: v,
            }
            | EffectSpec::ThermalLag { tau_s: v }
            | EffectSpec::AccelQuadratic { k2_per_mps2: v }
            | EffectSpec::GyroScaleAsymmetry { asymmetry: v }
            | EffectSpec::GyroGSensitivity {
                coeff_radps_per_mps2: v,
            }
            | EffectSpec::AccelTimeOffset { delay_s: v }
            | EffectSpec::GyroBiasRandomWalk {
                intensity_radps_per_sqrt_s: v,
                ..
            }
            | EffectSpec::AccelBiasRandomWalk {
                intensity_mps2_per_sqrt_s: v,
                ..
            }
            | EffectSpec::GyroBiasOscillation {
                amplitude_radps: v, ..
            }
            | EffectSpec::AccelBiasStep { step_mps2: v, .. }
            | EffectSpec::AccelCrossCoupling { coeff_per_mps2: v }
            | EffectSpec::BiasEvent {
                magnitude_si: v, ..
            }
            | EffectSpec::BiasProfile {
                magnitude_si: v, ..
            } => v,
        };
        for (i, m) in v.iter_mut().enumerate() {
            f(i, m);
        }
    }
}

/// The time profile of a time-local kind (a step for any other kind).
pub fn event_shape(kind: EffectKind, time_constant_s: f64) -> EventShape {
    match kind {
        EffectKind::GyroBiasRamp | EffectKind::AccelBiasRamp => EventShape::Ramp,
        EffectKind::GyroBiasTransient | EffectKind::AccelBiasTransient => {
            EventShape::Transient { time_constant_s }
        }
        _ => EventShape::Step,
    }
}

/// The time profile of any time-local kind: the shapes of [`event_shape`], and a ramp to a
/// plateau (rise time `duration_s`), a pulse (duration `duration_s`) or a decaying oscillation
/// (period `duration_s`, decay `time_constant_s`).
pub fn profile_shape(kind: EffectKind, duration_s: f64, time_constant_s: f64) -> EventShape {
    match kind {
        EffectKind::GyroBiasPlateau | EffectKind::AccelBiasPlateau => {
            EventShape::Plateau { rise_s: duration_s }
        }
        EffectKind::GyroBiasPulse | EffectKind::AccelBiasPulse => EventShape::Pulse { duration_s },
        EffectKind::GyroBiasDecayingOscillation | EffectKind::AccelBiasDecayingOscillation => {
            EventShape::DecayingOscillation {
                period_s: duration_s,
                time_constant_s,
            }
        }
        _ => event_shape(kind, time_constant_s),
    }
}
