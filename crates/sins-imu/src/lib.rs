//! The IMU error model of Wang et al. 2021, "A system-level calibration method including
//! temperature-related error coefficients for a SINS": the forward model of eqs (1)-(2) that a
//! simulator applies to true increments, its exact inverse (the compensation of eqs (3)-(5)) that a
//! calibrated system applies to raw increments, the 30- and 42-state parameter sets in SI units,
//! and the hook through which effects outside the paper's model are added.

pub mod effects;
pub mod model;
pub mod params;
pub mod sample;

pub use effects::{
    ContextTracker, EffectContext, EffectKind, EffectSpec, ExtraEffect, Linearity, MagnitudeUnit,
};
pub use model::{Compensator, ForwardModel};
pub use params::{AccelParams, GyroParams, ImuErrorParams, ParamModel, TemperatureCoeffs};
pub use sample::ImuSample;
