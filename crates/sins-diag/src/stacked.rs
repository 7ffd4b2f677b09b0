//! Every run's whitened signals held at once, stacked run after run: what the rival fit and the
//! confound measure need (a time course common to every run is one direction across all
//! runs). Runs are whitened one by one with their own covariance (the scan's whitening; the
//! calibration uncertainty common to the runs is kept within each run, not across them).

use crate::error::DiagError;
use crate::events::{EventScanConfig, Prepared, ScanRun, prepare};
use nalgebra::DVector;

/// The prepared runs and where each run's rows sit in the stacked vector.
pub(crate) struct Stacked {
    /// Prepared runs (whitened step signals, the whitened residual).
    pub runs: Vec<Prepared>,
    /// First stacked row of each run.
    pub offsets: Vec<usize>,
    /// Stacked rows.
    pub rows: usize,
    /// Onsets every run has, at the same time since its start: a common time course is
    /// defined on these.
    pub common_onsets: usize,
}

impl Stacked {
    /// Prepare `runs` (see [`crate::events`]).
    pub fn new(runs: &[ScanRun<'_>], cfg: &EventScanConfig) -> Result<Self, DiagError> {
        let runs: Vec<Prepared> = runs
            .iter()
            .map(|r| prepare(r, cfg))
            .collect::<Result<_, _>>()?;
        let mut offsets = Vec::with_capacity(runs.len());
        let mut rows = 0;
        for p in &runs {
            offsets.push(rows);
            rows += p.residual.len();
        }
        let first = &runs[0];
        let common_onsets = (0..first.onset_s.len())
            .take_while(|&m| {
                runs.iter().all(|p| {
                    p.onset_s.get(m).is_some_and(|t| {
                        ((t - p.start_s) - (first.onset_s[m] - first.start_s)).abs() < 1e-6
                    })
                })
            })
            .count();
        Ok(Self {
            runs,
            offsets,
            rows,
            common_onsets,
        })
    }

    /// Take `runs` (the same runs): their residuals, nuisances and candidates, whitened again
    /// where a run's covariance changed.
    pub fn take(&mut self, runs: &[ScanRun<'_>], cfg: &EventScanConfig) -> Result<(), DiagError> {
        for (p, r) in self.runs.iter_mut().zip(runs) {
            p.take(r, cfg)?;
        }
        Ok(())
    }

    /// The stacked whitened residual.
    pub fn residual(&self) -> DVector<f64> {
        let mut out = DVector::zeros(self.rows);
        for (p, &o) in self.runs.iter().zip(&self.offsets) {
            out.rows_mut(o, p.residual.len()).copy_from(&p.residual);
        }
        out
    }

    /// Run `run`'s block of a stacked vector.
    pub fn block(&self, run: usize, x: &DVector<f64>) -> DVector<f64> {
        x.rows(self.offsets[run], self.runs[run].residual.len())
            .into_owned()
    }
}
