//! Turntable + thermal chamber + sensor simulator: exact angular and velocity increments of an
//! IMU on a turntable at a fixed site, passed through the truth error model (`sins-imu`), with
//! accelerometer thermal lags, thermometer noise, gyro and accelerometer noise, and laser-gyro
//! quantization. Deterministic: the same scenario and seed give bit-identical samples.
//!
//! Modules: [`motion`] (timeline, closed-form attitude and body rate), [`quadrature`]
//! (Gauss-Legendre tables), [`increments`] (exact increments), [`thermal`] (chamber and
//! accelerometer temperatures), [`noise`] (seeded noise streams), [`generator`] (the streaming
//! simulator), [`scenario`] (the input contract), [`error`].
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
