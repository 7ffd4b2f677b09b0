//! The least-squares baseline on noise-free data: at a stable temperature the 30-state model is
//! exact, so each point recovers the truth at that temperature, `C + T_coef (T_j − T_ref)`, and
//! the straight-line fit returns the truth's temperature coefficients and constants.

use sins_calstudy::units::{PARAMS, vec_to_paper};
use sins_calstudy::{LsStudy, calibrate_scenario, config_for_scenario, truncate_motion};
use sins_imu::ParamModel;
use sins_kf::FilterNoise;
use sins_sim::NoiseModel;
use std::path::PathBuf;

#[test]
fn noise_free_points_give_the_truth_slopes() {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments/paper_ls_baseline.toml");
    let exp = sins_config::load_experiment(path).expect("experiment loads");
    let mut scenarios = exp.scenarios;
    for sc in &mut scenarios {
        sc.noise = NoiseModel::default();
        sc.thermal.thermometer_noise_degc = 0.0;
        truncate_motion(sc, 4680.5);
    }
    let runs: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = scenarios
            .iter()
            .map(|sc| {
                s.spawn(move || {
                    let mut c = config_for_scenario(sc, ParamModel::States30);
                    c.noise = FilterNoise::none();
                    calibrate_scenario(sc, c).expect("calibration runs")
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("no panic"))
            .collect()
    });
    let truth = scenarios[0].truth;
    let ls = LsStudy::new("noise-free".into(), &scenarios, &runs, &truth, 4.0, 3.0).expect("fits");
    let t = vec_to_paper(&sins_kf::params_to_vec(&truth, ParamModel::States42));
    let mut failures = Vec::new();
    for c in &ls.coefficients {
        let k = PARAMS.iter().position(|p| p.name == c.name).expect("known");
        let kc = PARAMS
            .iter()
            .position(|p| p.name == c.constant)
            .expect("known");
        // Tolerances: a fifth of Table 3's printed resolution (0.01 per degC) for the slopes,
        // 0.01 of the constants' units; one pass of the scheme leaves the noise-free 30-state
        // points within ~1e-3 of the truth at their temperature (the filter's numerical floor).
        eprintln!(
            "{:<7} slope {:>10.5} truth {:>7.2}  constant {:>9.4} truth {:>7.2}  rms {:.1e}",
            c.name, c.slope, t[k], c.constant_at_reference, t[kc], c.residual_rms
        );
        failures.extend(
            ((c.slope - t[k]).abs() >= 2e-3)
                .then(|| format!("{}: {} vs {}", c.name, c.slope, t[k])),
        );
        failures.extend(
            ((c.constant_at_reference - t[kc]).abs() >= 1e-2)
                .then(|| format!("{}: {} vs {}", c.constant, c.constant_at_reference, t[kc])),
        );
    }
    assert!(failures.is_empty(), "{failures:#?}");
    assert_eq!(ls.total_h, 4.0 + 4.0 * 3.0);
}
