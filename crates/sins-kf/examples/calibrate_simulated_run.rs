//! Calibrate an IMU with the 42-state filter: simulate the paper's 4.2 h turntable run
//! (`experiments/paper_calibration.toml`: Table 1's coefficients, the chamber ramping from 0 to
//! 42 degC, the paper's noise), stream its samples into a [`sins_kf::CalibrationFilter`] and print
//! every coefficient's estimate beside the truth with its error in filter sigmas.
//!
//! `cargo run --release -p sins-kf --example calibrate_simulated_run` (about 10 s). With real
//! turntable data, the samples of the recording take the simulator's place.

use sins_imu::{ImuErrorParams, ParamModel};
use sins_kf::{
    CalibrationConfig, CalibrationFilter, FilterNoise, STATE_NAMES, STATE_UNITS, params_to_vec,
};
use sins_nav::{ARCSEC, DEG_PER_H, UG};
use sins_sim::Simulator;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../experiments/paper_calibration.toml");
    let scenario = sins_config::load_experiment(&file)?.scenarios.remove(0);
    let model = ParamModel::States42;

    // The filter: the paper's 1 s zero-velocity updates, process noise matching the sensors.
    let mut config = CalibrationConfig::new(model, 1.0 / scenario.rate_hz, scenario.site);
    let n = &scenario.noise;
    config.noise = FilterNoise::from_sensor(
        n.gyro_arw_rad_per_sqrt_s,
        n.gyro_bias_instability_radps,
        n.gyro_bias_correlation_s,
        n.accel_vrw_mps_per_sqrt_s,
        n.accel_bias_instability_mps2,
        n.accel_bias_correlation_s,
    );
    let mut start = ImuErrorParams::ideal(model);
    start.reference_temperature_degc = scenario.truth.reference_temperature_degc;
    let mut filter = CalibrationFilter::new(config, start)?;

    // Stream the simulated run into it, one batch at a time.
    let mut sim = Simulator::from_scenario(&scenario)?;
    sim.run(65_536, |batch| {
        batch.samples.iter().try_for_each(|s| filter.push(s))
    })?;
    let result = filter.finish()?;

    let est = params_to_vec(&result.params, model);
    let sigma = params_to_vec(&result.sigma, model);
    let truth = params_to_vec(&scenario.truth, model);
    println!(
        "{:<8} {:>12} {:>12} {:>10} {:>8}",
        "coef", "truth", "estimate", "1-sigma", "z"
    );
    let mut within = 0;
    for (k, name) in STATE_NAMES[9..9 + est.len()].iter().enumerate() {
        let (per, unit) = paper_unit(STATE_UNITS[9 + k], name);
        let z = (est[k] - truth[k]) / sigma[k];
        within += usize::from(z.abs() < 3.0);
        println!(
            "{name:<8} {:>12.4} {:>12.4} {:>10.4} {z:>8.2}  {unit}",
            truth[k] / per,
            est[k] / per,
            sigma[k] / per
        );
    }
    println!(
        "{within} of {} coefficients within 3 sigma of the truth; {} updates",
        est.len(),
        result.updates
    );
    Ok(())
}

/// The paper's unit of a coefficient given its SI unit and name.
fn paper_unit(si: &str, name: &str) -> (f64, &'static str) {
    let misalignment = name.starts_with("dM") || name.starts_with("TM");
    let per_degc = name.starts_with('T');
    match (si, misalignment, per_degc) {
        ("rad/s", _, _) => (DEG_PER_H, "deg/h"),
        ("m/s^2", _, false) => (UG, "ug"),
        (_, true, false) => (ARCSEC, "arcsec"),
        (_, true, true) => (ARCSEC, "arcsec/degC"),
        (_, false, true) if name.starts_with("TB") => (UG, "ug/degC"),
        (_, false, true) => (1e-6, "ppm/degC"),
        _ => (1e-6, "ppm"),
    }
}
