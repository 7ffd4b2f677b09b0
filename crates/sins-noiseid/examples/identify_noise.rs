//! Identify an IMU's noise from a still run: simulate two hours at rest with known noise (an
//! ideal, tactical-grade IMU on a level table), hand the samples to
//! [`sins_noiseid::identify_noise`] and print each identified term beside the truth.
//!
//! `cargo run --release -p sins-noiseid --example identify_noise` (a few seconds). With real data,
//! a [`sins_diag::source::SampleSource`] over the recording takes the simulator's place.

use sins_diag::source::SimSource;
use sins_imu::{ForwardModel, ImuErrorParams, ParamModel};
use sins_nav::{DEG, DEG_PER_H, Euler, Geodetic, UG, ned_from_body_euler};
use sins_noiseid::{NoiseIdConfig, RunStationary, identify_noise};
use sins_sim::noise::gauss_markov_sigma_from_allan;
use sins_sim::{
    ChamberSegment, MotionProgram, MotionSegment, NoiseModel, Scenario, Simulator, ThermalModel,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let deg_per_h = DEG_PER_H;
    let ug = UG;
    // Tactical grade: 0.05 deg/√h, 1 deg/h bias instability; 50 ug/√Hz, 20 ug.
    let noise = NoiseModel {
        gyro_arw_rad_per_sqrt_s: 0.05 * DEG / 60.0,
        gyro_bias_instability_radps: gauss_markov_sigma_from_allan(1.0 * deg_per_h),
        gyro_bias_correlation_s: 600.0,
        gyro_quantum_rad: 0.0,
        accel_vrw_mps_per_sqrt_s: 50.0 * ug,
        accel_bias_instability_mps2: gauss_markov_sigma_from_allan(20.0 * ug),
        accel_bias_correlation_s: 600.0,
    };
    let hours = 2.0;
    let truth = ImuErrorParams::ideal(ParamModel::States42);
    let scenario = Scenario {
        name: "still".into(),
        description: "two hours at rest".into(),
        site: Geodetic::from_deg(28.22, 112.99, 60.0),
        rate_hz: 100.0,
        quadrature_nodes: 1,
        motion: MotionProgram {
            initial_ned_from_body: ned_from_body_euler(&Euler::from_deg(0.0, 0.0, 30.0)),
            segments: vec![MotionSegment::Dwell {
                duration_s: hours * 3600.0,
                label: "stationary".into(),
            }],
        },
        thermal: ThermalModel {
            chamber_start_degc: 20.0,
            chamber: vec![ChamberSegment::Hold {
                duration_s: hours * 3600.0,
                temp_degc: 20.0,
            }],
            accel_time_constant_s: [720.0, 1200.0, 1680.0],
            accel_offset_degc: [0.0; 3],
            accel_initial_degc: None,
            thermometer_noise_degc: 0.0,
        },
        noise,
        truth,
        effects: Vec::new(),
        seed: 7,
        with_reference: false,
    };
    let mut source = SimSource::new(Simulator::new(&scenario, ForwardModel::new(truth))?);
    let labels = source.segment_labels();
    let mut runs = [RunStationary {
        name: "still".into(),
        source: &mut source,
        segment_labels: labels,
        site: scenario.site,
        compensation: None,
    }];
    let id = identify_noise(&mut runs, &NoiseIdConfig::default())?;
    let g = &id.gyro;
    let a = &id.accel;
    println!("term                              identified              truth");
    println!(
        "gyro ARW [deg/√h]                 {:.5} ± {:.5}     0.05000",
        g.white_per_sqrt_s.value * 60.0 / DEG,
        g.white_per_sqrt_s.sigma * 60.0 / DEG
    );
    println!(
        "gyro bias instability [deg/h]     {:.3} ± {:.3}         1.000",
        g.bias_instability.value / deg_per_h,
        g.bias_instability.sigma / deg_per_h
    );
    println!(
        "accel VRW [ug/√Hz]                {:.2} ± {:.2}         50.00",
        a.white_per_sqrt_s.value / ug,
        a.white_per_sqrt_s.sigma / ug
    );
    println!(
        "accel bias instability [ug]       {:.2} ± {:.2}         20.00",
        a.bias_instability.value / ug,
        a.bias_instability.sigma / ug
    );
    println!(
        "consistent with its own data: {}",
        if id.inconsistent.is_empty() {
            "yes".to_string()
        } else {
            id.inconsistent.join("; ")
        }
    );
    Ok(())
}
