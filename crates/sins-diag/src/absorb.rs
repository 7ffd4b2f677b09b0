//! Calibration absorption: how the system-level calibration turns an unmodelled effect that is
//! present during the calibration run into biased coefficients.
//!
//! The parameter set the twin replays with was identified by the 42-state (or 30-state) filter
//! on a calibration run of the same IMU. An effect outside the paper's model is present there
//! too, and the filter, which has no state for it, explains part of it with its coefficients: a
//! quadratic nonlinearity of 85 ug/g² on the z accelerometer moves the calibrated gyro scale
//! factors by 24 ppm (75 sigma) and the installation errors by 9 arcsec. In navigation the
//! effect then acts twice: directly on the increments, and through the coefficients the
//! compensation got wrong. With `J = ∂θ̂/∂m` (coefficients per unit magnitude) the navigation
//! error of magnitude `m` is `(a_direct - Σ_i a_param,i J_i) m`, `a_param,i` being the response to
//! a coefficient that the compensation leaves uncorrected.
//!
//! `J` is measured with the real pipeline: the calibration run is recalibrated once as recorded
//! and once per candidate component with that component's perturbation added to every raw
//! sample (finite differences with common samples, so the noise cancels exactly). The filter is
//! set up as `sinsbench calibrate` sets it up for this model and reference temperature, with
//! the twin's noise; one pass over the data feeds every filter. The perturbed filters follow the
//! recorded run's filter (`sins_kf::CalibrationFilter::following`: its gains applied to their
//! own innovations, no covariance or transition sums of their own, about half the work): the
//! gains of two runs a small perturbation apart differ to first order, so each Jacobian moves
//! by that difference times the innovations, under 0.025 sigma of any coefficient at a
//! component's typical magnitude. The accelerometer time offset, whose step changes the gains
//! more (2.7 sigma), keeps filters of its own.

use crate::error::DiagError;
use crate::noise::NoiseSpec;
use crate::recalibration::{Arms, recalibrate_arms};
pub use crate::recalibration::{CalibrationRun, Recalibration, recalibrate};
use crate::sensitivity::{ColumnId, RunSensitivity};
use sins_imu::{EffectKind, EffectSpec, ImuErrorParams};
use sins_kf::{StandardizedInnovation, params_to_vec};

/// Size of the finite-difference perturbation, in multiples of the kind's typical magnitude.
const STEP_TIMES_TYPICAL: f64 = 10.0;

/// The coefficients' response to each candidate component.
#[derive(Clone, Debug)]
pub struct Absorption {
    /// The calibration run.
    pub run: String,
    /// Candidate components, in the order of `jacobian`.
    pub components: Vec<(EffectKind, usize)>,
    /// `∂θ̂/∂m` per component: SI coefficient (eq 8 order, 21 or 33 entries) per SI magnitude.
    pub jacobian: Vec<Vec<f64>>,
    /// The recalibration of the run as recorded (SI, eq 8 order).
    pub recalibrated: Vec<f64>,
    /// That recalibration's standardized innovations, one per update (see
    /// [`crate::cal_innovations`]).
    pub recorded_innovations: Vec<StandardizedInnovation>,
}

impl Absorption {
    /// `∂θ̂/∂m` of `kind`'s component `c`, if computed.
    pub fn of(&self, kind: EffectKind, c: usize) -> Option<&[f64]> {
        self.components
            .iter()
            .position(|&k| k == (kind, c))
            .map(|i| self.jacobian[i].as_slice())
    }

    /// `params` with the coefficients moved by `-J m` for `kind`'s SI magnitudes `values`:
    /// the set the calibration would have identified without the effect.
    pub fn without(
        &self,
        params: &ImuErrorParams,
        kind: EffectKind,
        values: &[f64],
    ) -> ImuErrorParams {
        let model = params.model;
        let mut theta = params_to_vec(params, model);
        for (c, &m) in values.iter().enumerate() {
            if let Some(j) = self.of(kind, c) {
                for (t, d) in theta.iter_mut().zip(j) {
                    *t -= d * m;
                }
            }
        }
        sins_kf::params_from_vec(&theta, model, params.reference_temperature_degc)
    }

