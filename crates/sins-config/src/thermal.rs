//! `[thermal]` of an experiment file (or of one `[[run]]`) → [`ThermalModel`].

use crate::ctx::{Ctx, Deferred};
use crate::error::ConfigError;
use crate::plausible;
use crate::units::S_PER_H;
use serde::Deserialize;
use sins_sim::scenario::{ChamberSegment, ThermalModel};

/// `[thermal]`: chamber profile, accelerometer lags and thermometers.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ThermalFile {
    chamber_start_degc: f64,
    accel_time_constant_s: [f64; 3],
    #[serde(default)]
    accel_offset_degc: [f64; 3],
    accel_initial_degc: Option<[f64; 3]>,
    #[serde(default)]
    thermometer_noise_degc: f64,
    #[serde(default)]
    chamber: Vec<Deferred<ChamberFile>>,
}

/// `[[thermal.chamber]]`, tagged by `kind`.
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum ChamberFile {
    Hold {
        duration_s: Option<f64>,
        duration_h: Option<f64>,
        temp_degc: f64,
    },
    Ramp {
        duration_s: Option<f64>,
        duration_h: Option<f64>,
        rate_degc_per_h: f64,
    },
    Fluctuating {
        duration_s: Option<f64>,
        duration_h: Option<f64>,
        rate_degc_per_h: f64,
        fluctuation_amplitude_degc: f64,
        fluctuation_period_s: f64,
    },
}

/// Builds the thermal model; `prefix` is the key path of the table (`thermal` or
/// `run[i].thermal`).
pub(crate) fn build_thermal(
    ctx: &Ctx<'_>,
    prefix: &str,
    raw: &ThermalFile,
) -> Result<ThermalModel, ConfigError> {
    let k = |name: &str| format!("{prefix}.{name}");
    let mut time_constant = [0.0; 3];
    for (i, tau) in raw.accel_time_constant_s.iter().enumerate() {
        time_constant[i] = ctx.positive(&format!("{prefix}.accel_time_constant_s[{i}]"), *tau)?;
    }
    let mut chamber = Vec::with_capacity(raw.chamber.len());
    for (i, seg) in raw.chamber.iter().enumerate() {
        let p = format!("{prefix}.chamber[{i}]");
        let kp = |name: &str| format!("{p}.{name}");
        chamber.push(match seg.get(ctx, &p)? {
            ChamberFile::Hold {
                duration_s,
                duration_h,
                temp_degc,
            } => ChamberSegment::Hold {
                duration_s: ctx.duration(&p, *duration_s, *duration_h)?,
                temp_degc: ctx.finite(&kp("temp_degc"), *temp_degc)?,
            },
            ChamberFile::Ramp {
                duration_s,
                duration_h,
                rate_degc_per_h,
            } => ChamberSegment::Ramp {
                duration_s: ctx.duration(&p, *duration_s, *duration_h)?,
                rate_degc_per_s: ctx.finite(&kp("rate_degc_per_h"), *rate_degc_per_h)? / S_PER_H,
            },
            ChamberFile::Fluctuating {
                duration_s,
                duration_h,
                rate_degc_per_h,
                fluctuation_amplitude_degc,
                fluctuation_period_s,
            } => ChamberSegment::Fluctuating {
                duration_s: ctx.duration(&p, *duration_s, *duration_h)?,
                rate_degc_per_s: ctx.finite(&kp("rate_degc_per_h"), *rate_degc_per_h)? / S_PER_H,
                fluctuation_amplitude_degc: ctx.non_negative(
                    &kp("fluctuation_amplitude_degc"),
                    *fluctuation_amplitude_degc,
                )?,
                fluctuation_period_s: ctx
                    .positive(&kp("fluctuation_period_s"), *fluctuation_period_s)?,
            },
        });
    }
    let model = ThermalModel {
        chamber_start_degc: ctx.finite(&k("chamber_start_degc"), raw.chamber_start_degc)?,
        chamber,
        accel_time_constant_s: time_constant,
        accel_offset_degc: ctx.finite3(&k("accel_offset_degc"), raw.accel_offset_degc)?,
        accel_initial_degc: match raw.accel_initial_degc {
            Some(t) => Some(ctx.finite3(&k("accel_initial_degc"), t)?),
            None => None,
        },
        thermometer_noise_degc: ctx
            .non_negative(&k("thermometer_noise_degc"), raw.thermometer_noise_degc)?,
    };
    check_plausible(ctx, prefix, &model)?;
    Ok(model)
}

