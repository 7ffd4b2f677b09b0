//! `report.md` of a UQ study: Table 5 as a prediction with the V&V 20 verdict per cell, the
//! global sensitivity, Table 2 against the replica's spread, the gap diagnosis and the declared
//! assumptions.

use sins_config::markdown::Table;
use sins_uq::summary::UqSummary;
use std::fmt::Write as _;

/// The Markdown report of `s`.
pub fn render_uq_markdown(s: &UqSummary) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "# The replica of Table 5 as a validated prediction\n");
    let _ = writeln!(
        o,
        "Monte Carlo of the replica over its declared assumptions and sensor-noise seeds: {} samples, seed {}. \
         S = the Monte Carlo median; D = the paper's real measurement; u_input = the standard deviation over the Monte Carlo; \
         u_num = the bootstrap error of the median and the replay's error-free floor (0.3 m); u_D = the standard deviation of \
         the paper's three experiments in the same column. Verdict (ASME V&V 20): the model-error interval delta_model = E ± 2 u_val; *validated* only when it contains 0 and \
         2 u_val < |D| (the comparison could see a model error the size of the paper's figure), *not informative* when 2 u_val >= |D|, \
         *model error* when |E| > 2 u_val.\n",
        s.samples, s.seed
    );
    o.push_str(&uq_table_for_report(s));
    let _ = writeln!(
        o,
        "\nBootstrap standard errors of the quantiles (5 % / 50 % / 95 %):\n"
    );
    let mut t = Table::new([
        "cell",
        "se 5 %",
        "se median",
        "se 95 %",
        "u_input",
        "u_num",
        "u_D",
    ]);
    for c in &s.cells {
        let (ui, un, ud) = c
            .validation
            .as_ref()
            .map_or((f64::NAN, f64::NAN, f64::NAN), |v| {
                (v.u_input, v.u_num, v.u_d)
            });
        let [a, b, d] = c.bootstrap_se;
        t.row([
            c.cell.clone(),
            format!("{a:.3}"),
            format!("{b:.3}"),
            format!("{d:.3}"),
            format!("{ui:.3}"),
            format!("{un:.4}"),
            format!("{ud:.3}"),
        ]);
    }
    o.push_str(&t.render());
    by_level(&mut o, s);
    sensitivity(&mut o, s);
    table2(&mut o, s);
    gap(&mut o, s);
    let mut t = Table::new(["assumption", "group", "distribution", "justification"]);
    for a in &s.assumptions {
        t.row([
            a.name.clone(),
            a.group.clone(),
            a.distribution.clone(),
            a.justification.replace('|', "/"),
        ]);
    }
    o.push_str("\n## Declared assumptions\n\n");
    o.push_str(&t.render());
    o
}

/// The cells split by the levels of their dominant choice assumption.
fn by_level(o: &mut String, s: &UqSummary) {
    if s.cells.iter().all(|c| c.by_level.is_empty()) {
        return;
    }
    let _ = writeln!(
        o,
        "\nWhere one choice assumption dominates a cell (discovered, first-order index >= {}), the cell is bimodal and its \
         median lies between the modes (hence the large bootstrap error above); per level, with the V&V 20 comparison of \
         that level alone (a bimodal cell's u_input spans both modes, so only a level's comparison can be informative):\n",
        sins_uq::summary::DOMINANT_INDEX
    );
    let mut t = Table::new([
        "cell",
        "assumption = level",
        "samples",
        "median (se)",
        "5-95 %",
        "E",
        "u_val",
        "V&V 20",
    ]);
    for c in &s.cells {
        for l in &c.by_level {
            t.row([
                c.cell.clone(),
                format!("{} = {}", l.assumption, l.level),
                l.samples.to_string(),
                format!("{:.2} ({:.2})", l.median, l.median_se),
                format!("{:.2} - {:.2}", l.p05, l.p95),
                l.validation
                    .as_ref()
                    .map_or_else(|| "-".into(), |v| format!("{:.2}", v.e)),
                l.validation
                    .as_ref()
                    .map_or_else(|| "-".into(), |v| format!("{:.2}", v.u_val)),
                l.validation
                    .as_ref()
                    .map_or_else(|| "-".into(), |v| v.verdict()),
            ]);
        }
    }
    o.push_str(&t.render());
}

