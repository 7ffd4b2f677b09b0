//! The streaming simulator: sample timing, segment indices, forward-model wiring, determinism,
//! stream independence and scenario validation.

use crate::common;

use common::*;
use sins_imu::{EffectContext, ExtraEffect, ForwardModel};
use sins_nav::{ARCSEC, DEG, DEG_PER_H, UG, Vec3};
use sins_sim::{
    AccelThermal, ChamberSegment, IncrementIntegrator, MotionSegment, MotionTimeline, NoiseModel,
    Scenario, SimBatch, SimError, Simulator, simulate_to_vec,
};
use std::sync::{Arc, Mutex};

fn noisy(mut sc: Scenario) -> Scenario {
    sc.noise = NoiseModel {
        gyro_arw_rad_per_sqrt_s: 0.0005 * DEG / 60.0,
        gyro_bias_instability_radps: 0.005 * DEG_PER_H,
        gyro_bias_correlation_s: 3600.0,
        gyro_quantum_rad: ARCSEC,
        accel_vrw_mps_per_sqrt_s: 5.0 * UG,
        accel_bias_instability_mps2: 20.0 * UG,
        accel_bias_correlation_s: 1800.0,
    };
    sc.thermal.chamber = vec![ChamberSegment::Ramp {
        duration_s: 100.0,
        rate_degc_per_s: 0.01,
    }];
    sc.thermal.thermometer_noise_degc = 0.01;
    sc
}

fn short_program() -> Vec<MotionSegment> {
    vec![
        dwell(1.0, "stationary"),
        rotate([0.0, 1.0, 0.0], 90.0, 9.0, "rotation"),
        dwell(1.0, "stationary"),
        pattern3(2.0, [0.1, 0.2, 0.3]),
    ]
}

fn run(sc: &Scenario) -> SimBatch {
    simulate_to_vec(sc, ForwardModel::new(sc.truth)).unwrap()
}

fn bits(b: &SimBatch) -> Vec<u64> {
    b.samples
        .iter()
        .flat_map(|s| {
            let mut v: Vec<u64> = s
                .dtheta_rad
                .iter()
                .chain(s.dv_mps.iter())
                .map(|x| x.to_bits())
                .collect();
            v.extend(s.temp_degc.iter().map(|x| x.to_bits()));
            v.push(s.t_s.to_bits());
            v
        })
        .collect()
}

#[test]
fn sample_times_counts_and_segment_indices() {
    let sc = scenario(short_program());
    let sim = Simulator::from_scenario(&sc).unwrap();
    // 1 + 10 + 1 + 2 s at 200 Hz (the rotation lasts (π/2)/(π/20) s up to rounding).
    assert_eq!(sim.n_samples(), 2800);
    assert_eq!(sim.sample_interval_s(), 0.005);
    assert_eq!(sim.segment_labels(), ["stationary", "rotation", "pattern3"]);
    assert_eq!(sim.segment_label_indices(), [0, 1, 0, 2]);
    let out = run(&sc);
    assert_eq!(out.len(), 2800);
    assert!(out.reference.is_none());
    for (k, s) in out.samples.iter().enumerate() {
        assert_eq!(s.t_s, (k + 1) as f64 / 200.0);
    }
    // Segment of the interval midpoint.
    let want = |k: usize| match (k as f64 + 0.5) / 200.0 {
        t if t < 1.0 => 0u16,
        t if t < 11.0 => 1,
        t if t < 12.0 => 2,
        _ => 3,
    };
    for (k, &seg) in out.segment_index.iter().enumerate() {
        assert_eq!(seg, want(k), "sample {k}");
    }
}

