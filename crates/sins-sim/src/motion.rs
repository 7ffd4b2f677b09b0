//! The turntable motion as a function of time: a validated timeline built from a
//! [`MotionProgram`], with exact segment start attitudes and a closed-form attitude and body rate
//! at any instant.
//!
//! Attitudes are `ned_from_body` (C_b^n); body rates are ω_nb^b, the rate of the body relative to
//! the (Earth-fixed) navigation frame, in body axes (rad/s).

use crate::error::{SimError, finite_reason, positive_reason};
use crate::scenario::{MotionProgram, MotionSegment};
use crate::trig::sin_cos;
use crate::vibration::{VibrationAxis, vibration_body_rate, vibration_rotation};
use sins_nav::{Mat3, Quat, Vec3};

/// Tolerance on the norm of a rotation axis and of the initial attitude quaternion.
const UNIT_NORM_TOL: f64 = 1e-9;

/// Validated kind of a timeline segment.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum SegmentKind {
    /// Constant attitude.
    Dwell,
    /// Constant body rate `axis_body · rate_radps` (rate signed by the sense of rotation).
    Rotate {
        /// Unit axis in body coordinates.
        axis_body: Vec3,
        /// Signed rate (rad/s).
        rate_radps: f64,
        /// Total signed angle (rad).
        angle_rad: f64,
    },
    /// `C(t) = C_start · Rz(θz) · Ry(θy) · Rx(θx)`.
    Vibrate {
        /// Channels about body x, y, z.
        axes: [VibrationAxis; 3],
    },
}

/// One segment of the timeline with its exact start time and start attitude.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TimelineSegment {
    /// Start time (s).
    pub start_s: f64,
    /// End time (s), equal to the next segment's start.
    pub end_s: f64,
    /// Attitude at the start.
    pub start_ned_from_body: Quat,
    /// The same attitude as a matrix.
    pub start_ned_from_body_mat: Mat3,
    /// What the segment does.
    pub kind: SegmentKind,
    /// Label written to datasets.
    pub label: String,
}

/// Attitude and body rate at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionState {
    /// Attitude C_b^n as a unit quaternion.
    pub ned_from_body: Quat,
    /// Body rate relative to the navigation frame, ω_nb^b (rad/s, body axes).
    pub omega_nb_body_radps: Vec3,
    /// Index of the segment the instant belongs to (the last segment after the end).
    pub segment_index: usize,
}

/// The motion program turned into a timeline: segment `i` covers `[start_i, start_{i+1})`; after
/// the last segment the table holds the final attitude.
#[derive(Clone, Debug)]
pub struct MotionTimeline {
    segments: Vec<TimelineSegment>,
    end_ned_from_body: Quat,
}

/// Kind name of a segment for error messages.
fn kind_name(seg: &MotionSegment) -> &'static str {
    match seg {
        MotionSegment::Dwell { .. } => "dwell",
        MotionSegment::Rotate { .. } => "rotate",
        MotionSegment::Vibrate { .. } => "vibrate",
    }
}

fn motion_error(index: usize, kind: &'static str, field: &'static str, reason: String) -> SimError {
    SimError::MotionSegment {
        index,
        kind,
        field,
        reason,
    }
}

fn check_positive(
    index: usize,
    kind: &'static str,
    field: &'static str,
    v: f64,
) -> Result<(), SimError> {
    positive_reason(v).map_or(Ok(()), |r| Err(motion_error(index, kind, field, r)))
}

fn check_vec3(
    index: usize,
    field: &'static str,
    v: &Vec3,
    reason: fn(f64) -> Option<String>,
) -> Result<(), SimError> {
    for (name, c) in ["x", "y", "z"].iter().zip(v.iter()) {
        if let Some(r) = reason(*c) {
            return Err(motion_error(
                index,
                "vibrate",
                field,
                format!("{name} component {r}"),
            ));
        }
    }
    Ok(())
}

