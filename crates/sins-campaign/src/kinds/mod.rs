//! The kinds of campaign: each one's work (with the `work` feature) and the shape of its outcomes.

#[cfg(feature = "work")]
pub mod blind;
#[cfg(feature = "work")]
pub mod calmc;
#[cfg(feature = "work")]
pub mod reports;
pub mod shape;
#[cfg(feature = "work")]
pub mod uq;

pub use shape::check_shape;
#[cfg(feature = "work")]
pub(crate) use shape::parse;

#[cfg(feature = "work")]
use crate::{
    CampaignError,
    spec::{Campaign, Kind},
    work::Work,
};

/// The work of a campaign.
#[cfg(feature = "work")]
pub fn load_work(campaign: &Campaign) -> Result<Box<dyn Work>, CampaignError> {
    Ok(match &campaign.kind {
        Kind::Blind { .. } => Box::new(blind::BlindWork::new(campaign)?),
        Kind::CalibrationMc { .. } => Box::new(calmc::CalMcWork::new(campaign)?),
        Kind::ReplicaUq { .. } => Box::new(uq::UqWork::new(campaign)?),
        Kind::Reports { .. } => Box::new(reports::ReportsWork::new(campaign)?),
    })
}