fn sensitivity(o: &mut String, s: &UqSummary) {
    let _ = writeln!(
        o,
        "\n## Global sensitivity\n\nFirst-order Sobol index of every assumption that varies, estimated from the full runs \
         themselves (given data, no surrogate: the bias-corrected correlation ratio of the cell, in log error or improvement, \
         on the assumption binned into about sqrt(N) bins, a choice by level), with 90 % bootstrap intervals. With \
         independent inputs 1 - sum(first order) bounds the share of interactions, vibration phases and sensor-noise seeds. \
         p is a permutation p-value ({} reorderings) against \"the cell does not depend on it\": the bootstrap interval \
         alone is not a test, since a bimodal cell inflates the binned index's null spread; with about 50 assumptions \
         per cell about 2.5 reach p <= 0.05 by chance, so only those marked * are influential (Benjamini-Hochberg, \
         false-discovery rate {}). A sum above 1 is the noise of the unmarked ones.\n",
        sins_uq::summary::PERMUTATIONS,
        sins_uq::summary::FDR
    );
    let mut t = Table::new([
        "cell",
        "sum of first order",
        "leading assumptions: index [5 %, 95 %] p",
    ]);
    for c in &s.cells {
        let Some(sens) = &c.sensitivity else { continue };
        let top: Vec<String> = sens
            .inputs
            .iter()
            .take(4)
            .map(|g| {
                format!(
                    "{}{} {:.2} [{:.2}, {:.2}] p {:.3}",
                    g.name,
                    if g.discovered { "*" } else { "" },
                    g.first_order,
                    g.low,
                    g.high,
                    g.p_value
                )
            })
            .collect();
        t.row([
            c.cell.clone(),
            format!("{:.2}", sens.sum_first_order),
            top.join("; "),
        ]);
    }
    o.push_str(&t.render());
    group_indices(o, s);
}

/// The pick-freeze table: per cell and group, first-order and total index with intervals.
fn group_indices(o: &mut String, s: &UqSummary) {
    if s.pick_freeze_samples == 0 {
        let _ = writeln!(
            o,
            "\nGrouped first-order and total indices: not run (`pick_freeze_samples = 0`; `--pick-freeze N` adds \
             (groups + 1) N samples).\n"
        );
        return;
    }
    let _ = writeln!(
        o,
        "\n### Grouped first-order and total indices (pick-freeze, {} rows)\n\nSaltelli (2010) first-order and Jansen \
         total index of each group of assumptions (and of the sensor-noise realisation), with 90 % bootstrap intervals over \
         the rows. Total minus first order is the group's share in interactions; a first-order index below 0 or a wide \
         interval says the design is too small for that group.\n",
        s.pick_freeze_samples
    );
    let mut t = Table::new([
        "cell",
        "group",
        "first order [5 %, 95 %]",
        "total [5 %, 95 %]",
    ]);
    let interval = |v: [f64; 3]| format!("{:.2} [{:.2}, {:.2}]", v[0], v[1], v[2]);
    for c in &s.cells {
        let Some(sens) = &c.sensitivity else { continue };
        for g in &sens.groups {
            t.row([
                c.cell.clone(),
                g.group.clone(),
                interval(g.first_order),
                interval(g.total),
            ]);
        }
    }
    o.push_str(&t.render());
}

fn table2(o: &mut String, s: &UqSummary) {
    let _ = writeln!(
        o,
        "\n## Table 2: repeatability of the calibration\n\nThe paper's STD over three real calibrations against the replica's spread of the \
         42-state estimate minus the truth over the main Monte Carlo (the same IMU class, noise and assumptions drawn).\n"
    );
    let mut t = Table::new([
        "parameters",
        "unit",
        "paper STD",
        "replica STD",
        "replica / paper",
    ]);
    for r in &s.table2 {
        let f = |v: &[f64]| {
            v.iter()
                .map(|x| format!("{}", sig3(*x)))
                .collect::<Vec<_>>()
                .join("/")
        };
        let ratio: Vec<String> = r
            .paper
            .iter()
            .zip(&r.replica)
            .map(|(p, q)| {
                if *p > 0.0 {
                    format!("{:.2}", q / p)
                } else {
                    "-".into()
                }
            })
            .collect();
        t.row([
            r.name.clone(),
            r.unit.clone(),
            f(&r.paper),
            f(&r.replica),
            ratio.join("/"),
        ]);
    }
    o.push_str(&t.render());
}

