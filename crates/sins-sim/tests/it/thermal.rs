//! Chamber profile, accelerometer thermal lags and thermometer noise.

use crate::common;

use common::quiet_thermal;
use sins_sim::noise::stream;
use sins_sim::{AccelThermal, ChamberProfile, ChamberSegment, GaussianStream, Thermometers};

#[test]
fn step_response_reaches_1_minus_1_over_e_after_one_time_constant() {
    let mut m = quiet_thermal();
    m.chamber_start_degc = 20.0;
    m.chamber = vec![ChamberSegment::Hold {
        duration_s: 10_000.0,
        temp_degc: 30.0,
    }];
    m.accel_time_constant_s = [100.0, 200.0, 400.0];
    let mut th = AccelThermal::new(&m, 0.0025).unwrap();
    // Equilibrium with the chamber before the step.
    assert_eq!(th.temperature_degc(), [20.0; 3]);
    let mut t = 0.0;
    for (j, tau) in [100.0, 200.0, 400.0].into_iter().enumerate() {
        // March in 5 ms samples (two half steps) up to t = τ_j.
        let n = (tau * 200.0) as usize;
        let mut temps = [0.0; 3];
        for k in (t * 200.0) as usize..n {
            th.advance_to((2 * k + 1) as f64 / 400.0);
            temps = th.advance_to((k + 1) as f64 / 200.0);
        }
        t = tau;
        let want = 30.0 - 10.0 / std::f64::consts::E;
        // 80 000 half steps compound the rounding of e^{-h/2τ}: ~1e-11 degC.
        assert!(
            (temps[j] - want).abs() < 1e-10,
            "axis {j}: {} vs {want}",
            temps[j]
        );
    }
    // Rate at t = 400 s for the 400 s lag: (30 - T)/τ = 10/e/400.
    let rate = th.rate_degc_per_s();
    assert!((rate[2] - 10.0 / std::f64::consts::E / 400.0).abs() < 1e-13);
}

#[test]
fn ramp_lag_is_rate_times_tau_and_offsets_are_honoured() {
    let mut m = quiet_thermal();
    m.chamber_start_degc = 0.0;
    let rate = 10.0 / 3600.0; // 10 degC/h, the paper's calibration ramp
    m.chamber = vec![ChamberSegment::Ramp {
        duration_s: 6.0 * 3600.0,
        rate_degc_per_s: rate,
    }];
    m.accel_time_constant_s = [300.0, 450.0, 600.0];
    m.accel_offset_degc = [0.5, -1.0, 2.0];
    let mut th = AccelThermal::new(&m, 0.0025).unwrap();
    assert_eq!(th.temperature_degc(), [0.5, -1.0, 2.0]);
    let t = 5.5 * 3600.0; // 33 τ: the transient is below e^-33
    let temps = th.advance_to(t);
    let chamber = ChamberProfile::new(&m).unwrap().temperature_degc(t);
    assert!((chamber - 55.0).abs() < 1e-12);
    let rates = th.rate_degc_per_s();
    for (j, (temp, offset)) in temps.iter().zip(m.accel_offset_degc).enumerate() {
        let lag = chamber + offset - temp;
        let want = rate * m.accel_time_constant_s[j];
        assert!((lag - want).abs() < 1e-9, "axis {j}: lag {lag} vs {want}");
        assert!((rates[j] - rate).abs() < 1e-12);
    }
    // After the ramp ends the chamber holds 60 degC and the accelerometers settle to 60 + o_j.
    let temps = th.advance_to(12.0 * 3600.0);
    for (temp, offset) in temps.iter().zip(m.accel_offset_degc) {
        assert!((temp - 60.0 - offset).abs() < 1e-9);
    }
}

#[test]
fn solution_is_exact_for_any_step_pattern_and_satisfies_the_ode() {
    let mut m = quiet_thermal();
    m.chamber_start_degc = 25.0;
    m.chamber = vec![
        ChamberSegment::Ramp {
            duration_s: 700.3,
            rate_degc_per_s: -0.01,
        },
        ChamberSegment::Fluctuating {
            duration_s: 3000.0,
            rate_degc_per_s: -0.002,
            fluctuation_amplitude_degc: 0.8,
            fluctuation_period_s: 240.0,
        },
        ChamberSegment::Hold {
            duration_s: 500.0,
            temp_degc: 12.0,
        },
    ];
    m.accel_time_constant_s = [60.0, 90.0, 150.0];
    m.accel_offset_degc = [0.3, 0.0, -0.4];
    m.accel_initial_degc = Some([18.0, 19.0, 20.0]);
    let end = 4500.0;
    let mut fine = AccelThermal::new(&m, 0.0025).unwrap();
    let n = (end * 400.0) as usize;
    let mut max_ode_err = 0.0f64;
    let chamber = ChamberProfile::new(&m).unwrap();
    for k in 1..=n {
        let t = k as f64 / 400.0;
        let before = fine.temperature_degc();
        let after = fine.advance_to(t);
        // The chamber is continuous except at the hold step (t = 3700.3 s).
        if (t - 3700.3).abs() > 0.01 {
            let rate = fine.rate_degc_per_s();
            for j in 0..3 {
                // Central estimate of dT/dt from the state at t - h and t vs the ODE at t - h/2.
                let fd = (after[j] - before[j]) * 400.0;
                let u = chamber.temperature_degc(t) + m.accel_offset_degc[j];
                let ode_now = (u - after[j]) / m.accel_time_constant_s[j];
                assert!((rate[j] - ode_now).abs() < 1e-12);
                max_ode_err = max_ode_err.max((fd - ode_now).abs());
            }
        }
    }
    // The one-sided difference is O(h · d²T/dt²) ~ 1e-6 degC/s here.
    assert!(max_ode_err < 1e-5, "{max_ode_err}");
    // One step over every boundary gives the same temperatures as 1.8 M half steps.
    let mut coarse = AccelThermal::new(&m, 0.0025).unwrap();
    let a = coarse.advance_to(end);
    let b = fine.temperature_degc();
    for j in 0..3 {
        assert!(
            (a[j] - b[j]).abs() < 1e-10,
            "axis {j}: {} vs {}",
            a[j],
            b[j]
        );
    }
    // Chamber continuity at the ramp/fluctuation boundary and the hold step.
    assert!(
        (chamber.temperature_degc(700.3 - 1e-9) - chamber.temperature_degc(700.3)).abs() < 1e-9
    );
    assert_eq!(chamber.temperature_degc(3700.3 + 1e-6), 12.0);
    assert_eq!(chamber.temperature_degc(1e6), 12.0);
}

#[test]
fn thermometer_noise_has_the_configured_std() {
    let sigma = 0.02;
    let mut th = Thermometers::new(sigma, GaussianStream::new(5, stream::THERMOMETER));
    let n = 100_000;
    let mut s2 = [0.0; 3];
    let mut s1 = [0.0; 3];
    for _ in 0..n {
        let r = th.read([10.0, 20.0, 30.0]);
        for j in 0..3 {
            let d = r[j] - 10.0 * (j + 1) as f64;
            s1[j] += d;
            s2[j] += d * d;
        }
    }
    for j in 0..3 {
        let std = (s2[j] / n as f64).sqrt();
        assert!((std / sigma - 1.0).abs() < 0.05, "axis {j}: std {std}");
        assert!((s1[j] / n as f64).abs() < 5.0 * sigma / (n as f64).sqrt());
    }
    let mut quiet = Thermometers::new(0.0, GaussianStream::new(5, stream::THERMOMETER));
    assert_eq!(quiet.read([1.5, 2.5, 3.5]), [1.5, 2.5, 3.5]);
}
