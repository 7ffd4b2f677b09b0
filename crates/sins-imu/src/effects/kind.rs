//! The kinds of extra effect as a fieldless enum: names, magnitude units (paper-style label + SI
//! factor), components, typical navigation-grade magnitudes, linearity and catalogue membership.

use sins_nav::{DEG_PER_H, G0_MPS2, UG};

/// Unit of the magnitude components of an effect kind: the label used in files and reports and
/// the SI value of one such unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MagnitudeUnit {
    /// Paper-style label, e.g. `"ug/degC^2"`, `"deg/h/g"`.
    pub label: &'static str,
    /// SI value of one unit (`value_si = value * si`).
    pub si: f64,
    /// The SI unit, e.g. `"m/s^2/degC^2"`.
    pub si_label: &'static str,
}

impl MagnitudeUnit {
    /// A value in this unit converted to SI.
    pub fn to_si(&self, value: f64) -> f64 {
        value * self.si
    }

    /// An SI value converted to this unit.
    pub fn from_si(&self, si: f64) -> f64 {
        si / self.si
    }
}

/// Which sensor triad an effect perturbs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sensor {
    /// The gyros (angular increments).
    Gyro,
    /// The accelerometers (velocity increments).
    Accel,
}

/// How the perturbation depends on the magnitude, i.e. how a diagnosis can use the effect.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Linearity {
    /// Deterministic and exactly linear in the magnitude components given the context: the
    /// perturbation of [`crate::EffectSpec::unit`] is a regression column (`apply(a x) = a
    /// apply(x)`).
    Linear,
    /// Deterministic but nonlinear in the magnitude (thermal lag's τ): linearise about zero. The
    /// unit spec (τ = 1 s) is already in the linear regime for temperatures varying over minutes,
    /// so its perturbation is the linearised column to better than 1 %.
    Linearised,
    /// A random process whose realisation is unknown (the random walks; linear in the magnitude
    /// only for a fixed seed): treat as a noise term of intensity `magnitude^2` (a process noise
    /// added to the corresponding bias state), not as a regression column.
    RandomProcess,
}

/// Every kind of extra effect (fieldless). See the effect types for the physics.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EffectKind {
    /// [`crate::effects::temperature::AccelBiasQuadraticTemp`]: `K2T_j (T_j - T_ref)^2`.
    AccelBiasQuadraticTemp,
    /// [`crate::effects::temperature::GyroBiasTemp`]: `TB_g,j (T_mean - T_ref)`.
    GyroBiasTemp,
    /// [`crate::effects::temperature::AccelBiasTempRate`]: `c_j dT_j/dt`.
    AccelBiasTempRate,
    /// [`crate::effects::temperature::GyroBiasTempRate`]: `c_j dT_mean/dt`.
    GyroBiasTempRate,
    /// [`crate::effects::thermal_lag::ThermalLag`]: sensor temperature lags the thermometer by τ_j.
    ThermalLag,
    /// [`crate::effects::nonlinearity::AccelQuadratic`]: `K2_j f_j^2` (vibration rectification).
    AccelQuadratic,
    /// [`crate::effects::size_effect::SizeEffect`]: accelerometer lever arms r_j.
    SizeEffect,
    /// [`crate::effects::gyro::GyroScaleAsymmetry`]: `a_j |ω_j|`.
    GyroScaleAsymmetry,
    /// [`crate::effects::gyro::GyroGSensitivity`]: `G_j f_j`.
    GyroGSensitivity,
    /// [`crate::effects::timing::AccelTimeOffset`]: accelerometers delayed by τ_j behind the gyros.
    AccelTimeOffset,
    /// [`crate::effects::random_walk::BiasRandomWalk`] on the gyros.
    GyroBiasRandomWalk,
    /// [`crate::effects::random_walk::BiasRandomWalk`] on the accelerometers.
    AccelBiasRandomWalk,
    /// Outside the catalogue: [`crate::effects::out_of_catalogue::GyroBiasOscillation`].
    GyroBiasOscillation,
    /// Outside the catalogue: [`crate::effects::out_of_catalogue::AccelBiasStep`].
    AccelBiasStep,
    /// Outside the catalogue: [`crate::effects::nonlinearity::AccelCrossCoupling`].
    AccelCrossCoupling,
    /// Outside the catalogue, time-local: a gyro bias step ([`crate::effects::time_local`]).
    GyroBiasStep,
    /// Outside the catalogue, time-local: a gyro bias ramp from an onset.
    GyroBiasRamp,
    /// Outside the catalogue, time-local: an accelerometer bias ramp from an onset.
    AccelBiasRamp,
    /// Outside the catalogue, time-local: a decaying gyro bias transient.
    GyroBiasTransient,
    /// Outside the catalogue, time-local: a decaying accelerometer bias transient.
    AccelBiasTransient,
    /// Outside the catalogue, time-local: a gyro bias rising linearly from an onset over a rise
    /// time, then holding its plateau (the magnitude is the plateau level).
    GyroBiasPlateau,
    /// Outside the catalogue, time-local: the same on the accelerometers.
    AccelBiasPlateau,
    /// Outside the catalogue, time-local: a rectangular gyro bias pulse (the level for a
    /// duration from the onset, then back to zero).
    GyroBiasPulse,
    /// Outside the catalogue, time-local: the same on the accelerometers.
    AccelBiasPulse,
    /// Outside the catalogue, time-local: a decaying gyro bias oscillation from an onset,
    /// `m sin(2π (t - t0)/P) exp(-(t - t0)/τ)`.
    GyroBiasDecayingOscillation,
    /// Outside the catalogue, time-local: the same on the accelerometers.
    AccelBiasDecayingOscillation,
}