#[test]
fn batches_are_bounded_and_concatenate_to_the_full_run() {
    let sc = noisy(scenario(short_program()));
    let whole = run(&sc);
    let mut sim = Simulator::from_scenario(&sc).unwrap();
    let mut joined = SimBatch::default();
    let mut sizes = Vec::new();
    sim.run(333, |b| {
        sizes.push(b.len());
        joined.samples.extend_from_slice(&b.samples);
        joined.segment_index.extend_from_slice(&b.segment_index);
        Ok::<(), ()>(())
    })
    .unwrap();
    assert!(sizes.iter().all(|&n| n <= 333));
    assert_eq!(sizes.iter().sum::<usize>(), 2800);
    assert_eq!(bits(&joined), bits(&whole));
    assert_eq!(joined.segment_index, whole.segment_index);
    // A second run of the same simulator restarts noise and temperatures.
    let mut again = SimBatch::default();
    sim.run(10_000, |b| {
        again.samples.extend_from_slice(&b.samples);
        Ok::<(), ()>(())
    })
    .unwrap();
    assert_eq!(bits(&again), bits(&whole));
    // The sink's error stops the run and is returned.
    let mut calls = 0;
    let r = sim.run(100, |_| {
        calls += 1;
        if calls == 3 { Err("disk full") } else { Ok(()) }
    });
    assert_eq!((r, calls), (Err("disk full"), 3));
}

#[test]
fn reference_states_follow_the_timeline() {
    let mut sc = scenario(short_program());
    sc.with_reference = true;
    let out = run(&sc);
    let timeline = MotionTimeline::new(&sc.motion).unwrap();
    let reference = out.reference.as_ref().unwrap();
    assert_eq!(reference.len(), out.len());
    for k in [0, 150, 600, 1999, 2100, 2500, 2799] {
        let r = &reference[k];
        let want = timeline.eval(out.samples[k].t_s).ned_from_body;
        assert!(r.ned_from_body.angle_to(&want) < 1e-15);
        assert_eq!(r.position, sc.site);
        assert_eq!(r.vel_ned_mps, Vec3::zeros());
    }
}

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

#[test]
fn forward_model_sees_true_increments_and_midpoint_temperatures() {
    let mut sc = scenario(short_program());
    sc.thermal.chamber = vec![ChamberSegment::Ramp {
        duration_s: 100.0,
        rate_degc_per_s: 0.05,
    }];
    sc.thermal.accel_time_constant_s = [5.0, 7.0, 9.0];
    // A truth IMU with a large temperature-dependent accelerometer bias.
    sc.truth.temperature.bias_mps2_per_degc = Vec3::new(1e-3, 2e-3, 3e-3);
    sc.truth.gyro.bias_radps = Vec3::new(1e-5, 0.0, 0.0);
    let log = Arc::new(Mutex::new(Vec::new()));
    let fwd = ForwardModel::new(sc.truth).with_effect(Box::new(Recorder(log.clone())));
    let out = simulate_to_vec(&sc, fwd).unwrap();
    let ctxs = log.lock().unwrap().clone();
    assert_eq!(ctxs.len(), out.len());
    let timeline = MotionTimeline::new(&sc.motion).unwrap();
    let integ = IncrementIntegrator::new(&timeline, &sc.site, 6, 0.005).unwrap();
    let mut thermal = AccelThermal::new(&sc.thermal, 0.0025).unwrap();
    let mut plain = ForwardModel::new(sc.truth);
    for (k, (s, ctx)) in out.samples.iter().zip(&ctxs).enumerate() {
        let (t0, t1) = (k as f64 / 200.0, (k + 1) as f64 / 200.0);
        let (th, dv) = integ.increments(t0, t1);
        let mid = thermal.advance_to((2 * k + 1) as f64 / 400.0);
        let rate = thermal.rate_degc_per_s();
        let end = thermal.advance_to(t1);
        assert_eq!(
            (ctx.true_dtheta_rad, ctx.true_dv_mps),
            (th, dv),
            "sample {k}"
        );
        assert_eq!(
            (ctx.accel_temp_degc, ctx.accel_temp_rate_degc_per_s),
            (mid, rate)
        );
        assert_eq!((ctx.t_s, ctx.dt_s), (t1, 0.005));
        // No noise: raw = forward(true) with the midpoint temperatures; thermometers read T(t1).
        let (rth, rdv) = plain.apply(&th, &dv, 0.005, &mid, ctx);
        assert_eq!((s.dtheta_rad, s.dv_mps, s.temp_degc), (rth, rdv, end));
    }
    // The temperature terms act: the x accelerometer gains TB_x · T_x(mid) · dt (T_ref = 0).
    let (last, ctx) = (out.samples.last().unwrap(), ctxs.last().unwrap());
    assert!(ctx.accel_temp_degc[0] > 20.4 && ctx.accel_temp_rate_degc_per_s[0] > 0.04);
    let extra = last.dv_mps.x - ctx.true_dv_mps.x;
    assert!(
        (extra - 1e-3 * ctx.accel_temp_degc[0] * 0.005).abs() < 1e-15,
        "{extra}"
    );
}

