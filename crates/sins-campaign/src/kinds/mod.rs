//! The kinds of campaign.

pub mod blind;
pub mod calmc;
pub mod reports;
pub mod uq;
