//! The rival and confound sections of the diagnosis report: the time courses outside the
//! catalogue a verdict was tested against, and how much of each temperature-driven
//! candidate's information a time course common to every run takes away.

use sins_config::markdown::Table;
use sins_diag::report::{Diagnosis, Verdict};
use sins_diag::{Confound, TimeCourseAlternative};
use std::fmt::Write as _;

/// The rivals a verdict cites (empty when it cites none).
pub fn render_rivals(rivals: &[TimeCourseAlternative]) -> String {
    if rivals.is_empty() {
        return String::new();
    }
    let mut md = String::from(
        "\n### Time courses outside the catalogue\n\nThe gap of the twin alone was also fitted \
         with steps, ramps, transients and oscillations on any channel, in one run or common \
         to every run. These explain it in place of the catalogue (verdict: unexplained) or as \
         well as it (not separable):\n\n",
    );
    let mut t = Table::new([
        "channel",
        "runs",
        "shape",
        "onset (s)",
        "τ or period (s)",
        "size",
        "χ² drop",
    ]);
    for r in rivals {
        t.row([
            r.channel.clone(),
            r.runs.clone(),
            r.shape.clone(),
            format!("{:.0}", r.onset_s),
            r.time_s.map_or("-".into(), |t| format!("{t:.0}")),
            format!("{:.3e} {}", r.size, r.unit),
            format!("{:.1}", r.dchi2),
        ]);
    }
    md.push_str(&t.render());
    md
}

/// The suggested extra run for the most confounded candidate, if any loses half its
/// information.
fn suggestion(c: &[Confound]) -> Option<String> {
    let worst = c
        .iter()
        .max_by(|a, b| a.information_lost.total_cmp(&b.information_lost))?;
    if worst.information_lost < 0.5 {
        return None;
    }
    let (name, with) = if worst.with_held_run <= worst.with_reversed_run {
        (
            "a run with the chamber held at one temperature",
            worst.with_held_run,
        )
    } else {
        (
            "a run with the temperature excursion reversed (warming where these runs cool)",
            worst.with_reversed_run,
        )
    };
    Some(format!(
        "**Suggested experiment**: `{}` loses {:.0} % of its information to a common time \
         course with these runs; {name}, otherwise like `{}`, would cut that to {:.0} %.",
        worst.kind,
        100.0 * worst.information_lost,
        worst.like_run,
        100.0 * with
    ))
}

/// A line under the verdict when a cause it names is confounded with a common time course
/// (half its information lost or more).
pub fn confound_line(d: &Diagnosis) -> Option<String> {
    let causes: Vec<&String> = match &d.verdict {
        Verdict::Explained { by } | Verdict::PartlyExplained { by } => vec![by],
        Verdict::NotSeparable { candidates, .. } => candidates.iter().collect(),
        _ => Vec::new(),
    };
    let c = d
        .confound
        .iter()
        .filter(|c| causes.contains(&&c.kind) && c.information_lost >= 0.5)
        .max_by(|a, b| a.information_lost.total_cmp(&b.information_lost))?;
    Some(format!(
        "**A limit of these data**: with these runs' temperature histories, `{}` loses {:.0} % \
         of its information to a bias time course common to every run; the verdict rests on \
         the rest (see \"Confounds of this design\").",
        c.kind,
        100.0 * c.information_lost
    ))
}

/// The confound table and the experiment it suggests.
pub fn render_confound(d: &Diagnosis) -> String {
    if d.confound.is_empty() {
        return String::new();
    }
    let mut md = String::from(
        "\n### Confounds of this design\n\nA limit of the data, not of the IMU: the share of \
         each temperature-driven candidate's Fisher information that a bias time course \
         common to every run (piecewise linear, knots every hour, any channel) takes away. \
         Near 100 %, the runs' temperature histories cannot tell the candidate from an effect \
         that merely follows the time since turn-on. The last two columns add one run like \
         the longest, with the chamber held or the excursion reversed (first order).\n\n",
    );
    let mut t = Table::new([
        "candidate",
        "information lost",
        "worst component",
        "with a held run",
        "with a reversed run",
    ]);
    for c in &d.confound {
        t.row([
            format!("`{}`", c.kind),
            format!("{:.0} %", 100.0 * c.information_lost),
            format!(
                "{} ({:.0} %)",
                c.worst_component,
                100.0 * c.worst_component_lost
            ),
            format!("{:.0} %", 100.0 * c.with_held_run),
            format!("{:.0} %", 100.0 * c.with_reversed_run),
        ]);
    }
    md.push_str(&t.render());
    if let Some(s) = suggestion(&d.confound) {
        let _ = writeln!(md, "\n{s}");
    }
    md
}
