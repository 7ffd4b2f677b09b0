//! The one context of the diagnosis's stages: what every stage after the ranking reads and none
//! changes. It is made once the gaps are ranked, from the twin's and the gap stage's values, and
//! given the refined candidates once the refinement has made them.

use crate::absorb::Absorption;
use crate::catalogue::Catalogue;
use crate::input::DiagnoseConfig;
use crate::localise::GapSeries;
use crate::problem::{Problem, RunFitData};
use crate::rank::{Layout, NullDist, TestContext};
use crate::refinement::Refinement;
use crate::sensitivity::RunSensitivity;
use sins_imu::EffectKind;

/// What the stages read of the diagnosis so far (every slice in the input's run order).
#[derive(Clone, Copy)]
pub(crate) struct Context<'a> {
    /// The configuration (its grids already fitted to the runs' length).
    pub cfg: &'a DiagnoseConfig,
    /// The candidate kinds.
    pub kinds: &'a [EffectKind],
    /// Deterministic candidates: their columns among the candidate columns.
    pub layouts: &'a [Layout],
    /// Random-walk candidates: kind and first bias axis (0 gyro, 3 accelerometer).
    pub walks: &'a [(EffectKind, usize)],
    /// Sensitivity passes, one per run (the calibration run's absorption folded in).
    pub sens: &'a [RunSensitivity],
    /// How the calibration absorbs the candidates, when a calibration run was given.
    pub absorption: Option<&'a Absorption>,
    /// Gap series on the output grid, one per run.
    pub series: &'a [GapSeries],
    /// Fit data on the fit grid, one per run.
    pub data: &'a [RunFitData],
    /// The runs' stacked fit problem.
    pub problem: &'a Problem,
    /// Its null distribution (the twin alone).
    pub dist: &'a NullDist,
    /// The number of data, the twin-alone chi-square and the catalogue's number of tests.
    pub tests: TestContext,
    /// The part of the metric's floor that the data are not expected to carry (m²).
    pub floor_var: f64,
    /// The refined candidates (empty until the refinement stage has run).
    pub refinements: &'a [Refinement],
}

/// The gap stage's values that the context lends.
pub(crate) struct GapFit {
    /// Gap series on the output grid, one per run.
    pub series: Vec<GapSeries>,
    /// Fit data on the fit grid, one per run.
    pub data: Vec<RunFitData>,
    /// The part of the metric's floor that the data are not expected to carry (m²).
    pub floor_var: f64,
    /// The runs' stacked fit problem.
    pub problem: Problem,
    /// Its null distribution.
    pub dist: NullDist,
}

impl<'a> Context<'a> {
    /// The context of the twin's catalogue, sensitivities and absorption and of the gaps `fit`,
    /// before any refinement.
    pub fn new(
        cfg: &'a DiagnoseConfig,
        kinds: &'a [EffectKind],
        cat: &'a Catalogue,
        sens: &'a [RunSensitivity],
        absorption: Option<&'a Absorption>,
        fit: &'a GapFit,
    ) -> Self {
        Self {
            cfg,
            kinds,
            layouts: &cat.layouts,
            walks: &cat.walks,
            sens,
            absorption,
            series: &fit.series,
            data: &fit.data,
            problem: &fit.problem,
            dist: &fit.dist,
            tests: TestContext::new(&fit.problem, &cat.layouts, &cat.walks),
            floor_var: fit.floor_var,
            refinements: &[],
        }
    }

    /// This context with the refined candidates.
    pub fn with_refinements(self, refinements: &'a [Refinement]) -> Self {
        Self {
            refinements,
            ..self
        }
    }
}