    /// [`Absorption::without`] through the filter itself instead of `J`: `params` moved by
    /// `θ̂(−m) − θ̂(0)`, the recalibration of `cal` with `kind`'s SI magnitudes `values`
    /// removed from every sample against its recalibration as recorded. Exact where the
    /// calibration responds nonlinearly to a large effect (a time offset of several ms under
    /// the scheme's rotations); one filter pass over the run.
    pub fn without_exact(
        &self,
        cal: CalibrationRun<'_>,
        params: &ImuErrorParams,
        noise: &NoiseSpec,
        kind: EffectKind,
        values: &[f64],
    ) -> Result<ImuErrorParams, DiagError> {
        let negated: Vec<f64> = values.iter().map(|v| -v).collect();
        let spec = EffectSpec::zero(kind)
            .with_magnitudes_si(&negated)
            .ok_or_else(|| {
                DiagError::input(&self.run, format!("{}: bad magnitudes", kind.name()))
            })?;
        let theta_without = recalibrate(cal, params, noise, &[Some(spec)], 0, 1)?
            .pop()
            .ok_or_else(|| DiagError::Numerical("no recalibration".into()))?
            .theta;
        let model = params.model;
        let theta: Vec<f64> = params_to_vec(params, model)
            .iter()
            .zip(theta_without.iter().zip(&self.recalibrated))
            .map(|(g, (w, r))| g + w - r)
            .collect();
        Ok(sins_kf::params_from_vec(
            &theta,
            model,
            params.reference_temperature_degc,
        ))
    }
}

/// Whether `kind`'s finite-difference recalibration may follow the recorded run's filter:
/// not the accelerometer time offset, whose step (5 ms) tilts the specific force by 0.8 mrad
/// while the table turns at 9 deg/s, enough to change the gains (followers missed its
/// Jacobian by 2.7 sigma at its typical magnitude, every other component by under 0.025
/// sigma: `the_led_absorption_is_the_absorption_of_filters_with_their_own_covariance`).
fn may_follow(kind: EffectKind) -> bool {
    kind != EffectKind::AccelTimeOffset
}

/// Measure the absorption on calibration run `cal` for `components` (see [`recalibrate`]):
/// finite differences of `STEP_TIMES_TYPICAL` typical magnitudes against the run as recorded.
pub fn absorption(
    cal: CalibrationRun<'_>,
    params: &ImuErrorParams,
    noise: &NoiseSpec,
    components: &[(EffectKind, usize)],
    threads: usize,
) -> Result<Absorption, DiagError> {
    let run = cal.run.to_string();
    let mut perturbations = vec![None];
    let mut steps = Vec::with_capacity(components.len());
    for &(kind, c) in components {
        let step = STEP_TIMES_TYPICAL * kind.typical_magnitude_si();
        let mut values = vec![0.0; kind.n_components()];
        values[c] = step;
        let spec = EffectSpec::zero(kind)
            .with_magnitudes_si(&values)
            .ok_or_else(|| DiagError::input(&run, format!("{}: bad component {c}", kind.name())))?;
        perturbations.push(Some(spec));
        steps.push(step);
    }
    let follows: Vec<bool> = std::iter::once(false)
        .chain(components.iter().map(|&(kind, _)| may_follow(kind)))
        .collect();
    let arms = Arms {
        perturbations: &perturbations,
        keep_innovations: 1,
        follows: &follows,
    };
    let mut results = recalibrate_arms(cal, params, noise, arms, threads)?;
    let base = results.remove(0);
    let jacobian = results
        .iter()
        .zip(&steps)
        .map(|(r, step)| {
            r.theta
                .iter()
                .zip(&base.theta)
                .map(|(a, b)| (a - b) / step)
                .collect()
        })
        .collect();
    Ok(Absorption {
        run,
        components: components.to_vec(),
        jacobian,
        recalibrated: base.theta,
        recorded_innovations: base.innovations,
    })
}

impl Absorption {
    /// Add the path through the calibration to the candidate columns of `target`: each effect
    /// column `a_direct` becomes `a_direct - Σ_i a_param,i J_i`, the coefficient responses
    /// `a_param,i` taken from `params_of` (a pass with calibration columns on the same output
    /// grid; `None`: `target` itself).
    pub fn fold(&self, target: &mut RunSensitivity, params_of: Option<&RunSensitivity>) {
        let n = target.times.times_s.len();
        let mut updates = Vec::new();
        {
            let src = params_of.unwrap_or(&*target);
            if src.times.times_s.len() != n {
                return;
            }
            for (&(kind, c), jac) in self.components.iter().zip(&self.jacobian) {
                let Some(ie) = target.column(ColumnId::Effect(kind, c)) else {
                    continue;
                };
                let (mut dn, mut de) = (vec![0.0; n], vec![0.0; n]);
                for (slot, &j) in jac.iter().enumerate() {
                    let Some(ip) = src.column(ColumnId::Param(slot)).filter(|_| j != 0.0) else {
                        continue;
                    };
                    for t in 0..n {
                        dn[t] += j * src.north_m[ip][t];
                        de[t] += j * src.east_m[ip][t];
                    }
                }
                updates.push((ie, dn, de));
            }
        }
        for (ie, dn, de) in updates {
            for t in 0..n {
                target.north_m[ie][t] -= dn[t];
                target.east_m[ie][t] -= de[t];
            }
        }
    }
}
