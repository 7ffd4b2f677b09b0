//! The study's results as one serialisable summary: per Table 5 cell the point replica, the
//! Monte Carlo median and 5-95 % interval with their bootstrap errors, the V&V 20 comparison,
//! the first-order Sobol indices; Table 2 against the replica's spread; the gap diagnosis.
//! Everything is a function of the sorted sample outcomes, so the summary is identical whatever
//! the thread count or sharding.

use crate::assumptions::{AssumptionSet, Distribution};
use crate::gap::{CandidateCells, GapDiagnosis, diagnose};
use crate::sample::SampleOutcome;
use crate::sobol::{GroupIndex, design_rows, group_indices};
use crate::stats::{self, IndexInterval, bootstrap_quantile_se, mean_sd, quantile};
use crate::vv::Validation;
use crate::{NMI_M, UqError};
use serde::{Deserialize, Serialize};

/// Schema version of [`UqSummary`].
pub const UQ_SCHEMA: u32 = 1;
/// Bootstrap resamples for quantile errors and Sobol intervals.
pub const BOOTSTRAP_RESAMPLES: usize = 400;
/// Permutations behind each first-order index's p-value (999: the smallest p, 0.001, can pass
/// a false-discovery control over about 50 assumptions).
pub const PERMUTATIONS: usize = 999;
/// False-discovery rate of the per-cell Benjamini-Hochberg selection of influential assumptions.
pub const FDR: f64 = 0.1;
/// The replay's error-free floor over the paper's 15 h run (m): the numerical uncertainty of a
/// single replay.
pub const FLOOR_M: f64 = 0.3;

pub use crate::cell::{CellId, CellKind, PaperCell};

/// The value of a cell in a sample (here: it needs the sample's outcome).
impl CellId {
    /// The cell's value in a sample (nmi or %), NaN when the sample has no such run.
    pub fn value(&self, o: &SampleOutcome) -> f64 {
        let Some([e30, e42]) = o.max_horizontal_m.get(self.experiment - 1) else {
            return f64::NAN;
        };
        match self.kind {
            CellKind::Without => e30 / NMI_M,
            CellKind::With => e42 / NMI_M,
            CellKind::Improvement => 100.0 * (e30 - e42) / e30,
        }
    }
}

/// Every cell of `runs` experiments: without, with, improvement per experiment.
pub fn all_cells(runs: usize) -> Vec<CellId> {
    (1..=runs)
        .flat_map(|experiment| {
            [CellKind::Without, CellKind::With, CellKind::Improvement]
                .map(|kind| CellId { experiment, kind })
        })
        .collect()
}

/// One group of Table 2: coefficient indices (state order of eq 8), unit and the paper's STDs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Table2Group {
    /// The paper's row name.
    pub name: String,
    /// Paper unit label.
    pub unit: String,
    /// SI value of one unit.
    pub unit_si: f64,
    /// Coefficient indices in state order.
    pub indices: Vec<usize>,
    /// The paper's STD of each (paper units).
    pub paper_std: Vec<f64>,
}

/// The paper's data the study compares with.
#[derive(Clone, Debug, PartialEq)]
pub struct PaperData {
    /// Table 5 per cell, aligned with [`all_cells`] of the replica's runs.
    pub cells: Vec<PaperCell>,
    /// Table 2.
    pub table2: Vec<Table2Group>,
}

/// One cell's results.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CellSummary {
    /// "exp1 without" etc.
    pub cell: String,
    /// The point replica (`sinsbench report`).
    pub point: f64,
    /// Monte Carlo median.
    pub median: f64,
    /// 5 % quantile.
    pub p05: f64,
    /// 95 % quantile.
    pub p95: f64,
    /// Bootstrap standard errors of the 5 %, 50 % and 95 % quantiles.
    pub bootstrap_se: [f64; 3],
    /// The V&V 20 comparison (when the paper has the cell).
    pub validation: Option<Validation>,
    /// First-order Sobol indices of the assumptions (given-data estimator).
    pub sensitivity: Option<CellSensitivity>,
    /// The cell per level of its dominant choice assumption (a discovered choice with a
    /// first-order index of at least [`DOMINANT_INDEX`]): a bimodal cell's median falls between
    /// its modes, so each mode's interval is the useful prediction.
    #[serde(default)]
    pub by_level: Vec<LevelSummary>,
}

/// First-order index from which a discovered choice assumption splits a cell by level.
pub const DOMINANT_INDEX: f64 = 0.5;

