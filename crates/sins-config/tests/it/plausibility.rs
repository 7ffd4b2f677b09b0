//! Plausibility guards of experiment, parameter and effect files: a value no real IMU on the
//! Earth can have is refused with an error naming the file, the key (with its line) and the limit.

use crate::common;

use common::{SEGMENTS, experiment_text, experiments_dir, write_temp};
use sins_config::{ConfigError, load_experiment, parse_effects_toml, parse_params_toml};

/// Load the template experiment after replacing `from` by `to`; the error and its message.
fn refused(from: &str, to: &str, segments: &str) -> (ConfigError, String) {
    let text = experiment_text("", segments);
    assert!(text.contains(from), "template lacks {from:?}");
    let (_dir, path) = write_temp("absurd.toml", &text.replacen(from, to, 1));
    let err = load_experiment(&path).expect_err("an implausible experiment must be refused");
    let msg = err.to_string();
    eprintln!("{msg}");
    assert!(msg.contains("absurd.toml"), "{msg}");
    (err, msg)
}

fn assert_mentions(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "{p:?} missing from:\n{msg}");
    }
}

#[test]
fn the_shipped_experiments_pass_the_guards() {
    let dir = experiments_dir();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            load_experiment(&path).unwrap_or_else(|e| panic!("{e}"));
        }
    }
}

#[test]
fn sample_rate_of_1e9_hz_is_refused() {
    let (_, msg) = refused("rate_hz = 200.0", "rate_hz = 1e9", SEGMENTS);
    assert_mentions(
        &msg,
        &["sampling.rate_hz", "10000 Hz maximum", "absurd.toml:9:"],
    );
}

#[test]
fn a_run_of_1e12_s_is_refused() {
    let (_, msg) = refused("duration_s = 60.0", "duration_s = 1e12", SEGMENTS);
    assert_mentions(&msg, &["motion.segment[0].duration_s", "366 days"]);
}

#[test]
fn many_long_segments_adding_up_beyond_a_year_are_refused() {
    let seg = "\n[[motion.segment]]\nkind = \"dwell\"\nduration_h = 8000.0\n";
    let (_, msg) = refused("", "", &format!("{SEGMENTS}{seg}{seg}"));
    assert_mentions(&msg, &["motion.segment", "lasts", "366 days"]);
}

#[test]
fn a_scheme_repeated_four_billion_times_is_refused_before_expanding() {
    let seg = format!(
        "\n[[motion.segment]]\nkind = \"scheme\"\nfile = \"{}\"\nrate_deg_per_s = 9.0\n\
         dwell_s = 1.0\nrepeat = 4000000000\n",
        common::exp_file("schemes/calibration_18step.csv")
    );
    let (_, msg) = refused("", "", &format!("{SEGMENTS}{seg}"));
    assert_mentions(&msg, &["motion.segment[2].repeat", "segments"]);
}

#[test]
fn a_turntable_faster_than_the_gyro_full_scale_is_refused() {
    let (_, msg) = refused("rate_deg_per_s = 9.0", "rate_deg_per_s = 5000.0", SEGMENTS);
    assert_mentions(
        &msg,
        &["motion.segment[1].rate_deg_per_s", "1000 deg/s full scale"],
    );
}

#[test]
fn a_vibration_beyond_the_gyro_full_scale_is_refused() {
    let seg = "\n[[motion.segment]]\nkind = \"vibrate\"\nduration_s = 10.0\n\
               amplitude_deg = [1.0, 30.0, 1.0]\nperiod_s = [0.1, 0.1, 0.1]\n";
    let (_, msg) = refused("", "", &format!("{SEGMENTS}{seg}"));
    assert_mentions(
        &msg,
        &[
            "motion.segment[2].amplitude_deg[1]",
            "1885 deg/s",
            "full scale",
        ],
    );
}

