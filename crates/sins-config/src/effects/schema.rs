//! The file keys of every effect kind: magnitude keys (paper-style units, three components
//! each) and auxiliary keys, with access to the auxiliary values of a spec.

use crate::exact::ExactFactor;
use sins_imu::{EffectKind, EffectSpec};
use sins_nav::DEG;

/// An auxiliary (non-magnitude) key of an effect kind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Aux {
    /// `reference_degc` (optional, default 20 degC).
    ReferenceDegc,
    /// `correlation_s` (optional, default `inf` = random walk; > 0).
    CorrelationS,
    /// `seed` (required integer >= 0).
    Seed,
    /// `period_s` (optional, default 2700 s; > 0).
    PeriodS,
    /// `phase_deg` (optional, default 0).
    PhaseDeg,
    /// `time_s` (optional, default 7200 s).
    TimeS,
    /// `time_constant_s` (optional, default 1800 s, 7200 s for a decaying oscillation; > 0).
    TimeConstantS,
    /// `rise_time_s` of a ramp to a plateau (optional, default 3600 s; > 0).
    RiseTimeS,
    /// `duration_s` of a pulse (optional, default 3600 s; > 0).
    DurationS,
}

impl Aux {
    pub(super) fn key(self) -> &'static str {
        match self {
            Aux::ReferenceDegc => "reference_degc",
            Aux::CorrelationS => "correlation_s",
            Aux::Seed => "seed",
            Aux::PeriodS => "period_s",
            Aux::PhaseDeg => "phase_deg",
            Aux::TimeS => "time_s",
            Aux::TimeConstantS => "time_constant_s",
            Aux::RiseTimeS => "rise_time_s",
            Aux::DurationS => "duration_s",
        }
    }

    pub(super) fn factor(self) -> ExactFactor {
        match self {
            Aux::PhaseDeg => ExactFactor::binary(DEG),
            _ => ExactFactor::ONE,
        }
    }
}

/// The file keys of a kind: magnitude keys (each three components, in component order) and
/// auxiliary keys.
pub(super) fn schema(kind: EffectKind) -> (&'static [&'static str], &'static [Aux]) {
    match kind {
        EffectKind::AccelBiasQuadraticTemp => (&["coeff_ug_per_degc2"], &[Aux::ReferenceDegc]),
        EffectKind::GyroBiasTemp => (&["coeff_deg_per_h_per_degc"], &[Aux::ReferenceDegc]),
        EffectKind::AccelBiasTempRate => (&["coeff_ug_per_degc_per_min"], &[]),
        EffectKind::GyroBiasTempRate => (&["coeff_deg_per_h_per_degc_per_min"], &[]),
        EffectKind::ThermalLag => (&["tau_s"], &[]),
        EffectKind::AccelQuadratic => (&["k2_ug_per_g2"], &[]),
        EffectKind::SizeEffect => (&["lever_arm_x_mm", "lever_arm_y_mm", "lever_arm_z_mm"], &[]),
        EffectKind::GyroScaleAsymmetry => (&["asymmetry_ppm"], &[]),
        EffectKind::GyroGSensitivity => (&["coeff_deg_per_h_per_g"], &[]),
        EffectKind::AccelTimeOffset => (&["delay_ms"], &[]),
        EffectKind::GyroBiasRandomWalk => (
            &["intensity_deg_per_h_per_sqrt_h"],
            &[Aux::Seed, Aux::CorrelationS],
        ),
        EffectKind::AccelBiasRandomWalk => (
            &["intensity_ug_per_sqrt_h"],
            &[Aux::Seed, Aux::CorrelationS],
        ),
        EffectKind::GyroBiasOscillation => {
            (&["amplitude_deg_per_h"], &[Aux::PeriodS, Aux::PhaseDeg])
        }
        EffectKind::AccelBiasStep => (&["step_ug"], &[Aux::TimeS]),
        EffectKind::AccelCrossCoupling => (&["coeff_ug_per_g2"], &[]),
        EffectKind::GyroBiasStep => (&["step_deg_per_h"], &[Aux::TimeS]),
        EffectKind::GyroBiasRamp => (&["rate_deg_per_h_per_h"], &[Aux::TimeS]),
        EffectKind::AccelBiasRamp => (&["rate_ug_per_h"], &[Aux::TimeS]),
        EffectKind::GyroBiasTransient => {
            (&["amplitude_deg_per_h"], &[Aux::TimeS, Aux::TimeConstantS])
        }
        EffectKind::AccelBiasTransient => (&["amplitude_ug"], &[Aux::TimeS, Aux::TimeConstantS]),
        EffectKind::GyroBiasPlateau => (&["level_deg_per_h"], &[Aux::TimeS, Aux::RiseTimeS]),
        EffectKind::AccelBiasPlateau => (&["level_ug"], &[Aux::TimeS, Aux::RiseTimeS]),
        EffectKind::GyroBiasPulse => (&["level_deg_per_h"], &[Aux::TimeS, Aux::DurationS]),
        EffectKind::AccelBiasPulse => (&["level_ug"], &[Aux::TimeS, Aux::DurationS]),
        EffectKind::GyroBiasDecayingOscillation => (
            &["amplitude_deg_per_h"],
            &[Aux::TimeS, Aux::PeriodS, Aux::TimeConstantS],
        ),
        EffectKind::AccelBiasDecayingOscillation => (
            &["amplitude_ug"],
            &[Aux::TimeS, Aux::PeriodS, Aux::TimeConstantS],
        ),
    }
}