/// A cell conditional on one level of a choice assumption.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LevelSummary {
    /// The choice assumption.
    pub assumption: String,
    /// The level's label.
    pub level: String,
    /// Main samples at this level.
    pub samples: usize,
    /// Median.
    pub median: f64,
    /// 5 % quantile.
    pub p05: f64,
    /// 95 % quantile.
    pub p95: f64,
    /// Bootstrap standard error of the median.
    pub median_se: f64,
    /// The V&V 20 comparison of this level alone with the paper (when the paper has the
    /// cell): a bimodal cell's u_input spans both modes, so only a level's comparison can be
    /// informative.
    #[serde(default)]
    pub validation: Option<Validation>,
}

/// Global sensitivity of one cell.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CellSensitivity {
    /// Sum of the first-order indices: 1 minus it is the share of interactions, per-element
    /// draws (vibration phases) and sensor-noise seeds.
    pub sum_first_order: f64,
    /// Per assumption that varies: its first-order index with a 90 % bootstrap interval,
    /// largest first.
    pub inputs: Vec<InputIndex>,
    /// Per group (the file's groups and the noise realisation): first-order and total indices
    /// from the pick-freeze design, when it ran (`pick_freeze_samples` > 0).
    #[serde(default)]
    pub groups: Vec<GroupIndex>,
}

/// One assumption's first-order Sobol index.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct InputIndex {
    /// Assumption name.
    pub name: String,
    /// Its group.
    pub group: String,
    /// First-order index.
    pub first_order: f64,
    /// 5 % bootstrap quantile.
    pub low: f64,
    /// 95 % bootstrap quantile.
    pub high: f64,
    /// Permutation p-value against "the cell does not depend on it"
    /// ([`stats::first_order_permutation_p`], [`PERMUTATIONS`] reorderings).
    #[serde(default)]
    pub p_value: f64,
    /// Influential at false-discovery rate [`FDR`] over the cell's assumptions
    /// (Benjamini-Hochberg on the p-values).
    #[serde(default)]
    pub discovered: bool,
}

/// Table 2 against the replica.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Table2Row {
    /// Group name.
    pub name: String,
    /// Unit.
    pub unit: String,
    /// The paper's STDs.
    pub paper: Vec<f64>,
    /// The replica's spread of the 42-state estimate minus truth over the main Monte Carlo.
    pub replica: Vec<f64>,
}

/// An assumption as the summary shows it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AssumptionInfo {
    /// Name.
    pub name: String,
    /// Group.
    pub group: String,
    /// Distribution in the file's unit.
    pub distribution: String,
    /// Justification.
    pub justification: String,
}

/// Everything the study found.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UqSummary {
    /// [`UQ_SCHEMA`].
    pub schema: u32,
    /// The program and version that made it (e.g. "sinsbench 0.1.0"; empty in older files).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub generated_by: String,
    /// Master seed.
    pub seed: u64,
    /// Main Monte Carlo samples.
    pub samples: usize,
    /// Rows of the pick-freeze design behind the grouped indices (0: not run).
    #[serde(default)]
    pub pick_freeze_samples: usize,
    /// The assumptions.
    pub assumptions: Vec<AssumptionInfo>,
    /// Per cell.
    pub cells: Vec<CellSummary>,
    /// Table 2 comparison.
    pub table2: Vec<Table2Row>,
    /// The gap diagnosis.
    pub gap: Option<GapDiagnosis>,
}

/// Describes a distribution in the assumption's file unit.
pub fn describe(d: &Distribution, unit: &str, unit_si: f64) -> String {
    let u = |v: f64| format!("{}", sig(v / unit_si));
    match d {
        Distribution::Fixed(v) => format!("fixed {} {unit}", u(*v)),
        Distribution::Uniform { low, high } => {
            format!("uniform [{}, {}] {unit}", u(*low), u(*high))
        }
        Distribution::LogUniform { low, high } => {
            format!("log-uniform [{}, {}] {unit}", u(*low), u(*high))
        }
        Distribution::Normal { mean, sd } => format!("normal({}, sd {}) {unit}", u(*mean), u(*sd)),
        Distribution::Choice { labels, weights } => {
            let t: f64 = weights.iter().sum();
            let parts: Vec<String> = labels
                .iter()
                .zip(weights)
                .map(|(l, w)| format!("{l} {:.0} %", 100.0 * w / t))
                .collect();
            format!("choice: {}", parts.join(", "))
        }
    }
}

/// Six significant digits (so the summary reads back as written).
fn sig(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let scale = 10f64.powi(5 - v.abs().log10().floor() as i32);
    (v * scale).round() / scale
}

