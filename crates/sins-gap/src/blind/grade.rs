//! Grading the blind diagnoses against the opened manifests.

use super::plan::{CaseAnswer, HiddenEffect};
use super::time_local::{self, TimeLocalGrade};
use serde::Serialize;
use sins_config::markdown::Table;
use sins_diag::report::{Diagnosis, Verdict};
use sins_imu::EffectKind;
use sins_imu::effects::Sensor;
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// One graded case.
#[derive(Clone, Debug, Serialize)]
pub struct CaseGrade {
    /// The answer.
    pub answer: CaseAnswer,
    /// What the diagnosis concluded (confusion-table column): `none`, an effect kind,
    /// `unexplained`, `partly: <kind>` or `not separable: a / b`.
    pub outcome: String,
    /// The kind the diagnosis named first, if any.
    pub identified: Option<String>,
    /// Magnitude the diagnosis reports as detectable for the hidden kind and component (paper
    /// unit), when it can say.
    pub detectable: Option<f64>,
    /// The hidden magnitude is above that level (true when the level is unknown).
    pub above_detectable: bool,
    /// Fitted magnitude and 1-sigma of the hidden component (paper unit), when identified.
    pub fitted: Option<(f64, f64)>,
    /// The fit is within 3 sigma of the hidden magnitude.
    pub within_3_sigma: Option<bool>,
    /// Systematic gap shrinkage on withheld runs when the hidden kind was identified (%,
    /// mean over the withheld runs): the part of the gap beyond the twin's spread that the
    /// fitted effect removes (`ValidationReport::systematic_shrinkage_percent`), over the
    /// withheld runs that have a systematic gap (none: `None`).
    pub shrinkage_percent: Option<f64>,
    /// RMS gap shrinkage on the same runs (%), diluted by the noise the twin already predicts.
    pub rms_shrinkage_percent: Option<f64>,
    /// The time-local grade, for a time-local hidden effect.
    pub time_local: Option<TimeLocalGrade>,
    /// The diagnosis reports a time-local event that no catalogue term explains.
    pub unexplained_event: bool,
    /// The causes the verdict names (see [`named_causes`]), each with whether it is right.
    #[serde(default)]
    pub named_causes: Vec<NamedCause>,
    /// A confident misattribution: the verdict is explained, partly explained or not
    /// separable, and every cause it names is wrong.
    #[serde(default)]
    pub confident_misattribution: bool,
}

/// One cause a verdict names: a catalogue kind, or a time course outside the catalogue (a
/// `TimeCourseAlternative` of a "not separable" verdict).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NamedCause {
    /// The kind name.
    pub kind: String,
    /// The channel of a time course (`gyro x` ... `accel z`), none for a catalogue kind.
    pub channel: Option<String>,
    /// The run(s) of a time course (a run name or `all runs`).
    pub runs: Option<String>,
    /// Right: the hidden kind itself, or, for a time-local hidden effect, a time-local cause on
    /// the same sensor (gyro or accelerometer).
    pub right: bool,
    /// A right cause on the hidden effect's own channel.
    pub right_channel: bool,
}

impl NamedCause {
    fn label(&self) -> String {
        match (&self.channel, &self.runs) {
            (Some(c), Some(r)) => format!("{} {c} ({r})", self.kind),
            (Some(c), None) => format!("{} {c}", self.kind),
            _ => self.kind.clone(),
        }
    }
}

/// The causes a verdict names, as (kind, channel, runs): `Explained { by }` and
/// `PartlyExplained { by }` one catalogue kind, `NotSeparable` its candidates and its
/// time-local alternatives; the others none.
pub fn named_causes(v: &Verdict) -> Vec<(String, Option<String>, Option<String>)> {
    match v {
        Verdict::Explained { by } | Verdict::PartlyExplained { by } => {
            vec![(by.clone(), None, None)]
        }
        Verdict::NotSeparable {
            candidates,
            time_local,
        } => candidates
            .iter()
            .map(|c| (c.clone(), None, None))
            .chain(time_local.iter().map(|t| {
                (
                    t.kind.clone(),
                    Some(t.channel.clone()),
                    Some(t.runs.clone()),
                )
            }))
            .collect(),
        Verdict::NoSignificantGap | Verdict::Unexplained => Vec::new(),
    }
}

