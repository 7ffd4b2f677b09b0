//! How well the baseline gate ([`crate::baseline`]) works on one release's own run-to-run
//! spread: from a `reports` campaign of `M` noise seeds, the spread of every cell, the rate at
//! which the release fails against itself, and the smallest worsening of one parameter set it
//! catches, at `N` seeds a side.
//!
//! Each draw takes `2N` distinct seeds of the `M` (a seeded partial shuffle): the first `N` are
//! the baseline, the next `N` the candidate, so every comparison is of the release with itself on
//! other seeds. A worsening by `r` % multiplies the candidate's maximum horizontal error of the
//! chosen set by `1 + r/100` in every experiment; the same draws serve every `r` (common random
//! numbers), so the rows differ only by `r`. Draws share seeds with one another, so the counts
//! are not independent trials: they estimate rates, with a spread wider than binomial.

use crate::baseline::{BaselineRule, compare};
use crate::config::{SPLITMIX_GAMMA, splitmix64};
use crate::shift::quantile;
use crate::summary::Summary;

/// The run-to-run spread of one cell over a campaign's noise seeds (nmi).
#[derive(Clone, Debug, PartialEq)]
pub struct CellSpread {
    /// Experiment name.
    pub experiment: String,
    /// Parameter set key.
    pub set: String,
    /// Median maximum horizontal error (nmi).
    pub median_nmi: f64,
    /// 5 % and 95 % quantiles (nmi; type 7, [`quantile`]).
    pub p05_p95_nmi: (f64, f64),
}

/// How often the gate failed, at one worsening and one number of seeds a side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerRow {
    /// Seeds per side.
    pub seeds_per_side: usize,
    /// Worsening of the chosen set's cells (%); 0 is the release against itself.
    pub worsen_percent: f64,
    /// Comparisons drawn.
    pub draws: usize,
    /// Comparisons in which the gate failed (any cell).
    pub failed: usize,
}

/// What [`power_study`] measures.
#[derive(Clone, Debug, PartialEq)]
pub struct PowerStudy {
    /// Seeds in the campaign.
    pub seeds: usize,
    /// The set whose cells are worsened.
    pub worsened_set: String,
    /// Every cell's spread over all seeds.
    pub spreads: Vec<CellSpread>,
    /// One row per (seeds a side, worsening), seeds a side outermost.
    pub rows: Vec<PowerRow>,
}

impl PowerStudy {
    /// The smallest worsening (%) caught in at least `share` of the draws at `seeds_per_side`,
    /// or `None` when no measured worsening is.
    pub fn smallest_caught(&self, seeds_per_side: usize, share: f64) -> Option<f64> {
        self.rows
            .iter()
            .filter(|r| r.seeds_per_side == seeds_per_side && r.worsen_percent > 0.0)
            .find(|r| r.failed as f64 >= share * r.draws as f64)
            .map(|r| r.worsen_percent)
    }
}

/// What to measure: seeds a side, worsenings (%, increasing; 0 is added), the set to worsen,
/// the number of draws, the gate's rule and the draws' seed.
#[derive(Clone, Debug)]
pub struct PowerPlan {
    /// Seeds per side, each at most half the campaign's.
    pub seeds_per_side: Vec<usize>,
    /// Worsenings of the chosen set (%).
    pub worsen_percent: Vec<f64>,
    /// The set to worsen (e.g. "42-state"); `None`: the campaign's compared (compensated) set.
    pub set: Option<String>,
    /// Comparisons per row.
    pub draws: usize,
    /// The gate's margin and confidence.
    pub rule: BaselineRule,
    /// Seed of the draws.
    pub seed: u64,
}

