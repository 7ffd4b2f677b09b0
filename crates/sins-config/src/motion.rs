//! `[motion]` of an experiment file → [`MotionProgram`].

use crate::csv::{VibrationPattern, parse_patterns, parse_scheme};
use crate::ctx::{Ctx, Deferred};
use crate::error::ConfigError;
use crate::plausible::{GYRO_FULL_SCALE_DEG_PER_S, MAX_MOTION_SEGMENTS, MAX_RUN_DURATION_S};
use serde::Deserialize;
use sins_nav::{DEG, Euler, Vec3, ned_from_body_euler};
use sins_sim::scenario::{MotionProgram, MotionSegment};
use std::collections::BTreeMap;

/// `[motion]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MotionFile {
    initial_attitude_deg: AttitudeFile,
    /// Path of the Table 4 CSV used by `pattern = n` segments (relative to the experiment file).
    vibration_patterns: Option<String>,
    segment: Vec<Deferred<SegmentFile>>,
}

/// `initial_attitude_deg = { pitch, roll, yaw }` (deg, right-forward-up Euler convention).
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct AttitudeFile {
    pitch: f64,
    roll: f64,
    yaw: f64,
}

/// `[[motion.segment]]`, tagged by `kind`.
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum SegmentFile {
    Dwell {
        duration_s: Option<f64>,
        duration_h: Option<f64>,
        label: Option<String>,
    },
    Rotate {
        axis: [f64; 3],
        angle_deg: f64,
        rate_deg_per_s: f64,
        label: Option<String>,
    },
    Scheme {
        file: String,
        rate_deg_per_s: f64,
        dwell_s: Option<f64>,
        total_s: Option<f64>,
        repeat: Option<u32>,
        label: Option<String>,
    },
    Vibrate {
        duration_s: Option<f64>,
        duration_h: Option<f64>,
        pattern: Option<u32>,
        amplitude_deg: Option<[f64; 3]>,
        period_s: Option<[f64; 3]>,
        phase_deg: Option<[f64; 3]>,
        label: Option<String>,
    },
}

fn label(
    ctx: &Ctx<'_>,
    key: &str,
    given: &Option<String>,
    default: String,
) -> Result<String, ConfigError> {
    match given {
        Some(l) if l.trim().is_empty() => Err(ctx.invalid(key, "the label must not be empty")),
        Some(l) => Ok(l.clone()),
        None => Ok(default),
    }
}

