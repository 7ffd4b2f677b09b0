//! Time-local events of the calibration run acting through the calibration. An effect outside
//! the catalogue that the scan locates in the calibration run (a bias step two hours into the
//! scheme) was also seen by the calibration filter, which has no state for it and moved its
//! coefficients to explain part of it. Every run's replay then carries the coefficients' error:
//! with `Δθ = θ̂(as recorded) − θ̂(the event removed)` the navigation error it leaves is
//! `−Σ_i a_param,i Δθ_i`, `a_param,i` being the response to coefficient `i` left uncorrected.
//!
//! Without this path, what the event did to the coefficients is an unexplained signal in the
//! navigation runs, and a catalogue effect whose signature resembles it takes the credit (a
//! 510 ug accelerometer step in every run was named a quadratic nonlinearity).
//!
//! `Δθ` is measured with the real filter (one recalibration per event, its fitted perturbation
//! removed from every sample; the run as recorded is the absorption's own recalibration), so
//! the path is exact for the event as fitted.

use crate::absorb::{Absorption, CalibrationRun, recalibrate};
use crate::error::DiagError;
use crate::events::{AXES, EventScan, EventSignal, TimeLocalEvent};
use crate::input::{DiagnoseConfig, DiagnosisInput};
use crate::report::{Note, NoteKind};
use crate::sensitivity::{ColumnId, RunSensitivity};
use nalgebra::DVector;
use sins_imu::{EffectKind, EffectSpec};

/// The calibration-run events' path through the coefficients.
pub(crate) struct AbsorbedEvents {
    /// Its contribution to every run's gap (fit rows; one entry per run).
    pub signals: Vec<EventSignal>,
    /// The note that reports it.
    pub note: Note,
}

/// The effect an event describes, as fitted: kind, axis, SI size, onset and shape parameters
/// (the time constant, duration or rise time it was fitted with). `None` for a kind that is
/// not a time-local event.
pub(crate) fn event_effect(e: &TimeLocalEvent) -> Option<EffectSpec> {
    let kind = EffectKind::from_name(&e.kind)?;
    let axis = AXES.iter().position(|a| *a == e.channel)? % 3;
    let mut values = vec![0.0; kind.n_components()];
    *values.get_mut(axis)? = kind.unit().to_si(e.size);
    let mut spec = EffectSpec::zero(kind).with_magnitudes_si(&values)?;
    match &mut spec {
        EffectSpec::AccelBiasStep { time_s, .. } => *time_s = e.onset_s,
        EffectSpec::BiasEvent {
            onset_s,
            time_constant_s,
            ..
        } => {
            *onset_s = e.onset_s;
            *time_constant_s = e.time_constant_s.unwrap_or(*time_constant_s);
        }
        EffectSpec::BiasProfile {
            onset_s,
            duration_s,
            ..
        } => {
            *onset_s = e.onset_s;
            *duration_s = e.duration_s?;
        }
        _ => return None,
    }
    Some(spec)
}

/// The path through the coefficients of the calibration run's events outside the catalogue
/// (see the module docs); `None` without a calibration run or without such events.
pub(crate) fn absorbed_events(
    input: &mut DiagnosisInput,
    absorption: Option<&Absorption>,
    events: &EventScan,
    sens: &[RunSensitivity],
    cfg: &DiagnoseConfig,
) -> Result<Option<AbsorbedEvents>, DiagError> {
    let Some(a) = absorption else {
        return Ok(None);
    };
    let removed: Vec<Option<EffectSpec>> = events
        .events
        .iter()
        .filter(|e| e.run == a.run && e.explained_by.is_none())
        .filter_map(event_effect)
        .map(|spec| spec.scaled(-1.0))
        .map(Some)
        .collect();
    if removed.is_empty() {
        return Ok(None);
    }
    let (params, noise) = (input.params, input.noise);
    let cal = CalibrationRun::among(&mut input.runs, &a.run)?;
    let without = recalibrate(cal, &params, &noise, &removed, 0, cfg.threads)?;
    // Δθ of all the events together (each measured alone; the filter is linear in them to
    // the order the columns are).
    let mut delta = vec![0.0; a.recalibrated.len()];
    for recal in &without {
        for ((d, r), w) in delta.iter_mut().zip(&a.recalibrated).zip(&recal.theta) {
            *d += r - w;
        }
    }
    let signals: Vec<EventSignal> = sens
        .iter()
        .enumerate()
        .map(|(ri, s)| EventSignal {
            run: ri,
            contribution: through_coefficients(s, &delta),
        })
        .collect();
    let largest_m = signals
        .iter()
        .map(|s| s.contribution.amax())
        .fold(0.0, f64::max);
    let text = format!(
        "the calibration run's {} time-local event(s) outside the catalogue, recalibrated away \
         (one filter pass each): the coefficients they moved leave up to {largest_m:.1} m in \
         the runs' gaps at the fit points, taken off with the events",
        removed.len()
    );
    let note = Note::new(NoteKind::CalibrationAbsorption, text)
        .run(a.run.as_str())
        .figure("events", removed.len() as f64)
        .figure("largest_m", largest_m);
    Ok(Some(AbsorbedEvents { signals, note }))
}

