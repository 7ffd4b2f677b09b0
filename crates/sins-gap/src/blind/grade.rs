//! Grading the blind diagnoses against the opened manifests.

use super::plan::CaseAnswer;
use serde::Serialize;
use sins_diag::report::{Diagnosis, Verdict};
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
    /// RMS gap shrinkage on withheld runs for the identified kind (%).
    pub shrinkage_percent: Option<f64>,
}

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
    /// Identified cases with the fit within 3 sigma / identified cases with a sigma.
    pub magnitudes_within_3_sigma: (usize, usize),
    /// Median RMS gap shrinkage on withheld runs over the identified cases (%).
    pub median_shrinkage_percent: Option<f64>,
    /// Rows: hidden kind (`none` for null cases); columns: outcome; counts.
    pub confusion: BTreeMap<String, BTreeMap<String, usize>>,
    /// Detectable level per kind (paper unit): the median over the cases of that kind.
    pub detectable_by_kind: BTreeMap<String, f64>,
}

fn outcome_of(v: &Verdict) -> (String, Option<String>) {
    match v {
        Verdict::NoSignificantGap => ("none".into(), None),
        Verdict::Explained { by } => (by.clone(), Some(by.clone())),
        Verdict::PartlyExplained { by } => (format!("partly: {by}"), Some(by.clone())),
        Verdict::Unexplained => ("unexplained".into(), None),
        Verdict::NotSeparable { candidates } => (
            format!("not separable: {}", candidates.join(" / ")),
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
        let shrink: Vec<f64> = d
            .validation
            .iter()
            .filter(|v| identified.as_deref() == Some(v.kind.as_str()))
            .map(|v| v.rms_shrinkage_percent)
            .collect();
        out.push(CaseGrade {
            answer: a.clone(),
            outcome,
            identified,
            detectable,
            above_detectable,
            fitted,
            within_3_sigma,
            shrinkage_percent: (!shrink.is_empty())
                .then(|| shrink.iter().sum::<f64>() / shrink.len() as f64),
        });
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
    let ooc: Vec<&CaseGrade> = out
        .iter()
        .filter(|g| g.answer.hidden.as_ref().is_some_and(|h| !h.in_catalogue))
        .collect();
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
        magnitudes_within_3_sigma: (checked.iter().filter(|&&b| b).count(), checked.len()),
        median_shrinkage_percent: median(out.iter().filter_map(|g| g.shrinkage_percent).collect()),
        detectable_by_kind: levels
            .into_iter()
            .filter_map(|(k, v)| median(v).map(|m| (k, m)))
            .collect(),
        confusion,
        cases: out,
    }
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
    let _ = writeln!(md, "| figure | result | target |\n|---|---|---|");
    let _ = writeln!(
        md,
        "| top-1 identification, in-catalogue cases above the detectable level | {} | ≥ 90 % |",
        frac(g.top1)
    );
    let _ = writeln!(
        md,
        "| false alarms on null cases | {} | ≤ 1 in 5 |",
        frac(g.false_alarms)
    );
    let _ = writeln!(
        md,
        "| out-of-catalogue cases reported unexplained | {} | ≥ 2 in 3 |",
        frac(g.out_of_catalogue_unexplained)
    );
    let _ = writeln!(
        md,
        "| fitted magnitudes within 3 sigma of the hidden truth | {} | all |",
        frac(g.magnitudes_within_3_sigma)
    );
    let _ = writeln!(
        md,
        "| median RMS gap shrinkage on withheld runs | {} | ≥ 80 % |\n",
        g.median_shrinkage_percent
            .map_or("-".into(), |v| format!("{v:.0} %"))
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
    let _ = writeln!(md, "| hidden \\ reported | {} |", cols.join(" | "));
    let _ = writeln!(md, "|---|{}", "---|".repeat(cols.len()));
    for (row, counts) in &g.confusion {
        let cells: Vec<String> = cols
            .iter()
            .map(|c| counts.get(c).map_or(String::new(), |n| n.to_string()))
            .collect();
        let _ = writeln!(md, "| {row} | {} |", cells.join(" | "));
    }
    let _ = writeln!(
        md,
        "\n## Detectable level per effect (median over its cases, paper unit)\n\n| effect | detectable magnitude |\n|---|---|"
    );
    for (k, v) in &g.detectable_by_kind {
        let _ = writeln!(md, "| {k} | {v:.3e} |");
    }
    let _ = writeln!(
        md,
        "\n## Cases\n\n| case | hidden | magnitude (× typical) | detectable | diagnosis | fitted ± 1σ | within 3σ | shrinkage |\n|---|---|---|---|---|---|---|---|"
    );
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
        let _ = writeln!(
            md,
            "| {} | {hidden} | {mag} | {} | {} | {} | {} | {} |",
            c.answer.case,
            c.detectable.map_or("-".into(), |v| format!("{v:.2e}")),
            c.outcome,
            c.fitted
                .map_or("-".into(), |(v, s)| format!("{v:.3e} ± {s:.1e}")),
            c.within_3_sigma
                .map_or("-", |b| if b { "yes" } else { "no" }),
            c.shrinkage_percent
                .map_or("-".into(), |v| format!("{v:.0} %"))
        );
    }
    md
}
