//! Per-segment maxima over contiguous stretches of the error track. A label that occurs more than
//! once (the stationary stretches between the vibration patterns) gives one entry per
//! occurrence, so that "stationary after pattern 2" is not merged with "stationary, first 5 h".

use serde::{Deserialize, Serialize};
use sins_replay::ErrorPoint;

/// Largest horizontal error within one contiguous stretch of a segment label.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SegmentStretch {
    /// Segment label (e.g. "stationary", "pattern1").
    pub label: String,
    /// Which occurrence of this label it is (1 = first).
    pub occurrence: usize,
    /// Time of the first error point in the stretch (s).
    pub start_s: f64,
    /// Time of the last error point in the stretch (s).
    pub end_s: f64,
    /// Largest horizontal error in the stretch (m).
    pub max_horizontal_m: f64,
    /// Time of that maximum (s).
    pub t_max_s: f64,
    /// RMS horizontal error over the stretch (m).
    pub rms_horizontal_m: f64,
}

impl SegmentStretch {
    /// Display name: the label, with the occurrence number when it is not the first.
    pub fn display_name(&self) -> String {
        if self.occurrence > 1 {
            format!("{} ({})", self.label, self.occurrence)
        } else {
            self.label.clone()
        }
    }
}

/// The label of segment index `i` in `labels`, or `segment i` when it is out of range.
pub fn label_of(labels: &[String], i: u16) -> String {
    labels
        .get(i as usize)
        .cloned()
        .unwrap_or_else(|| format!("segment {i}"))
}

/// Split `points` into contiguous stretches of equal segment index and summarise each.
pub fn stretches(points: &[ErrorPoint], labels: &[String]) -> Vec<SegmentStretch> {
    let mut out: Vec<SegmentStretch> = Vec::new();
    let mut sum_sq = 0.0;
    let mut n = 0usize;
    let mut current: Option<u16> = None;
    for p in points {
        let h = p.horizontal_m();
        if current != Some(p.segment) {
            close(&mut out, sum_sq, n);
            let label = label_of(labels, p.segment);
            let occurrence = out.iter().filter(|s| s.label == label).count() + 1;
            out.push(SegmentStretch {
                label,
                occurrence,
                start_s: p.t_s,
                end_s: p.t_s,
                max_horizontal_m: h,
                t_max_s: p.t_s,
                rms_horizontal_m: 0.0,
            });
            current = Some(p.segment);
            sum_sq = 0.0;
            n = 0;
        }
        #[allow(clippy::expect_used, reason = "a stretch was just opened")]
        let s = out.last_mut().expect("a stretch was just opened");
        s.end_s = p.t_s;
        if h > s.max_horizontal_m {
            s.max_horizontal_m = h;
            s.t_max_s = p.t_s;
        }
        sum_sq += h * h;
        n += 1;
    }
    close(&mut out, sum_sq, n);
    out
}

fn close(out: &mut [SegmentStretch], sum_sq: f64, n: usize) {
    if let Some(s) = out.last_mut()
        && n > 0
    {
        s.rms_horizontal_m = (sum_sq / n as f64).sqrt();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sins_nav::Quat;

    fn point(t_s: f64, north_m: f64, segment: u16) -> ErrorPoint {
        ErrorPoint {
            t_s,
            north_m,
            east_m: 0.0,
            vel_n_mps: 0.0,
            vel_e_mps: 0.0,
            segment,
            ned_from_body: Quat::identity(),
        }
    }

    #[test]
    fn repeated_labels_are_separate_stretches() {
        let labels = vec!["stationary".to_string(), "pattern1".to_string()];
        let pts = [
            point(1.0, 1.0, 0),
            point(2.0, 3.0, 0),
            point(3.0, 5.0, 1),
            point(4.0, 2.0, 0),
            point(5.0, -7.0, 0),
        ];
        let s = stretches(&pts, &labels);
        assert_eq!(s.len(), 3);
        assert_eq!(s[0].max_horizontal_m, 3.0);
        assert_eq!(s[0].t_max_s, 2.0);
        assert!((s[0].rms_horizontal_m - 5.0f64.sqrt()).abs() < 1e-12);
        assert_eq!(s[1].label, "pattern1");
        assert_eq!(s[2].occurrence, 2);
        assert_eq!(s[2].display_name(), "stationary (2)");
        assert_eq!(s[2].max_horizontal_m, 7.0);
        assert_eq!((s[2].start_s, s[2].end_s), (4.0, 5.0));
    }
}