#[test]
fn a_site_1e30_m_high_is_refused() {
    let (_, msg) = refused(
        "longitude_deg = 112.99",
        "longitude_deg = 112.99\nheight_m = 1e30",
        SEGMENTS,
    );
    assert_mentions(&msg, &["site.height_m", "not a place on the Earth"]);
}

#[test]
fn a_chamber_of_a_million_degc_is_refused() {
    let (_, msg) = refused(
        "chamber_start_degc = 0.0",
        "chamber_start_degc = 1e6",
        SEGMENTS,
    );
    assert_mentions(&msg, &["thermal.chamber_start_degc", "-60..125 degC"]);
    // A ramp that leaves the range names its rate.
    let (_, msg) = refused(
        "rate_degc_per_h = 10.0",
        "rate_degc_per_h = 1000.0",
        SEGMENTS,
    );
    assert_mentions(
        &msg,
        &[
            "thermal.chamber[0].rate_degc_per_h",
            "1000 degC",
            "-60..125 degC",
        ],
    );
}

#[test]
fn a_noise_beyond_ten_times_mems_is_refused() {
    let (_, msg) = refused(
        "[thermal]",
        "[imu.noise]\naccel_vrw_ug_per_sqrt_hz = 1e9\n\n[thermal]",
        SEGMENTS,
    );
    assert_mentions(
        &msg,
        &[
            "imu.noise.accel_vrw_ug_per_sqrt_hz",
            "plausibility limit 10000",
        ],
    );
}

/// The repository's Table 1 parameter file with `from` replaced by `to`.
fn params_refused(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(experiments_dir().join("imu/paper_table1.toml")).unwrap();
    assert!(text.contains(from), "file lacks {from:?}");
    let err = parse_params_toml(&text.replacen(from, to, 1), "absurd_params.toml")
        .expect_err("implausible coefficient must be refused");
    let msg = err.to_string();
    eprintln!("{msg}");
    assert!(msg.contains("absurd_params.toml"), "{msg}");
    msg
}

#[test]
fn a_scale_factor_error_of_1e300_ppm_is_refused() {
    let text = std::fs::read_to_string(experiments_dir().join("imu/paper_table1.toml")).unwrap();
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("dK_x_ppm"))
        .expect("dK_x_ppm")
        .to_string();
    let msg = params_refused(&line, "dK_x_ppm = 1e300");
    assert_mentions(
        &msg,
        &["dK_x_ppm", "plausibility limit of 100000 ppm", "10x"],
    );
}

#[test]
fn a_reference_temperature_of_a_million_degc_is_refused() {
    let text = std::fs::read_to_string(experiments_dir().join("imu/paper_table1.toml")).unwrap();
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("reference_temperature_degc"))
        .map(str::to_string);
    let msg = match line {
        Some(l) => params_refused(&l, "reference_temperature_degc = 1e6"),
        None => params_refused("model =", "reference_temperature_degc = 1e6\nmodel ="),
    };
    assert_mentions(&msg, &["reference_temperature_degc", "-60..125 degC"]);
}

#[test]
fn an_effect_beyond_ten_times_the_largest_plausible_is_refused() {
    let text = "[[imu.effect]]\nkind = \"size_effect\"\nlever_arm_x_mm = [0, 0, 5e4]\n";
    let err = parse_effects_toml(text, "absurd_effects.toml").expect_err("refused");
    let msg = err.to_string();
    assert_mentions(
        &msg,
        &[
            "absurd_effects.toml",
            "imu.effect[0].lever_arm_x_mm[2]",
            "plausibility limit of 1000 mm",
        ],
    );
    let text = "[[imu.effect]]\nkind = \"gyro_bias_temp\"\ncoeff_deg_per_h_per_degc = [0, 0, 1e-3]\nreference_degc = 900\n";
    let msg = parse_effects_toml(text, "hot_effects.toml")
        .expect_err("refused")
        .to_string();
    assert_mentions(
        &msg,
        &[
            "hot_effects.toml",
            "imu.effect[0].reference_degc",
            "-60..125 degC",
        ],
    );
}