/// Builds the summary from every sample (any order: they are sorted here).
pub fn summarize(
    set: &AssumptionSet,
    outcomes: &[SampleOutcome],
    paper: &PaperData,
) -> Result<UqSummary, UqError> {
    let pick = |study: &str| {
        let mut v: Vec<&SampleOutcome> = outcomes.iter().filter(|o| o.study == study).collect();
        v.sort_by_key(|o| o.index);
        v
    };
    let main = pick("replica");
    let point = pick("point");
    if main.len() < 4 {
        return Err(UqError::TooFewSamples {
            what: "the main Monte Carlo".into(),
            needed: 4,
            got: main.len(),
        });
    }
    let runs = main[0].max_horizontal_m.len();
    let ids = all_cells(runs);
    let inputs = varying_inputs(set, &main);
    let mut cells: Vec<CellSummary> = ids
        .iter()
        .enumerate()
        .map(|(k, id)| {
            let vals: Vec<f64> = main.iter().map(|o| id.value(o)).collect();
            cell_summary(
                set,
                *id,
                k,
                &vals,
                point.first().map(|o| id.value(o)),
                paper.cells.get(k),
                &inputs,
            )
        })
        .collect();
    let rows = design_rows(set, outcomes);
    for (k, (id, cell)) in ids.iter().zip(&mut cells).enumerate() {
        if let Some(sens) = &mut cell.sensitivity {
            let value = |o: &SampleOutcome| crate::gap::transform(*id, id.value(o));
            let seed = set.seed ^ (0x50b0_0000 + k as u64);
            sens.groups = group_indices(set, &rows, &value, BOOTSTRAP_RESAMPLES, seed);
        }
    }
    let table2 = paper
        .table2
        .iter()
        .map(|g| Table2Row {
            name: g.name.clone(),
            unit: g.unit.clone(),
            paper: g.paper_std.clone(),
            replica: table2_sigma(&main, g),
        })
        .collect();
    let gap = gap_diagnosis(set, paper, &ids, &pick);
    Ok(UqSummary {
        schema: UQ_SCHEMA,
        generated_by: format!("sins-uq {}", env!("CARGO_PKG_VERSION")),
        seed: set.seed,
        samples: main.len(),
        pick_freeze_samples: rows.len(),
        assumptions: set
            .assumptions
            .iter()
            .map(|a| AssumptionInfo {
                name: a.name.clone(),
                group: a.group.clone(),
                distribution: describe(&a.distribution, &a.unit, a.unit_si),
                justification: a.justification.clone(),
            })
            .collect(),
        cells,
        table2,
        gap,
    })
}

fn table2_sigma(samples: &[&SampleOutcome], g: &Table2Group) -> Vec<f64> {
    g.indices
        .iter()
        .map(|&i| {
            let v: Vec<f64> = samples
                .iter()
                .filter_map(|o| o.error42.get(i).copied())
                .collect();
            mean_sd(&v).1 / g.unit_si
        })
        .collect()
}

/// The assumptions that vary from sample to sample (per-element ones excluded), with their
/// drawn values over the main Monte Carlo.
struct Inputs {
    columns: Vec<(String, String, bool, Vec<f64>)>,
}

fn varying_inputs(set: &AssumptionSet, main: &[&SampleOutcome]) -> Inputs {
    let columns = set
        .assumptions
        .iter()
        .enumerate()
        .filter(|(_, a)| !a.knob.is_per_element() && a.distribution.varies())
        .map(|(i, a)| {
            let v = main.iter().map(|o| o.values[i].unwrap_or(0.0)).collect();
            (
                a.name.clone(),
                a.group.clone(),
                a.distribution.labels().is_some(),
                v,
            )
        })
        .collect();
    Inputs { columns }
}

