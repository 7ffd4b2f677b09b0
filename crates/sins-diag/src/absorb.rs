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
use crate::input::RunData;
use crate::noise::NoiseSpec;
use crate::replay::sample_context;
use crate::sensitivity::{ColumnId, RunSensitivity};
use crate::source::SampleSource;
use crate::temperature::TemperatureSeries;
use sins_harness::pipeline::calibration_filter;
use sins_imu::effects::{ContextTracker, EffectContext, ExtraEffect};
use sins_imu::{Compensator, EffectKind, EffectSpec, ImuErrorParams, ImuSample};
use sins_kf::{CalibrationFilter, FilterNoise, SharedGain, StandardizedInnovation, params_to_vec};
use sins_nav::Geodetic;

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

/// What one recalibration of the calibration run gives.
#[derive(Clone, Debug)]
pub struct Recalibration {
    /// The estimate (SI, eq 8 order).
    pub theta: Vec<f64>,
    /// The standardized innovation of every update.
    pub innovations: Vec<StandardizedInnovation>,
}

/// One filter fed with the run plus one perturbation.
struct Arm {
    effect: Option<Box<dyn ExtraEffect>>,
    filter: CalibrationFilter,
    /// True when the filter follows the first one's gains.
    follows: bool,
}

/// The calibration run as the absorption needs it.
pub struct CalibrationRun<'a> {
    /// Its name.
    pub run: &'a str,
    /// Its samples.
    pub source: &'a mut dyn SampleSource,
    /// Turntable site.
    pub site: &'a Geodetic,
    /// Its temperature series (rates for the temperature-rate candidates).
    pub temps: &'a TemperatureSeries,
}

impl<'a> CalibrationRun<'a> {
    /// The run named `name` among `runs`, with its temperature series: an error naming it when
    /// it is not there or its temperatures were not computed.
    pub(crate) fn among(runs: &'a mut [RunData], name: &str) -> Result<Self, DiagError> {
        let run = runs
            .iter_mut()
            .find(|r| r.name == name)
            .ok_or_else(|| DiagError::input(name, "the calibration run is not among the runs"))?;
        let temps = run
            .temperatures
            .as_ref()
            .ok_or_else(|| DiagError::input(name, "temperature series missing"))?;
        Ok(CalibrationRun {
            run: &run.name,
            source: run.source.as_mut(),
            site: &run.site,
            temps,
        })
    }
}

/// Recalibrate calibration run `cal` once per entry of `perturbations` (`None`: as recorded;
/// `Some(spec)`: with `spec`'s perturbation added to every sample), with the filter of
/// `params.model` referred to `params`' reference temperature and driven by the twin's `noise`;
/// the estimates in eq 8 order (SI), and the standardized innovation of every update for the
/// first `keep_innovations` entries (the others' are left empty: three numbers per update and
/// filter). One pass over the data feeds every filter, `threads` at once (the result does not
/// depend on it).
pub fn recalibrate(
    cal: CalibrationRun<'_>,
    params: &ImuErrorParams,
    noise: &NoiseSpec,
    perturbations: &[Option<EffectSpec>],
    keep_innovations: usize,
    threads: usize,
) -> Result<Vec<Recalibration>, DiagError> {
    let arms = Arms {
        perturbations,
        keep_innovations,
        follows: &vec![false; perturbations.len()],
    };
    recalibrate_arms(cal, params, noise, arms, threads)
}

/// The filters of a recalibration.
struct Arms<'a> {
    perturbations: &'a [Option<EffectSpec>],
    keep_innovations: usize,
    /// Per perturbation: whether its filter follows the first one (its gains and gating, see
    /// [`CalibrationFilter::following`]: about half the work) instead of keeping a covariance.
    follows: &'a [bool],
}

