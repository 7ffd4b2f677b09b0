#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod error;
pub mod gaussian;
pub mod generator;
pub mod increments;
pub mod motion;
pub mod noise;
pub mod quadrature;
pub mod scenario;
pub mod thermal;
mod trig;
mod vibration;

pub use error::SimError;
pub use generator::{ReferenceState, SimBatch, Simulator, simulate_to_vec};
pub use increments::IncrementIntegrator;
pub use motion::{MotionState, MotionTimeline};
pub use noise::{GaussMarkov, GaussianStream, Quantizer, SensorNoise};
pub use quadrature::gauss_legendre_unit;
pub use scenario::{
    ChamberSegment, MotionProgram, MotionSegment, NoiseModel, Scenario, ThermalModel,
};
pub use thermal::{AccelThermal, ChamberProfile, Thermometers};