/// Builds the motion program; `pattern` segments read `vibration_patterns` and `scheme` segments
/// their CSV, both relative to the experiment file.
pub(crate) fn build_motion(ctx: &Ctx<'_>, raw: &MotionFile) -> Result<MotionProgram, ConfigError> {
    let a = &raw.initial_attitude_deg;
    for (name, v) in [("pitch", a.pitch), ("roll", a.roll), ("yaw", a.yaw)] {
        ctx.finite(&format!("motion.initial_attitude_deg.{name}"), v)?;
    }
    if raw.segment.is_empty() {
        return Err(ctx.missing(
            "motion.segment",
            "the motion program needs at least one [[motion.segment]]",
        ));
    }
    let mut patterns: Option<BTreeMap<u32, VibrationPattern>> = None;
    let mut segments = Vec::new();
    for (i, seg) in raw.segment.iter().enumerate() {
        let p = format!("motion.segment[{i}]");
        match seg.get(ctx, &p)? {
            SegmentFile::Dwell {
                duration_s,
                duration_h,
                label: l,
            } => segments.push(MotionSegment::Dwell {
                duration_s: ctx.duration(&p, *duration_s, *duration_h)?,
                label: label(ctx, &format!("{p}.label"), l, "dwell".into())?,
            }),
            SegmentFile::Rotate {
                axis,
                angle_deg,
                rate_deg_per_s,
                label: l,
            } => {
                let v = Vec3::from(ctx.finite3(&format!("{p}.axis"), *axis)?);
                if v.norm() == 0.0 {
                    return Err(
                        ctx.invalid(&format!("{p}.axis"), "the rotation axis must be non-zero")
                    );
                }
                let angle = ctx.finite(&format!("{p}.angle_deg"), *angle_deg)?;
                if angle == 0.0 {
                    return Err(ctx.invalid(
                        &format!("{p}.angle_deg"),
                        "the rotation angle must be non-zero",
                    ));
                }
                let rate_key = format!("{p}.rate_deg_per_s");
                let rate = table_rate(ctx, &rate_key, *rate_deg_per_s)?;
                let duration_s = angle.abs() / rate;
                if duration_s > MAX_RUN_DURATION_S {
                    let msg = format!(
                        "{angle} deg at {rate} deg/s takes {duration_s} s, longer than the \
                         {MAX_RUN_DURATION_S} s (366 days) a run may last"
                    );
                    return Err(ctx.invalid(&format!("{p}.angle_deg"), msg));
                }
                segments.push(MotionSegment::Rotate {
                    axis_body: v.normalize(),
                    angle_rad: angle * DEG,
                    rate_radps: rate * DEG,
                    label: label(ctx, &format!("{p}.label"), l, "rotate".into())?,
                });
            }
            SegmentFile::Scheme {
                file,
                rate_deg_per_s,
                dwell_s,
                total_s,
                repeat,
                label: l,
            } => {
                let rate = table_rate(ctx, &format!("{p}.rate_deg_per_s"), *rate_deg_per_s)? * DEG;
                let repeat = repeat.unwrap_or(1);
                if repeat == 0 {
                    return Err(ctx.invalid(&format!("{p}.repeat"), "must be at least 1"));
                }
                if dwell_s.is_some() == total_s.is_some() {
                    return Err(ctx.invalid(&p, "give exactly one of `dwell_s` and `total_s`"));
                }
                let key = format!("{p}.file");
                let (path, text) = ctx.read_referenced(&key, file)?;
                let steps = parse_scheme(&text, &path.display().to_string())
                    .map_err(|e| ctx.referenced(&key, e))?;
                let n = steps.len() as f64 * f64::from(repeat);
                let rotating_s: f64 =
                    f64::from(repeat) * steps.iter().map(|s| s.angle_rad.abs() / rate).sum::<f64>();
                let dwell = match (dwell_s, total_s) {
                    (Some(d), _) => ctx.positive(&format!("{p}.dwell_s"), *d)?,
                    (None, t) => {
                        let key = format!("{p}.total_s");
                        let t = ctx.positive(&key, t.unwrap_or(f64::NAN))?;
                        if t <= rotating_s {
                            let msg = format!(
                                "{t} s leaves no time to dwell: the rotations alone take {rotating_s} s"
                            );
                            return Err(ctx.invalid(&key, msg));
                        }
                        (t - rotating_s) / n
                    }
                };
                let l = label(ctx, &format!("{p}.label"), l, "scheme".into())?;
                let expanded = 2.0 * n;
                let scheme_s = rotating_s + n * dwell;
                if segments.len() as f64 + expanded > MAX_MOTION_SEGMENTS as f64 {
                    let msg = format!(
                        "{} steps x {repeat} repeats expand to {expanded} segments, more than \
                         the {MAX_MOTION_SEGMENTS} a motion program may have",
                        steps.len()
                    );
                    return Err(ctx.invalid(&format!("{p}.repeat"), msg));
                }
                if scheme_s > MAX_RUN_DURATION_S {
                    let msg = format!(
                        "the scheme lasts {scheme_s} s, longer than the {MAX_RUN_DURATION_S} s \
                         (366 days) a run may last"
                    );
                    return Err(ctx.invalid(&p, msg));
                }
                for _ in 0..repeat {
                    for s in &steps {
                        segments.push(MotionSegment::Rotate {
                            axis_body: s.axis,
                            angle_rad: s.angle_rad,
                            rate_radps: rate,
                            label: l.clone(),
                        });
                        segments.push(MotionSegment::Dwell {
                            duration_s: dwell,
                            label: l.clone(),
                        });
                    }
                }
            }
            SegmentFile::Vibrate {
                duration_s,
                duration_h,
                pattern,
                amplitude_deg,
                period_s,
                phase_deg,
                label: l,
            } => {
                let duration_s = ctx.duration(&p, *duration_s, *duration_h)?;
                let (amplitude, period, default_label) = match (pattern, amplitude_deg, period_s) {
                    (Some(n), None, None) => {
                        let table = match &mut patterns {
                            Some(t) => t,
                            None => patterns.insert(load_patterns(ctx, raw, &p)?),
                        };
                        let Some(v) = table.get(n) else {
                            let known: Vec<String> = table.keys().map(u32::to_string).collect();
                            let msg = format!(
                                "pattern {n} is not in the table (it has {})",
                                known.join(", ")
                            );
                            return Err(ctx.invalid(&format!("{p}.pattern"), msg));
                        };
                        (v.amplitude_deg, v.period_s, format!("pattern{n}"))
                    }
                    (None, Some(a), Some(t)) => (*a, *t, "vibrate".to_owned()),
                    _ => {
                        return Err(ctx.invalid(
                            &p,
                            "give either `pattern` or both `amplitude_deg` and `period_s`",
                        ));
                    }
                };
                for k in 0..3 {
                    ctx.non_negative(&format!("{p}.amplitude_deg[{k}]"), amplitude[k])?;
                    ctx.positive(&format!("{p}.period_s[{k}]"), period[k])?;
                    // Peak rate of a sinusoid of amplitude A and period T: 2 pi A / T.
                    let peak = std::f64::consts::TAU * amplitude[k] / period[k];
                    if peak > GYRO_FULL_SCALE_DEG_PER_S {
                        let key = match pattern {
                            Some(_) => format!("{p}.pattern"),
                            None => format!("{p}.amplitude_deg[{k}]"),
                        };
                        let msg = format!(
                            "axis {k}: {} deg every {} s peaks at {peak:.0} deg/s, beyond the \
                             {GYRO_FULL_SCALE_DEG_PER_S} deg/s full scale of a navigation-grade \
                             gyro (the dataset would be refused when read)",
                            amplitude[k], period[k]
                        );
                        return Err(ctx.invalid(&key, msg));
                    }
                }
                let phase =
                    ctx.finite3(&format!("{p}.phase_deg"), phase_deg.unwrap_or([0.0; 3]))?;
                segments.push(MotionSegment::Vibrate {
                    duration_s,
                    amplitude_rad: Vec3::from(amplitude) * DEG,
                    period_s: Vec3::from(period),
                    phase_rad: Vec3::from(phase) * DEG,
                    label: label(ctx, &format!("{p}.label"), l, default_label)?,
                });
            }
        }
    }
    if segments.len() > MAX_MOTION_SEGMENTS {
        let msg = format!(
            "the program has {} segments, more than the {MAX_MOTION_SEGMENTS} it may have",
            segments.len()
        );
        return Err(ctx.invalid("motion.segment", msg));
    }
    let program = MotionProgram {
        initial_ned_from_body: ned_from_body_euler(&Euler::from_deg(a.pitch, a.roll, a.yaw)),
        segments,
    };
    let total_s = motion_duration_s(&program);
    if total_s > MAX_RUN_DURATION_S {
        let msg = format!(
            "the motion program lasts {total_s} s ({:.0} days), longer than the \
             {MAX_RUN_DURATION_S} s (366 days) a run may last",
            total_s / 86_400.0
        );
        return Err(ctx.invalid("motion.segment", msg));
    }
    Ok(program)
}

