//! Machine-readable results of a report (`summary.json`): per experiment and parameter set the
//! maximum horizontal error (when, in which segment), RMS and final error, per-segment maxima,
//! and the improvement of the compensated set over the baseline, in the layout of the paper's
//! Table 5. The JSON file is written and read by `sins_config::summary_to_json` and
//! `sins_config::read_summary`.

use crate::pipeline::{RunOutcome, Track};
use crate::reference::PaperRow;
use crate::segments::{SegmentStretch, label_of};
use serde::{Deserialize, Serialize};
use sins_nav::NMI_M;
use std::collections::BTreeMap;

/// Version of the `summary.json` layout.
pub const SUMMARY_SCHEMA: u32 = 1;

/// A parameter set as the report describes it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParamSetInfo {
    /// Key (e.g. "42-state").
    pub key: String,
    /// Human label (e.g. "with temperature compensation").
    pub label: String,
    /// "30-state" or "42-state".
    pub model: String,
    /// Where it came from (a file, or the calibration that produced it).
    pub source: String,
}

/// Which parameter sets the improvement compares.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// Key of the set without temperature compensation.
    pub baseline: String,
    /// Key of the set with it.
    pub compensated: String,
    /// Why the baseline is calibrated as it is (one line; e.g. which calibration condition the
    /// evidence supports), shown under Table 5.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Keys of sets shown as variant rows of the baseline column (the other calibration
    /// condition), each with its own improvement.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub variant_baselines: Vec<String>,
}

/// Results of one parameter set on one experiment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SetResult {
    /// Maximum horizontal error after alignment (nautical miles, 1852 m).
    pub max_horizontal_nmi: f64,
    /// The same in metres.
    pub max_horizontal_m: f64,
    /// Time of the maximum (s from the start of the data).
    pub t_max_s: f64,
    /// Segment (stretch) in which the maximum occurs.
    pub segment_at_max: String,
    /// RMS horizontal error over the navigation (m).
    pub rms_horizontal_m: f64,
    /// Horizontal error at the end (m).
    pub final_horizontal_m: f64,
    /// Navigated time after alignment (s).
    pub navigated_s: f64,
    /// Per-stretch maxima in time order.
    pub segments: Vec<SegmentStretch>,
}

impl SetResult {
    /// Summarise a track.
    pub fn from_track(track: &Track, labels: &[String]) -> Self {
        let s = &track.summary;
        let at_max = track
            .stretches
            .iter()
            .find(|g| g.start_s <= s.t_max_s && s.t_max_s <= g.end_s)
            .map_or_else(|| label_of(labels, s.segment_at_max), |g| g.display_name());
        Self {
            max_horizontal_nmi: s.max_horizontal_m / NMI_M,
            max_horizontal_m: s.max_horizontal_m,
            t_max_s: s.t_max_s,
            segment_at_max: at_max,
            rms_horizontal_m: s.rms_horizontal_m,
            final_horizontal_m: s.final_horizontal_m,
            navigated_s: s.navigated_s,
            segments: track.stretches.clone(),
        }
    }
}

/// One experiment (run or dataset) under every parameter set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExperimentSummary {
    /// Experiment name (e.g. "nav1").
    pub name: String,
    /// What was replayed (simulated run or dataset path).
    pub source: String,
    /// Length of the data (h).
    pub duration_h: f64,
    /// Results keyed by parameter set.
    pub results: BTreeMap<String, SetResult>,
    /// `100 (baseline - compensated) / baseline` of the maximum horizontal error (%), when the
    /// report compares two sets.
    pub improvement_percent: Option<f64>,
    /// The paper's Table 5 row for the experiment in the same position, when given.
    pub paper: Option<PaperRow>,
}

/// The whole `summary.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Layout version ([`SUMMARY_SCHEMA`]).
    pub schema: u32,
    /// Report name.
    pub name: String,
    /// Report description.
    pub description: String,
    /// Program and version that wrote it.
    pub generated_by: String,
    /// The parameter sets replayed.
    pub parameter_sets: Vec<ParamSetInfo>,
    /// The compared pair, if any.
    pub comparison: Option<Comparison>,
    /// One entry per experiment, in order.
    pub experiments: Vec<ExperimentSummary>,
    /// The sensor-noise seed the simulated runs were drawn with
    /// ([`crate::config::ReportConfig::noise_seed`]); absent: the experiment files' own seeds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise_seed: Option<u64>,
}

impl Summary {
    /// A small valid summary, for tests and examples of what reads or checks one: one 15 h
    /// experiment `nav1` replayed under "42-state" (maximum horizontal error `with_nmi`, at
    /// 10 h in `pattern2`) and "30-state" (`without_nmi`), compared as compensated against
    /// baseline.
    pub fn example(with_nmi: f64, without_nmi: f64) -> Summary {
        let result = |nmi: f64| SetResult {
            max_horizontal_nmi: nmi,
            max_horizontal_m: nmi * NMI_M,
            t_max_s: 36_000.0,
            segment_at_max: "pattern2".into(),
            rms_horizontal_m: 900.0,
            final_horizontal_m: 1000.0,
            navigated_s: 52_800.0,
            segments: vec![SegmentStretch {
                label: "pattern2".into(),
                occurrence: 1,
                start_s: 30_000.0,
                end_s: 40_000.0,
                max_horizontal_m: nmi * NMI_M,
                t_max_s: 36_000.0,
                rms_horizontal_m: 800.0,
            }],
        };
        Summary {
            schema: SUMMARY_SCHEMA,
            name: "test".into(),
            description: String::new(),
            generated_by: "test".into(),
            parameter_sets: vec![],
            comparison: Some(Comparison {
                baseline: "30-state".into(),
                compensated: "42-state".into(),
                reason: None,
                variant_baselines: Vec::new(),
            }),
            experiments: vec![ExperimentSummary {
                name: "nav1".into(),
                source: "test".into(),
                duration_h: 15.0,
                results: BTreeMap::from([
                    ("42-state".to_string(), result(with_nmi)),
                    ("30-state".to_string(), result(without_nmi)),
                ]),
                improvement_percent: Some(improvement_percent(without_nmi, with_nmi)),
                paper: None,
            }],
            noise_seed: None,
        }
    }
}

/// `100 (baseline - compensated) / baseline` (%).
pub fn improvement_percent(baseline_m: f64, compensated_m: f64) -> f64 {
    100.0 * (baseline_m - compensated_m) / baseline_m
}

impl ExperimentSummary {
    /// Summarise one run's outcome; `source` says what was replayed.
    pub fn from_outcome(
        outcome: &RunOutcome,
        source: &str,
        comparison: Option<&Comparison>,
        paper: Option<PaperRow>,
    ) -> Self {
        let results: BTreeMap<String, SetResult> = outcome
            .tracks
            .iter()
            .map(|t| (t.set.clone(), SetResult::from_track(t, &outcome.labels)))
            .collect();
        let improvement_percent = comparison.and_then(|c| {
            let b = results.get(&c.baseline)?;
            let k = results.get(&c.compensated)?;
            Some(improvement_percent(b.max_horizontal_m, k.max_horizontal_m))
        });
        Self {
            name: outcome.run.clone(),
            source: source.to_string(),
            duration_h: outcome.duration_s / 3600.0,
            results,
            improvement_percent,
            paper,
        }
    }
}
