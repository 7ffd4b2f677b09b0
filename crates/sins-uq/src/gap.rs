//! The replica-vs-paper gap diagnosed: the likelihood of the paper's Table 5 cells (and Table 2's
//! repeatability) under each candidate, with the candidate's own Monte Carlo spread and the
//! paper's scatter as the noise; the choice on some cells; the shrinkage of the gap on the cells
//! withheld from the choice.

use crate::cell::{CellId, CellKind, PaperCell};
use crate::stats::{mean_sd, quantile};
use serde::{Deserialize, Serialize};

/// The space a cell is compared in: log for the maximum errors (they span orders of
/// magnitude and are positive), linear for the improvement.
pub fn transform(id: CellId, value: f64) -> f64 {
    match id.kind {
        CellKind::Improvement => value,
        _ => value.max(1e-9).ln(),
    }
}

/// The log predictive density of the paper's value `paper` under a candidate whose Monte Carlo
/// gave `samples` in the cell: normal in the cell's space with the samples' mean, their variance
/// (times 1 + 1/n for the mean's own error) plus the paper's scatter squared.
pub fn log_predictive(id: CellId, samples: &[f64], paper: &PaperCell) -> f64 {
    let t: Vec<f64> = samples.iter().map(|v| transform(id, *v)).collect();
    let (m, sd) = mean_sd(&t);
    let n = t.len() as f64;
    let scatter = paper_scatter_in_space(id, paper);
    let var = sd * sd * (1.0 + 1.0 / n) + scatter * scatter;
    let d = transform(id, paper.value) - m;
    -0.5 * (d * d / var + (std::f64::consts::TAU * var).ln())
}

/// The paper's scatter of a cell in the comparison space (log: relative scatter).
pub fn paper_scatter_in_space(id: CellId, paper: &PaperCell) -> f64 {
    match id.kind {
        CellKind::Improvement => paper.scatter,
        _ => paper.scatter / paper.value.max(1e-9),
    }
}

/// Log-likelihood of the paper's Table 2 STDs (three calibrations, 2 degrees of freedom each)
/// under a candidate's per-coefficient spread `sigma` (same units): the STD s of three normal
/// values has 2 s²/σ² ~ χ²(2), so ln p(s²) = -ln σ² - s²/σ².
pub fn table2_log_likelihood(paper_std: &[f64], sigma: &[f64]) -> f64 {
    paper_std
        .iter()
        .zip(sigma)
        .filter(|(_, s)| **s > 0.0)
        .map(|(p, s)| -(s * s).ln() - (p * p) / (s * s))
        .sum()
}

/// One candidate's evidence.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CandidateEvidence {
    /// Candidate name.
    pub name: String,
    /// Samples it ran.
    pub samples: usize,
    /// Log predictive density summed over the choice cells.
    pub log_lik_choice: f64,
    /// Log predictive density summed over the withheld Table 5 cells.
    pub log_lik_withheld: f64,
    /// Log-likelihood of Table 2 (withheld).
    pub log_lik_table2: f64,
    /// The candidate's median per cell (in [`crate::summary::all_cells`] order).
    pub median: Vec<f64>,
    /// Its 5 % and 95 % quantiles per cell.
    pub interval: Vec<[f64; 2]>,
}

/// A withheld cell before and after the correction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WithheldCell {
    /// The cell, e.g. "exp2 without".
    pub cell: String,
    /// The paper's value.
    pub paper: f64,
    /// The baseline (first candidate, the replica as built): median.
    pub baseline: f64,
    /// The chosen candidate: median.
    pub corrected: f64,
    /// 1 - |E_corrected| / |E_baseline| (%); 100 % = gap closed, negative = wider.
    pub shrinkage_percent: f64,
}

/// The evidence of every candidate, the one chosen on the choice cells, and the gap on the
/// withheld cells.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GapDiagnosis {
    /// The cells the choice used.
    pub choose_on: Vec<String>,
    /// Every candidate, in file order.
    pub candidates: Vec<CandidateEvidence>,
    /// The chosen candidate (highest log predictive density on the choice cells).
    pub chosen: String,
    /// Its rank on the withheld cells (1 = best there too).
    pub chosen_rank_withheld: usize,
    /// Withheld cells before and after.
    pub withheld: Vec<WithheldCell>,
    /// Median shrinkage over the withheld cells (%).
    pub median_shrinkage_percent: f64,
}