/// Refuses a thermal model whose chamber, sensors or thermometers leave the temperatures an IMU
/// can have ([`plausible::MIN_TEMPERATURE_DEGC`]..[`plausible::MAX_TEMPERATURE_DEGC`]), naming
/// the key of the segment or value that leaves them; and a thermometer noise beyond
/// [`plausible::MAX_THERMOMETER_NOISE_DEGC`].
fn check_plausible(ctx: &Ctx<'_>, prefix: &str, m: &ThermalModel) -> Result<(), ConfigError> {
    let out_of_range = |key: String, what: &str, t: f64| {
        let msg = format!("{what} {t} degC, {}", plausible::temperature_range_text());
        Err(ctx.invalid(&key, msg))
    };
    let mut t = m.chamber_start_degc;
    if !plausible::temperature_ok(t) {
        return out_of_range(
            format!("{prefix}.chamber_start_degc"),
            "the chamber starts at",
            t,
        );
    }
    // Extremes of the chamber over the whole profile (a fluctuation may peak inside a segment).
    let (mut lo, mut hi) = (t, t);
    for (i, seg) in m.chamber.iter().enumerate() {
        let p = format!("{prefix}.chamber[{i}]");
        let (trend_key, amplitude_key) = (
            format!("{p}.rate_degc_per_h"),
            format!("{p}.fluctuation_amplitude_degc"),
        );
        let (start, end, amplitude, trend_key) = match *seg {
            ChamberSegment::Hold { temp_degc, .. } => {
                (temp_degc, temp_degc, 0.0, format!("{p}.temp_degc"))
            }
            ChamberSegment::Ramp {
                duration_s,
                rate_degc_per_s,
            } => (t, t + rate_degc_per_s * duration_s, 0.0, trend_key),
            ChamberSegment::Fluctuating {
                duration_s,
                rate_degc_per_s,
                fluctuation_amplitude_degc,
                ..
            } => (
                t,
                t + rate_degc_per_s * duration_s,
                fluctuation_amplitude_degc,
                trend_key,
            ),
        };
        for x in [start, end] {
            if !plausible::temperature_ok(x) {
                return out_of_range(trend_key, "in this segment the chamber reaches", x);
            }
        }
        let (seg_lo, seg_hi) = (start.min(end) - amplitude, start.max(end) + amplitude);
        for x in [seg_lo, seg_hi] {
            if !plausible::temperature_ok(x) {
                return out_of_range(amplitude_key, "with its fluctuation the chamber reaches", x);
            }
        }
        (lo, hi) = (lo.min(seg_lo), hi.max(seg_hi));
        t = end;
    }
    for (i, off) in m.accel_offset_degc.iter().enumerate() {
        for x in [lo + off, hi + off] {
            if !plausible::temperature_ok(x) {
                let key = format!("{prefix}.accel_offset_degc[{i}]");
                return out_of_range(key, "with this offset the accelerometer reaches", x);
            }
        }
    }
    if let Some(initial) = m.accel_initial_degc {
        for (i, x) in initial.iter().enumerate() {
            if !plausible::temperature_ok(*x) {
                let key = format!("{prefix}.accel_initial_degc[{i}]");
                return out_of_range(key, "the accelerometer starts at", *x);
            }
        }
    }
    let noise = m.thermometer_noise_degc;
    if noise > plausible::MAX_THERMOMETER_NOISE_DEGC {
        let msg = format!(
            "{noise} degC is beyond the plausibility limit {} degC (10x the 1 degC of the \
             coarsest on-chip thermometers)",
            plausible::MAX_THERMOMETER_NOISE_DEGC
        );
        return Err(ctx.invalid(&format!("{prefix}.thermometer_noise_degc"), msg));
    }
    Ok(())
}

/// Total length of the explicit chamber profile (s); the chamber holds its last temperature after.
pub fn chamber_duration_s(thermal: &ThermalModel) -> f64 {
    thermal
        .chamber
        .iter()
        .map(|c| match c {
            ChamberSegment::Hold { duration_s, .. }
            | ChamberSegment::Ramp { duration_s, .. }
            | ChamberSegment::Fluctuating { duration_s, .. } => *duration_s,
        })
        .sum()
}
