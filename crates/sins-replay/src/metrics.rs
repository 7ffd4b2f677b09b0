//! Navigation error points and summaries (metres internally; nautical miles at the edges).

use sins_nav::{NMI_M, Quat};

/// Navigation error at one output time, relative to the reference (the fixed site at rest).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorPoint {
    /// Time (s).
    pub t_s: f64,
    /// North position error (m).
    pub north_m: f64,
    /// East position error (m).
    pub east_m: f64,
    /// North velocity error (m/s).
    pub vel_n_mps: f64,
    /// East velocity error (m/s).
    pub vel_e_mps: f64,
    /// Segment index of the sample at this time (into the caller's label list).
    pub segment: u16,
    /// Estimated attitude `ned_from_body` at this time (the navigation solution's own; compare
    /// it with a reference attitude when the data carry one).
    pub ned_from_body: Quat,
}

impl ErrorPoint {
    /// Horizontal position error (m).
    pub fn horizontal_m(&self) -> f64 {
        self.north_m.hypot(self.east_m)
    }
}

/// Maximum horizontal error within one segment label.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentSummary {
    /// Segment index.
    pub segment: u16,
    /// Largest horizontal error in the segment (m).
    pub max_horizontal_m: f64,
    /// Time of that maximum (s).
    pub t_max_s: f64,
}

/// Summary of a replay.
#[derive(Clone, Debug, PartialEq)]
pub struct ReplaySummary {
    /// Largest horizontal error after alignment (m).
    pub max_horizontal_m: f64,
    /// Time of the maximum (s).
    pub t_max_s: f64,
    /// Segment index at the maximum.
    pub segment_at_max: u16,
    /// RMS horizontal error over the output points (m).
    pub rms_horizontal_m: f64,
    /// Horizontal error at the last output point (m).
    pub final_horizontal_m: f64,
    /// Per-segment maxima in order of first appearance.
    pub segments: Vec<SegmentSummary>,
    /// Navigated time after alignment (s).
    pub navigated_s: f64,
}

impl ReplaySummary {
    /// Maximum horizontal error in nautical miles (1852 m).
    pub fn max_horizontal_nmi(&self) -> f64 {
        self.max_horizontal_m / NMI_M
    }

    /// Summarise a track of error points.
    pub fn from_points(points: &[ErrorPoint], navigated_s: f64) -> Self {
        let mut s = ReplaySummary {
            max_horizontal_m: 0.0,
            t_max_s: 0.0,
            segment_at_max: 0,
            rms_horizontal_m: 0.0,
            final_horizontal_m: points.last().map_or(0.0, ErrorPoint::horizontal_m),
            segments: Vec::new(),
            navigated_s,
        };
        let mut sum_sq = 0.0;
        for p in points {
            let h = p.horizontal_m();
            sum_sq += h * h;
            if h > s.max_horizontal_m {
                (s.max_horizontal_m, s.t_max_s, s.segment_at_max) = (h, p.t_s, p.segment);
            }
            match s.segments.iter_mut().find(|g| g.segment == p.segment) {
                Some(g) if h > g.max_horizontal_m => (g.max_horizontal_m, g.t_max_s) = (h, p.t_s),
                Some(_) => {}
                None => s.segments.push(SegmentSummary {
                    segment: p.segment,
                    max_horizontal_m: h,
                    t_max_s: p.t_s,
                }),
            }
        }
        if !points.is_empty() {
            s.rms_horizontal_m = (sum_sq / points.len() as f64).sqrt();
        }
        s
    }
}
