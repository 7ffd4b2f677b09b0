//! `report.md` of a diagnosis: inputs and assumptions, the verdict, where the gap lies, which
//! effect explains it, and how far it shrinks on withheld data.

use crate::run::DiagnosisOutcome;
use sins_config::markdown::Table;
use sins_diag::report::{CandidateModel, NoteKind, Verdict};
use std::fmt::Write as _;

/// `v` with `digits` significant digits (fixed notation from 1e-3 to 1e5, else exponent).
fn g(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let mag = v.abs().log10().floor() as i32;
    if (-3..5).contains(&mag) {
        let decimals = (digits as i32 - 1 - mag).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.prec$e}", prec = digits.saturating_sub(1))
    }
}

fn yes_no(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

fn verdict_line(v: &Verdict) -> String {
    match v {
        Verdict::NoSignificantGap => {
            "**No significant gap**: the real error tracks are consistent with the twin, and no candidate effect is significant.".into()
        }
        Verdict::Explained { by } => format!(
            "**Explained by `{by}`**: it is significant and, once added, what is left is consistent with the twin."
        ),
        Verdict::PartlyExplained { by } => format!(
            "**Partly explained by `{by}`**: it is significant, but the gap left after adding it is still inconsistent with the twin (a further unmodelled effect remains)."
        ),
        Verdict::Unexplained => {
            "**None of the catalogue explains it**: the gap is significant, and no candidate effect both passes the test and leaves a consistent residual.".into()
        }
        Verdict::NotSeparable {
            candidates,
            time_local,
        } => {
            let mut named: Vec<String> = candidates.iter().map(|c| format!("`{c}`")).collect();
            named.extend(time_local.iter().map(|t| {
                format!("a {} on {} in {} from {:.0} s", t.shape, t.channel, t.runs, t.onset_s)
            }));
            format!(
                "**Not separable**: {} leave signatures that these data cannot tell apart; the tool does not guess between them (more varied motion or temperature would separate them; see the confounds below).",
                named.join(", ")
            )
        }
    }
}

/// Render the diagnosis report; `plots` are the PNG files written beside it.
pub fn render_markdown(o: &DiagnosisOutcome, plots: &[String]) -> String {
    let d = &o.diagnosis;
    let mut md = String::from("# Sim-to-real gap diagnosis\n\n");
    let _ = writeln!(md, "{}\n", verdict_line(&d.verdict));
    for n in d
        .notes
        .iter()
        .filter(|n| n.kind == NoteKind::CalibrationInnovations)
    {
        let _ = writeln!(md, "**The calibration run's own evidence**: {n}.\n");
    }
    if let Some(line) = crate::markdown_rivals::confound_line(d) {
        let _ = writeln!(md, "{line}\n");
    }
    if !d.noise_untrusted.is_empty() {
        let _ = writeln!(
            md,
            "**The twin's noise cannot be trusted**, so neither can this verdict: the noise \
             identification found its model inconsistent with the data it came from:\n"
        );
        for r in &d.noise_untrusted {
            let _ = writeln!(md, "- {r}");
        }
        md.push('\n');
    }
    let mut t = Table::new([
        "run",
        "dataset",
        "length (h)",
        "max horizontal error of the real replay (m)",
    ]);
    for r in &o.runs {
        t.row([
            r.name.clone(),
            format!("`{}`", r.path.display()),
            format!("{:.2}", r.duration_h),
            format!("{:.0}", r.max_horizontal_m),
        ]);
    }
    md.push_str("## Inputs\n\n");
    md.push_str(&t.render());
    let _ = writeln!(
        md,
        "\nNull test of the twin over {} fit points: chi-square {:.1} against {:.1} expected, p = {} ({}).\n",
        d.n_data,
        d.null_test.chi2,
        d.null_test.dof,
        g(d.null_test.p_value, 3),
        if d.null_test.consistent {
            "consistent"
        } else {
            "inconsistent: there is a gap"
        }
    );
    let _ = writeln!(md, "## 1. Where the real error parts from the twin\n");
    for l in &d.localisation {
        let exit = match (l.first_exit_s, &l.first_exit_channel, &l.first_exit_segment) {
            (Some(t), Some(c), Some(s)) => format!(
                "first leaves the twin's 3-sigma envelope at t = {:.2} h ({c} channel, segment '{s}')",
                t / 3600.0
            ),
            _ => "stays inside the twin's 3-sigma envelope".to_string(),
        };
        let _ = writeln!(md, "### {}\n\nThe gap {exit}.\n", l.run);
        let mut t = Table::new([
            "segment",
            "channel",
            "max |gap| (m)",
            "RMS (m)",
            "max gap / sigma",
        ]);
        for g in &l.segments {
            t.row([
                g.segment.clone(),
                g.channel.clone(),
                format!("{:.1}", g.max_abs_m),
                format!("{:.1}", g.rms_m),
                format!("{:.1}", g.max_sigmas),
            ]);
        }
        md.push_str(&t.render());
        if !l.time_scales.is_empty() {
            let mut t = Table::new(["channel", "basis", "share"]);
            for s in &l.time_scales {
                t.row([
                    s.channel.clone(),
                    s.basis.clone(),
                    format!("{:.0} %", 100.0 * s.share),
                ]);
            }
            md.push_str("\nTime scales (share of the gap's energy):\n\n");
            md.push_str(&t.render());
        }
        let _ = writeln!(md);
    }
    let _ = writeln!(md, "## 2. Which unmodelled effect explains it\n");
    let _ = writeln!(
        md,
        "Candidates ranked by evidence: the drop of the chi-square when the effect is added to the twin \
         (2 × log-likelihood ratio), its tail probability (Bonferroni over the catalogue), and the BIC \
         improvement Δχ² − k ln n. A candidate passes when both are significant; the verdict also \
         requires the residual to be consistent.\n"
    );
    let mut t = Table::new([
        "rank",
        "effect",
        "magnitude (± 1σ)",
        "Δχ²",
        "k",
        "p",
        "ΔBIC",
        "passes",
        "residual consistent",
    ]);
    for (i, c) in d.candidates.iter().enumerate() {
        let mags: Vec<String> = c
            .components
            .iter()
            .filter(|x| x.retained)
            .map(|x| match x.sigma {
                Some(s) => format!("{} {} ± {}", x.label, g(x.value, 3), g(s, 2)),
                None => format!("{} {}", x.label, g(x.value, 3)),
            })
            .collect();
        let model = match c.model {
            CandidateModel::Regression => "",
            CandidateModel::NoiseTerm => " (noise term)",
        };
        let mags = if mags.is_empty() {
            "-".to_string()
        } else {
            mags.join(", ")
        };
        t.row([
            (i + 1).to_string(),
            format!("`{}`{model}", c.kind),
            format!("{mags} {}", c.unit),
            format!("{:.1}", c.dchi2),
            c.dof.to_string(),
            g(c.p_value, 2),
            format!("{:.1}", c.delta_bic),
            yes_no(c.passes).to_string(),
            yes_no(c.residual.consistent).to_string(),
        ]);
    }
    md.push_str(&t.render());
    let walks: Vec<String> = d
        .candidates
        .iter()
        .filter_map(|c| c.whiteness.as_ref().map(|w| (c, w)))
        .map(|(c, w)| {
            format!(
                "- `{}`: largest standardised increment |z| = {:.1} over {} increments, lag-one \
                 correlation z = {:.1}, stationarity z = {:.1}, cross-run alignment z = {:.1}{}, \
                 p = {} ({})",
                c.kind,
                w.max_abs_z,
                w.increments,
                w.lag1_z,
                w.stationarity_z,
                w.aligned_z,
                w.without_events_dchi2.map_or(String::new(), |x| format!(
                    ", Δχ² without the time-local events {x:.1}"
                )),
                g(w.p_value, 2),
                if w.consistent {
                    "increments look like a walk's"
                } else {
                    "not a walk: a step, an oscillation or a drift shaped like one"
                }
            )
        })
        .collect();
    if let Some((c, t)) = d
        .candidates
        .iter()
        .find_map(|c| c.constancy.as_ref().map(|t| (c, t)))
    {
        let runs: Vec<String> = t
            .per_run
            .iter()
            .map(|e| match (e.value, e.sigma) {
                (Some(v), Some(s)) => format!("{} {} ± {}", e.run, g(v, 3), g(s, 2)),
                _ => format!("{} -", e.run),
            })
            .collect();
        let _ = writeln!(
            md,
            "\nConstancy of `{}` across runs (one magnitude per run against one for all, a \
             physical coefficient is shared by every run): Δχ² = {:.1} on {} dof, p = {} ({}). \
             Component {} per run ({}): {}.",
            c.kind,
            t.dchi2,
            t.dof,
            g(t.p_value, 2),
            if t.consistent {
                "consistent"
            } else {
                "the magnitude differs between runs: the effect reproduces the signature, not \
                 its physics"
            },
            t.per_run.first().map_or("?", |e| e.label.as_str()),
            c.unit,
            runs.join(", ")
        );
    }
    if !walks.is_empty() {
        let _ = writeln!(
            md,
            "\nWhiteness of the noise terms: a walk's smoothed increments, standardised under the \
             fitted walk, hold no outlier and no lag-one correlation; a noise term that fails \
             this does not pass.\n\n{}",
            walks.join("\n")
        );
    }
    md.push_str(&crate::markdown_events::render_events(&d.events));
    md.push_str(&crate::markdown_rivals::render_rivals(&d.rivals));
    md.push_str(&crate::markdown_rivals::render_confound(d));
    let _ = writeln!(md, "\n## 3. How far the gap shrinks on withheld data\n");
    if d.validation.is_empty() {
        let _ = writeln!(
            md,
            "No validation: nothing was fitted, or there was a single run or segment.\n"
        );
    } else {
        let mut t = Table::new([
            "effect",
            "fitted on",
            "evaluated on",
            "max gap before (m)",
            "after (m)",
            "RMS gap before (m)",
            "after (m)",
            "systematic gap before",
            "after",
            "shrinkage (systematic / RMS / max)",
        ]);
        for v in &d.validation {
            t.row([
                format!("`{}`", v.kind),
                v.fitted_on.to_string(),
                v.evaluated_on.to_string(),
                format!("{:.1}", v.before.max_horizontal_gap_m),
                format!("{:.1}", v.after.max_horizontal_gap_m),
                format!("{:.1}", v.before.rms_gap_m),
                format!("{:.1}", v.after.rms_gap_m),
                format!("{:.1}", v.systematic_before),
                format!("{:.1}", v.systematic_after),
                format!(
                    "{:.0} % / {:.0} % / {:.0} %",
                    v.systematic_shrinkage_percent,
                    v.rms_shrinkage_percent,
                    v.max_shrinkage_percent
                ),
            ]);
        }
        md.push_str(&t.render());
        let _ = writeln!(
            md,
            "\nThe systematic gap is √max(0, χ² − E χ²) on the withheld run's fit points in the \
             twin's metric (noise, calibration uncertainty): the gap beyond the twin's own spread, \
             which is what an unmodelled effect adds. The RMS gap also carries the noise the twin \
             already predicts, so it cannot shrink below that noise whatever the model.\n"
        );
    }
    if !plots.is_empty() {
        let _ = writeln!(md, "## Plots\n");
        for p in plots {
            let _ = writeln!(md, "![{p}]({p})\n");
        }
    }
    let _ = writeln!(
        md,
        "Rerun recording: [diagnosis.rrd](diagnosis.rrd) (gap, 3-sigma envelope and fitted effect per run and channel). Machine-readable: [diagnosis.json](diagnosis.json).\n"
    );
    let _ = writeln!(md, "## Assumptions\n");
    for n in &d.notes {
        let _ = writeln!(md, "- {n}");
    }
    let _ = writeln!(
        md,
        "- Every run is a turntable run at the fixed site of its file's metadata; the first 20 min are a stationary self-alignment; errors are horizontal position errors against the site.\n\
         - The twin is the calibrated parameter set with the given noise model; candidate effects are linearised about zero (about the refined estimate for refined candidates).\n\
         - Limits: an effect outside the catalogue that leaves the same signature as a candidate, with one magnitude in every run, is reported as that candidate (runs with different motions and temperature profiles sharpen the constancy test), unless it also acted during the calibration run and left innovations there that the candidate does not explain; bias random walks are modelled in 20 min lumps, so a bias step shows as a misfit of the walk rather than as one outlier increment.\n\
         - Run time: replays {:.1} s, diagnosis {:.1} s.",
        o.replay_s, o.diagnose_s
    );
    md
}
