//! The kinds of campaign.

pub mod blind;
pub mod calmc;
pub mod reports;
pub mod uq;

use crate::CampaignError;
use crate::spec::{Campaign, Kind};
use crate::work::Work;
use serde::de::DeserializeOwned;

/// The work of a campaign.
pub fn load_work(campaign: &Campaign) -> Result<Box<dyn Work>, CampaignError> {
    Ok(match &campaign.kind {
        Kind::Blind { .. } => Box::new(blind::BlindWork::new(campaign)?),
        Kind::CalibrationMc { .. } => Box::new(calmc::CalMcWork::new(campaign)?),
        Kind::ReplicaUq { .. } => Box::new(uq::UqWork::new(campaign)?),
        Kind::Reports { .. } => Box::new(reports::ReportsWork::new(campaign)?),
    })
}

/// Checks that `outcome` has the shape of an outcome of the campaign kind named `kind` (what
/// the files alone can tell: it parses, its arrays have their fixed lengths); a kind's
/// [`Work::check_outcome`] checks it against its job. An unknown kind checks nothing (the
/// manifest holding it cannot be opened).
pub fn check_shape(kind: &str, outcome: &serde_json::Value) -> Result<(), String> {
    match kind {
        "blind" => parse::<sins_diag::report::Diagnosis>(outcome).map(drop),
        "calibration-mc" => calmc::check_shape(&parse(outcome)?),
        "replica-uq" => uq::check_shape(&parse(outcome)?),
        "reports" => parse::<sins_harness::summary::Summary>(outcome).map(drop),
        _ => Ok(()),
    }
}

/// An outcome as its kind's type, or what does not parse.
pub(crate) fn parse<T: DeserializeOwned>(outcome: &serde_json::Value) -> Result<T, String> {
    T::deserialize(outcome).map_err(|e| format!("does not parse ({e})"))
}

/// An array's length against the one it must have.
pub(crate) fn check_len(name: &str, len: usize, want: usize, what: &str) -> Result<(), String> {
    if len == want {
        return Ok(());
    }
    Err(format!("{name} has {len} values where {what} has {want}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_checks_the_shape_of_its_outcomes() {
        for kind in crate::spec::KINDS {
            assert!(
                check_shape(kind, &serde_json::Value::Null).is_err(),
                "{kind}"
            );
        }
    }
}