const XYZ: &[&str] = &["x", "y", "z"];
const LEVER: &[&str] = &[
    "ax.x", "ax.y", "ax.z", "ay.x", "ay.y", "ay.z", "az.x", "az.y", "az.z",
];
const SQRT_S_PER_SQRT_H: f64 = 60.0;
const S_PER_MIN: f64 = 60.0;
const S_PER_H: f64 = 3600.0;

impl EffectKind {
    /// Every kind, in a fixed order (the catalogue first, then those outside it).
    pub const ALL: [EffectKind; 26] = [
        EffectKind::AccelBiasQuadraticTemp,
        EffectKind::GyroBiasTemp,
        EffectKind::AccelBiasTempRate,
        EffectKind::GyroBiasTempRate,
        EffectKind::ThermalLag,
        EffectKind::AccelQuadratic,
        EffectKind::SizeEffect,
        EffectKind::GyroScaleAsymmetry,
        EffectKind::GyroGSensitivity,
        EffectKind::AccelTimeOffset,
        EffectKind::GyroBiasRandomWalk,
        EffectKind::AccelBiasRandomWalk,
        EffectKind::GyroBiasOscillation,
        EffectKind::AccelBiasStep,
        EffectKind::AccelCrossCoupling,
        EffectKind::GyroBiasStep,
        EffectKind::GyroBiasRamp,
        EffectKind::AccelBiasRamp,
        EffectKind::GyroBiasTransient,
        EffectKind::AccelBiasTransient,
        EffectKind::GyroBiasPlateau,
        EffectKind::AccelBiasPlateau,
        EffectKind::GyroBiasPulse,
        EffectKind::AccelBiasPulse,
        EffectKind::GyroBiasDecayingOscillation,
        EffectKind::AccelBiasDecayingOscillation,
    ];

    /// The six time-local kinds that existed before the plateaus, pulses and decaying
    /// oscillations, in [`Self::ALL`] order: the blind suite's original time-local section
    /// cycles over exactly these (so that its seeds keep drawing the same cases).
    pub const ORIGINAL_TIME_LOCAL: [EffectKind; 6] = [
        EffectKind::AccelBiasStep,
        EffectKind::GyroBiasStep,
        EffectKind::GyroBiasRamp,
        EffectKind::AccelBiasRamp,
        EffectKind::GyroBiasTransient,
        EffectKind::AccelBiasTransient,
    ];

