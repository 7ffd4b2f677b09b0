//! One cell of the paper's Table 5: an experiment and which of its three numbers.

use serde::{Deserialize, Serialize};

/// Which number of a Table 5 row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum CellKind {
    /// Maximum horizontal error without temperature compensation (30-state set, nmi).
    Without,
    /// With temperature compensation (42-state set, nmi).
    With,
    /// Improvement (%).
    Improvement,
}

/// One cell of Table 5.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct CellId {
    /// Experiment (1-based).
    pub experiment: usize,
    /// Which number.
    pub kind: CellKind,
}

impl CellId {
    /// "exp1 without", "exp2 with", "exp3 improvement".
    pub fn label(&self) -> String {
        let k = match self.kind {
            CellKind::Without => "without",
            CellKind::With => "with",
            CellKind::Improvement => "improvement",
        };
        format!("exp{} {k}", self.experiment)
    }

    /// Parses [`Self::label`]'s form.
    pub fn parse(text: &str) -> Option<Self> {
        let (e, k) = text.trim().split_once(' ')?;
        let experiment = e.strip_prefix("exp")?.parse().ok().filter(|e| *e >= 1)?;
        let kind = match k.trim() {
            "without" => CellKind::Without,
            "with" => CellKind::With,
            "improvement" => CellKind::Improvement,
            _ => return None,
        };
        Some(Self { experiment, kind })
    }
}

/// The paper's value of a cell and its own scatter (the STD of its three experiments in that
/// column).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperCell {
    /// Value (nmi or %).
    pub value: f64,
    /// Scatter (same unit).
    pub scatter: f64,
}
