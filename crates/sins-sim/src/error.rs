//! Errors of the simulator: a scenario that cannot be simulated, named by the offending field.

/// Why a [`crate::Scenario`] was rejected. Every variant names the field, and the segment index
/// where the field belongs to a segment, so a configuration error can be traced to its source.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// A field of a motion segment is invalid.
    #[error("motion segment {index} ({kind}): `{field}` {reason}")]
    MotionSegment {
        /// Index of the segment in `motion.segments` (0-based).
        index: usize,
        /// Segment kind ("dwell", "rotate", "vibrate").
        kind: &'static str,
        /// Field name as in [`crate::MotionSegment`].
        field: &'static str,
        /// What is wrong, with the offending value.
        reason: String,
    },
    /// A field of a chamber segment is invalid.
    #[error("chamber segment {index} ({kind}): `{field}` {reason}")]
    ChamberSegment {
        /// Index of the segment in `thermal.chamber` (0-based).
        index: usize,
        /// Segment kind ("hold", "ramp", "fluctuating").
        kind: &'static str,
        /// Field name as in [`crate::ChamberSegment`].
        field: &'static str,
        /// What is wrong, with the offending value.
        reason: String,
    },
    /// A scenario-level field (not inside a segment) is invalid.
    #[error("scenario field `{field}` {reason}")]
    Field {
        /// Dotted path of the field, e.g. `noise.gyro_arw_rad_per_sqrt_s`.
        field: &'static str,
        /// What is wrong, with the offending value.
        reason: String,
    },
}

/// Reason text for a value that must be finite and strictly positive.
pub(crate) fn positive_reason(value: f64) -> Option<String> {
    (!(value.is_finite() && value > 0.0))
        .then(|| format!("must be finite and positive, got {value}"))
}

/// Reason text for a value that must be finite and non-negative.
pub(crate) fn non_negative_reason(value: f64) -> Option<String> {
    (!(value.is_finite() && value >= 0.0))
        .then(|| format!("must be finite and non-negative, got {value}"))
}

/// Reason text for a value that must be finite.
pub(crate) fn finite_reason(value: f64) -> Option<String> {
    (!value.is_finite()).then(|| format!("must be finite, got {value}"))
}
