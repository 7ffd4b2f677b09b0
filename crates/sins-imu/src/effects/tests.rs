//! Catalogue-wide properties: names, units, constructors, linearity and locality of every kind.

use super::*;
use crate::{ForwardModel, ImuErrorParams, ParamModel};
use sins_nav::{UG, Vec3};

/// A truth set with the paper's Table 3 temperature coefficients (so thermal lag acts).
fn truth() -> ImuErrorParams {
    let mut p = ImuErrorParams::ideal(ParamModel::States42);
    p.temperature.bias_mps2_per_degc = Vec3::new(-2.77, 2.63, -25.45) * UG;
    p.temperature.scale_per_degc = Vec3::new(19.33e-6, 13.96e-6, 35.58e-6);
    p.temperature.misalignment_rad_per_degc =
        [-0.12, -0.02, -0.13, 0.14, 0.37, -0.47].map(|a| a * sins_nav::ARCSEC);
    p.reference_temperature_degc = 20.0;
    p
}

/// `n` contexts of a moving, warming IMU: angular vibration on all axes, gravity plus vibration in
/// the specific force, temperatures ramping with a fluctuation (all channels non-zero).
fn rich_contexts(n: usize) -> Vec<EffectContext> {
    let h = 0.005;
    let mut tracker = ContextTracker::new();
    (0..n)
        .map(|k| {
            let t = (k + 1) as f64 * h;
            let tm = t - 0.5 * h;
            let w = Vec3::new(
                0.3 * (7.0 * tm).sin() + 0.05,
                -0.2 * (11.0 * tm).cos(),
                0.4 * (5.0 * tm + 1.0).sin(),
            );
            let f = Vec3::new(
                1.5 * (3.0 * tm).sin() + 0.2,
                -2.0 * (4.0 * tm).cos() + 0.1,
                9.8 + 0.5 * (6.0 * tm).sin(),
            );
            let temp: [f64; 3] =
                std::array::from_fn(|j| 25.0 + 0.01 * t + 0.5 * (0.05 * t + j as f64).sin());
            let rate: [f64; 3] =
                std::array::from_fn(|j| 0.01 + 0.025 * (0.05 * t + j as f64).cos());
            tracker.next(t, h, w * h, f * h, temp, rate)
        })
        .collect()
}

/// `EffectSpec::typical(k, i)`, with the bias steps and events moved inside the short test
/// windows.
fn typical(k: EffectKind, i: usize) -> EffectSpec {
    match EffectSpec::typical(k, i) {
        EffectSpec::AccelBiasStep { step_mps2, .. } => EffectSpec::AccelBiasStep {
            step_mps2,
            time_s: 0.1,
        },
        EffectSpec::BiasEvent {
            kind, magnitude_si, ..
        } => EffectSpec::BiasEvent {
            kind,
            magnitude_si,
            onset_s: 0.1,
            time_constant_s: 1.0,
        },
        EffectSpec::BiasProfile {
            kind, magnitude_si, ..
        } => EffectSpec::BiasProfile {
            kind,
            magnitude_si,
            onset_s: 0.1,
            duration_s: 0.7,
            time_constant_s: 1.0,
        },
        s => s,
    }
}

fn run(spec: &EffectSpec, ctxs: &[EffectContext]) -> Vec<(Vec3, Vec3)> {
    let mut e = spec.build(&truth());
    ctxs.iter().map(|c| e.perturbation(c)).collect()
}

fn max_norm(p: &[(Vec3, Vec3)]) -> (f64, f64) {
    p.iter().fold((0.0f64, 0.0f64), |(a, b), (x, y)| {
        (a.max(x.norm()), b.max(y.norm()))
    })
}

#[test]
fn kinds_are_named_uniquely_and_the_catalogue_has_ten_plus_three_outside() {
    let names: std::collections::BTreeSet<_> = EffectKind::ALL.iter().map(|k| k.name()).collect();
    assert_eq!(names.len(), EffectKind::ALL.len());
    for k in EffectKind::ALL {
        assert_eq!(EffectKind::from_name(k.name()), Some(k));
        assert!(k.name().chars().all(|c| c.is_ascii_lowercase() || c == '_'));
        assert!(k.typical_magnitude() > 0.0 && k.unit().si > 0.0);
        assert_eq!(k.component_labels().len(), k.n_components());
        assert_eq!(EffectSpec::zero(k).kind(), k);
    }
    assert!(EffectKind::catalogue().len() >= 10);
    assert!(EffectKind::ALL.iter().filter(|k| !k.in_catalogue()).count() >= 3);
    assert_eq!(EffectKind::from_name("warp_drive"), None);
}

