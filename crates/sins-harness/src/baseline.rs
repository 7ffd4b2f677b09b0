//! The release gate against a baseline: is a candidate release's maximum horizontal error worse
//! than the baseline's by more than a margin, given the run-to-run spread over sensor-noise
//! seeds?
//!
//! Each side is a campaign of the same report configuration over `N` noise seeds (the
//! `reports` campaign kind with `noise_seeds = N`): `N` summaries. For every experiment and
//! parameter set (a cell), the shift of the candidate's values over the baseline's is estimated
//! by Hodges-Lehmann with its distribution-free lower bound ([`crate::shift`]). The cell fails
//! when that lower bound exceeds the margin: the candidate is worse than the margin at the
//! stated confidence. The confidence is family-wise over the cells (Bonferroni), so a release
//! that differs only in its noise seeds fails with probability at most `1 − confidence`
//! whatever the number of cells (less, since the margin is above zero).

use crate::gate::Check;
use crate::shift::{bound_rank, shift};
use crate::summary::Summary;

/// How the candidate is judged against the baseline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BaselineRule {
    /// Largest tolerated worsening of a cell's maximum horizontal error, as a percentage of the
    /// baseline's median for that cell.
    pub margin_percent: f64,
    /// Family-wise confidence that a failed cell is worse than the margin (e.g. 0.95).
    pub confidence: f64,
}

impl Default for BaselineRule {
    fn default() -> Self {
        Self {
            margin_percent: 10.0,
            confidence: 0.95,
        }
    }
}

/// One cell's comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct CellShift {
    /// Experiment name.
    pub experiment: String,
    /// Parameter set key.
    pub set: String,
    /// Median of the baseline's values (nmi).
    pub baseline_median_nmi: f64,
    /// Hodges-Lehmann shift of the candidate over the baseline (nmi).
    pub shift_nmi: f64,
    /// One-sided lower and upper bounds of the shift at the per-cell level (nmi).
    pub bounds_nmi: (f64, f64),
    /// The margin (nmi).
    pub margin_nmi: f64,
}

/// Compare `candidate` against `baseline` (each the summaries of one report configuration over
/// its noise seeds). Errors (bad input, exit 2 in the CLI) name what does not match: another
/// configuration, different seed counts, a cell missing on one side, too few seeds for the
/// confidence, a value that is not finite.
pub fn compare(
    baseline: &[Summary],
    candidate: &[Summary],
    rule: &BaselineRule,
) -> Result<(Vec<CellShift>, Vec<Check>), String> {
    if !(rule.confidence > 0.0 && rule.confidence < 1.0) {
        return Err(format!(
            "confidence {} must lie between 0 and 1 (e.g. 0.95)",
            rule.confidence
        ));
    }
    if !(rule.margin_percent.is_finite() && rule.margin_percent >= 0.0) {
        return Err(format!(
            "margin {} % must be a number of percent, 0 or more",
            rule.margin_percent
        ));
    }
    let base = one_configuration(baseline, "baseline")?;
    let cand = one_configuration(candidate, "candidate")?;
    if base.name != cand.name {
        return Err(format!(
            "the baseline is report configuration '{}' and the candidate '{}': a release is \
             compared with a baseline of the same configuration",
            base.name, cand.name
        ));
    }
    if baseline.len() != candidate.len() {
        return Err(format!(
            "the baseline has {} noise seeds and the candidate {}: run both campaigns with the \
             same `noise_seeds`",
            baseline.len(),
            candidate.len()
        ));
    }
    let cells = cells(base);
    for (e, s) in cells_of(cand) {
        if !cells.contains(&(e.clone(), s.clone())) {
            return Err(format!(
                "the candidate has cell {e} / {s}, which the baseline does not: the two \
                 campaigns ran different configurations"
            ));
        }
    }
    let alpha = (1.0 - rule.confidence) / cells.len().max(1) as f64;
    let n = baseline.len();
    if bound_rank(n, n, alpha) == 0 {
        let mut need = n;
        while bound_rank(need, need, alpha) == 0 {
            need += 1;
        }
        return Err(format!(
            "{n} noise seeds per side cannot bound a shift at {} confidence over {} cells \
             (family-wise): at least {need} are needed",
            rule.confidence,
            cells.len()
        ));
    }
    let mut shifts = Vec::new();
    let mut checks = Vec::new();
    for (e, s) in &cells {
        let x = values(baseline, e, s, "baseline")?;
        let y = values(candidate, e, s, "candidate")?;
        let sh =
            shift(&x, &y, alpha).ok_or_else(|| format!("cell {e} / {s}: a value is not finite"))?;
        let median = median(&x);
        let margin = rule.margin_percent / 100.0 * median;
        let passed = sh.lower <= margin;
        let message = format!(
            "{e} {s}: candidate − baseline {:+.3} nmi (Hodges-Lehmann over {n} + {n} seeds; \
             one-sided {:.2} % bounds [{:+.3}, {:+.3}]) against a margin of {:.3} nmi \
             ({} % of the baseline median {:.3} nmi){}",
            sh.estimate,
            100.0 * (1.0 - alpha),
            sh.lower,
            sh.upper,
            margin,
            rule.margin_percent,
            median,
            if passed {
                ""
            } else {
                ": worse than the margin at the stated confidence"
            }
        );
        checks.push(Check {
            experiment: e.clone(),
            name: format!("baseline_shift[{s}]"),
            passed,
            message,
        });
        shifts.push(CellShift {
            experiment: e.clone(),
            set: s.clone(),
            baseline_median_nmi: median,
            shift_nmi: sh.estimate,
            bounds_nmi: (sh.lower, sh.upper),
            margin_nmi: margin,
        });
    }
    Ok((shifts, checks))
}

