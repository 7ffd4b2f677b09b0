#![doc = include_str!("../README.md")]

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