#[test]
fn unit_specs_carry_one_si_unit_on_one_component_and_scale() {
    for k in EffectKind::ALL {
        for i in 0..k.n_components() {
            let u = EffectSpec::unit(k, i);
            let m = u.magnitudes_si();
            assert_eq!(m.len(), k.n_components());
            for (j, v) in m.iter().enumerate() {
                assert_eq!(*v, if i == j { 1.0 } else { 0.0 });
            }
            assert!(u.is_valid(), "{k}");
            let s = u.scaled(-3.5);
            assert_eq!(s.magnitudes_si()[i], -3.5);
            assert_eq!(s.with_magnitudes_si(&m), Some(u.clone()));
            let t = EffectSpec::typical(k, i);
            assert_eq!(t.magnitudes_si()[i], k.typical_magnitude_si());
        }
        assert_eq!(EffectSpec::zero(k).with_magnitudes_si(&[1.0]), None);
    }
}

#[test]
fn every_unit_effect_acts_on_its_own_sensor_only_and_is_named_after_its_kind() {
    let ctxs = rich_contexts(400);
    for k in EffectKind::ALL {
        for i in 0..k.n_components() {
            let spec = typical(k, i);
            assert_eq!(spec.build(&truth()).name(), k.name());
            let (gyro, accel) = max_norm(&run(&spec, &ctxs));
            match k.sensor() {
                Sensor::Gyro => assert!(gyro > 0.0 && accel == 0.0, "{k}[{i}]"),
                Sensor::Accel => assert!(accel > 0.0 && gyro == 0.0, "{k}[{i}]"),
            }
        }
    }
}

#[test]
fn linear_effects_double_with_their_magnitude_and_superpose() {
    let ctxs = rich_contexts(400);
    for k in EffectKind::ALL.into_iter().filter(|k| k.is_linear()) {
        let n = k.n_components();
        let x: Vec<f64> = (0..n)
            .map(|i| (i as f64 + 1.0) * k.typical_magnitude_si())
            .collect();
        let spec = typical(k, 0).with_magnitudes_si(&x).unwrap();
        let one = run(&spec, &ctxs);
        let two = run(&spec.scaled(2.0), &ctxs);
        // Sum of the unit columns weighted by the magnitudes.
        let cols: Vec<_> = (0..n)
            .map(|i| run(&typical(k, i).scaled(1.0 / k.typical_magnitude_si()), &ctxs))
            .collect();
        let (sg, sa) = max_norm(&one);
        for s in 0..ctxs.len() {
            assert!((two[s].0 - one[s].0 * 2.0).norm() <= 1e-14 * sg, "{k}");
            assert!((two[s].1 - one[s].1 * 2.0).norm() <= 1e-14 * sa, "{k}");
            let mut g = Vec3::zeros();
            let mut a = Vec3::zeros();
            for (i, c) in cols.iter().enumerate() {
                g += c[s].0 * x[i];
                a += c[s].1 * x[i];
            }
            assert!((g - one[s].0).norm() <= 1e-13 * sg.max(1e-300), "{k}");
            assert!((a - one[s].1).norm() <= 1e-13 * sa.max(1e-300), "{k}");
        }
    }
}

#[test]
fn thermal_lag_unit_spec_is_its_linearisation_but_typical_lags_are_not_linear() {
    // Temperature with a 20 min fluctuation, 1 s samples, level IMU: the 1 s column is the
    // derivative at tau = 0 to 1 % (checked against 0.01 s x 100), while tau = 60 s departs from
    // 60 x the column by more than 10 % (hence `Linearity::Linearised`).
    let mut tracker = ContextTracker::new();
    let w = std::f64::consts::TAU / 1200.0;
    let ctxs: Vec<_> = (0..3600)
        .map(|k| {
            let t = (k + 1) as f64;
            let tm = t - 0.5;
            let f = Vec3::new(0.0, 0.0, 9.8);
            tracker.next(
                t,
                1.0,
                Vec3::zeros(),
                f,
                [25.0 + 2.0 * (w * tm).sin(); 3],
                [2.0 * w * (w * tm).cos(); 3],
            )
        })
        .collect();
    let col = run(&EffectSpec::unit(EffectKind::ThermalLag, 2), &ctxs);
    let tiny = run(
        &EffectSpec::unit(EffectKind::ThermalLag, 2).scaled(0.01),
        &ctxs,
    );
    let (_, scale) = max_norm(&col);
    assert!(scale > 0.0);
    for (c, t) in col.iter().zip(&tiny) {
        assert!((c.1 - t.1 * 100.0).norm() < 0.01 * scale);
    }
    let big = run(
        &EffectSpec::unit(EffectKind::ThermalLag, 2).scaled(60.0),
        &ctxs,
    );
    let worst = col
        .iter()
        .zip(&big)
        .map(|(c, b)| (c.1 * 60.0 - b.1).norm())
        .fold(0.0, f64::max);
    assert!(worst > 0.1 * 60.0 * scale, "{worst}");
}