/// Validate one segment and turn it into (duration, kind, label).
fn validate_segment(
    index: usize,
    seg: &MotionSegment,
) -> Result<(f64, SegmentKind, String), SimError> {
    match seg {
        MotionSegment::Dwell { duration_s, label } => {
            check_positive(index, "dwell", "duration_s", *duration_s)?;
            Ok((*duration_s, SegmentKind::Dwell, label.clone()))
        }
        MotionSegment::Rotate {
            axis_body,
            angle_rad,
            rate_radps,
            label,
        } => {
            let norm = axis_body.norm();
            if !(norm.is_finite() && (norm - 1.0).abs() <= UNIT_NORM_TOL) {
                let reason = format!("must be a unit vector (norm 1 within 1e-9), got norm {norm}");
                return Err(motion_error(index, "rotate", "axis_body", reason));
            }
            if let Some(r) = finite_reason(*angle_rad) {
                return Err(motion_error(index, "rotate", "angle_rad", r));
            }
            if *angle_rad == 0.0 {
                return Err(motion_error(
                    index,
                    "rotate",
                    "angle_rad",
                    "must be non-zero".into(),
                ));
            }
            check_positive(index, "rotate", "rate_radps", *rate_radps)?;
            let duration_s = angle_rad.abs() / rate_radps;
            check_positive(
                index,
                "rotate",
                "angle_rad / rate_radps (duration)",
                duration_s,
            )?;
            let kind = SegmentKind::Rotate {
                axis_body: axis_body / norm,
                rate_radps: rate_radps.copysign(*angle_rad),
                angle_rad: *angle_rad,
            };
            Ok((duration_s, kind, label.clone()))
        }
        MotionSegment::Vibrate {
            duration_s,
            amplitude_rad,
            period_s,
            phase_rad,
            label,
        } => {
            check_positive(index, "vibrate", "duration_s", *duration_s)?;
            check_vec3(index, "amplitude_rad", amplitude_rad, finite_reason)?;
            check_vec3(index, "period_s", period_s, positive_reason)?;
            check_vec3(index, "phase_rad", phase_rad, finite_reason)?;
            let axes = std::array::from_fn(|j| VibrationAxis {
                amp_rad: amplitude_rad[j],
                omega_radps: std::f64::consts::TAU / period_s[j],
                phase_rad: phase_rad[j],
                offset_rad: amplitude_rad[j] * phase_rad[j].sin(),
            });
            Ok((*duration_s, SegmentKind::Vibrate { axes }, label.clone()))
        }
    }
}

impl MotionTimeline {
    /// Validate `program` and build the timeline. Errors name the segment index and field.
    pub fn new(program: &MotionProgram) -> Result<Self, SimError> {
        let q0 = program.initial_ned_from_body.quaternion();
        let n0 = q0.norm();
        if !(n0.is_finite() && (n0 - 1.0).abs() <= UNIT_NORM_TOL) {
            return Err(SimError::Field {
                field: "motion.initial_ned_from_body",
                reason: format!("must be a finite unit quaternion, got norm {n0}"),
            });
        }
        if program.segments.is_empty() || program.segments.len() > usize::from(u16::MAX) + 1 {
            return Err(SimError::Field {
                field: "motion.segments",
                reason: format!(
                    "must hold 1..=65536 segments, got {}",
                    program.segments.len()
                ),
            });
        }
        let mut attitude = Quat::new_normalize(*q0);
        let mut start_s = 0.0;
        let mut segments = Vec::with_capacity(program.segments.len());
        for (index, seg) in program.segments.iter().enumerate() {
            let (duration_s, kind, label) = validate_segment(index, seg)?;
            let end_s = start_s + duration_s;
            if !end_s.is_finite() {
                let reason = format!("makes the program end at {end_s} s");
                return Err(motion_error(index, kind_name(seg), "duration", reason));
            }
            let segment = TimelineSegment {
                start_s,
                end_s,
                start_ned_from_body: attitude,
                start_ned_from_body_mat: attitude.to_rotation_matrix().into_inner(),
                kind,
                label,
            };
            attitude = segment.end_attitude();
            segments.push(segment);
            start_s = end_s;
        }
        Ok(Self {
            segments,
            end_ned_from_body: attitude,
        })
    }

    /// Number of segments.
    pub fn n_segments(&self) -> usize {
        self.segments.len()
    }

    /// Total duration of the program (s).
    pub fn total_duration_s(&self) -> f64 {
        self.segments.last().map_or(0.0, |s| s.end_s)
    }

    /// Start time (s) of segment `index`.
    pub fn segment_start_s(&self, index: usize) -> Option<f64> {
        self.segments.get(index).map(|s| s.start_s)
    }

    /// End time (s) of segment `index` (the start of the next one).
    pub fn segment_end_s(&self, index: usize) -> Option<f64> {
        self.segments.get(index).map(|s| s.end_s)
    }

    /// Exact attitude C_b^n at the start of segment `index`.
    pub fn segment_start_ned_from_body(&self, index: usize) -> Option<Quat> {
        self.segments.get(index).map(|s| s.start_ned_from_body)
    }

    /// Label of segment `index`.
    pub fn segment_label(&self, index: usize) -> Option<&str> {
        self.segments.get(index).map(|s| s.label.as_str())
    }

    /// Exact attitude C_b^n at the end of the program (held afterwards).
    pub fn end_ned_from_body(&self) -> Quat {
        self.end_ned_from_body
    }