fn cell_summary(
    set: &AssumptionSet,
    id: CellId,
    k: usize,
    vals: &[f64],
    point: Option<f64>,
    paper: Option<&PaperCell>,
    inputs: &Inputs,
) -> CellSummary {
    let seed = set.seed ^ (0x5eed_0000 + k as u64);
    let se = bootstrap_quantile_se(vals, &[0.05, 0.5, 0.95], BOOTSTRAP_RESAMPLES, seed);
    let median = quantile(vals, 0.5);
    let floor = match id.kind {
        CellKind::Improvement => 0.0,
        _ => FLOOR_M / NMI_M,
    };
    let validation = paper.map(|p| {
        Validation::new(
            median,
            p.value,
            se[1].hypot(floor),
            mean_sd(vals).1,
            p.scatter,
        )
    });
    let y: Vec<f64> = vals.iter().map(|v| crate::gap::transform(id, *v)).collect();
    let sensitivity = (!inputs.columns.is_empty()).then(|| {
        let mut list: Vec<InputIndex> = inputs
            .columns
            .iter()
            .enumerate()
            .map(|(j, (name, group, choice, x))| {
                let i: IndexInterval = stats::first_order_bootstrap(
                    x,
                    &y,
                    *choice,
                    BOOTSTRAP_RESAMPLES / 2,
                    seed ^ ((j as u64) << 20),
                );
                let p_value = stats::first_order_permutation_p(
                    x,
                    &y,
                    *choice,
                    PERMUTATIONS,
                    seed ^ ((j as u64) << 20),
                );
                InputIndex {
                    name: name.clone(),
                    group: group.clone(),
                    first_order: i.value,
                    low: i.low,
                    high: i.high,
                    p_value: sig(p_value),
                    discovered: false,
                }
            })
            .collect();
        let p: Vec<f64> = list.iter().map(|i| i.p_value).collect();
        for (i, d) in list.iter_mut().zip(stats::benjamini_hochberg(&p, FDR)) {
            i.discovered = d;
        }
        list.sort_by(|a, b| {
            b.first_order
                .total_cmp(&a.first_order)
                .then(a.name.cmp(&b.name))
        });
        CellSensitivity {
            sum_first_order: list.iter().map(|g| g.first_order).sum(),
            inputs: list,
            groups: Vec::new(),
        }
    });
    CellSummary {
        cell: id.label(),
        point: point.unwrap_or(f64::NAN),
        median,
        p05: quantile(vals, 0.05),
        p95: quantile(vals, 0.95),
        bootstrap_se: [se[0], se[1], se[2]],
        by_level: by_level(set, inputs, sensitivity.as_ref(), vals, seed)
            .into_iter()
            .map(|l| {
                let mut level = l.summary;
                level.validation = paper.map(|p| {
                    Validation::new(
                        level.median,
                        p.value,
                        level.median_se.hypot(floor),
                        l.sd,
                        p.scatter,
                    )
                });
                level
            })
            .collect(),
        validation,
        sensitivity,
    }
}

/// [`CellSummary::by_level`]: the cell's values split by the levels of its leading assumption
/// when that is a discovered choice with index >= [`DOMINANT_INDEX`].
/// A level's summary and the standard deviation of its values (its u_input).
struct LevelValues {
    summary: LevelSummary,
    sd: f64,
}

fn by_level(
    set: &AssumptionSet,
    inputs: &Inputs,
    sens: Option<&CellSensitivity>,
    vals: &[f64],
    seed: u64,
) -> Vec<LevelValues> {
    let Some(top) = sens.and_then(|s| s.inputs.first()) else {
        return Vec::new();
    };
    let labels = set
        .assumptions
        .iter()
        .find(|a| a.name == top.name)
        .and_then(|a| a.distribution.labels());
    let column = inputs.columns.iter().find(|c| c.0 == top.name);
    let (Some(labels), Some(column)) = (labels, column) else {
        return Vec::new();
    };
    if !top.discovered || top.first_order < DOMINANT_INDEX {
        return Vec::new();
    }
    labels
        .iter()
        .enumerate()
        .filter_map(|(level, label)| {
            let v: Vec<f64> = column
                .3
                .iter()
                .zip(vals)
                .filter(|(x, _)| **x == level as f64)
                .map(|(_, v)| *v)
                .collect();
            (v.len() >= 2).then(|| LevelValues {
                summary: LevelSummary {
                    assumption: top.name.clone(),
                    level: label.clone(),
                    samples: v.len(),
                    median: sig(quantile(&v, 0.5)),
                    p05: sig(quantile(&v, 0.05)),
                    p95: sig(quantile(&v, 0.95)),
                    median_se: sig(bootstrap_quantile_se(
                        &v,
                        &[0.5],
                        BOOTSTRAP_RESAMPLES,
                        seed ^ level as u64,
                    )[0]),
                    validation: None,
                },
                sd: mean_sd(&v).1,
            })
        })
        .collect()
}

