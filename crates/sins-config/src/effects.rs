//! `[[imu.effect]]` tables: effects outside the paper's model, switched on per experiment.

use crate::ctx::Ctx;
use crate::error::ConfigError;
use serde::Deserialize;
use sins_imu::EffectSpec;
use sins_nav::{DEG_PER_H, UG, Vec3};

/// One `[[imu.effect]]` table in file units.
#[derive(Deserialize)]
#[serde(tag = "kind", deny_unknown_fields)]
pub(crate) enum EffectFile {
    /// Accelerometer bias ∝ (T − T_ref)² per axis.
    #[serde(rename = "accel_bias_quadratic_temp")]
    AccelBiasQuadraticTemp {
        coeff_ug_per_degc2: [f64; 3],
        reference_degc: f64,
    },
    /// Gyro bias ∝ (T − T_ref) per axis (mean accelerometer temperature).
    #[serde(rename = "gyro_bias_temp")]
    GyroBiasTemp {
        coeff_deg_per_h_per_degc: [f64; 3],
        reference_degc: f64,
    },
}

/// Convert the effect tables to SI specs, naming `imu.effect[i].<key>` on bad values.
pub(crate) fn build_effects(
    ctx: &Ctx<'_>,
    files: &[EffectFile],
) -> Result<Vec<EffectSpec>, ConfigError> {
    files
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let k = |name: &str| format!("imu.effect[{i}].{name}");
            Ok(match e {
                EffectFile::AccelBiasQuadraticTemp {
                    coeff_ug_per_degc2,
                    reference_degc,
                } => {
                    let c = ctx.finite3(&k("coeff_ug_per_degc2"), *coeff_ug_per_degc2)?;
                    EffectSpec::AccelBiasQuadraticTemp {
                        coeff_mps2_per_degc2: Vec3::from(c) * UG,
                        reference_degc: ctx.finite(&k("reference_degc"), *reference_degc)?,
                    }
                }
                EffectFile::GyroBiasTemp {
                    coeff_deg_per_h_per_degc,
                    reference_degc,
                } => {
                    let c =
                        ctx.finite3(&k("coeff_deg_per_h_per_degc"), *coeff_deg_per_h_per_degc)?;
                    EffectSpec::GyroBiasTemp {
                        coeff_radps_per_degc: Vec3::from(c) * DEG_PER_H,
                        reference_degc: ctx.finite(&k("reference_degc"), *reference_degc)?,
                    }
                }
            })
        })
        .collect()
}