/// Per-candidate cell samples: `cells[k]` are the candidate's values of cell `ids[k]`.
pub struct CandidateCells<'a> {
    /// Name.
    pub name: &'a str,
    /// Samples per cell.
    pub cells: Vec<Vec<f64>>,
    /// Per-coefficient spread for Table 2 (paper units, Table 2 order).
    pub table2_sigma: Vec<f64>,
}

/// Diagnoses the gap. `ids` and `paper` are aligned; `table2_paper` is Table 2 flattened.
pub fn diagnose(
    ids: &[CellId],
    paper: &[PaperCell],
    candidates: &[CandidateCells<'_>],
    choose_on: &[CellId],
    table2_paper: &[f64],
) -> Option<GapDiagnosis> {
    let evidence: Vec<CandidateEvidence> = candidates
        .iter()
        .map(|c| {
            let mut ll = [0.0, 0.0];
            for ((id, p), s) in ids.iter().zip(paper).zip(&c.cells) {
                ll[usize::from(!choose_on.contains(id))] += log_predictive(*id, s, p);
            }
            CandidateEvidence {
                name: c.name.to_string(),
                samples: c.cells.first().map_or(0, Vec::len),
                log_lik_choice: ll[0],
                log_lik_withheld: ll[1],
                log_lik_table2: table2_log_likelihood(table2_paper, &c.table2_sigma),
                median: c.cells.iter().map(|s| quantile(s, 0.5)).collect(),
                interval: c
                    .cells
                    .iter()
                    .map(|s| [quantile(s, 0.05), quantile(s, 0.95)])
                    .collect(),
            }
        })
        .collect();
    let best = (0..evidence.len()).max_by(|&a, &b| {
        evidence[a]
            .log_lik_choice
            .total_cmp(&evidence[b].log_lik_choice)
    })?;
    let rank = 1 + evidence
        .iter()
        .filter(|e| e.log_lik_withheld > evidence[best].log_lik_withheld)
        .count();
    let withheld: Vec<WithheldCell> = ids
        .iter()
        .enumerate()
        .filter(|(_, id)| !choose_on.contains(id))
        .map(|(k, id)| {
            let (b, c) = (evidence[0].median[k], evidence[best].median[k]);
            let (eb, ec) = ((b - paper[k].value).abs(), (c - paper[k].value).abs());
            WithheldCell {
                cell: id.label(),
                paper: paper[k].value,
                baseline: b,
                corrected: c,
                shrinkage_percent: if eb > 0.0 {
                    100.0 * (1.0 - ec / eb)
                } else {
                    0.0
                },
            }
        })
        .collect();
    let shr: Vec<f64> = withheld.iter().map(|w| w.shrinkage_percent).collect();
    Some(GapDiagnosis {
        choose_on: choose_on.iter().map(|c| c.label()).collect(),
        chosen: evidence[best].name.clone(),
        chosen_rank_withheld: rank,
        median_shrinkage_percent: quantile(&shr, 0.5),
        candidates: evidence,
        withheld,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn predictive_density_prefers_the_candidate_near_the_paper() {
        let id = CellId {
            experiment: 1,
            kind: CellKind::Without,
        };
        let paper = PaperCell {
            value: 3.38,
            scatter: 0.2,
        };
        let near = [3.0, 3.5, 3.2, 3.9, 2.8];
        let far = [80.0, 86.0, 90.0, 75.0, 95.0];
        assert!(log_predictive(id, &near, &paper) > log_predictive(id, &far, &paper) + 50.0);
    }

    #[test]
    fn table2_likelihood_peaks_at_the_paper_spread() {
        // d/dσ² of (-ln σ² - s²/σ²) vanishes at σ = s.
        let s = [2.0];
        let at = table2_log_likelihood(&s, &[2.0]);
        assert!(at > table2_log_likelihood(&s, &[1.8]) && at > table2_log_likelihood(&s, &[2.2]));
    }
}