#[test]
fn same_seed_is_bit_identical_and_another_seed_differs() {
    let sc = noisy(scenario(short_program()));
    let a = run(&sc);
    let b = run(&sc);
    assert_eq!(bits(&a), bits(&b));
    let mut other = sc.clone();
    other.seed = 2;
    let c = run(&other);
    let differing = bits(&a)
        .iter()
        .zip(bits(&c))
        .filter(|(x, y)| *x != y)
        .count();
    assert!(differing > a.len() * 3, "only {differing} values differ");
}

#[test]
fn each_noise_source_has_its_own_stream() {
    let base = noisy(scenario(short_program()));
    let a = run(&base);
    // Thermometer noise off: gyro and accelerometer numbers unchanged, temperatures change.
    let mut sc = base.clone();
    sc.thermal.thermometer_noise_degc = 0.0;
    let b = run(&sc);
    for (x, y) in a.samples.iter().zip(&b.samples) {
        assert_eq!(
            x.dtheta_rad.map(f64::to_bits),
            y.dtheta_rad.map(f64::to_bits)
        );
        assert_eq!(x.dv_mps.map(f64::to_bits), y.dv_mps.map(f64::to_bits));
    }
    assert!(
        a.samples
            .iter()
            .zip(&b.samples)
            .all(|(x, y)| x.temp_degc != y.temp_degc)
    );
    // Accelerometer noise off: gyro numbers unchanged.
    let mut sc = base.clone();
    sc.noise.accel_vrw_mps_per_sqrt_s = 0.0;
    sc.noise.accel_bias_instability_mps2 = 0.0;
    let c = run(&sc);
    for (x, y) in a.samples.iter().zip(&c.samples) {
        assert_eq!(
            x.dtheta_rad.map(f64::to_bits),
            y.dtheta_rad.map(f64::to_bits)
        );
        assert_eq!(x.temp_degc, y.temp_degc);
    }
    assert!(
        a.samples
            .iter()
            .zip(&c.samples)
            .any(|(x, y)| x.dv_mps != y.dv_mps)
    );
    // The gyro quantum of 1 arcsec holds in the output.
    for s in &a.samples {
        for c in s.dtheta_rad.iter() {
            let p = c / ARCSEC;
            assert!((p - p.round()).abs() < 1e-6, "{p}");
        }
    }
}

/// The Display text of the validation error of `sc`.
fn error_of(sc: &Scenario) -> (SimError, String) {
    match Simulator::from_scenario(sc) {
        Ok(_) => panic!("scenario should be rejected"),
        Err(e) => {
            let text = e.to_string();
            (e, text)
        }
    }
}

