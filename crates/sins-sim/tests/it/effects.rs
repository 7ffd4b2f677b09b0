//! Extra effects in the simulator: switching one on changes the samples of the same seed by
//! exactly that effect's perturbation, computed independently from the recorded contexts.

use crate::common;

use common::{dwell, pattern3, rotate, scenario};
use sins_imu::{EffectContext, EffectKind, EffectSpec, ExtraEffect, ForwardModel, ImuSample};
use sins_nav::{DEG_PER_H, UG, Vec3};
use sins_sim::{ChamberSegment, Scenario, Simulator};
use std::sync::{Arc, Mutex};

/// Records the context of every sample.
struct Recorder(Arc<Mutex<Vec<EffectContext>>>);

impl ExtraEffect for Recorder {
    fn name(&self) -> &'static str {
        "recorder"
    }
    fn apply(&mut self, ctx: &EffectContext, _dtheta: &mut Vec3, _dv: &mut Vec3) {
        if let Ok(mut v) = self.0.lock() {
            v.push(*ctx);
        }
    }
}

/// 10 s: dwell, a 90 deg turn about z, Table 4 pattern 3, dwell; chamber warming at 3 degC/min;
/// sensor noise on (no quantization: it is not additive); a truth set with temperature terms.
fn base() -> Scenario {
    let mut sc = scenario(vec![
        dwell(2.0, "stationary"),
        rotate([0.0, 0.0, 1.0], 90.0, 30.0, "turn"),
        pattern3(3.0, [0.1, 0.2, 0.3]),
        dwell(2.0, "stationary"),
    ]);
    sc.thermal.chamber = vec![ChamberSegment::Ramp {
        duration_s: 10.0,
        rate_degc_per_s: 0.05,
    }];
    sc.thermal.accel_time_constant_s = [5.0, 7.0, 9.0];
    sc.noise.gyro_arw_rad_per_sqrt_s = 0.001 * DEG_PER_H * 60.0;
    sc.noise.accel_vrw_mps_per_sqrt_s = 10.0 * UG;
    sc.noise.gyro_bias_instability_radps = 0.003 * DEG_PER_H;
    sc.noise.gyro_bias_correlation_s = 100.0;
    sc.truth.gyro.bias_radps = Vec3::new(0.003, -0.002, 0.001) * DEG_PER_H;
    sc.truth.accel.bias_mps2 = Vec3::new(20.0, -10.0, 30.0) * UG;
    sc.truth.temperature.bias_mps2_per_degc = Vec3::new(-2.77, 2.63, -25.45) * UG;
    sc.truth.temperature.scale_per_degc = Vec3::new(19.33e-6, 13.96e-6, 35.58e-6);
    sc.truth.reference_temperature_degc = 20.0;
    sc.seed = 11;
    sc
}

fn samples(sim: &mut Simulator) -> Vec<ImuSample> {
    let mut out = Vec::new();
    sim.run(700, |b| {
        out.extend_from_slice(&b.samples);
        Ok::<(), ()>(())
    })
    .unwrap();
    out
}

/// Every component at its typical magnitude (different per axis), the step inside the run.
fn spec_of(kind: EffectKind) -> EffectSpec {
    let n = kind.n_components();
    let x: Vec<f64> = (0..n)
        .map(|i| kind.typical_magnitude_si() * (1.0 + 0.5 * i as f64))
        .collect();
    match EffectSpec::zero(kind).with_magnitudes_si(&x).unwrap() {
        EffectSpec::AccelBiasStep { step_mps2, .. } => EffectSpec::AccelBiasStep {
            step_mps2,
            time_s: 5.0,
        },
        EffectSpec::BiasEvent {
            kind, magnitude_si, ..
        } => EffectSpec::BiasEvent {
            kind,
            magnitude_si,
            onset_s: 1.003,
            time_constant_s: 2.0,
        },
        EffectSpec::BiasProfile {
            kind, magnitude_si, ..
        } => EffectSpec::BiasProfile {
            kind,
            magnitude_si,
            onset_s: 1.003,
            duration_s: 1.5,
            time_constant_s: 2.0,
        },
        EffectSpec::GyroBiasRandomWalk {
            intensity_radps_per_sqrt_s,
            correlation_s,
            ..
        } => EffectSpec::GyroBiasRandomWalk {
            intensity_radps_per_sqrt_s,
            correlation_s,
            seed: 5,
        },
        s => s,
    }
}

#[test]
fn switching_an_effect_on_adds_exactly_its_perturbation() {
    let without = base();
    let log = Arc::new(Mutex::new(Vec::new()));
    let fwd = ForwardModel::new(without.truth).with_effect(Box::new(Recorder(log.clone())));
    let plain = samples(&mut Simulator::new(&without, fwd).unwrap());
    let ctxs = log.lock().unwrap().clone();
    assert_eq!(ctxs.len(), plain.len());
    // The contexts carry the previous sample's true increments.
    assert_eq!(ctxs[0].prev_true_dtheta_rad, ctxs[0].true_dtheta_rad);
    for k in 1..ctxs.len() {
        assert_eq!(ctxs[k].prev_true_dv_mps, ctxs[k - 1].true_dv_mps);
    }
    for kind in EffectKind::ALL {
        let spec = spec_of(kind);
        let mut with = without.clone();
        with.effects = vec![spec.clone()];
        let mut sim = Simulator::from_scenario(&with).unwrap();
        let raw = samples(&mut sim);
        let mut effect = spec.build(&with.truth);
        let (mut max_g, mut max_a) = (0.0f64, 0.0f64);
        for ((a, b), c) in raw.iter().zip(&plain).zip(&ctxs) {
            let (pg, pa) = effect.perturbation(c);
            let dg = a.dtheta_rad - b.dtheta_rad;
            let da = a.dv_mps - b.dv_mps;
            // Equal to the rounding of adding the perturbation to the raw increment.
            assert!(
                (dg - pg).norm() <= 4e-16 * (b.dtheta_rad.norm() + pg.norm()),
                "{kind} {dg:?} {pg:?}"
            );
            assert!(
                (da - pa).norm() <= 4e-16 * (b.dv_mps.norm() + pa.norm()),
                "{kind} {da:?} {pa:?}"
            );
            assert_eq!(a.temp_degc, b.temp_degc);
            max_g = max_g.max(pg.norm());
            max_a = max_a.max(pa.norm());
        }
        // The perturbation is there (well above the rounding floor) on its own sensor only.
        match kind.sensor() {
            sins_imu::effects::Sensor::Gyro => assert!(max_g > 1e-14 && max_a == 0.0, "{kind}"),
            sins_imu::effects::Sensor::Accel => assert!(max_a > 1e-12 && max_g == 0.0, "{kind}"),
        }
        // A second run of the same simulator is identical (stateful effects are reset).
        assert_eq!(samples(&mut sim), raw, "{kind}");
    }
}

#[test]
fn invalid_effect_values_are_rejected_by_name() {
    let mut sc = base();
    sc.effects = vec![EffectSpec::GyroBiasOscillation {
        amplitude_radps: Vec3::zeros(),
        period_s: 0.0,
        phase_rad: 0.0,
    }];
    let err = Simulator::from_scenario(&sc).err().unwrap().to_string();
    assert!(
        err.contains("effects") && err.contains("gyro_bias_oscillation"),
        "{err}"
    );
    sc.effects = vec![EffectSpec::ThermalLag {
        tau_s: Vec3::new(1.0, -1.0, 0.0),
    }];
    assert!(Simulator::from_scenario(&sc).is_err());
}
