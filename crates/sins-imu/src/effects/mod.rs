//! Effects outside the paper's error model: the catalogue of candidate unmodelled terms of the
//! sim-to-real diagnosis, plus a few deliberately outside it (for blind out-of-catalogue cases).
//!
//! Each effect is a named, parameterised term applied after eqs (1)-(2) by [`crate::ForwardModel`].
//! It sees the true motion and temperatures of the sample through [`EffectContext`] and **adds** a
//! perturbation to the raw increments computed from the context alone (never from the raw
//! increments it is handed), so [`ExtraEffect::perturbation`] of a fresh effect fed the same
//! contexts reproduces exactly what the simulator added.
//!
//! - [`EffectKind`]: the fieldless list of kinds ([`EffectKind::ALL`], [`EffectKind::catalogue`]),
//!   with name, magnitude unit ([`MagnitudeUnit`]: paper-style label + SI factor), components,
//!   typical navigation-grade magnitude, [`Linearity`] and catalogue membership.
//! - [`EffectSpec`]: the data of one effect in SI (what experiment files name), with
//!   [`EffectSpec::unit`] (1 SI unit on one component), [`EffectSpec::scaled`],
//!   [`EffectSpec::magnitudes_si`] and [`EffectSpec::build`] (needs the truth parameter set: the
//!   thermal lag acts through its TB, TK, TM).
//!
//! Families, one file each: [`temperature`] (quadratic accelerometer bias, gyro bias temperature
//! coefficient, temperature-rate terms), [`thermal_lag`], [`nonlinearity`] (K2 and, outside the
//! catalogue, cross-axis coupling), [`size_effect`], [`gyro`] (scale-factor asymmetry,
//! g-sensitivity), [`timing`] (gyro-accelerometer time offset), [`random_walk`] (bias drift beyond
//! the modelled noise), [`out_of_catalogue`] (45 min gyro bias oscillation, accelerometer bias
//! step).
//!
//! Signatures that the available data cannot tell apart (the diagnosis should report them as not
//! separable rather than guess):
//! - `thermal_lag` linearised is `-τ_j` times the temperature-rate signature of the truth TB_j
//!   (`accel_bias_temp_rate` with coefficient `-τ_j TB_j`); only the TK/TM part (proportional to
//!   the specific force) separates them.
//! - `accel_quadratic_nonlinearity`, `accel_bias_quadratic_temp` or `gyro_g_sensitivity` on an axis
//!   whose specific force (or temperature) never changes is a constant bias, absorbed by the
//!   calibration; orientation (temperature) changes are needed.
//! - `gyro_bias_temp` under a monotonic temperature ramp looks like a gyro bias random walk or a
//!   trend; `accel_bias_step` and `gyro_bias_oscillation` (outside the catalogue) can partly be
//!   mimicked by the random walks.

pub mod context;
pub mod gyro;
pub mod kind;
pub mod nonlinearity;
pub mod out_of_catalogue;
pub mod random_walk;
pub mod size_effect;
pub mod spec;
pub mod temperature;
pub mod thermal_lag;
pub mod time_local;
pub mod timing;

pub use context::{ContextTracker, EffectContext};
pub use kind::{EffectKind, Linearity, MagnitudeUnit, Sensor};
pub use spec::EffectSpec;

use sins_nav::Vec3;

/// An error term that the paper's model leaves out.
pub trait ExtraEffect: Send {
    /// Stable snake_case name used in files and reports (equals [`EffectKind::name`] for the
    /// effects of this module).
    fn name(&self) -> &'static str;

    /// Perturb the raw increments of one sample (after the paper's terms): add this effect's
    /// angular (rad) and velocity (m/s) increment errors. Samples must come in time order;
    /// stateful effects (thermal lag, random walk) advance one sample per call.
    fn apply(&mut self, ctx: &EffectContext, dtheta_rad: &mut Vec3, dv_mps: &mut Vec3);

    /// The perturbation alone: what [`Self::apply`] adds to `(dtheta_rad, dv_mps)` for this
    /// sample (rad, m/s). Advances the state like [`Self::apply`].
    fn perturbation(&mut self, ctx: &EffectContext) -> (Vec3, Vec3) {
        let (mut dtheta, mut dv) = (Vec3::zeros(), Vec3::zeros());
        self.apply(ctx, &mut dtheta, &mut dv);
        (dtheta, dv)
    }

    /// [`Self::perturbation`] of consecutive samples, one per context in time order, into
    /// `out` (cleared first; rad, m/s): the same values as calling it sample by sample, with one
    /// dynamic call per batch instead of one per sample.
    fn perturbations(&mut self, ctxs: &[EffectContext], out: &mut Vec<(Vec3, Vec3)>) {
        out.clear();
        out.extend(ctxs.iter().map(|c| self.perturbation(c)));
    }

    /// Return to the state before the first sample (a no-op for stateless effects), so that a
    /// second pass over the same samples gives the same perturbations.
    fn reset(&mut self) {}
}

#[cfg(test)]
mod tests;
