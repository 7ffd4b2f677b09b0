//! The kinds of campaign.

pub mod blind;
pub mod calmc;
pub mod reports;
pub mod uq;

use crate::CampaignError;
use crate::spec::{Campaign, Kind};
use crate::work::Work;

/// The work of a campaign.
pub fn load_work(campaign: &Campaign) -> Result<Box<dyn Work>, CampaignError> {
    Ok(match &campaign.kind {
        Kind::Blind { .. } => Box::new(blind::BlindWork::new(campaign)?),
        Kind::CalibrationMc { .. } => Box::new(calmc::CalMcWork::new(campaign)?),
        Kind::ReplicaUq { .. } => Box::new(uq::UqWork::new(campaign)?),
        Kind::Reports { .. } => Box::new(reports::ReportsWork::new(campaign)?),
    })
}
