//! Recalibrations of the calibration run: the filter of `sinsbench calibrate`, fed the run once
//! per perturbation (none: as recorded), one pass over the data feeding every filter, the
//! perturbed ones optionally following the first one's gains (`sins_kf`'s
//! `CalibrationFilter::following`). The absorption ([`crate::absorb`]), the calibration run's
//! events and its innovations are measured with them.

use crate::error::DiagError;
use crate::input::RunData;
use crate::noise::NoiseSpec;
use crate::replay::sample_context;
use crate::source::SampleSource;
use crate::temperature::TemperatureSeries;
use sins_harness::pipeline::calibration_filter;
use sins_imu::effects::{ContextTracker, EffectContext, ExtraEffect};
use sins_imu::{Compensator, EffectSpec, ImuErrorParams, ImuSample};
use sins_kf::{CalibrationFilter, FilterNoise, SharedGain, StandardizedInnovation, params_to_vec};
use sins_nav::Geodetic;

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
pub(crate) struct Arms<'a> {
    pub(crate) perturbations: &'a [Option<EffectSpec>],
    pub(crate) keep_innovations: usize,
    /// Per perturbation: whether its filter follows the first one (its gains and gating, see
    /// [`CalibrationFilter::following`]: about half the work) instead of keeping a covariance.
    pub(crate) follows: &'a [bool],
}

pub(crate) fn recalibrate_arms(
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

/// Samples that every filter of a thread takes in turn before the next sub-batch: a
/// sub-batch's samples, contexts and perturbations (about 300 bytes a sample) stay in the
/// core's cache while its filters read them, instead of each filter streaming a whole batch
/// (up to 131,072 samples, about 40 MB) from memory.
const SUB_BATCH: usize = 1024;

/// Feed a batch to some filters, each with its perturbation added; those that follow take the
/// `gains` of their leader, fed the same batch first. Each filter takes its samples in order,
/// so the sub-batches change only the order in which the filters take turns.
fn feed(
    arms: &mut [Arm],
    samples: &[ImuSample],
    ctxs: &[EffectContext],
    gains: &[SharedGain],
) -> Result<(), DiagError> {
    let mut perturbations = Vec::with_capacity(SUB_BATCH.min(samples.len()));
    let mut perturbed = Vec::with_capacity(SUB_BATCH.min(samples.len()));
    let filter_err =
        |e: sins_kf::CalibrationError| DiagError::Numerical(format!("calibration filter: {e}"));
    // Each filter's place in the leader's gains, kept from one sub-batch to the next.
    let mut led: Vec<std::slice::Iter<'_, SharedGain>> =
        arms.iter().map(|_| gains.iter()).collect();
    for (samples, ctxs) in samples.chunks(SUB_BATCH).zip(ctxs.chunks(SUB_BATCH)) {
        for (arm, led) in arms.iter_mut().zip(&mut led) {
            match arm.effect.as_mut() {
                Some(effect) => effect.perturbations(ctxs, &mut perturbations),
                None => perturbations.clear(),
            }
            perturbed.clear();
            perturbed.extend(samples.iter().enumerate().map(|(k, s)| {
                let mut x = *s;
                if let Some((p_theta, p_v)) = perturbations.get(k) {
                    x.dtheta_rad += p_theta;
                    x.dv_mps += p_v;
                }
                x
            }));
            let led = arm.follows.then_some(led);
            arm.filter.push_batch(&perturbed, led).map_err(filter_err)?;
        }
    }
    Ok(())
}