fn gap_diagnosis<'a>(
    set: &AssumptionSet,
    paper: &PaperData,
    ids: &[CellId],
    pick: &dyn Fn(&str) -> Vec<&'a SampleOutcome>,
) -> Option<GapDiagnosis> {
    if paper.cells.len() != ids.len() {
        return None;
    }
    let studies: Vec<(String, Vec<&SampleOutcome>)> = set
        .candidates
        .iter()
        .map(|c| (c.name.clone(), pick(&c.name)))
        .filter(|(_, s)| s.len() >= 2)
        .collect();
    let cands: Vec<CandidateCells<'_>> = studies
        .iter()
        .map(|(name, s)| CandidateCells {
            name,
            cells: ids
                .iter()
                .map(|id| s.iter().map(|o| id.value(o)).collect())
                .collect(),
            table2_sigma: paper
                .table2
                .iter()
                .flat_map(|g| table2_sigma(s, g))
                .collect(),
        })
        .collect();
    let table2: Vec<f64> = paper
        .table2
        .iter()
        .flat_map(|g| g.paper_std.iter().copied())
        .collect();
    diagnose(ids, &paper.cells, &cands, &set.choose_on, &table2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assumptions::{Assumption, Knob};
    use crate::cell::{CellKind, PaperCell};
    use crate::vv::VvWord;

    fn set() -> AssumptionSet {
        AssumptionSet {
            assumptions: vec![Assumption {
                name: "chamber".into(),
                knob: Knob::Cal30Chamber,
                distribution: Distribution::Choice {
                    labels: vec!["ramp".into(), "stable".into()],
                    weights: vec![1.0, 1.0],
                },
                group: "g".into(),
                unit: String::new(),
                unit_si: 1.0,
                justification: "t".into(),
            }],
            candidates: vec![],
            samples: 40,
            pick_freeze_samples: 0,
            seed: 1,
            choose_on: vec![],
        }
    }

    fn sens(first_order: f64, discovered: bool) -> CellSensitivity {
        CellSensitivity {
            sum_first_order: first_order,
            inputs: vec![InputIndex {
                name: "chamber".into(),
                group: "g".into(),
                first_order,
                low: 0.0,
                high: 1.0,
                p_value: 0.001,
                discovered,
            }],
            groups: vec![],
        }
    }

    /// Even samples "ramp" at 50 + k nmi, odd ones "stable" at 1 + k / 100 (k = 0..19).
    fn bimodal() -> (Inputs, Vec<f64>) {
        let x: Vec<f64> = (0..40).map(|i| (i % 2) as f64).collect();
        let vals: Vec<f64> = (0..40)
            .map(|i| {
                let k = (i / 2) as f64;
                if i % 2 == 0 {
                    50.0 + k
                } else {
                    1.0 + k / 100.0
                }
            })
            .collect();
        let inputs = Inputs {
            columns: vec![("chamber".into(), "g".into(), true, x)],
        };
        (inputs, vals)
    }

    #[test]
    fn a_bimodal_cell_is_compared_with_the_paper_level_by_level() {
        // "ramp" near 60 nmi, "stable" near 1.1 nmi; the paper says 1.1 ± 0.1.
        let (inputs, vals) = bimodal();
        let id = CellId {
            experiment: 1,
            kind: CellKind::Without,
        };
        let paper = PaperCell {
            value: 1.1,
            scatter: 0.1,
        };
        let c = cell_summary(&set(), id, 0, &vals, None, Some(&paper), &inputs);
        // The whole cell spans both modes: u_input ~ 27 nmi bounds nothing about a 1.1 nmi cell.
        assert_eq!(
            c.validation.as_ref().map(|v| v.word),
            Some(VvWord::NotInformative)
        );
        assert_eq!(c.by_level.len(), 2, "{:?}", c.by_level);
        let word = |l: &LevelSummary| l.validation.as_ref().map(|v| v.word);
        // The stable level: E = -0.005, u_val about 0.12, validated; the ramp level is a model
        // error of about 58 nmi.
        assert_eq!(
            word(&c.by_level[1]),
            Some(VvWord::Validated),
            "{:?}",
            c.by_level[1]
        );
        assert_eq!(
            word(&c.by_level[0]),
            Some(VvWord::ModelError),
            "{:?}",
            c.by_level[0]
        );
    }

    #[test]
    fn a_dominant_choice_splits_the_cell_by_level() {
        let (inputs, vals) = bimodal();
        let levels: Vec<LevelSummary> = by_level(&set(), &inputs, Some(&sens(0.9, true)), &vals, 3)
            .into_iter()
            .map(|l| l.summary)
            .collect();
        assert_eq!(levels.len(), 2);
        assert_eq!((levels[0].level.as_str(), levels[0].samples), ("ramp", 20));
        assert!((levels[0].median - 59.5).abs() < 1e-9, "{:?}", levels[0]);
        assert!((levels[1].median - 1.095).abs() < 1e-9, "{:?}", levels[1]);
        assert!(levels[1].p05 >= 1.0 && levels[1].p95 <= 1.19);
        // Not discovered, or not dominant: no split.
        assert!(by_level(&set(), &inputs, Some(&sens(0.9, false)), &vals, 3).is_empty());
        assert!(by_level(&set(), &inputs, Some(&sens(0.3, true)), &vals, 3).is_empty());
    }
}
