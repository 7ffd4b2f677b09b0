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
//!
//! A key that matches nothing in the summary (an experiment it does not have, a parameter set
//! none of its experiments has) is refused by [`Thresholds::check`]: a misspelt name must not
//! make the gate check less than it says. The JUnit report begins with [`JUNIT_HEAD`], the
//! mark by which the gate recognises a report it may replace.

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
    /// when there is nothing to check (no experiment, or none the limits apply to: a gate that
    /// checks nothing must not pass) and when a key of the thresholds matches nothing in the
    /// summary ([`Thresholds::unmatched_keys`]: a misspelt name would otherwise check nothing
    /// or fail for the wrong reason).
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
        let unmatched = self.unmatched_keys(summary);
        if !unmatched.is_empty() {
            return Err(malformed(&unmatched_message(&unmatched, summary)));
        }
        let checks = self.evaluate(summary);
        if checks.is_empty() {
            return Err(malformed(
                "no threshold applies to any experiment of this summary, so the gate would check nothing",
            ));
        }
        Ok(checks)
    }

    /// The keys that match nothing in `summary`, as `experiment.NAME` (no such experiment),
    /// `default.max_horizontal_nmi."SET"` (no experiment has that parameter set) or
    /// `experiment.NAME.max_horizontal_nmi."SET"` (that experiment has no such set). A set of
    /// `[default]` that some experiments have and others lack is not listed: for those it is a
    /// failed check.
    pub fn unmatched_keys(&self, summary: &Summary) -> Vec<String> {
        let mut keys = Vec::new();
        let has_set = |set: &str| {
            summary
                .experiments
                .iter()
                .any(|e| e.results.contains_key(set))
        };
        for set in self.default.max_horizontal_nmi.keys() {
            if !has_set(set) {
                keys.push(format!("default.max_horizontal_nmi.\"{set}\""));
            }
        }
        for (name, limits) in &self.experiment {
            let Some(e) = summary.experiments.iter().find(|e| &e.name == name) else {
                keys.push(format!("experiment.{name}"));
                continue;
            };
            for set in limits.max_horizontal_nmi.keys() {
                if !e.results.contains_key(set) {
                    keys.push(format!("experiment.{name}.max_horizontal_nmi.\"{set}\""));
                }
            }
        }
        keys
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

/// The refusal of thresholds keys that match nothing: each key, then the names the summary has.
fn unmatched_message(keys: &[String], summary: &Summary) -> String {
    let experiments: Vec<&str> = summary
        .experiments
        .iter()
        .map(|e| e.name.as_str())
        .collect();
    let sets: std::collections::BTreeSet<&str> = summary
        .experiments
        .iter()
        .flat_map(|e| e.results.keys().map(String::as_str))
        .collect();
    let sets: Vec<&str> = sets.into_iter().collect();
    format!(
        "the thresholds name what this summary does not have: {}; the summary's experiments are \
         {} and its parameter sets {}; correct those keys of the thresholds (names are \
         case-sensitive) or gate the summary they were written for",
        keys.join(", "),
        experiments.join(", "),
        sets.join(", ")
    )
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// How every JUnit report of the gate begins: the root `<testsuites name="sinsbench gate">` is
/// the mark by which `sinsbench gate --junit` knows a file it may replace ([`is_gate_junit`]).
pub const JUNIT_HEAD: &str =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"sinsbench gate\">\n";

/// How the reports of the gate began before [`JUNIT_HEAD`] (an unnamed root, then the suite
/// `sinsbench gate <summary name>`); still recognised as the gate's own.
const JUNIT_HEAD_UNMARKED: &str =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n  <testsuite name=\"sinsbench gate ";

/// True when `head` (the first bytes of a file: 128 suffice) is the beginning of a JUnit report
/// the gate wrote.
pub fn is_gate_junit(head: &[u8]) -> bool {
    head.starts_with(JUNIT_HEAD.as_bytes()) || head.starts_with(JUNIT_HEAD_UNMARKED.as_bytes())
}

/// JUnit XML of the checks (one test case per check), beginning with [`JUNIT_HEAD`].
pub fn junit_xml(suite: &str, checks: &[Check]) -> String {
    let failures = checks.iter().filter(|c| !c.passed).count();
    let mut x = format!(
        "{JUNIT_HEAD}  <testsuite name=\"{}\" tests=\"{}\" failures=\"{failures}\">\n",
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

#[cfg(test)]
mod tests {
    use super::*;

    fn limits(sets: &[&str]) -> Limits {
        Limits {
            max_horizontal_nmi: sets.iter().map(|s| (s.to_string(), 3.0)).collect(),
            min_improvement_percent: None,
        }
    }

    #[test]
    fn keys_that_match_nothing_are_named_and_refused() {
        let summary = Summary::example(2.0, 3.0);
        let mut t = Thresholds {
            schema: THRESHOLDS_SCHEMA,
            default: limits(&["42-state", "99-state"]),
            experiment: BTreeMap::from([
                ("NAV1".to_string(), limits(&["42-state"])),
                ("nav1".to_string(), limits(&["30-state", "42-State"])),
            ]),
        };
        assert_eq!(
            t.unmatched_keys(&summary),
            [
                "default.max_horizontal_nmi.\"99-state\"",
                "experiment.NAV1",
                "experiment.nav1.max_horizontal_nmi.\"42-State\""
            ]
        );
        let e = t
            .check(&summary, Path::new("s.json"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("s.json: the thresholds name what this summary does not have: ")
                && e.contains("experiments are nav1 and its parameter sets 30-state, 42-state;"),
            "{e}"
        );
        t.default = limits(&["42-state"]);
        t.experiment = BTreeMap::from([("nav1".to_string(), limits(&["30-state"]))]);
        assert!(t.unmatched_keys(&summary).is_empty());
        assert_eq!(
            t.check(&summary, Path::new("s.json")).map(|c| c.len()).ok(),
            Some(2)
        );
    }

    #[test]
    fn the_gate_knows_its_own_junit_reports() {
        let xml = junit_xml("sinsbench gate x", &[]);
        assert!(is_gate_junit(xml.as_bytes()));
        assert!(is_gate_junit(&xml.as_bytes()[..JUNIT_HEAD.len()]));
        assert!(!is_gate_junit(&xml.as_bytes()[..JUNIT_HEAD.len() - 1]));
        assert!(!is_gate_junit(
            b"<testsuites><testsuite name=\"unit\"/></testsuites>"
        ));
        assert!(!is_gate_junit(b""));
    }
}
