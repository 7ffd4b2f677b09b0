//! Shared helpers of the physics tests: the paper's calibration experiment, a streaming
//! simulator → filter run with the filter's own time measured, and Table 1.
#![allow(dead_code)]

use sins_imu::{ImuErrorParams, ParamModel};
use sins_kf::{
    CalibrationConfig, CalibrationError, CalibrationFilter, CalibrationResult, FilterNoise,
};
use sins_sim::{NoiseModel, Scenario, Simulator};
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// The paper's calibration scenario (`experiments/paper_calibration.toml`, run `cal1`).
pub fn paper_scenario() -> Scenario {
    let p =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments/paper_calibration.toml");
    sins_config::load_experiment(p)
        .expect("experiment loads")
        .scenarios
        .remove(0)
}

/// The same scenario with every noise source (sensor and thermometer) switched off.
pub fn noise_free(mut sc: Scenario) -> Scenario {
    sc.noise = NoiseModel::default();
    sc.thermal.thermometer_noise_degc = 0.0;
    sc
}

/// The filter's process noise for a scenario's sensor noise model.
pub fn filter_noise(n: &NoiseModel) -> FilterNoise {
    FilterNoise::from_sensor(
        n.gyro_arw_rad_per_sqrt_s,
        n.gyro_bias_instability_radps,
        n.gyro_bias_correlation_s,
        n.accel_vrw_mps_per_sqrt_s,
        n.accel_bias_instability_mps2,
        n.accel_bias_correlation_s,
    )
}

/// Default configuration of `model` for a scenario, with the filter noise matching its sensors.
pub fn config_for(sc: &Scenario, model: ParamModel) -> CalibrationConfig {
    let mut c = CalibrationConfig::new(model, 1.0 / sc.rate_hz, sc.site);
    c.noise = filter_noise(&sc.noise);
    c
}

/// The first three segments of the paper's calibration run with a 300 s alignment (about
/// 190,000 samples), the 42-state configuration for it and an ideal initial estimate at the
/// run's reference temperature.
pub fn short_run_setup() -> (Scenario, CalibrationConfig, ImuErrorParams) {
    let mut sc = paper_scenario();
    sc.motion.segments.truncate(3);
    let mut config = config_for(&sc, ParamModel::States42);
    config.alignment.duration_s = 300.0;
    let mut initial = ImuErrorParams::ideal(ParamModel::States42);
    initial.reference_temperature_degc = sc.truth.reference_temperature_degc;
    (sc, config, initial)
}

/// Simulate `sc` and calibrate it; returns the result and the time spent inside the filter.
pub fn run(
    sc: &Scenario,
    config: CalibrationConfig,
) -> (Result<CalibrationResult, CalibrationError>, Duration) {
    let mut initial = ImuErrorParams::ideal(config.model);
    initial.reference_temperature_degc = sc.truth.reference_temperature_degc;
    let mut filter = CalibrationFilter::new(config, initial).expect("valid configuration");
    let mut sim = Simulator::from_scenario(sc).expect("valid scenario");
    let mut spent = Duration::ZERO;
    let fed = sim.run(65_536, |b| {
        let t0 = Instant::now();
        let r = b.samples.iter().try_for_each(|s| filter.push(s));
        spent += t0.elapsed();
        r
    });
    let t0 = Instant::now();
    let result = fed.and_then(|_| filter.finish());
    spent += t0.elapsed();
    (result, spent)
}

/// Table 1 of the paper: name, unit, preset, paper residual (from the shared CSV copy).
pub const TABLE1: [(&str, &str, f64, f64); 33] = [
    ("B_gx", "deg/h", 0.003, 0.00016),
    ("B_gy", "deg/h", 0.003, 0.00026),
    ("B_gz", "deg/h", 0.003, 0.00002),
    ("B_ax", "ug", 1.0, 0.01),
    ("B_ay", "ug", 1.0, 0.02),
    ("B_az", "ug", 1.0, 0.01),
    ("dK_gx", "ppm", 20.0, 0.03),
    ("dM_gyx", "arcsec", -61.88, 0.10),
    ("dM_gzx", "arcsec", 41.25, 0.01),
    ("dK_gy", "ppm", 40.0, 0.07),
    ("dM_gzy", "arcsec", -20.63, 0.01),
    ("dK_gz", "ppm", 60.0, 0.02),
    ("dK_ax", "ppm", 10.0, 0.06),
    ("dM_ayx", "arcsec", -41.25, 0.03),
    ("dM_azx", "arcsec", 20.62, 0.02),
    ("dM_axy", "arcsec", 61.88, 0.07),
    ("dK_ay", "ppm", 30.0, 0.08),
    ("dM_azy", "arcsec", -61.88, 0.01),
    ("dM_axz", "arcsec", -20.62, 0.03),
    ("dM_ayz", "arcsec", 41.25, 0.01),
    ("dK_az", "ppm", 50.0, 0.02),
    ("TB_ax", "ug/degC", 0.2, 0.0018),
    ("TB_ay", "ug/degC", 1.0, 0.0068),
    ("TB_az", "ug/degC", 2.0, 0.0010),
    ("TK_ax", "ppm/degC", 1.0, 0.001),
    ("TK_ay", "ppm/degC", 2.0, 0.001),
    ("TK_az", "ppm/degC", 3.0, 0.001),
    ("TM_ayx", "arcsec/degC", -0.1, 0.002),
    ("TM_azx", "arcsec/degC", 0.2, 0.002),
    ("TM_axy", "arcsec/degC", 0.3, 0.003),
    ("TM_azy", "arcsec/degC", 0.4, 0.001),
    ("TM_axz", "arcsec/degC", 0.5, 0.0),
    ("TM_ayz", "arcsec/degC", -0.6, 0.001),
];

/// SI value of one paper unit.
pub fn unit_si(unit: &str) -> f64 {
    use sins_nav::{ARCSEC, DEG_PER_H, UG};
    match unit {
        "deg/h" => DEG_PER_H,
        "ug" | "ug/degC" => UG,
        "arcsec" | "arcsec/degC" => ARCSEC,
        _ => 1e-6, // ppm, ppm/degC
    }
}

/// Print our estimates beside Table 1 and return, per coefficient, (name, our residual,
/// our 1-sigma, paper residual) in paper units.
pub fn table1_comparison(
    r: &CalibrationResult,
    truth: &[f64],
) -> Vec<(&'static str, f64, f64, f64)> {
    let est = sins_kf::params_to_vec(&r.params, r.params.model);
    let sig = sins_kf::params_to_vec(&r.sigma, r.params.model);
    eprintln!(
        "{:<8} {:>11} {:>9} {:>12} {:>11} {:>10} {:>11}",
        "coef", "unit", "preset", "estimate", "residual", "1-sigma", "paper res."
    );
    let mut out = Vec::new();
    for (k, &(name, unit, preset, paper)) in TABLE1.iter().enumerate().take(est.len()) {
        let u = unit_si(unit);
        let (e, s, t) = (est[k] / u, sig[k] / u, truth[k] / u);
        let res = e - t;
        eprintln!(
            "{name:<8} {unit:>11} {preset:>9.4} {e:>12.6} {res:>11.6} {s:>10.6} {paper:>11.5}"
        );
        out.push((name, res, s, paper));
    }
    out
}
