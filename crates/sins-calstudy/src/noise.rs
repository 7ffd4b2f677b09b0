//! The filter's process noise from an experiment's `[imu.noise]` section.

/// The calibration filter's process noise for an experiment's sensor noise (`Scenario::noise`,
/// i.e. the `[imu.noise]` section already in SI, with the Allan bias-instability figures turned
/// into Gauss-Markov σ by `sins_config`): white gyro and accelerometer noise as given, and the
/// Gauss-Markov bias wander with the same σ and correlation time, which the filter carries as
/// nuisance states beside eq (8). The one conversion lives in `sins_harness::pipeline`.
///
/// The gyro output quantum (`gyro_quantum_rad`) is not modelled: pulse counting with the
/// remainder carried leaves an attitude error bounded by half a quantum (0.5 arcsec for the
/// paper's IMU) that does not accumulate.
pub use sins_harness::pipeline::filter_noise_for as filter_noise_from_experiment;

#[cfg(test)]
mod tests {
    use super::*;
    use sins_kf::FilterNoise;
    use sins_nav::{DEG_PER_H, UG};
    use sins_sim::noise::gauss_markov_sigma_from_allan;

    /// The CLI's hand-set defaults (sinsbench calibrate) and the experiment file describe the
    /// same IMU: both paths must give the same filter noise.
    #[test]
    fn matches_the_cli_conversion_of_the_paper_figures() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../experiments/paper_calibration.toml");
        let exp = sins_config::load_experiment(path).expect("experiment loads");
        let got = filter_noise_from_experiment(&exp.scenarios[0].noise);
        let want = FilterNoise::from_sensor(
            0.0005 * sins_nav::DEG / 60.0,
            gauss_markov_sigma_from_allan(0.0005 * DEG_PER_H),
            3600.0,
            10.0 * UG,
            gauss_markov_sigma_from_allan(5.0 * UG),
            3600.0,
        );
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
        assert!(close(
            got.gyro_arw_rad_per_sqrt_s,
            want.gyro_arw_rad_per_sqrt_s
        ));
        assert!(close(
            got.gyro_bias_wander_radps,
            want.gyro_bias_wander_radps
        ));
        assert!(close(
            got.accel_vrw_mps_per_sqrt_s,
            want.accel_vrw_mps_per_sqrt_s
        ));
        assert!(close(
            got.accel_bias_wander_mps2,
            want.accel_bias_wander_mps2
        ));
        assert_eq!(got.gyro_bias_correlation_s, 3600.0);
        assert_eq!(got.accel_bias_correlation_s, 3600.0);
    }
}