#[test]
fn validation_errors_name_the_segment_and_field() {
    let mut sc = scenario(short_program());
    sc.motion.segments[2] = dwell(-1.0, "bad");
    let (e, text) = error_of(&sc);
    assert!(
        matches!(
            e,
            SimError::MotionSegment {
                index: 2,
                field: "duration_s",
                ..
            }
        ),
        "{text}"
    );
    assert!(
        text.contains("segment 2") && text.contains("duration_s"),
        "{text}"
    );

    let mut sc = scenario(short_program());
    sc.motion.segments[1] = rotate([0.0, 1.0, 0.1], 90.0, 9.0, "r");
    let (_, text) = error_of(&sc);
    assert!(
        text.contains("segment 1") && text.contains("axis_body"),
        "{text}"
    );

    let mut sc = scenario(short_program());
    sc.motion.segments[1] = rotate([0.0, 1.0, 0.0], 90.0, f64::NAN, "r");
    let (_, text) = error_of(&sc);
    assert!(
        text.contains("segment 1") && text.contains("rate_radps"),
        "{text}"
    );

    let mut sc = scenario(short_program());
    if let MotionSegment::Vibrate { period_s, .. } = &mut sc.motion.segments[3] {
        period_s.y = 0.0;
    }
    let (_, text) = error_of(&sc);
    assert!(
        text.contains("segment 3") && text.contains("period_s") && text.contains("y"),
        "{text}"
    );

    let mut sc = scenario(short_program());
    sc.thermal.chamber = vec![
        ChamberSegment::Hold {
            duration_s: 10.0,
            temp_degc: 20.0,
        },
        ChamberSegment::Fluctuating {
            duration_s: 10.0,
            rate_degc_per_s: 0.0,
            fluctuation_amplitude_degc: 1.0,
            fluctuation_period_s: -5.0,
        },
    ];
    let (e, text) = error_of(&sc);
    assert!(
        matches!(e, SimError::ChamberSegment { index: 1, .. }),
        "{text}"
    );
    assert!(
        text.contains("chamber segment 1") && text.contains("fluctuation_period_s"),
        "{text}"
    );

    type Mutation = Box<dyn Fn(&mut Scenario)>;
    let cases: Vec<(Mutation, &str)> = vec![
        (Box::new(|s| s.rate_hz = 0.0), "rate_hz"),
        (Box::new(|s| s.quadrature_nodes = 9), "quadrature_nodes"),
        (Box::new(|s| s.quadrature_nodes = 0), "quadrature_nodes"),
        (Box::new(|s| s.site.lat_rad = 2.0), "site.lat_rad"),
        (Box::new(|s| s.motion.segments.clear()), "motion.segments"),
        (
            Box::new(|s| s.thermal.accel_time_constant_s[1] = 0.0),
            "accel_time_constant_s",
        ),
        (
            Box::new(|s| s.thermal.thermometer_noise_degc = -1.0),
            "thermometer_noise_degc",
        ),
        (
            Box::new(|s| s.noise.gyro_arw_rad_per_sqrt_s = f64::INFINITY),
            "gyro_arw",
        ),
        (
            Box::new(|s| {
                s.noise.accel_bias_instability_mps2 = 1e-4;
                s.noise.accel_bias_correlation_s = 0.0;
            }),
            "accel_bias_correlation_s",
        ),
        (Box::new(|s| s.truth.gyro.scale.x = f64::NAN), "truth"),
    ];
    for (mutate, field) in cases {
        let mut sc = scenario(short_program());
        mutate(&mut sc);
        let (_, text) = error_of(&sc);
        assert!(text.contains(field), "{field}: {text}");
    }
}

/// An extra effect named in the scenario changes exactly the channel it acts on.
#[test]
fn scenario_effects_are_switchable_and_local() {
    use sins_imu::EffectSpec;
    let base = common::scenario(vec![sins_sim::MotionSegment::Dwell {
        duration_s: 2.0,
        label: "d".into(),
    }]);
    let mut with = base.clone();
    with.thermal.chamber_start_degc = 30.0;
    let mut without = with.clone();
    without.effects.clear();
    with.effects = vec![EffectSpec::AccelBiasQuadraticTemp {
        coeff_mps2_per_degc2: sins_nav::Vec3::new(1e-5, 0.0, 0.0),
        reference_degc: 20.0,
    }];
    let a = sins_sim::Simulator::from_scenario(&with).unwrap();
    let b = sins_sim::Simulator::from_scenario(&without).unwrap();
    let (mut a, mut b) = (a, b);
    let mut sa = Vec::new();
    let mut sb = Vec::new();
    a.run(1000, |x| {
        sa.extend_from_slice(&x.samples);
        Ok::<(), ()>(())
    })
    .unwrap();
    b.run(1000, |x| {
        sb.extend_from_slice(&x.samples);
        Ok::<(), ()>(())
    })
    .unwrap();
    for (x, y) in sa.iter().zip(&sb) {
        assert_eq!(x.dtheta_rad, y.dtheta_rad);
        assert_eq!(x.dv_mps.y, y.dv_mps.y);
        assert!(x.dv_mps.x > y.dv_mps.x, "the effect must add to x");
    }
}