/// The first summary, after checking that every one is of the same configuration and cells.
fn one_configuration<'a>(list: &'a [Summary], side: &str) -> Result<&'a Summary, String> {
    let first = list
        .first()
        .ok_or_else(|| format!("the {side} holds no report"))?;
    let want = cells(first);
    for s in list {
        if s.name != first.name {
            return Err(format!(
                "the {side} mixes report configurations '{}' and '{}': a baseline is one \
                 configuration over noise seeds",
                first.name, s.name
            ));
        }
        if cells(s) != want {
            return Err(format!(
                "the {side}'s reports do not all have the same experiments and parameter sets \
                 (report '{}')",
                s.name
            ));
        }
    }
    Ok(first)
}

/// The median of finite values.
fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    crate::shift::median_of_sorted(&s)
}

/// Every (experiment, parameter set) of a summary, in order.
fn cells(s: &Summary) -> Vec<(String, String)> {
    cells_of(s).collect()
}

fn cells_of(s: &Summary) -> impl Iterator<Item = (String, String)> + '_ {
    s.experiments
        .iter()
        .flat_map(|e| e.results.keys().map(|k| (e.name.clone(), k.clone())))
}

/// One cell's maximum horizontal error in every summary (nmi).
fn values(list: &[Summary], e: &str, s: &str, side: &str) -> Result<Vec<f64>, String> {
    list.iter()
        .map(|sum| {
            sum.experiments
                .iter()
                .find(|x| x.name == e)
                .and_then(|x| x.results.get(s))
                .map(|r| r.max_horizontal_nmi)
                .ok_or_else(|| format!("the {side} lacks cell {e} / {s}"))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic uniform generator (xorshift64*).
    struct Rng(u64);
    impl Rng {
        fn uniform(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            ((self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        }
        /// A skewed positive value (log-normal, median `m`, log sd 0.3): a maximum error.
        fn error(&mut self, m: f64) -> f64 {
            let (u, v) = (self.uniform(), self.uniform());
            let z = (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos();
            m * (0.3 * z).exp()
        }
    }

    fn side(rng: &mut Rng, n: usize, with_nmi: f64) -> Vec<Summary> {
        (0..n)
            .map(|_| Summary::example(rng.error(with_nmi), rng.error(80.0)))
            .collect()
    }

    #[test]
    fn same_release_other_seeds_fails_at_most_at_the_stated_rate() {
        // 2000 comparisons of 8 + 8 seeds from one distribution, margin 0: the family-wise
        // false-failure probability is at most 5 %. Binomial(2000, 0.05) exceeds 125 with
        // probability below 1e-3.
        let rule = BaselineRule {
            margin_percent: 0.0,
            confidence: 0.95,
        };
        let mut rng = Rng(0x5eed);
        let mut failed = 0;
        for _ in 0..2000 {
            let (b, c) = (side(&mut rng, 8, 1.6), side(&mut rng, 8, 1.6));
            let (_, checks) = compare(&b, &c, &rule).expect("valid");
            failed += usize::from(checks.iter().any(|c| !c.passed));
        }
        eprintln!("same release, other seeds: {failed} of 2000 comparisons failed");
        assert!(failed <= 125, "{failed} of 2000");
        // And it is not vacuous: more than 1 % fail at margin 0 (Bonferroni over 2 cells
        // keeps the rate between 2.5 and 5 %).
        assert!(failed >= 20, "{failed} of 2000");
    }

    #[test]
    fn a_regression_beyond_the_margin_is_caught_and_named() {
        // The 42-state error 40 % worse, margin 10 %, 32 seeds a side.
        let rule = BaselineRule::default();
        let mut rng = Rng(7);
        let (b, c) = (side(&mut rng, 32, 1.6), side(&mut rng, 32, 1.6 * 1.4));
        let (shifts, checks) = compare(&b, &c, &rule).expect("valid");
        let bad: Vec<&Check> = checks.iter().filter(|c| !c.passed).collect();
        assert_eq!(bad.len(), 1, "{checks:?}");
        assert_eq!(bad[0].name, "baseline_shift[42-state]");
        let s = shifts.iter().find(|s| s.set == "42-state").expect("cell");
        // The true shift of the medians is 0.64 nmi; it lies inside the bounds.
        assert!(s.bounds_nmi.0 < 0.64 && 0.64 < s.bounds_nmi.1, "{s:?}");
        assert!(
            bad[0].message.contains("nav1 42-state"),
            "{}",
            bad[0].message
        );
    }

    #[test]
    fn mismatched_campaigns_are_refused_with_what_differs() {
        let rule = BaselineRule::default();
        let mut rng = Rng(3);
        let b = side(&mut rng, 8, 1.6);
        let e = compare(&b, &side(&mut rng, 16, 1.6), &rule).expect_err("seed counts");
        assert!(e.contains("8 noise seeds") && e.contains("16"), "{e}");
        let mut other = side(&mut rng, 8, 1.6);
        for s in &mut other {
            s.name = "another".into();
        }
        let e = compare(&b, &other, &rule).expect_err("configuration");
        assert!(e.contains("'another'"), "{e}");
        let mut missing = side(&mut rng, 8, 1.6);
        for s in &mut missing {
            s.experiments[0].name = "nav9".into();
        }
        let e = compare(&b, &missing, &rule).expect_err("cell");
        assert!(e.contains("nav9"), "{e}");
        let e = compare(&b[..3], &side(&mut rng, 3, 1.6), &rule).expect_err("too few");
        // Two cells at 0.95 family-wise: 0.025 each; P(U = 0) is 1/20 with 3 + 3, 1/70 with 4 + 4.
        assert!(e.contains("at least 4"), "{e}");
    }
}