fn sensor_name(s: Sensor) -> &'static str {
    match s {
        Sensor::Gyro => "gyro",
        Sensor::Accel => "accel",
    }
}

/// Whether a named cause is right for the hidden effect, and on its channel (see
/// [`NamedCause`]); for a null case every cause is wrong.
fn judge(
    hidden: Option<&HiddenEffect>,
    (kind, channel, runs): (String, Option<String>, Option<String>),
) -> NamedCause {
    let cause_kind = EffectKind::from_name(&kind);
    let (right, right_channel) = match hidden {
        None => (false, false),
        Some(h) => {
            let hidden_kind = EffectKind::from_name(&h.kind);
            let hidden_channel =
                hidden_kind.map(|k| format!("{} {}", sensor_name(k.sensor()), h.component_label));
            // A time course's sensor is its channel's; failing that, its kind's.
            let cause_sensor = channel
                .as_deref()
                .and_then(|c| c.split_whitespace().next())
                .map(str::to_string)
                .or_else(|| cause_kind.map(|k| sensor_name(k.sensor()).to_string()));
            let time_local_cause =
                channel.is_some() || cause_kind.is_some_and(|k| k.is_time_local());
            let same_sensor = hidden_kind
                .is_some_and(|k| cause_sensor.as_deref() == Some(sensor_name(k.sensor())));
            let right = kind == h.kind || (h.is_time_local() && time_local_cause && same_sensor);
            let on_channel = match &channel {
                Some(c) => hidden_channel.as_deref() == Some(c.as_str()),
                // A catalogue kind has no channel: the hidden kind itself is on its channel.
                None => kind == h.kind,
            };
            (right, right && on_channel)
        }
    };
    NamedCause {
        kind,
        channel,
        runs,
        right,
        right_channel,
    }
}

/// The named causes of `v` judged against `hidden`, and whether the verdict is a confident
/// misattribution (explained, partly explained or not separable, and every named cause wrong).
pub fn misattribution(hidden: Option<&HiddenEffect>, v: &Verdict) -> (Vec<NamedCause>, bool) {
    let causes: Vec<NamedCause> = named_causes(v)
        .into_iter()
        .map(|c| judge(hidden, c))
        .collect();
    let confident = matches!(
        v,
        Verdict::Explained { .. } | Verdict::PartlyExplained { .. } | Verdict::NotSeparable { .. }
    );
    let wrong = confident && !causes.is_empty() && causes.iter().all(|c| !c.right);
    (causes, wrong)
}

/// The sections of a suite, in report order (see [`CaseAnswer::section`]).
pub const SECTIONS: [&str; 6] = [
    "null",
    "in-catalogue",
    "out-of-catalogue",
    "time-local",
    "wide time-local",
    "different histories",
];

/// The suite's grades.
#[derive(Clone, Debug, Serialize)]
pub struct Grades {
    /// Every case.
    pub cases: Vec<CaseGrade>,
    /// Top-1 hits / in-catalogue cases above the detectable level.
    pub top1: (usize, usize),
    /// Null cases with a reported effect or gap / null cases.
    pub false_alarms: (usize, usize),
    /// Out-of-catalogue cases reported as unexplained (or only partly explained) / such cases.
    pub out_of_catalogue_unexplained: (usize, usize),
    /// The same over the out-of-catalogue cases that left a significant gap (those reported
    /// `none` left nothing to explain at their magnitude, as in-catalogue cases below the
    /// detectable level).
    pub out_of_catalogue_unexplained_with_gap: (usize, usize),
    /// Identified cases with the fit within 3 sigma / identified cases with a sigma.
    pub magnitudes_within_3_sigma: (usize, usize),
    /// Median systematic gap shrinkage on withheld runs over the correctly identified cases (%).
    pub median_shrinkage_percent: Option<f64>,
    /// Median RMS gap shrinkage over the same cases (%).
    pub median_rms_shrinkage_percent: Option<f64>,
    /// Rows: hidden kind (`none` for null cases); columns: outcome; counts.
    pub confusion: BTreeMap<String, BTreeMap<String, usize>>,
    /// Detectable level per kind (paper unit): the median over the cases of that kind.
    pub detectable_by_kind: BTreeMap<String, f64>,
    /// Time-local cases above their detectable level reported with the onset within 3 sigma and
    /// their channel named (the event's own or an indistinguishable alternative) / such cases.
    pub time_local_found: (usize, usize),
    /// The same with the channel the event's own.
    pub time_local_found_on_channel: (usize, usize),
    /// Null cases with a time-local event outside the catalogue / null cases.
    pub time_local_false_alarms: (usize, usize),
    /// The same as [`Self::time_local_found`] over the widened draw's cases in navigation runs
    /// (those of the calibration run only have no onset to locate).
    #[serde(default)]
    pub wide_time_local_found: (usize, usize),
    /// The same with the channel the event's own.
    #[serde(default)]
    pub wide_time_local_found_on_channel: (usize, usize),
    /// Confident misattributions / cases graded.
    #[serde(default)]
    pub confident_misattributions: (usize, usize),
    /// The same per section (`null`, `in-catalogue`, `out-of-catalogue`, `time-local`,
    /// `wide time-local`, `different histories`; only those with cases).
    #[serde(default)]
    pub misattributions_by_section: BTreeMap<String, (usize, usize)>,
    /// The cases with a confident misattribution.
    #[serde(default)]
    pub misattributed_cases: Vec<String>,
}

