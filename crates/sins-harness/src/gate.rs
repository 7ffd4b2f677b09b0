//! The release gate: thresholds on a report's `summary.json`, one readable line per failure,
//! and JUnit XML for CI systems. The thresholds file (TOML) is read by
//! `sins_config::load_thresholds`:
//!
//! ```toml
//! schema = 1
//! [default]                                   # every experiment
//! max_horizontal_nmi = { "30-state" = 5.0, "42-state" = 3.0 }
//! min_improvement_percent = 0.0
//! [experiment.nav2]                           # overrides for one experiment
//! max_horizontal_nmi = { "42-state" = 2.5 }
//! ```

use crate::HarnessError;
use crate::summary::Summary;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Version of the thresholds layout.
pub const THRESHOLDS_SCHEMA: u32 = 1;

/// Limits for one experiment.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Limits {
    /// Largest allowed maximum horizontal error per parameter set (nmi).
    #[serde(default)]
    pub max_horizontal_nmi: BTreeMap<String, f64>,
    /// Smallest allowed improvement of the compensated set over the baseline (%).
    pub min_improvement_percent: Option<f64>,
}

impl Limits {
    /// True when these limits check nothing.
    pub fn is_empty(&self) -> bool {
        self.max_horizontal_nmi.is_empty() && self.min_improvement_percent.is_none()
    }
}

/// A thresholds file.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Thresholds {
    /// Layout version ([`THRESHOLDS_SCHEMA`]).
    pub schema: u32,
    /// Limits for every experiment.
    #[serde(default)]
    pub default: Limits,
    /// Per-experiment overrides (by experiment name).
    #[serde(default)]
    pub experiment: BTreeMap<String, Limits>,
}

/// The outcome of one check.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// Experiment name.
    pub experiment: String,
    /// What is checked, e.g. `max_horizontal_nmi[42-state]`.
    pub name: String,
    /// True when within the threshold.
    pub passed: bool,
    /// One line saying what was measured against what.
    pub message: String,
}

impl Thresholds {
    /// Every limit is a usable number (nmi > 0, finite %) and there is at least one; the
    /// message names the key (`default.max_horizontal_nmi."42-state"`), the caller the file.
    pub fn validate(&self) -> Result<(), String> {
        if self.is_empty() {
            return Err(
                "defines no checks: a gate that checks nothing cannot pass; give \
                        max_horizontal_nmi or min_improvement_percent under [default] or \
                        [experiment.NAME]"
                    .into(),
            );
        }
        let all = std::iter::once(("default".to_string(), &self.default)).chain(
            self.experiment
                .iter()
                .map(|(k, v)| (format!("experiment.{k}"), v)),
        );
        for (at, l) in all {
            for (set, v) in &l.max_horizontal_nmi {
                if !(v.is_finite() && *v > 0.0) {
                    return Err(format!(
                        "{at}.max_horizontal_nmi.\"{set}\" = {v} must be a positive number of nautical miles"
                    ));
                }
            }
            if let Some(v) = l.min_improvement_percent
                && !v.is_finite()
            {
                return Err(format!("{at}.min_improvement_percent = {v} is not finite"));
            }
        }
        Ok(())
    }

    /// True when no limit is set anywhere (neither in `[default]` nor for any experiment).
    pub fn is_empty(&self) -> bool {
        self.default.is_empty() && self.experiment.values().all(Limits::is_empty)
    }

    /// Check every experiment of `summary`, read from `summary_path`; an error names that file
    /// when there is nothing to check (no experiment, or none the limits apply to): a gate that
    /// checks nothing must not pass.
    pub fn check(
        &self,
        summary: &Summary,
        summary_path: &Path,
    ) -> Result<Vec<Check>, HarnessError> {
        let malformed = |message: &str| HarnessError::Malformed {
            path: summary_path.to_owned(),
            message: message.to_string(),
        };
        if summary.experiments.is_empty() {
            return Err(malformed(
                "the summary has no experiments, so the gate would check nothing",
            ));
        }
        let checks = self.evaluate(summary);
        if checks.is_empty() {
            return Err(malformed(
                "no threshold applies to any experiment of this summary, so the gate would check nothing",
            ));
        }
        Ok(checks)
    }

    /// Check every experiment of `summary` (no check at all when it has no experiment or the
    /// limits are empty; [`Thresholds::check`] refuses that).
    pub fn evaluate(&self, summary: &Summary) -> Vec<Check> {
        let mut checks = Vec::new();
        for name in self.experiment.keys() {
            if !summary.experiments.iter().any(|e| &e.name == name) {
                checks.push(Check {
                    experiment: name.clone(),
                    name: "present".into(),
                    passed: false,
                    message: format!(
                        "{name}: the thresholds name this experiment but the summary has no such experiment"
                    ),
                });
            }
        }
        for e in &summary.experiments {
            let own = self.experiment.get(&e.name);
            let mut max = self.default.max_horizontal_nmi.clone();
            if let Some(o) = own {
                max.extend(o.max_horizontal_nmi.clone());
            }
            for (set, limit) in &max {
                let name = format!("max_horizontal_nmi[{set}]");
                let (passed, message) = match e.results.get(set) {
                    Some(r) => (
                        r.max_horizontal_nmi <= *limit,
                        format!(
                            "{}: max horizontal error with '{set}' is {:.3} nmi (limit {limit:.3} nmi), at t = {:.2} h in '{}'",
                            e.name,
                            r.max_horizontal_nmi,
                            r.t_max_s / 3600.0,
                            r.segment_at_max
                        ),
                    ),
                    None => (
                        false,
                        format!(
                            "{}: no result for parameter set '{set}' in the summary",
                            e.name
                        ),
                    ),
                };
                checks.push(Check {
                    experiment: e.name.clone(),
                    name,
                    passed,
                    message,
                });
            }
            let min = own
                .and_then(|o| o.min_improvement_percent)
                .or(self.default.min_improvement_percent);
            if let Some(min) = min {
                let (passed, message) = match e.improvement_percent {
                    Some(v) => (
                        v >= min,
                        format!(
                            "{}: improvement with temperature compensation is {v:.1} % (minimum {min:.1} %)",
                            e.name
                        ),
                    ),
                    None => (
                        false,
                        format!(
                            "{}: the summary has no improvement figure (no [comparison] in the report)",
                            e.name
                        ),
                    ),
                };
                checks.push(Check {
                    experiment: e.name.clone(),
                    name: "min_improvement_percent".into(),
                    passed,
                    message,
                });
            }
        }
        checks
    }
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// JUnit XML of the checks (one test case per check).
pub fn junit_xml(suite: &str, checks: &[Check]) -> String {
    let failures = checks.iter().filter(|c| !c.passed).count();
    let mut x = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n  <testsuite name=\"{}\" tests=\"{}\" failures=\"{failures}\">\n",
        xml_escape(suite),
        checks.len()
    );
    for c in checks {
        x.push_str(&format!(
            "    <testcase classname=\"{}\" name=\"{}\">",
            xml_escape(&c.experiment),
            xml_escape(&c.name)
        ));
        if c.passed {
            x.push_str(&format!(
                "<system-out>{}</system-out>",
                xml_escape(&c.message)
            ));
        } else {
            x.push_str(&format!(
                "<failure message=\"{}\"/>",
                xml_escape(&c.message)
            ));
        }
        x.push_str("</testcase>\n");
    }
    x.push_str("  </testsuite>\n</testsuites>\n");
    x
}