/// The SI factor of a kind's magnitude keys.
pub(super) fn magnitude_factor(kind: EffectKind) -> ExactFactor {
    ExactFactor::binary(kind.unit().si)
}

/// Value of an auxiliary key of `spec` (SI; the seed as `u64` in the second slot).
pub(super) fn get_aux(spec: &EffectSpec, aux: Aux) -> (f64, u64) {
    match (spec, aux) {
        (
            EffectSpec::AccelBiasQuadraticTemp { reference_degc, .. }
            | EffectSpec::GyroBiasTemp { reference_degc, .. },
            Aux::ReferenceDegc,
        ) => (*reference_degc, 0),
        (
            EffectSpec::GyroBiasRandomWalk {
                correlation_s,
                seed,
                ..
            }
            | EffectSpec::AccelBiasRandomWalk {
                correlation_s,
                seed,
                ..
            },
            _,
        ) => (*correlation_s, *seed),
        (EffectSpec::GyroBiasOscillation { period_s, .. }, Aux::PeriodS) => (*period_s, 0),
        (EffectSpec::GyroBiasOscillation { phase_rad, .. }, Aux::PhaseDeg) => (*phase_rad, 0),
        (EffectSpec::AccelBiasStep { time_s, .. }, Aux::TimeS) => (*time_s, 0),
        (EffectSpec::BiasEvent { onset_s, .. }, Aux::TimeS) => (*onset_s, 0),
        (
            EffectSpec::BiasEvent {
                time_constant_s, ..
            },
            Aux::TimeConstantS,
        ) => (*time_constant_s, 0),
        (EffectSpec::BiasProfile { onset_s, .. }, Aux::TimeS) => (*onset_s, 0),
        (
            EffectSpec::BiasProfile { duration_s, .. },
            Aux::RiseTimeS | Aux::DurationS | Aux::PeriodS,
        ) => (*duration_s, 0),
        (
            EffectSpec::BiasProfile {
                time_constant_s, ..
            },
            Aux::TimeConstantS,
        ) => (*time_constant_s, 0),
        _ => (0.0, 0),
    }
}

/// Set an auxiliary value of `spec` (SI; `seed` for [`Aux::Seed`]).
pub(super) fn set_aux(spec: &mut EffectSpec, aux: Aux, value: f64, seed_value: u64) {
    match (spec, aux) {
        (
            EffectSpec::AccelBiasQuadraticTemp { reference_degc, .. }
            | EffectSpec::GyroBiasTemp { reference_degc, .. },
            Aux::ReferenceDegc,
        ) => *reference_degc = value,
        (
            EffectSpec::GyroBiasRandomWalk { correlation_s, .. }
            | EffectSpec::AccelBiasRandomWalk { correlation_s, .. },
            Aux::CorrelationS,
        ) => *correlation_s = value,
        (
            EffectSpec::GyroBiasRandomWalk { seed, .. }
            | EffectSpec::AccelBiasRandomWalk { seed, .. },
            Aux::Seed,
        ) => *seed = seed_value,
        (EffectSpec::GyroBiasOscillation { period_s, .. }, Aux::PeriodS) => *period_s = value,
        (EffectSpec::GyroBiasOscillation { phase_rad, .. }, Aux::PhaseDeg) => *phase_rad = value,
        (EffectSpec::AccelBiasStep { time_s, .. }, Aux::TimeS) => *time_s = value,
        (EffectSpec::BiasEvent { onset_s, .. }, Aux::TimeS) => *onset_s = value,
        (
            EffectSpec::BiasEvent {
                time_constant_s, ..
            },
            Aux::TimeConstantS,
        ) => *time_constant_s = value,
        (EffectSpec::BiasProfile { onset_s, .. }, Aux::TimeS) => *onset_s = value,
        (
            EffectSpec::BiasProfile { duration_s, .. },
            Aux::RiseTimeS | Aux::DurationS | Aux::PeriodS,
        ) => *duration_s = value,
        (
            EffectSpec::BiasProfile {
                time_constant_s, ..
            },
            Aux::TimeConstantS,
        ) => *time_constant_s = value,
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn magnitude_keys_name_the_unit_of_their_kind() {
        // The key suffix spells the unit label: ug/degC^2 -> ug_per_degc2, deg/h/sqrt(h) ->
        // deg_per_h_per_sqrt_h, ...
        let spell = |label: &str| {
            label
                .to_lowercase()
                .replace("sqrt(", "sqrt_")
                .replace("^2", "2")
                .replace("/(", "_per_")
                .replace(['(', ')'], "")
                .replace('/', "_per_")
        };
        for kind in EffectKind::ALL {
            let (keys, _) = schema(kind);
            assert_eq!(keys.len() * 3, kind.n_components(), "{kind}");
            let suffix = spell(kind.unit().label);
            for key in keys {
                assert!(key.ends_with(&suffix), "{kind}: {key} vs {suffix}");
            }
        }
    }
}
