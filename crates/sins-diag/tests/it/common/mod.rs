//! Scenario builders and pipeline helpers shared by the integration tests.
#![allow(dead_code)]

use sins_diag::Grid;
use sins_diag::noise::NoiseSpec;
use sins_diag::replay::{RealTrack, ReplaySetup, replay_run};
use sins_diag::sensitivity::{RunSensitivity, SensitivitySetup, run_sensitivity};
use sins_diag::source::SimSource;
use sins_imu::{EffectKind, EffectSpec, ForwardModel, ImuErrorParams, ParamModel};
use sins_nav::{DEG, Euler, Geodetic, Vec3, ned_from_body_euler};
use sins_sim::{
    ChamberSegment, MotionProgram, MotionSegment, NoiseModel, Scenario, Simulator, ThermalModel,
};

pub fn site() -> Geodetic {
    Geodetic::from_deg(28.22, 112.99, 60.0)
}

pub fn dwell(duration_s: f64, label: &str) -> MotionSegment {
    MotionSegment::Dwell {
        duration_s,
        label: label.into(),
    }
}

pub fn rotate(axis: [f64; 3], angle_deg: f64, label: &str) -> MotionSegment {
    MotionSegment::Rotate {
        axis_body: Vec3::from(axis),
        angle_rad: angle_deg * DEG,
        rate_radps: 9.0 * DEG,
        label: label.into(),
    }
}

/// 20 min alignment, then dwells and 90 degree turns about all three axes (total `hours`).
pub fn turning_motion(hours: f64) -> Vec<MotionSegment> {
    let nav = hours * 3600.0 - 1200.0;
    let d = (nav - 60.0) / 7.0;
    vec![
        dwell(1200.0, "alignment"),
        dwell(d, "stationary"),
        rotate([0.0, 0.0, 1.0], 90.0, "turn"),
        dwell(d, "stationary"),
        rotate([1.0, 0.0, 0.0], 90.0, "turn"),
        dwell(d, "stationary"),
        rotate([0.0, 1.0, 0.0], -90.0, "turn"),
        dwell(d, "stationary"),
        rotate([0.0, 0.0, 1.0], -90.0, "turn"),
        dwell(d, "stationary"),
        rotate([1.0, 0.0, 0.0], -90.0, "turn"),
        dwell(d, "stationary"),
        rotate([0.0, 1.0, 0.0], 90.0, "turn"),
        dwell(d, "stationary"),
    ]
}

/// Chamber ramp from `start_degc` at `rate_degc_per_h`, accelerometers lagging it.
pub fn ramp_thermal(start_degc: f64, rate_degc_per_h: f64, hours: f64) -> ThermalModel {
    ThermalModel {
        chamber_start_degc: start_degc,
        chamber: vec![ChamberSegment::Ramp {
            duration_s: hours * 3600.0,
            rate_degc_per_s: rate_degc_per_h / 3600.0,
        }],
        accel_time_constant_s: [720.0, 1200.0, 1680.0],
        accel_offset_degc: [0.5, -0.3, 0.8],
        accel_initial_degc: None,
        thermometer_noise_degc: 0.0,
    }
}

/// A noise-free scenario with an ideal 42-state truth (reference 20 degC).
pub fn scenario(segments: Vec<MotionSegment>, rate_hz: f64, thermal: ThermalModel) -> Scenario {
    let mut truth = ImuErrorParams::ideal(ParamModel::States42);
    truth.reference_temperature_degc = 20.0;
    Scenario {
        name: "diag-test".into(),
        description: "sins-diag test".into(),
        site: site(),
        rate_hz,
        quadrature_nodes: 6,
        motion: MotionProgram {
            initial_ned_from_body: ned_from_body_euler(&Euler::from_deg(0.5, -0.3, 30.0)),
            segments,
        },
        thermal,
        noise: NoiseModel::default(),
        truth,
        effects: Vec::new(),
        seed: 11,
        with_reference: false,
    }
}

/// A re-readable source of `sc`.
pub fn source(sc: &Scenario) -> SimSource {
    let fwd = sc.effects.iter().fold(ForwardModel::new(sc.truth), |f, e| {
        f.with_effect(e.build(&sc.truth))
    });
    SimSource::new(Simulator::new(sc, fwd).expect("valid scenario"))
}

/// Replay `sc` with `params`.
pub fn track(sc: &Scenario, params: &ImuErrorParams) -> (SimSource, RealTrack) {
    let mut src = source(sc);
    let t =
        replay_run("test", &mut src, params, &sc.site, &ReplaySetup::default()).expect("replay");
    (src, t)
}

/// Sensitivities of `src` (with its real track) to the `candidates`.
pub fn sensitivity(
    src: &mut SimSource,
    sc: &Scenario,
    t: &RealTrack,
    params: &ImuErrorParams,
    noise: &NoiseSpec,
    candidates: &[EffectKind],
    grid: Grid,
) -> RunSensitivity {
    let replay = ReplaySetup::default();
    let setup = SensitivitySetup {
        params,
        noise,
        replay: &replay,
        candidates,
        grid,
        refine: None,
        turn_on_taus_s: &[],
    };
    run_sensitivity("test", src, &sc.site, &t.points, &t.temperatures, &setup).expect("pass")
}

/// The effect spec of `kind` with `value` (in the kind's unit) on component `c`.
pub fn effect(kind: EffectKind, c: usize, value: f64) -> EffectSpec {
    EffectSpec::unit(kind, c).scaled(kind.unit().to_si(value))
}

