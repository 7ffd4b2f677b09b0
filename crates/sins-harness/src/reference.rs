//! The paper's Table 5 (maximum horizontal error of its three 15 h experiments with and without
//! temperature compensation) as data. The file
//! (`experiments/reference/table5_navigation_results.csv`) is read by `sins_config::load_table5`.

use serde::{Deserialize, Serialize};

/// One row of the paper's Table 5.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperRow {
    /// Experiment number (1-based).
    pub experiment: u32,
    /// Maximum horizontal error with temperature compensation (nmi).
    pub with_compensation_nmi: f64,
    /// Maximum horizontal error without it (nmi).
    pub without_compensation_nmi: f64,
    /// Improvement (%).
    pub improvement_percent: f64,
}