    /// Index of the segment containing `t_s`: 0 before the start, the last one after the end.
    pub fn segment_index_at(&self, t_s: f64) -> usize {
        let i = self.segments.partition_point(|s| s.end_s <= t_s);
        i.min(self.segments.len() - 1)
    }

    /// Attitude and body rate at `t_s` in closed form. Before 0 the initial attitude and after
    /// the end the final attitude are held with zero rate.
    pub fn eval(&self, t_s: f64) -> MotionState {
        if t_s < 0.0 {
            return MotionState {
                ned_from_body: self.segments[0].start_ned_from_body,
                omega_nb_body_radps: Vec3::zeros(),
                segment_index: 0,
            };
        }
        let index = self.segment_index_at(t_s);
        let seg = &self.segments[index];
        if t_s >= seg.end_s {
            return MotionState {
                ned_from_body: self.end_ned_from_body,
                omega_nb_body_radps: Vec3::zeros(),
                segment_index: index,
            };
        }
        let (ned_from_body, omega_nb_body_radps) = seg.eval((t_s - seg.start_s).max(0.0));
        MotionState {
            ned_from_body,
            omega_nb_body_radps,
            segment_index: index,
        }
    }

    /// Attitude C_b^n at `t_s` only (cheaper than [`Self::eval`]); `cursor` is a segment index
    /// hint (0 initially) kept between calls with increasing times.
    pub fn ned_from_body_at(&self, t_s: f64, cursor: &mut usize) -> Quat {
        let last = self.segments.len() - 1;
        if *cursor > last || self.segments[*cursor].start_s > t_s {
            *cursor = 0;
        }
        while *cursor < last && self.segments[*cursor].end_s <= t_s {
            *cursor += 1;
        }
        let seg = &self.segments[*cursor];
        if t_s >= seg.end_s {
            return self.end_ned_from_body;
        }
        seg.attitude((t_s - seg.start_s).max(0.0))
    }

    pub(crate) fn segments(&self) -> &[TimelineSegment] {
        &self.segments
    }
}

impl TimelineSegment {
    /// Attitude and body rate at `tau_s` seconds into the segment.
    pub fn eval(&self, tau_s: f64) -> (Quat, Vec3) {
        match &self.kind {
            SegmentKind::Dwell => (self.start_ned_from_body, Vec3::zeros()),
            SegmentKind::Rotate {
                axis_body,
                rate_radps,
                ..
            } => {
                let rot = Quat::from_scaled_axis(axis_body * (rate_radps * tau_s));
                (self.start_ned_from_body * rot, axis_body * *rate_radps)
            }
            SegmentKind::Vibrate { axes } => {
                let [(tx, rx), (ty, ry), (tz, rz)] = axes.map(|a| a.angle_and_rate(tau_s));
                let q = self.start_ned_from_body * vibration_rotation([tx, ty, tz]);
                let w = vibration_body_rate(sin_cos(tx), sin_cos(ty), [rx, ry, rz]);
                (q, w)
            }
        }
    }

    /// Attitude at `tau_s` seconds into the segment.
    pub fn attitude(&self, tau_s: f64) -> Quat {
        match &self.kind {
            SegmentKind::Dwell => self.start_ned_from_body,
            SegmentKind::Rotate {
                axis_body,
                rate_radps,
                ..
            } => {
                let half = sin_cos(0.5 * rate_radps * tau_s);
                let v = axis_body * half.0;
                let rot = nalgebra::Quaternion::new(half.1, v.x, v.y, v.z);
                Quat::new_normalize(self.start_ned_from_body.into_inner() * rot)
            }
            SegmentKind::Vibrate { axes } => {
                let theta = axes.map(|a| a.angle_and_rate(tau_s).0);
                self.start_ned_from_body * vibration_rotation(theta)
            }
        }
    }

    /// Exact attitude at the end: `start · exp(angle · axis)` for a rotation, `start · R(θ(T))`
    /// for a vibration.
    fn end_attitude(&self) -> Quat {
        let duration_s = self.end_s - self.start_s;
        let q = match &self.kind {
            SegmentKind::Dwell => return self.start_ned_from_body,
            SegmentKind::Rotate {
                axis_body,
                angle_rad,
                ..
            } => self.start_ned_from_body * Quat::from_scaled_axis(axis_body * *angle_rad),
            SegmentKind::Vibrate { axes } => {
                let theta = axes.map(|a| a.angle_and_rate(duration_s).0);
                self.start_ned_from_body * vibration_rotation(theta)
            }
        };
        Quat::new_normalize(q.into_inner())
    }
}
