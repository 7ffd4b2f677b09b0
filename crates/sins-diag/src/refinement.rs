//! What the refine stage makes of a candidate: its refined fit and the data about its final
//! linearisation point (a type of its own, so that the context that lends the refinements and
//! the refinement that reads the context do not import each other).

use crate::candidates::RegressionFit;
use crate::problem::RunFitData;
use crate::rank::Layout;
use crate::validate::OutputColumns;

/// A refined candidate and the data about its final linearisation point.
pub struct Refinement {
    /// The candidate.
    pub layout: Layout,
    /// The refined fit: `fit.theta` the estimate (candidate units, retained components),
    /// `fit.cov` its covariance from the last step, `fit.dchi2` the drop from the twin alone
    /// to the corrected runs' residual.
    pub rf: RegressionFit,
    /// The runs' fit data with the gap corrected by the effect at the linearisation point and
    /// the candidate's columns recomputed about it.
    pub data: Vec<RunFitData>,
    /// The corrected gap on each run's output grid (m).
    pub corrected_gap: Vec<Vec<[f64; 2]>>,
    /// The candidate's columns about the linearisation point, on each run's output grid.
    pub out_cols: Vec<OutputColumns>,
    /// The linearisation point (candidate units, retained components).
    pub theta_lin: Vec<f64>,
    /// Chi-square of the corrected runs at the linearisation point (before the last step).
    pub chi2_at_lin: f64,
    /// Gauss-Newton steps taken.
    pub steps: usize,
    /// The last step moved every component by less than a tenth of its sigma.
    pub converged: bool,
    /// Stopped because the predicted residual stayed above the `stop_above` given to `refine`.
    pub uncompetitive: bool,
}