    /// The kinds the diagnosis considers (every kind with [`Self::in_catalogue`]), in
    /// [`Self::ALL`] order.
    pub fn catalogue() -> Vec<EffectKind> {
        Self::ALL.into_iter().filter(|k| k.in_catalogue()).collect()
    }

    /// Stable snake_case name (the `kind` of a `[[imu.effect]]` table).
    pub fn name(self) -> &'static str {
        match self {
            EffectKind::AccelBiasQuadraticTemp => "accel_bias_quadratic_temp",
            EffectKind::GyroBiasTemp => "gyro_bias_temp",
            EffectKind::AccelBiasTempRate => "accel_bias_temp_rate",
            EffectKind::GyroBiasTempRate => "gyro_bias_temp_rate",
            EffectKind::ThermalLag => "thermal_lag",
            EffectKind::AccelQuadratic => "accel_quadratic_nonlinearity",
            EffectKind::SizeEffect => "size_effect",
            EffectKind::GyroScaleAsymmetry => "gyro_scale_asymmetry",
            EffectKind::GyroGSensitivity => "gyro_g_sensitivity",
            EffectKind::AccelTimeOffset => "accel_time_offset",
            EffectKind::GyroBiasRandomWalk => "gyro_bias_random_walk",
            EffectKind::AccelBiasRandomWalk => "accel_bias_random_walk",
            EffectKind::GyroBiasOscillation => "gyro_bias_oscillation",
            EffectKind::AccelBiasStep => "accel_bias_step",
            EffectKind::AccelCrossCoupling => "accel_cross_coupling",
            EffectKind::GyroBiasStep => "gyro_bias_step",
            EffectKind::GyroBiasRamp => "gyro_bias_ramp",
            EffectKind::AccelBiasRamp => "accel_bias_ramp",
            EffectKind::GyroBiasTransient => "gyro_bias_transient",
            EffectKind::AccelBiasTransient => "accel_bias_transient",
            EffectKind::GyroBiasPlateau => "gyro_bias_plateau",
            EffectKind::AccelBiasPlateau => "accel_bias_plateau",
            EffectKind::GyroBiasPulse => "gyro_bias_pulse",
            EffectKind::AccelBiasPulse => "accel_bias_pulse",
            EffectKind::GyroBiasDecayingOscillation => "gyro_bias_decaying_oscillation",
            EffectKind::AccelBiasDecayingOscillation => "accel_bias_decaying_oscillation",
        }
    }

    /// The kind named `name` (see [`Self::name`]).
    pub fn from_name(name: &str) -> Option<EffectKind> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// One line of physics, for reports.
    pub fn description(self) -> &'static str {
        match self {
            EffectKind::AccelBiasQuadraticTemp => {
                "accelerometer bias second-order temperature coefficient K2T_j (T_j - T_ref)^2"
            }
            EffectKind::GyroBiasTemp => "gyro bias temperature coefficient TB_g,j (T_mean - T_ref)",
            EffectKind::AccelBiasTempRate => "accelerometer bias proportional to dT_j/dt",
            EffectKind::GyroBiasTempRate => "gyro bias proportional to dT_mean/dt",
            EffectKind::ThermalLag => {
                "sensor temperature lags the thermometer by a first-order time constant tau_j"
            }
            EffectKind::AccelQuadratic => {
                "accelerometer quadratic nonlinearity K2_j f_j^2 (vibration rectification)"
            }
            EffectKind::SizeEffect => {
                "size effect: accelerometer lever arms r_j, f_j += e_j.(w' x r_j + w x (w x r_j))"
            }
            EffectKind::GyroScaleAsymmetry => {
                "gyro scale-factor asymmetry: (1 + a_j) for positive, (1 - a_j) for negative rates"
            }
            EffectKind::GyroGSensitivity => "gyro g-sensitivity G_j f_j",
            EffectKind::AccelTimeOffset => {
                "accelerometer samples delayed by tau_j behind the gyros: -tau_j df_j/dt"
            }
            EffectKind::GyroBiasRandomWalk => "gyro bias random walk beyond the modelled noise",
            EffectKind::AccelBiasRandomWalk => {
                "accelerometer bias random walk beyond the modelled noise"
            }
            EffectKind::GyroBiasOscillation => "gyro bias oscillating with a 45 min period",
            EffectKind::AccelBiasStep => "accelerometer bias step at a given time",
            EffectKind::AccelCrossCoupling => {
                "accelerometer cross-axis coupling c_j f_(j+1) f_(j+2)"
            }
            EffectKind::GyroBiasStep => "gyro bias step at a given time",
            EffectKind::GyroBiasRamp => "gyro bias drifting linearly from a given time",
            EffectKind::AccelBiasRamp => "accelerometer bias drifting linearly from a given time",
            EffectKind::GyroBiasTransient => {
                "gyro bias jump at a given time decaying with a time constant (turn-on transient)"
            }
            EffectKind::AccelBiasTransient => {
                "accelerometer bias jump at a given time decaying with a time constant"
            }
            EffectKind::GyroBiasPlateau => {
                "gyro bias rising linearly from a given time over a rise time, then holding"
            }
            EffectKind::AccelBiasPlateau => {
                "accelerometer bias rising linearly from a given time over a rise time, then holding"
            }
            EffectKind::GyroBiasPulse => "gyro bias pulse: a level for a duration, then back to 0",
            EffectKind::AccelBiasPulse => {
                "accelerometer bias pulse: a level for a duration, then back to 0"
            }
            EffectKind::GyroBiasDecayingOscillation => {
                "gyro bias oscillation from a given time, decaying with a time constant"
            }
            EffectKind::AccelBiasDecayingOscillation => {
                "accelerometer bias oscillation from a given time, decaying with a time constant"
            }
        }
    }

    /// The sensor triad this kind perturbs.
    pub fn sensor(self) -> Sensor {
        match self {
            EffectKind::GyroBiasTemp
            | EffectKind::GyroBiasTempRate
            | EffectKind::GyroScaleAsymmetry
            | EffectKind::GyroGSensitivity
            | EffectKind::GyroBiasRandomWalk
            | EffectKind::GyroBiasOscillation
            | EffectKind::GyroBiasStep
            | EffectKind::GyroBiasRamp
            | EffectKind::GyroBiasTransient
            | EffectKind::GyroBiasPlateau
            | EffectKind::GyroBiasPulse
            | EffectKind::GyroBiasDecayingOscillation => Sensor::Gyro,
            _ => Sensor::Accel,
        }
    }

    /// Unit of the magnitude components.
    pub fn unit(self) -> MagnitudeUnit {
        let u = |label, si, si_label| MagnitudeUnit {
            label,
            si,
            si_label,
        };
        match self {
            EffectKind::AccelBiasQuadraticTemp => u("ug/degC^2", UG, "m/s^2/degC^2"),
            EffectKind::GyroBiasTemp => u("deg/h/degC", DEG_PER_H, "rad/s/degC"),
            EffectKind::AccelBiasTempRate => u("ug/(degC/min)", UG * S_PER_MIN, "m/s^2/(degC/s)"),
            EffectKind::GyroBiasTempRate => {
                u("deg/h/(degC/min)", DEG_PER_H * S_PER_MIN, "rad/s/(degC/s)")
            }
            EffectKind::ThermalLag => u("s", 1.0, "s"),
            EffectKind::AccelQuadratic | EffectKind::AccelCrossCoupling => {
                u("ug/g^2", UG / (G0_MPS2 * G0_MPS2), "1/(m/s^2)")
            }
            EffectKind::SizeEffect => u("mm", 1e-3, "m"),
            EffectKind::GyroScaleAsymmetry => u("ppm", 1e-6, "1"),
            EffectKind::GyroGSensitivity => u("deg/h/g", DEG_PER_H / G0_MPS2, "rad/s/(m/s^2)"),
            EffectKind::AccelTimeOffset => u("ms", 1e-3, "s"),
            EffectKind::GyroBiasRandomWalk => u(
                "deg/h/sqrt(h)",
                DEG_PER_H / SQRT_S_PER_SQRT_H,
                "rad/s/sqrt(s)",
            ),
            EffectKind::AccelBiasRandomWalk => {
                u("ug/sqrt(h)", UG / SQRT_S_PER_SQRT_H, "m/s^2/sqrt(s)")
            }
            EffectKind::GyroBiasOscillation
            | EffectKind::GyroBiasStep
            | EffectKind::GyroBiasTransient
            | EffectKind::GyroBiasPlateau
            | EffectKind::GyroBiasPulse
            | EffectKind::GyroBiasDecayingOscillation => u("deg/h", DEG_PER_H, "rad/s"),
            EffectKind::AccelBiasStep
            | EffectKind::AccelBiasTransient
            | EffectKind::AccelBiasPlateau
            | EffectKind::AccelBiasPulse
            | EffectKind::AccelBiasDecayingOscillation => u("ug", UG, "m/s^2"),
            EffectKind::GyroBiasRamp => u("deg/h/h", DEG_PER_H / S_PER_H, "rad/s/s"),
            EffectKind::AccelBiasRamp => u("ug/h", UG / S_PER_H, "m/s^2/s"),
        }
    }

    /// Labels of the magnitude components: `x`, `y`, `z` for per-axis kinds; for the size effect
    /// `ax.x` .. `az.z` (component c of the lever arm of accelerometer j, index `3 j + c`).
    pub fn component_labels(self) -> &'static [&'static str] {
        match self {
            EffectKind::SizeEffect => LEVER,
            _ => XYZ,
        }
    }

    /// Number of magnitude components (3, or 9 for the size effect).
    pub fn n_components(self) -> usize {
        self.component_labels().len()
    }

    /// Typical navigation-grade magnitude of one component, in [`Self::unit`], for this IMU class
    /// (laser gyros of 0.005 deg/h bias stability, quartz accelerometers of tens of ug).
    pub fn typical_magnitude(self) -> f64 {
        match self {
            // Quartz pendulous accelerometer: 0.01-0.1 ug/degC^2 (20 ug over +-20 degC).
            EffectKind::AccelBiasQuadraticTemp => 0.05,
            // Ring-laser gyro bias: 0.0002-0.001 deg/h/degC (0.01 deg/h over 20 degC).
            EffectKind::GyroBiasTemp => 5e-4,
            // Thermal gradients across the pendulum: ~10 ug per degC/min.
            EffectKind::AccelBiasTempRate => 10.0,
            // Laser-gyro bias under thermal transients: ~0.005 deg/h per degC/min.
            EffectKind::GyroBiasTempRate => 5e-3,
            // Case thermometer to proof mass: about a minute.
            EffectKind::ThermalLag => 60.0,
            // Quartz accelerometer K2: below 10-20 ug/g^2.
            EffectKind::AccelQuadratic => 10.0,
            // Proof masses sit 10-40 mm from the navigation centre; systems correct the nominal
            // geometry, what stays unmodelled is ~1 mm (still ~0.01 g rectified in pattern 3).
            EffectKind::SizeEffect => 1.0,
            // Laser-gyro scale-factor asymmetry: 1-5 ppm.
            EffectKind::GyroScaleAsymmetry => 2.0,
            // Laser gyros are nearly g-insensitive: ~0.001 deg/h/g.
            EffectKind::GyroGSensitivity => 1e-3,
            // Gyro/accelerometer sampling skew: a fraction of a millisecond.
            EffectKind::AccelTimeOffset => 0.5,
            // Gyro bias drift beyond the noise: 0.001 deg/h/sqrt(h) (0.004 deg/h in 15 h).
            EffectKind::GyroBiasRandomWalk => 1e-3,
            // Accelerometer bias drift: 2 ug/sqrt(h) (8 ug in 15 h).
            EffectKind::AccelBiasRandomWalk => 2.0,
            EffectKind::GyroBiasOscillation => 5e-3,
            EffectKind::AccelBiasStep => 20.0,
            EffectKind::AccelCrossCoupling => 20.0,
            // A laser-gyro bias jump: a few times its 0.0005 deg/h stability.
            EffectKind::GyroBiasStep => 2e-3,
            // Bias drift after a thermal event: 0.001 deg/h per hour, 10 ug per hour.
            EffectKind::GyroBiasRamp => 1e-3,
            EffectKind::AccelBiasRamp => 10.0,
            // Turn-on transient: 0.01 deg/h decaying over tens of minutes; accelerometer 30 ug.
            EffectKind::GyroBiasTransient => 1e-2,
            EffectKind::AccelBiasTransient => 30.0,
            // Plateaus, pulses and decaying oscillations: the size of a bias step.
            EffectKind::GyroBiasPlateau
            | EffectKind::GyroBiasPulse
            | EffectKind::GyroBiasDecayingOscillation => 2e-3,
            EffectKind::AccelBiasPlateau
            | EffectKind::AccelBiasPulse
            | EffectKind::AccelBiasDecayingOscillation => 20.0,
        }
    }

    /// [`Self::typical_magnitude`] in SI.
    pub fn typical_magnitude_si(self) -> f64 {
        self.unit().to_si(self.typical_magnitude())
    }

    /// True for the kinds the diagnosis considers; false for those kept to test that it reports
    /// "none of the catalogue explains it".
    pub fn in_catalogue(self) -> bool {
        !matches!(
            self,
            EffectKind::GyroBiasOscillation
                | EffectKind::AccelBiasStep
                | EffectKind::AccelCrossCoupling
        ) && !self.is_time_local()
    }

    /// True for the kinds that act from an onset time on (steps, ramps, transients, ramps to a
    /// plateau, pulses, decaying oscillations): outside the catalogue; the diagnosis's scan over
    /// onset time looks for steps, ramps and transients ([`Self::ORIGINAL_TIME_LOCAL`]), the
    /// other shapes are there to test it on shapes outside its own.
    pub fn is_time_local(self) -> bool {
        Self::ORIGINAL_TIME_LOCAL.contains(&self) || self.is_extra_time_local()
    }

    /// True for the time-local shapes added after [`Self::ORIGINAL_TIME_LOCAL`]: ramps to a
    /// plateau, pulses and decaying oscillations (gyro and accelerometer).
    pub fn is_extra_time_local(self) -> bool {
        matches!(
            self,
            EffectKind::GyroBiasPlateau
                | EffectKind::AccelBiasPlateau
                | EffectKind::GyroBiasPulse
                | EffectKind::AccelBiasPulse
                | EffectKind::GyroBiasDecayingOscillation
                | EffectKind::AccelBiasDecayingOscillation
        )
    }

    /// How the perturbation depends on the magnitude (see [`Linearity`]).
    pub fn linearity(self) -> Linearity {
        match self {
            EffectKind::ThermalLag => Linearity::Linearised,
            EffectKind::GyroBiasRandomWalk | EffectKind::AccelBiasRandomWalk => {
                Linearity::RandomProcess
            }
            _ => Linearity::Linear,
        }
    }

    /// True when the perturbation is a deterministic linear function of the magnitude components
    /// ([`Linearity::Linear`]).
    pub fn is_linear(self) -> bool {
        self.linearity() == Linearity::Linear
    }
}

impl std::fmt::Display for EffectKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
