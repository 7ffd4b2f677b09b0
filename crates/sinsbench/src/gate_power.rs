//! `sinsbench gate --power CAMPAIGN`: the baseline gate measured on one release's own
//! run-to-run spread ([`sins_harness::gate_power`]), printed as tables.

use crate::out::say;
use anyhow::{Result, anyhow};
use sins_harness::gate_power::{PowerPlan, power_study};
use std::path::Path;

/// Share of the draws in which a worsening counts as caught.
const CAUGHT_SHARE: f64 = 0.9;

/// Run `gate --power` on the `reports` campaign at `campaign` as `plan` says.
pub fn run(campaign: &Path, plan: &PowerPlan) -> Result<()> {
    let list = sins_config::read_report_list(campaign)?;
    let study = power_study(&list, plan)
        .map_err(|e| anyhow!("gate --power {}: {e}", campaign.display()))?;
    say!(
        "run-to-run spread over {} noise seeds (maximum horizontal error, nmi):",
        study.seeds
    )?;
    say!("| experiment | set | median | 5 % | 95 % | (95 % - 5 %) / median |")?;
    say!("|---|---|---|---|---|---|")?;
    for c in &study.spreads {
        let (lo, hi) = c.p05_p95_nmi;
        say!(
            "| {} | {} | {:.3} | {:.3} | {:.3} | {:.1} % |",
            c.experiment,
            c.set,
            c.median_nmi,
            lo,
            hi,
            100.0 * (hi - lo) / c.median_nmi
        )?;
    }
    say!(
        "\ngate --baseline at margin {} %, confidence {} (family-wise), {} draws of distinct \
         seeds per row; '{}' worsened in every experiment of the candidate:",
        plan.rule.margin_percent,
        plan.rule.confidence,
        plan.draws,
        study.worsened_set
    )?;
    say!("| seeds a side | worsening | gate failed | share |")?;
    say!("|---|---|---|---|")?;
    for r in &study.rows {
        say!(
            "| {} | {} % | {} of {} | {:.1} % |",
            r.seeds_per_side,
            r.worsen_percent,
            r.failed,
            r.draws,
            100.0 * r.failed as f64 / r.draws as f64
        )?;
    }
    for &n in &plan.seeds_per_side {
        match study.smallest_caught(n, CAUGHT_SHARE) {
            Some(w) => say!(
                "{n} seeds a side: the smallest worsening caught in {:.0} % of the draws is {w} %",
                100.0 * CAUGHT_SHARE
            )?,
            None => say!(
                "{n} seeds a side: no measured worsening is caught in {:.0} % of the draws",
                100.0 * CAUGHT_SHARE
            )?,
        }
    }
    Ok(())
}