fn recalibrate_arms(
    cal: CalibrationRun<'_>,
    params: &ImuErrorParams,
    noise: &NoiseSpec,
    spec: Arms<'_>,
    threads: usize,
) -> Result<Vec<Recalibration>, DiagError> {
    let CalibrationRun {
        run,
        source,
        site,
        temps,
    } = cal;
    let h = source.sample_interval_s();
    let model = params.model;
    let filter_err = |e: sins_kf::CalibrationError| DiagError::input(run, e.to_string());
    let filter_noise = FilterNoise::from_sensor(
        noise.gyro_arw_rad_per_sqrt_s,
        noise.gyro_bias.sigma,
        noise.gyro_bias.correlation_s,
        noise.accel_vrw_mps_per_sqrt_s,
        noise.accel_bias.sigma,
        noise.accel_bias.correlation_s,
    );
    let led = spec.follows.iter().skip(1).any(|&f| f);
    let mut arms = Vec::with_capacity(spec.perturbations.len());
    for (i, (p, &follows)) in spec.perturbations.iter().zip(spec.follows).enumerate() {
        let mut filter = calibration_filter(
            model,
            h,
            *site,
            filter_noise,
            params.reference_temperature_degc,
        )
        .map_err(filter_err)?;
        if i < spec.keep_innovations {
            filter = filter.keep_innovations();
        }
        let follows = follows && i > 0;
        filter = match (follows, led && i == 0) {
            (true, _) => filter.following(),
            (false, true) => filter.leading(),
            (false, false) => filter,
        };
        arms.push(Arm {
            effect: p.as_ref().map(|spec| spec.build(params)),
            filter,
            follows,
        });
    }
    let comp = Compensator::new(*params)
        .ok_or_else(|| DiagError::input(run, "parameter set is singular"))?;
    let mut tracker = ContextTracker::new();
    let mut ctxs = Vec::new();
    let threads = threads.max(1);
    source.visit(&mut |samples: &[ImuSample], _| {
        ctxs.clear();
        for s in samples {
            ctxs.push(sample_context(&mut tracker, &comp, s, h, temps));
        }
        let ctxs = &ctxs;
        let (first, rest) = arms.split_at_mut(led as usize);
        feed(first, samples, ctxs, &[])?;
        let gains: Vec<SharedGain> = first
            .iter_mut()
            .flat_map(|a| a.filter.take_gains())
            .collect();
        let gains = gains.as_slice();
        std::thread::scope(|scope| {
            let handles: Vec<_> = balanced_chunks(rest, threads)
                .into_iter()
                .map(|chunk| scope.spawn(move || feed(chunk, samples, ctxs, gains)))
                .collect();
            handles.into_iter().try_for_each(|h| {
                h.join().unwrap_or_else(|_| {
                    Err(DiagError::Numerical("a calibration thread panicked".into()))
                })
            })
        })
    })?;
    arms.into_iter()
        .map(|arm| match arm.follows {
            true => Ok(Recalibration {
                theta: params_to_vec(&arm.filter.finish_led().map_err(filter_err)?, model),
                innovations: Vec::new(),
            }),
            false => {
                let r = arm.filter.finish().map_err(filter_err)?;
                Ok(Recalibration {
                    theta: params_to_vec(&r.params, model),
                    innovations: r.innovations,
                })
            }
        })
        .collect()
}

/// `arms` cut into at most `threads` consecutive chunks of about equal work (a following
/// filter counted as half a filter with its own covariance).
fn balanced_chunks(arms: &mut [Arm], threads: usize) -> Vec<&mut [Arm]> {
    let cost = |a: &Arm| if a.follows { 1 } else { 2 };
    let threads = threads.max(1);
    let total: usize = arms.iter().map(cost).sum();
    let mut chunks = Vec::with_capacity(threads);
    let (mut rest, mut done) = (arms, 0);
    for k in 1..=threads {
        let target = (total * k).div_ceil(threads);
        let mut n = 0;
        while n < rest.len() && done < target {
            done += cost(&rest[n]);
            n += 1;
        }
        let (chunk, tail) = rest.split_at_mut(n);
        if !chunk.is_empty() {
            chunks.push(chunk);
        }
        rest = tail;
    }
    chunks
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

/// Feed a batch to some filters, each with its perturbation added; those that follow take the
/// `gains` of their leader, fed the same batch first.
fn feed(
    arms: &mut [Arm],
    samples: &[ImuSample],
    ctxs: &[EffectContext],
    gains: &[SharedGain],
) -> Result<(), DiagError> {
    let mut perturbations = Vec::with_capacity(samples.len());
    let filter_err =
        |e: sins_kf::CalibrationError| DiagError::Numerical(format!("calibration filter: {e}"));
    for arm in arms {
        match arm.effect.as_mut() {
            Some(effect) => effect.perturbations(ctxs, &mut perturbations),
            None => perturbations.clear(),
        }
        let mut led = gains.iter();
        for (k, s) in samples.iter().enumerate() {
            let mut x = *s;
            if let Some((p_theta, p_v)) = perturbations.get(k) {
                x.dtheta_rad += p_theta;
                x.dv_mps += p_v;
            }
            match arm.follows {
                true => arm.filter.push_led(&x, &mut led),
                false => arm.filter.push(&x),
            }
            .map_err(filter_err)?;
        }
    }
    Ok(())
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