/// North/east of the real track at time `t_s` (nearest point).
pub fn at(t: &RealTrack, t_s: f64) -> [f64; 2] {
    let k = t
        .points
        .partition_point(|p| p.t_s < t_s - 1e-6)
        .min(t.points.len() - 1);
    [t.points[k].north_m, t.points[k].east_m]
}

/// Table 4 pattern `p` (1, 2 or 3) for `duration_s`.
pub fn pattern(p: usize, duration_s: f64) -> MotionSegment {
    let (amp, per) = match p {
        1 => ([2.0, 4.0, 2.0], [0.1, 0.2, 0.3]),
        2 => ([6.0, 5.0, 6.0], [0.1, 0.2, 0.15]),
        _ => ([8.0, 9.0, 15.0], [0.2, 0.1, 0.15]),
    };
    MotionSegment::Vibrate {
        duration_s,
        amplitude_rad: Vec3::from(amp) * DEG,
        period_s: Vec3::from(per),
        phase_rad: Vec3::zeros(),
        label: format!("pattern{p}"),
    }
}

/// 20 min alignment, stationary, then patterns 1-3 with stationary gaps (total `hours`).
pub fn vibration_motion(hours: f64) -> Vec<MotionSegment> {
    let d = (hours * 3600.0 - 1200.0) / 7.0;
    vec![
        dwell(1200.0, "alignment"),
        dwell(d, "stationary"),
        pattern(1, d),
        dwell(d, "stationary"),
        pattern(2, d),
        dwell(d, "stationary"),
        pattern(3, d),
        dwell(d, "stationary"),
    ]
}

/// The paper's sensor noise (experiments/paper_navigation.toml [imu.noise]) in SI.
pub fn paper_noise() -> NoiseModel {
    use sins_nav::{ARCSEC, DEG_PER_H, UG};
    let ratio = sins_sim::noise::GM_ALLAN_PEAK_RATIO;
    NoiseModel {
        gyro_arw_rad_per_sqrt_s: 0.0005 * sins_nav::DEG / 60.0,
        gyro_bias_instability_radps: 0.0005 * DEG_PER_H / ratio,
        gyro_bias_correlation_s: 3600.0,
        gyro_quantum_rad: 1.0 * ARCSEC,
        accel_vrw_mps_per_sqrt_s: 10.0 * UG,
        accel_bias_instability_mps2: 5.0 * UG / ratio,
        accel_bias_correlation_s: 3600.0,
    }
}

/// Noisy runs of `motion(hours)` at `rate_hz` with the paper's sensor noise and a 0.01 degC
/// thermometer, one per `(chamber start degC, ramp degC/h, seed)`, each with `effects` hidden.
pub fn noisy_runs(
    motion: fn(f64) -> Vec<MotionSegment>,
    rate_hz: f64,
    hours: f64,
    runs: &[(f64, f64, u64)],
    effects: &[EffectSpec],
) -> Vec<Scenario> {
    runs.iter()
        .map(|&(start, rate, seed)| {
            let mut sc = scenario(motion(hours), rate_hz, ramp_thermal(start, rate, hours));
            sc.noise = paper_noise();
            sc.thermal.thermometer_noise_degc = 0.01;
            sc.seed = seed;
            sc.effects = effects.to_vec();
            sc
        })
        .collect()
}

/// A diagnosis input of the scenarios, replayed with `params`.
pub fn input(
    scenarios: &[Scenario],
    params: &ImuErrorParams,
    sigma: Option<ImuErrorParams>,
) -> sins_diag::input::DiagnosisInput {
    let runs = scenarios
        .iter()
        .enumerate()
        .map(|(i, sc)| {
            let (src, t) = track(sc, params);
            sins_diag::input::RunData {
                name: format!("run{i}"),
                segment_labels: src.segment_labels(),
                source: Box::new(src),
                site: sc.site,
                track: t.points,
                temperatures: Some(t.temperatures),
                twin_mean: None,
            }
        })
        .collect();
    sins_diag::input::DiagnosisInput {
        runs,
        params: *params,
        param_sigma: sigma,
        param_covariance: None,
        noise: NoiseSpec::from(&scenarios[0].noise),
        calibration_run: None,
    }
}

/// One line per candidate and the verdict.
pub fn summary(d: &sins_diag::report::Diagnosis) -> String {
    let mut s = format!(
        "null chi2 {:.1} / {} (p {:.3})  verdict {:?}\n",
        d.null_test.chi2, d.null_test.dof, d.null_test.p_value, d.verdict
    );
    for c in &d.candidates {
        let comps: Vec<String> = c
            .components
            .iter()
            .filter(|x| x.retained)
            .map(|x| {
                format!(
                    "{}={:.4}±{:.4}",
                    x.label,
                    x.value,
                    x.sigma.unwrap_or(f64::NAN)
                )
            })
            .collect();
        s += &format!(
            "  {:<30} dchi2 {:>10.1} dof {} p {:.2e} dBIC {:>9.1} pass {} resid {:.1} [{}]\n",
            c.kind,
            c.dchi2,
            c.dof,
            c.p_value,
            c.delta_bic,
            c.passes,
            c.residual.chi2,
            comps.join(" ")
        );
    }
    for v in &d.validation {
        s += &format!(
            "  validation {} -> {}: rms {:.1} -> {:.1} m ({:.0} %), max {:.1} -> {:.1} m ({:.0} %)\n",
            v.fitted_on,
            v.evaluated_on,
            v.before.rms_gap_m,
            v.after.rms_gap_m,
            v.rms_shrinkage_percent,
            v.before.max_horizontal_gap_m,
            v.after.max_horizontal_gap_m,
            v.max_shrinkage_percent
        );
    }
    s
}