/// Measure the gate on `campaign` (one configuration over its noise seeds) as `plan` says.
/// Errors name what is wrong: too few seeds for a side, a set the campaign lacks, a campaign
/// the gate itself refuses.
pub fn power_study(campaign: &[Summary], plan: &PowerPlan) -> Result<PowerStudy, String> {
    let m = campaign.len();
    let first = campaign
        .first()
        .ok_or_else(|| "the campaign holds no report".to_string())?;
    let set = match &plan.set {
        Some(s) => s.clone(),
        None => first
            .comparison
            .as_ref()
            .map(|c| c.compensated.clone())
            .ok_or_else(|| {
                "the reports name no comparison: name the set to worsen (gate --power: --worsen-set KEY)".to_string()
            })?,
    };
    if !first
        .experiments
        .iter()
        .any(|e| e.results.contains_key(&set))
    {
        return Err(format!(
            "the campaign has no parameter set '{set}' to worsen"
        ));
    }
    if plan.draws == 0 {
        return Err("at least one draw is needed".into());
    }
    let mut worsen = vec![0.0];
    worsen.extend(plan.worsen_percent.iter().copied().filter(|&r| r > 0.0));
    worsen.sort_by(f64::total_cmp);
    worsen.dedup();
    let mut rows = Vec::new();
    let mut rng = SplitMix(plan.seed);
    for &n in &plan.seeds_per_side {
        if n == 0 || 2 * n > m {
            return Err(format!(
                "{n} seeds a side need {} distinct seeds; the campaign has {m}",
                2 * n
            ));
        }
        let mut failed = vec![0usize; worsen.len()];
        for _ in 0..plan.draws {
            let picked = rng.pick(m, 2 * n);
            let base: Vec<Summary> = picked[..n].iter().map(|&i| campaign[i].clone()).collect();
            let cand: Vec<&Summary> = picked[n..].iter().map(|&i| &campaign[i]).collect();
            for (w, count) in worsen.iter().zip(&mut failed) {
                let worse: Vec<Summary> = cand
                    .iter()
                    .map(|s| worsened(s, &set, 1.0 + w / 100.0))
                    .collect();
                let (_, checks) = compare(&base, &worse, &plan.rule)?;
                *count += usize::from(checks.iter().any(|c| !c.passed));
            }
        }
        rows.extend(worsen.iter().zip(failed).map(|(&w, f)| PowerRow {
            seeds_per_side: n,
            worsen_percent: w,
            draws: plan.draws,
            failed: f,
        }));
    }
    Ok(PowerStudy {
        seeds: m,
        worsened_set: set,
        spreads: spreads(campaign),
        rows,
    })
}

/// Every cell's median and 5-95 % range over the campaign.
pub fn spreads(campaign: &[Summary]) -> Vec<CellSpread> {
    let Some(first) = campaign.first() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for e in &first.experiments {
        for set in e.results.keys() {
            let v: Vec<f64> = campaign
                .iter()
                .filter_map(|s| s.experiments.iter().find(|x| x.name == e.name))
                .filter_map(|x| x.results.get(set).map(|r| r.max_horizontal_nmi))
                .collect();
            out.push(CellSpread {
                experiment: e.name.clone(),
                set: set.clone(),
                median_nmi: quantile(&v, 0.5),
                p05_p95_nmi: (quantile(&v, 0.05), quantile(&v, 0.95)),
            });
        }
    }
    out
}

/// `s` with set `set`'s maximum horizontal error multiplied by `factor` in every experiment.
fn worsened(s: &Summary, set: &str, factor: f64) -> Summary {
    let mut out = s.clone();
    for e in &mut out.experiments {
        if let Some(r) = e.results.get_mut(set) {
            r.max_horizontal_nmi *= factor;
            r.max_horizontal_m *= factor;
        }
    }
    out
}