/// A turntable rate (deg/s): positive, finite and within the gyro full scale
/// [`GYRO_FULL_SCALE_DEG_PER_S`] (a faster table would saturate a navigation-grade gyro, and the
/// dataset would be refused when read).
fn table_rate(ctx: &Ctx<'_>, key: &str, rate_deg_per_s: f64) -> Result<f64, ConfigError> {
    let rate = ctx.positive(key, rate_deg_per_s)?;
    if rate > GYRO_FULL_SCALE_DEG_PER_S {
        let msg = format!(
            "{rate} deg/s is beyond the {GYRO_FULL_SCALE_DEG_PER_S} deg/s full scale of a \
             navigation-grade gyro (the dataset would be refused when read)"
        );
        return Err(ctx.invalid(key, msg));
    }
    Ok(rate)
}

fn load_patterns(
    ctx: &Ctx<'_>,
    raw: &MotionFile,
    segment: &str,
) -> Result<BTreeMap<u32, VibrationPattern>, ConfigError> {
    let key = "motion.vibration_patterns";
    let Some(file) = &raw.vibration_patterns else {
        return Err(ctx.missing(
            key,
            format!("{segment} uses `pattern`, which refers to this table"),
        ));
    };
    let (path, text) = ctx.read_referenced(key, file)?;
    parse_patterns(&text, &path.display().to_string()).map_err(|e| ctx.referenced(key, e))
}

/// Total length of a motion program (s), rotations at their constant rate.
pub fn motion_duration_s(motion: &MotionProgram) -> f64 {
    motion
        .segments
        .iter()
        .map(|s| match s {
            MotionSegment::Dwell { duration_s, .. } | MotionSegment::Vibrate { duration_s, .. } => {
                *duration_s
            }
            MotionSegment::Rotate {
                angle_rad,
                rate_radps,
                ..
            } => angle_rad.abs() / rate_radps,
        })
        .sum()
}