fn sig3(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let scale = 10f64.powi(2 - v.abs().log10().floor() as i32);
    (v * scale).round() / scale
}

fn gap(o: &mut String, s: &UqSummary) {
    let Some(g) = &s.gap else { return };
    let _ = writeln!(
        o,
        "\n## The replica-vs-paper gap diagnosed\n\nEach candidate is the replica with some assumptions fixed or an extra effect drawn \
         at a physically plausible size, run as its own Monte Carlo. Its evidence is the log predictive density of the paper's \
         cells (normal in log error / improvement, the candidate's spread plus the paper's scatter). Chosen on: {}; evaluated on \
         the withheld cells and on Table 2.\n",
        g.choose_on.join(", ")
    );
    let cells: Vec<&str> = s.cells.iter().map(|c| c.cell.as_str()).collect();
    let mut t = Table::new([
        "candidate".to_string(),
        "samples".to_string(),
        "ln p (choice)".to_string(),
        "ln p (withheld)".to_string(),
        "ln p (Table 2)".to_string(),
        format!("medians: {}", cells.join(" / ")),
    ]);
    for c in &g.candidates {
        let med: Vec<String> = c.median.iter().map(|m| format!("{m:.2}")).collect();
        t.row([
            c.name.clone(),
            c.samples.to_string(),
            format!("{:.2}", c.log_lik_choice),
            format!("{:.2}", c.log_lik_withheld),
            format!("{:.1}", c.log_lik_table2),
            med.join(" / "),
        ]);
    }
    o.push_str(&t.render());
    let _ = writeln!(
        o,
        "\n**Chosen: {}** (rank {} of {} on the withheld cells). Median shrinkage of the gap on the withheld cells: {:.0} %.\n",
        g.chosen,
        g.chosen_rank_withheld,
        g.candidates.len(),
        g.median_shrinkage_percent
    );
    let mut t = Table::new([
        "withheld cell".to_string(),
        "paper".to_string(),
        format!(
            "baseline ({})",
            g.candidates.first().map_or("", |c| c.name.as_str())
        ),
        format!("corrected ({})", g.chosen),
        "shrinkage".to_string(),
    ]);
    for w in &g.withheld {
        t.row([
            w.cell.clone(),
            format!("{:.2}", w.paper),
            format!("{:.2}", w.baseline),
            format!("{:.2}", w.corrected),
            format!("{:.0} %", w.shrinkage_percent),
        ]);
    }
    o.push_str(&t.render());
}

/// A short text of the per-cell interval and verdict for `report.md` (used by `report --uq`).
pub fn uq_table_for_report(s: &UqSummary) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "## Table 5 as a prediction (replica-uq, {} samples, seed {})\n",
        s.samples, s.seed
    );
    let mut t = Table::new([
        "cell",
        "point",
        "median",
        "5-95 %",
        "paper",
        "E = S - D",
        "u_val",
        "V&V 20 verdict",
    ]);
    for c in &s.cells {
        let (d, e, u, verdict) = match &c.validation {
            Some(v) => (
                format!("{:.2}", v.d),
                format!("{:+.2}", v.e),
                format!("{:.2}", v.u_val),
                v.verdict(),
            ),
            None => ("-".into(), "-".into(), "-".into(), "-".into()),
        };
        t.row([
            c.cell.clone(),
            format!("{:.2}", c.point),
            format!("{:.2}", c.median),
            format!("{:.2} - {:.2}", c.p05, c.p95),
            d,
            e,
            u,
            verdict,
        ]);
    }
    out.push_str(&t.render());
    out
}