#[test]
fn perturbations_do_not_depend_on_the_raw_increments_they_are_added_to() {
    let ctxs = rich_contexts(50);
    for k in EffectKind::ALL {
        let spec = typical(k, 0);
        let (mut a, mut b) = (spec.build(&truth()), spec.build(&truth()));
        for c in &ctxs {
            let (pg, pa) = a.perturbation(c);
            let (g0, v0) = (Vec3::new(1e-3, -2e-3, 3e-3), Vec3::new(0.05, 0.025, -0.04));
            let (mut g, mut v) = (g0, v0);
            b.apply(c, &mut g, &mut v);
            // Equal up to the rounding of the addition.
            assert!(((g - g0) - pg).norm() <= 1e-15 * g0.norm(), "{k}");
            assert!(((v - v0) - pa).norm() <= 1e-15 * v0.norm(), "{k}");
        }
    }
}

#[test]
fn reset_makes_a_second_pass_identical() {
    let ctxs = rich_contexts(200);
    for k in EffectKind::ALL {
        let mut e = typical(k, 1).build(&truth());
        let first: Vec<_> = ctxs.iter().map(|c| e.perturbation(c)).collect();
        e.reset();
        let second: Vec<_> = ctxs.iter().map(|c| e.perturbation(c)).collect();
        assert_eq!(first, second, "{k}");
    }
}

#[test]
fn forward_model_adds_the_effect_after_the_paper_terms() {
    let spec = EffectSpec::AccelBiasQuadraticTemp {
        coeff_mps2_per_degc2: Vec3::new(1e-6, 0.0, 0.0),
        reference_degc: 20.0,
    };
    let mut fwd = ForwardModel::new(ImuErrorParams::ideal(ParamModel::States42))
        .with_effect(spec.build(&truth()));
    assert_eq!(fwd.effect_names(), vec!["accel_bias_quadratic_temp"]);
    let temp = [30.0, 30.0, 30.0];
    let ctx = EffectContext::at_rest(0.0, 0.01, temp);
    let (_, dv) = fwd.apply(&Vec3::zeros(), &Vec3::zeros(), 0.01, &temp, &ctx);
    assert!((dv.x - 1e-6 * 100.0 * 0.01).abs() < 1e-18);
    assert_eq!(dv.y, 0.0);
}

#[test]
fn a_batch_of_perturbations_is_the_samples_one_by_one_to_the_bit() {
    let ctxs = rich_contexts(300);
    for k in EffectKind::ALL {
        for c in 0..k.n_components() {
            let spec = typical(k, c);
            let (mut one, mut batch) = (spec.build(&truth()), spec.build(&truth()));
            let want: Vec<_> = ctxs.iter().map(|x| one.perturbation(x)).collect();
            // Uneven batches: a stateful effect carries its state from one batch to the next.
            let mut got = Vec::new();
            let mut out = vec![(Vec3::repeat(f64::NAN), Vec3::zeros())];
            for part in ctxs.chunks(77) {
                batch.perturbations(part, &mut out);
                assert_eq!(out.len(), part.len(), "{k}");
                got.extend_from_slice(&out);
            }
            let bits = |v: &[(Vec3, Vec3)]| -> Vec<u64> {
                v.iter()
                    .flat_map(|(a, b)| a.iter().chain(b.iter()).map(|x| x.to_bits()))
                    .collect()
            };
            assert_eq!(bits(&got), bits(&want), "{k} component {c}");
            assert!(
                want.iter().any(|(a, b)| a.norm() + b.norm() > 0.0),
                "{k} {c}: all zero"
            );
        }
    }
}