/// `−Σ_i a_param,i Δθ_i` of run `s` at its fit rows `[N_0, E_0, ...]` (m).
fn through_coefficients(s: &RunSensitivity, delta: &[f64]) -> DVector<f64> {
    let fit = &s.times.fit_index;
    let mut v = DVector::zeros(2 * fit.len());
    for (slot, &d) in delta.iter().enumerate() {
        let Some(c) = s.column(ColumnId::Param(slot)).filter(|_| d != 0.0) else {
            continue;
        };
        for (i, &k) in fit.iter().enumerate() {
            v[2 * i] -= d * s.north_m[c][k];
            v[2 * i + 1] -= d * s.east_m[c][k];
        }
    }
    v
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is its failure message
    use super::*;
    use sins_imu::effects::EffectContext;
    use sins_imu::{ImuErrorParams, ParamModel};
    use sins_nav::Vec3;

    const UG: f64 = 9.80665e-6;
    const DEG_H: f64 = std::f64::consts::PI / 180.0 / 3600.0;

    fn event(kind: &str, channel: &str, size: f64, unit: &str, onset_s: f64) -> TimeLocalEvent {
        TimeLocalEvent {
            run: "cal".into(),
            channel: channel.into(),
            shape: String::new(),
            kind: kind.into(),
            onset_s,
            onset_sigma_s: 0.0,
            onset_interval_s: [onset_s; 2],
            size,
            size_sigma: 0.0,
            unit: unit.into(),
            time_constant_s: Some(1200.0),
            duration_s: Some(600.0),
            chi2: 0.0,
            p_value: 0.0,
            explained_by: None,
            alternatives: Vec::new(),
        }
    }

    /// `(dθ, dv)` of `spec` over the sample of `dt_s` ending at `t_s`.
    fn increments(spec: &EffectSpec, t_s: f64, dt_s: f64) -> (Vec3, Vec3) {
        let mut e = spec.build(&ImuErrorParams::ideal(ParamModel::States42));
        e.perturbation(&EffectContext::at_rest(t_s, dt_s, [20.0; 3]))
    }

    #[test]
    fn an_accelerometer_step_is_its_size_in_si_on_its_axis_from_its_onset() {
        let e = event("accel_bias_step", "accel y", -510.0, "ug", 7210.0);
        let spec = event_effect(&e).expect("a step is an effect");
        let h = 0.01;
        assert_eq!(increments(&spec, 7200.0, h).1, Vec3::zeros());
        let (dth, dv) = increments(&spec, 7300.0, h);
        assert_eq!(dth, Vec3::zeros());
        assert!((dv.y - (-510.0 * UG * h)).abs() < 1e-15, "{dv:?}");
        assert_eq!((dv.x, dv.z), (0.0, 0.0));
        // Removed, it is the same step of the opposite sign.
        let (_, minus) = increments(&spec.scaled(-1.0), 7300.0, h);
        assert_eq!(minus, -dv);
    }

    #[test]
    fn a_gyro_transient_starts_at_its_size_and_decays_with_its_time_constant() {
        let e = event("gyro_bias_transient", "gyro z", 0.05, "deg/h", 1000.0);
        let spec = event_effect(&e).expect("a transient is an effect");
        let h = 0.01;
        let at = |t: f64| increments(&spec, t, h).0.z / h;
        assert!((at(1000.0 + h) / (0.05 * DEG_H) - 1.0).abs() < 1e-4);
        let later = at(1000.0 + 1200.0) / at(1000.0 + h);
        assert!((later - (-1.0f64).exp()).abs() < 1e-4, "{later}");
        assert_eq!(at(999.0), 0.0);
    }

    #[test]
    fn a_catalogue_kind_is_no_event_effect() {
        let e = event("gyro_bias_temp", "gyro x", 1.0, "deg/h/degC", 0.0);
        assert!(event_effect(&e).is_none());
    }
}
