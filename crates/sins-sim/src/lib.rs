//! Turntable + thermal chamber + sensor simulator.
pub mod scenario;