/// SplitMix64 ([`crate::config::splitmix64`]): the draws' generator.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        let out = splitmix64(self.0);
        self.0 = self.0.wrapping_add(SPLITMIX_GAMMA);
        out
    }

    /// `k` distinct indices of `0..m` in random order (partial Fisher-Yates).
    fn pick(&mut self, m: usize, k: usize) -> Vec<usize> {
        let mut idx: Vec<usize> = (0..m).collect();
        for i in 0..k.min(m) {
            let j = i + (self.next() % (m - i) as u64) as usize;
            idx.swap(i, j);
        }
        idx.truncate(k);
        idx
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A campaign of `m` seeds whose 42-state cell is log-normal (median 1.6 nmi, log sd 0.35)
    /// and whose 30-state cell barely moves (median 85 nmi, log sd 0.005).
    fn campaign(m: usize) -> Vec<Summary> {
        let mut rng = SplitMix(11);
        let mut normal = || {
            let u = (rng.next() >> 11) as f64 / (1u64 << 53) as f64 + 1e-12;
            let v = (rng.next() >> 11) as f64 / (1u64 << 53) as f64;
            (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
        };
        (0..m)
            .map(|_| {
                let with = 1.6 * (0.35 * normal()).exp();
                let without = 85.0 * (0.005 * normal()).exp();
                Summary::example(with, without)
            })
            .collect()
    }

    fn plan(sides: Vec<usize>) -> PowerPlan {
        PowerPlan {
            seeds_per_side: sides,
            worsen_percent: vec![10.0, 25.0, 50.0, 100.0, 200.0],
            set: Some("42-state".into()),
            draws: 300,
            rule: BaselineRule::default(),
            seed: 1,
        }
    }

    #[test]
    fn the_release_against_itself_fails_at_most_at_the_stated_rate_and_power_grows_with_seeds() {
        let study = power_study(&campaign(64), &plan(vec![8, 32])).expect("valid");
        let row = |n: usize, w: f64| {
            *study
                .rows
                .iter()
                .find(|r| r.seeds_per_side == n && r.worsen_percent == w)
                .expect("row")
        };
        for n in [8, 32] {
            // Stated at most 5 % at margin 0; at the default 10 % margin, fewer. 300 draws
            // from 64 seeds overlap, so allow 8 %.
            let same = row(n, 0.0);
            assert!(same.failed <= 24, "{same:?}");
            // Failures never fall as the worsening grows (same draws).
            let counts: Vec<usize> = study
                .rows
                .iter()
                .filter(|r| r.seeds_per_side == n)
                .map(|r| r.failed)
                .collect();
            assert!(counts.windows(2).all(|w| w[0] <= w[1]), "{counts:?}");
        }
        // Doubling the error (log sd 0.35: a shift of 2 sd) is caught nearly always with 32
        // a side; a 10 % worsening (the margin itself) almost never.
        assert!(row(32, 100.0).failed >= 285, "{:?}", row(32, 100.0));
        assert!(row(32, 10.0).failed <= 30, "{:?}", row(32, 10.0));
        let (s8, s32) = (
            study.smallest_caught(8, 0.9).expect("caught at 8"),
            study.smallest_caught(32, 0.9).expect("caught at 32"),
        );
        assert!(s32 < s8, "32 a side catches less than 8: {s32} vs {s8}");
        // The spread of the 42-state cell: 5-95 % of a log-normal with log sd 0.35 is
        // median × e^(±0.576) = 0.90-2.85 nmi.
        let c = study
            .spreads
            .iter()
            .find(|c| c.set == "42-state")
            .expect("cell");
        assert!((c.median_nmi - 1.6).abs() < 0.2, "{c:?}");
        assert!((c.p05_p95_nmi.0 - 0.90).abs() < 0.25, "{c:?}");
        assert!((c.p05_p95_nmi.1 - 2.85).abs() < 0.6, "{c:?}");
    }

    #[test]
    fn a_side_larger_than_half_the_campaign_or_an_unknown_set_is_refused() {
        let c = campaign(20);
        let e = power_study(&c, &plan(vec![12])).expect_err("too many");
        assert!(
            e.contains("24 distinct seeds") && e.contains("has 20"),
            "{e}"
        );
        let mut p = plan(vec![8]);
        p.set = Some("99-state".into());
        let e = power_study(&c, &p).expect_err("set");
        assert!(e.contains("'99-state'"), "{e}");
    }

    #[test]
    fn draws_are_distinct_seeds() {
        let mut rng = SplitMix(5);
        for _ in 0..100 {
            let mut p = rng.pick(16, 16);
            p.sort_unstable();
            assert_eq!(p, (0..16).collect::<Vec<_>>());
        }
    }
}
