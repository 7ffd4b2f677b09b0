//! Sim-to-real gap diagnosis (work in progress).
pub mod align;
pub mod bank;
pub mod columns;
pub mod error;
pub mod model;
pub mod noise;
pub mod pass;
pub mod replay;
pub mod sensitivity;
pub mod source;
pub mod temperature;

pub use error::DiagError;
pub mod candidates;
pub mod diagnose;
pub mod gls;
pub mod input;
pub mod localise;
pub mod problem;
pub mod rank;
pub mod report;
pub mod stats;
pub mod validate;
