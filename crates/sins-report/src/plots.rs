//! PNG plots of one experiment (filled in with sins-plot).

use crate::ReportError;
use crate::run::ResolvedSet;
use sins_harness::pipeline::RunOutcome;

/// The plots of one experiment as (name, PNG bytes).
pub(crate) fn render(
    _o: &RunOutcome,
    _sets: &[ResolvedSet],
) -> Result<Vec<(&'static str, Vec<u8>)>, ReportError> {
    Ok(Vec::new())
}