fn outcome_of(v: &Verdict) -> (String, Option<String>) {
    match v {
        Verdict::NoSignificantGap => ("none".into(), None),
        Verdict::Explained { by } => (by.clone(), Some(by.clone())),
        Verdict::PartlyExplained { by } => (format!("partly: {by}"), Some(by.clone())),
        Verdict::Unexplained => ("unexplained".into(), None),
        Verdict::NotSeparable {
            candidates,
            time_local,
        } => (
            format!(
                "not separable: {}",
                candidates
                    .iter()
                    .cloned()
                    .chain(
                        time_local
                            .iter()
                            .map(|t| format!("{} {} ({})", t.kind, t.channel, t.runs))
                    )
                    .collect::<Vec<_>>()
                    .join(" / ")
            ),
            candidates.first().cloned(),
        ),
    }
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

/// Grade each case's diagnosis against its answer.
pub fn grade(cases: &[(CaseAnswer, Diagnosis)]) -> Grades {
    let mut out = Vec::new();
    for (a, d) in cases {
        let (outcome, identified) = outcome_of(&d.verdict);
        let hidden = a.hidden.as_ref();
        let cand = hidden.and_then(|h| d.candidates.iter().find(|c| c.kind == h.kind));
        let comp = hidden
            .zip(cand)
            .and_then(|(h, c)| c.components.get(h.component));
        let detectable = comp.and_then(|c| c.detectable);
        let above_detectable = match (hidden, detectable) {
            (Some(h), Some(level)) => h.magnitude.abs() > level,
            _ => true,
        };
        let right = hidden.is_some_and(|h| identified.as_deref() == Some(h.kind.as_str()));
        let fitted = comp
            .filter(|_| right)
            .and_then(|c| c.sigma.map(|s| (c.value, s)));
        let within_3_sigma = fitted
            .zip(hidden)
            .map(|((v, s), h)| (v - h.magnitude).abs() <= 3.0 * s);
        // Shrinkage counts where the diagnosis named the hidden effect (what was added to the
        // model is then the effect that is really there).
        let named: Vec<&sins_diag::report::ValidationReport> = d
            .validation
            .iter()
            .filter(|v| right && identified.as_deref() == Some(v.kind.as_str()))
            .collect();
        let mean =
            |f: &dyn Fn(&sins_diag::report::ValidationReport) -> f64,
             over: &dyn Fn(&sins_diag::report::ValidationReport) -> bool| {
                let v: Vec<f64> = named.iter().filter(|v| over(v)).map(|v| f(v)).collect();
                (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
            };
        out.push(CaseGrade {
            answer: a.clone(),
            outcome,
            identified,
            detectable,
            above_detectable,
            fitted,
            within_3_sigma,
            // A withheld run without a systematic gap has nothing to shrink (0/0).
            shrinkage_percent: mean(&|v| v.systematic_shrinkage_percent, &|v| {
                v.systematic_before > 0.0
            }),
            rms_shrinkage_percent: mean(&|v| v.rms_shrinkage_percent, &|_| true),
            time_local: time_local::grade_case(a, d),
            unexplained_event: time_local::has_unexplained_event(d),
            named_causes: Vec::new(),
            confident_misattribution: false,
        });
        let (causes, wrong) = misattribution(hidden, &d.verdict);
        if let Some(g) = out.last_mut() {
            g.named_causes = causes;
            g.confident_misattribution = wrong;
        }
    }
    let inside = |g: &&CaseGrade| g.answer.hidden.as_ref().is_some_and(|h| h.in_catalogue);
    let scored: Vec<&CaseGrade> = out
        .iter()
        .filter(inside)
        .filter(|g| g.above_detectable)
        .collect();
    let hits = scored
        .iter()
        .filter(|g| g.answer.hidden.as_ref().map(|h| h.kind.as_str()) == g.identified.as_deref())
        .count();
    let nulls: Vec<&CaseGrade> = out.iter().filter(|g| g.answer.hidden.is_none()).collect();
    let alarms = nulls.iter().filter(|g| g.outcome != "none").count();
    // The cases drawn in the time-local section have their own figures.
    let ooc: Vec<&CaseGrade> = out
        .iter()
        .filter(|g| {
            g.answer
                .hidden
                .as_ref()
                .is_some_and(|h| !h.in_catalogue && !h.drawn_time_local())
        })
        .collect();
    // The original time-local figures over the cases of the original draws; the widened
    // draw's own figures over its cases in navigation runs.
    let located = |wide: bool| {
        let tl: Vec<&TimeLocalGrade> = out
            .iter()
            .filter(|g| g.answer.hidden.as_ref().is_some_and(|h| h.drawn_wide()) == wide)
            .filter_map(|g| g.time_local.as_ref())
            .filter(|t| t.above_detectable && t.onset_graded)
            .collect();
        (
            (
                tl.iter().filter(|t| t.onset_within_3_sigma).count(),
                tl.len(),
            ),
            (
                tl.iter()
                    .filter(|t| t.onset_within_3_sigma && !t.as_alternative)
                    .count(),
                tl.len(),
            ),
        )
    };
    let (time_local_found, time_local_found_on_channel) = located(false);
    let (wide_time_local_found, wide_time_local_found_on_channel) = located(true);
    let mut misattributions_by_section: BTreeMap<String, (usize, usize)> = BTreeMap::new();
    for g in &out {
        let e = misattributions_by_section
            .entry(g.answer.section().to_string())
            .or_default();
        e.0 += usize::from(g.confident_misattribution);
        e.1 += 1;
    }
    let misattributed_cases: Vec<String> = out
        .iter()
        .filter(|g| g.confident_misattribution)
        .map(|g| g.answer.case.clone())
        .collect();
    let time_local_false_alarms = (
        nulls.iter().filter(|g| g.unexplained_event).count(),
        nulls.len(),
    );
    let unexplained = ooc
        .iter()
        .filter(|g| g.outcome == "unexplained" || g.outcome.starts_with("partly"))
        .count();
    let checked: Vec<bool> = out.iter().filter_map(|g| g.within_3_sigma).collect();
    let mut confusion: BTreeMap<String, BTreeMap<String, usize>> = BTreeMap::new();
    let mut levels: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for g in &out {
        let row = g
            .answer
            .hidden
            .as_ref()
            .map_or("none".to_string(), |h| h.kind.clone());
        *confusion
            .entry(row.clone())
            .or_default()
            .entry(g.outcome.clone())
            .or_default() += 1;
        if let Some(l) = g.detectable {
            levels.entry(row).or_default().push(l);
        }
    }
    Grades {
        top1: (hits, scored.len()),
        false_alarms: (alarms, nulls.len()),
        out_of_catalogue_unexplained: (unexplained, ooc.len()),
        out_of_catalogue_unexplained_with_gap: (
            unexplained,
            ooc.iter().filter(|g| g.outcome != "none").count(),
        ),
        magnitudes_within_3_sigma: (checked.iter().filter(|&&b| b).count(), checked.len()),
        median_shrinkage_percent: median(out.iter().filter_map(|g| g.shrinkage_percent).collect()),
        median_rms_shrinkage_percent: median(
            out.iter().filter_map(|g| g.rms_shrinkage_percent).collect(),
        ),
        detectable_by_kind: levels
            .into_iter()
            .filter_map(|(k, v)| median(v).map(|m| (k, m)))
            .collect(),
        confusion,
        time_local_found,
        time_local_found_on_channel,
        time_local_false_alarms,
        wide_time_local_found,
        wide_time_local_found_on_channel,
        confident_misattributions: (misattributed_cases.len(), out.len()),
        misattributions_by_section,
        misattributed_cases,
        cases: out,
    }
}

/// The confident misattributions as Markdown: the figure overall and per section, and the
/// cases.
fn render_misattributions(g: &Grades) -> String {
    let mut md = String::from(
        "\n## Confident misattributions\n\nA verdict of explained, partly explained or not \
         separable that names only wrong causes. A named cause is right when it is the hidden \
         kind, or, for a hidden effect local in time, a time-local cause on the same sensor \
         (gyro or accelerometer); for a null case every named cause is wrong. Unexplained and \
         no significant gap are never misattributions.\n\n",
    );
    let mut t = Table::new(["section", "confident misattributions", "target"]);
    t.row([
        "all cases".to_string(),
        frac(g.confident_misattributions),
        "0".to_string(),
    ]);
    for s in SECTIONS {
        if let Some(&c) = g.misattributions_by_section.get(s) {
            t.row([s.to_string(), frac(c), "0".to_string()]);
        }
    }
    let _ = writeln!(md, "{t}");
    let wrong: Vec<&CaseGrade> = g
        .cases
        .iter()
        .filter(|c| c.confident_misattribution)
        .collect();
    if !wrong.is_empty() {
        let mut t = Table::new(["case", "section", "hidden", "verdict", "named causes"]);
        for c in wrong {
            t.row([
                c.answer.case.clone(),
                c.answer.section().to_string(),
                c.answer.hidden.as_ref().map_or("none".into(), |h| {
                    format!("{} {}", h.kind, h.component_label)
                }),
                c.outcome.clone(),
                c.named_causes
                    .iter()
                    .map(NamedCause::label)
                    .collect::<Vec<_>>()
                    .join(", "),
            ]);
        }
        let _ = writeln!(md, "{t}");
    }
    let right_channel: Vec<&str> = g
        .cases
        .iter()
        .filter(|c| {
            c.named_causes
                .iter()
                .any(|n| n.right_channel && n.channel.is_some())
        })
        .map(|c| c.answer.case.as_str())
        .collect();
    if !right_channel.is_empty() {
        let _ = writeln!(
            md,
            "Verdicts naming a time course on the hidden effect's own channel: {}.\n",
            right_channel.join(", ")
        );
    }
    md
}

fn frac((k, n): (usize, usize)) -> String {
    if n == 0 {
        "- (no case)".into()
    } else {
        format!("{k} / {n} ({:.0} %)", 100.0 * k as f64 / n as f64)
    }
}

/// The grades as Markdown: the targets of the issue, the confusion table and every case.
pub fn render_grades(g: &Grades, suite_sha256: &str) -> String {
    let mut md = String::from("# Blind validation of the gap diagnosis\n\n");
    let _ = writeln!(
        md,
        "Manifests sealed before the diagnoses ran: suite SHA-256 `{suite_sha256}`; every manifest matched its sealed hash when opened.\n"
    );
    let mut t = Table::new(["figure", "result", "target"]);
    for (figure, counts, target) in [
        (
            "top-1 identification, in-catalogue cases above the detectable level",
            g.top1,
            "≥ 90 %",
        ),
        ("false alarms on null cases", g.false_alarms, "≤ 1 in 5"),
        (
            "out-of-catalogue cases reported unexplained",
            g.out_of_catalogue_unexplained,
            "≥ 2 in 3",
        ),
        (
            "... of those that left a significant gap",
            g.out_of_catalogue_unexplained_with_gap,
            "≥ 2 in 3",
        ),
        (
            "fitted magnitudes within 3 sigma of the hidden truth",
            g.magnitudes_within_3_sigma,
            "all",
        ),
        (
            "confident misattributions (a verdict that names only wrong causes)",
            g.confident_misattributions,
            "0",
        ),
    ] {
        t.row([figure.to_string(), frac(counts), target.to_string()]);
    }
    let percent = |v: Option<f64>| v.map_or("-".into(), |v| format!("{v:.0} %"));
    t.row([
        "median gap shrinkage on withheld runs, systematic (RMS)".to_string(),
        format!(
            "{} ({})",
            percent(g.median_shrinkage_percent),
            percent(g.median_rms_shrinkage_percent)
        ),
        "≥ 80 %".to_string(),
    ]);
    let _ = writeln!(md, "{t}");
    let _ = writeln!(
        md,
        "Shrinkage is counted where the hidden effect was named. The systematic gap is \
         √max(0, χ² − E χ²) of the withheld run in the twin's metric: the gap beyond what the \
         twin's noise and calibration uncertainty give on average. The RMS gap also carries \
         that noise, which no model of the effect can remove.\n"
    );
    let cols: Vec<String> = {
        let mut c: Vec<String> = g
            .confusion
            .values()
            .flat_map(|r| r.keys().cloned())
            .collect();
        c.sort();
        c.dedup();
        c
    };
    let _ = writeln!(
        md,
        "## Confusion table (rows: hidden effect; columns: diagnosis)\n"
    );
    let mut t =
        Table::new(std::iter::once("hidden \\ reported").chain(cols.iter().map(String::as_str)));
    for (row, counts) in &g.confusion {
        let cells = cols
            .iter()
            .map(|c| counts.get(c).map_or(String::new(), |n| n.to_string()));
        t.row(std::iter::once(row.clone()).chain(cells));
    }
    md.push_str(&t.render());
    let mut t = Table::new(["effect", "detectable magnitude"]);
    for (k, v) in &g.detectable_by_kind {
        t.row([k.clone(), format!("{v:.3e}")]);
    }
    let _ = write!(
        md,
        "\n## Detectable level per effect (median over its cases, paper unit)\n\n{t}"
    );
    let mut t = Table::new([
        "case",
        "hidden",
        "magnitude (× typical)",
        "detectable",
        "diagnosis",
        "fitted ± 1σ",
        "within 3σ",
        "shrinkage, systematic (RMS)",
    ]);
    for c in &g.cases {
        let (hidden, mag) = match &c.answer.hidden {
            Some(h) => (
                format!(
                    "{} {}{}",
                    h.kind,
                    h.component_label,
                    if h.in_catalogue { "" } else { " (outside)" }
                ),
                format!("{:.3e} {} ({:.1}×)", h.magnitude, h.unit, h.times_typical),
            ),
            None => ("none".into(), "-".into()),
        };
        t.row([
            c.answer.case.clone(),
            hidden,
            mag,
            c.detectable.map_or("-".into(), |v| format!("{v:.2e}")),
            c.outcome.clone(),
            c.fitted
                .map_or("-".into(), |(v, s)| format!("{v:.3e} ± {s:.1e}")),
            c.within_3_sigma
                .map_or("-", |b| if b { "yes" } else { "no" })
                .to_string(),
            match (c.shrinkage_percent, c.rms_shrinkage_percent) {
                (Some(s), Some(r)) => format!("{s:.0} % ({r:.0} %)"),
                _ => "-".into(),
            },
        ]);
    }
    let _ = write!(md, "\n## Cases\n\n{t}");
    let rows: Vec<(&CaseAnswer, &TimeLocalGrade)> = g
        .cases
        .iter()
        .filter_map(|c| c.time_local.as_ref().map(|t| (&c.answer, t)))
        .collect();
    if !rows.is_empty() || g.time_local_false_alarms.1 > 0 {
        let wide = g
            .cases
            .iter()
            .any(|c| c.answer.hidden.as_ref().is_some_and(|h| h.drawn_wide()))
            .then_some((g.wide_time_local_found, g.wide_time_local_found_on_channel));
        md.push_str(&time_local::render(
            &rows,
            g.time_local_found,
            g.time_local_found_on_channel,
            g.time_local_false_alarms,
            wide,
            frac,
        ));
    }
    md.push_str(&render_misattributions(g));
    md
}

#[cfg(test)]
#[path = "grade_tests.rs"]
mod tests;
