//! The linear sensitivities (alignment replica + binned linear error model) against the
//! nonlinear pipeline: simulate with the effect, replay with self-alignment, difference with
//! the same run without it.

use crate::common;
use common::*;
use sins_diag::Grid;
use sins_diag::noise::NoiseSpec;
use sins_diag::replay::RealTrack;
use sins_diag::sensitivity::ColumnId;
use sins_imu::{EffectKind, ImuErrorParams};
use sins_nav::{DEG_PER_H, UG, Vec3};
use sins_sim::Scenario;

fn quiet() -> NoiseSpec {
    NoiseSpec::NONE
}

#[test]
fn constant_biases_match_the_pipeline() {
    let hours = 2.5;
    let mut sc = scenario(turning_motion(hours), 100.0, ramp_thermal(10.0, 8.0, hours));
    let ideal = sc.truth;
    let (_, base) = track(&sc, &ideal);
    // Case 1: constant gyro bias on x and accelerometer bias on y in the truth.
    let mut truth = ideal;
    truth.gyro.bias_radps = Vec3::new(0.01 * DEG_PER_H, 0.0, 0.0);
    truth.accel.bias_mps2 = Vec3::new(0.0, 50.0 * UG, 0.0);
    sc.truth = truth;
    let (mut src, real) = track(&sc, &ideal);
    let grid = Grid {
        output_every_s: 10,
        fit_every: 12,
    };
    let sens = sensitivity(&mut src, &sc, &real, &ideal, &quiet(), &[], grid);
    let cg = sens.column(ColumnId::Param(0)).unwrap();
    let ca = sens.column(ColumnId::Param(4)).unwrap();
    let mut worst: f64 = 0.0;
    let mut peak: f64 = 0.0;
    for (k, &t) in sens.times.times_s.iter().enumerate() {
        let r = at(&real, t);
        let b = at(&base, t);
        let d = [r[0] - b[0], r[1] - b[1]];
        let lin = [
            sens.north_m[cg][k] * truth.gyro.bias_radps.x
                + sens.north_m[ca][k] * truth.accel.bias_mps2.y,
            sens.east_m[cg][k] * truth.gyro.bias_radps.x
                + sens.east_m[ca][k] * truth.accel.bias_mps2.y,
        ];
        worst = worst.max((d[0] - lin[0]).hypot(d[1] - lin[1]));
        peak = peak.max(d[0].hypot(d[1]));
    }
    eprintln!("biases: worst {worst:.3} m of peak {peak:.1} m");
    assert!(worst < 0.02 * peak, "{worst} vs {peak}");
}

/// Simulate `sc` with `effects` added (values in the kinds' units), replay, and compare the
/// difference with `base` to the linear prediction; returns (worst deviation, peak) in metres.
fn check(sc: &Scenario, base: &RealTrack, effects: &[(EffectKind, usize, f64)]) -> (f64, f64) {
    let ideal: ImuErrorParams = sc.truth;
    let mut sc = sc.clone();
    sc.effects = effects.iter().map(|&(k, c, v)| effect(k, c, v)).collect();
    let (mut src, real) = track(&sc, &ideal);
    let kinds: Vec<EffectKind> = effects.iter().map(|e| e.0).collect();
    let grid = Grid {
        output_every_s: 10,
        fit_every: 12,
    };
    let sens = sensitivity(&mut src, &sc, &real, &ideal, &quiet(), &kinds, grid);
    let (mut worst, mut peak) = (0.0f64, 0.0f64);
    for (k, &t) in sens.times.times_s.iter().enumerate() {
        let (r, b) = (at(&real, t), at(base, t));
        let d = [r[0] - b[0], r[1] - b[1]];
        let mut lin = [0.0, 0.0];
        for &(kind, c, v) in effects {
            let i = sens.column(ColumnId::Effect(kind, c)).expect("column");
            let si = kind.unit().to_si(v);
            lin[0] += sens.north_m[i][k] * si;
            lin[1] += sens.east_m[i][k] * si;
        }
        worst = worst.max((d[0] - lin[0]).hypot(d[1] - lin[1]));
        peak = peak.max(d[0].hypot(d[1]));
    }
    eprintln!("{effects:?}: worst {worst:.3} m of peak {peak:.1} m");
    (worst, peak)
}

#[test]
fn temperature_driven_terms_match_the_pipeline() {
    let hours = 2.5;
    let sc = scenario(turning_motion(hours), 100.0, ramp_thermal(10.0, 8.0, hours));
    let (_, base) = track(&sc, &sc.truth);
    for e in [
        (EffectKind::GyroBiasTemp, 2, 2e-3),
        (EffectKind::AccelBiasQuadraticTemp, 0, 0.2),
        (EffectKind::AccelBiasTempRate, 1, 100.0),
        (EffectKind::GyroBiasTempRate, 0, 0.05),
        (EffectKind::GyroGSensitivity, 0, 0.01),
    ] {
        let (worst, peak) = check(&sc, &base, &[e]);
        assert!(
            peak > 50.0 && worst < 0.02 * peak,
            "{e:?}: {worst} of {peak}"
        );
    }
    // The thermal lag acts through the temperature coefficients of the parameter set.
    let mut sc = sc;
    sc.truth.temperature.bias_mps2_per_degc = Vec3::new(-2.77, 2.63, -25.45) * UG;
    sc.truth.temperature.scale_per_degc = Vec3::new(19.33e-6, 13.96e-6, 35.58e-6);
    let (_, base) = track(&sc, &sc.truth);
    let e = (EffectKind::ThermalLag, 2, 300.0);
    let (worst, peak) = check(&sc, &base, &[e]);
    assert!(
        peak > 50.0 && worst < 0.02 * peak,
        "{e:?}: {worst} of {peak}"
    );
}

/// Effects that live on the vibration: rectification through the attitude (second-order
/// quadrature of the sample-rate forcing). The time offset's column is evaluated on data that
/// already carry the offset, which biases it by about 7 % per millisecond of offset (its
/// perturbation is a high-pass copy of the increments themselves); at 0.05 ms that is 0.4 %.
#[test]
fn vibration_and_motion_terms_match_the_pipeline() {
    let hours = 2.0;
    let sc = scenario(
        vibration_motion(hours),
        200.0,
        ramp_thermal(25.0, -4.0, hours),
    );
    let (_, base) = track(&sc, &sc.truth);
    for e in [
        (EffectKind::GyroScaleAsymmetry, 2, 0.1),
        (EffectKind::SizeEffect, 4, 0.1),
        (EffectKind::SizeEffect, 5, 0.1),
        (EffectKind::AccelQuadratic, 0, 50.0),
        (EffectKind::AccelTimeOffset, 0, 0.05),
    ] {
        let (worst, peak) = check(&sc, &base, &[e]);
        assert!(
            peak > 2.0 && worst < 0.02 * peak,
            "{e:?}: {worst} of {peak}"
        );
    }
}
