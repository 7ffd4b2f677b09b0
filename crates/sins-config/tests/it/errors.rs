//! Every rejection names the file, the key (or table / array index) and the problem.

use crate::common;

use common::{SEGMENTS, exp_file, experiment_text, experiments_dir, write_temp};
use sins_config::{
    ConfigError, load_experiment, load_params, parse_params_json, parse_params_toml,
};

fn experiment_error(extra_top: &str, segments: &str) -> (String, ConfigError) {
    let (dir, path) = write_temp("bad_experiment.toml", &experiment_text(extra_top, segments));
    let err = load_experiment(&path).expect_err("the experiment must be rejected");
    drop(dir);
    (err.to_string(), err)
}

fn assert_mentions(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "error message lacks {p:?}:\n{msg}");
    }
}

#[test]
fn the_template_itself_is_valid() {
    let (_dir, path) = write_temp("ok.toml", &experiment_text("", SEGMENTS));
    let e = load_experiment(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(e.scenarios.len(), 1);
}

#[test]
fn unknown_top_level_key_names_key_file_and_line() {
    let (msg, err) = experiment_error("colour = \"blue\"", SEGMENTS);
    assert_mentions(&msg, &["bad_experiment.toml", "colour", ":3:"]);
    assert!(
        matches!(err, ConfigError::Parse { line: Some(3), .. }),
        "{err:?}"
    );
}

#[test]
fn unknown_key_inside_a_segment_names_key_and_index() {
    let segments =
        format!("{SEGMENTS}\n[[motion.segment]]\nkind = \"dwell\"\nduration_s = 5.0\nspeed = 3\n");
    let (msg, _) = experiment_error("", &segments);
    assert_mentions(&msg, &["bad_experiment.toml", "speed", "motion.segment[2]"]);
}

#[test]
fn unknown_key_in_a_nested_table_is_rejected() {
    let text =
        experiment_text("", SEGMENTS).replace("rate_hz = 200.0", "rate_hz = 200.0\nrate_khz = 0.2");
    let (_dir, path) = write_temp("nested.toml", &text);
    let msg = load_experiment(&path).expect_err("rejected").to_string();
    assert_mentions(&msg, &["nested.toml", "rate_khz", "sampling.rate_khz"]);
}

#[test]
fn unknown_segment_kind_is_rejected() {
    let (msg, _) = experiment_error(
        "",
        "[[motion.segment]]\nkind = \"spin\"\nduration_s = 1.0\n",
    );
    assert_mentions(&msg, &["bad_experiment.toml", "spin", "motion.segment[0]"]);
}

#[test]
fn negative_and_nan_durations_name_the_segment_and_key() {
    let seg =
        |v: &str| format!("{SEGMENTS}\n[[motion.segment]]\nkind = \"dwell\"\nduration_s = {v}\n");
    for v in ["-5.0", "nan", "0.0", "inf"] {
        let (msg, err) = experiment_error("", &seg(v));
        assert_mentions(
            &msg,
            &[
                "bad_experiment.toml",
                "motion.segment[2].duration_s",
                "positive",
            ],
        );
        assert!(
            matches!(err, ConfigError::Invalid { line: Some(_), .. }),
            "{err:?}"
        );
    }
    let (msg, _) = experiment_error(
        "",
        "[[motion.segment]]\nkind = \"vibrate\"\npattern = 1\nduration_h = -1.0\n",
    );
    assert_mentions(&msg, &["motion.segment[0].duration_h"]);
}

#[test]
fn duration_needs_exactly_one_unit() {
    let (msg, _) = experiment_error(
        "",
        "[[motion.segment]]\nkind = \"dwell\"\nduration_s = 1.0\nduration_h = 1.0\n",
    );
    assert_mentions(&msg, &["motion.segment[0]", "exactly one"]);
    let (msg, _) = experiment_error("", "[[motion.segment]]\nkind = \"dwell\"\n");
    assert_mentions(&msg, &["motion.segment[0].duration_s", "missing"]);
}

#[test]
fn zero_axis_and_bad_rate_are_rejected() {
    let rot = |axis: &str, rate: &str| {
        format!(
            "[[motion.segment]]\nkind = \"rotate\"\naxis = {axis}\nangle_deg = 90.0\nrate_deg_per_s = {rate}\n"
        )
    };
    let (msg, _) = experiment_error("", &rot("[0, 0, 0]", "9.0"));
    assert_mentions(&msg, &["motion.segment[0].axis", "non-zero"]);
    let (msg, _) = experiment_error("", &rot("[0, 1, 0]", "-9.0"));
    assert_mentions(&msg, &["motion.segment[0].rate_deg_per_s"]);
}

#[test]
fn missing_scheme_file_names_the_path_and_key() {
    let seg = "[[motion.segment]]\nkind = \"scheme\"\nfile = \"schemes/no_such_scheme.csv\"\nrate_deg_per_s = 9.0\ndwell_s = 10.0\n";
    let (msg, err) = experiment_error("", seg);
    assert_mentions(
        &msg,
        &[
            "bad_experiment.toml",
            "motion.segment[0].file",
            "no_such_scheme.csv",
        ],
    );
    assert!(
        matches!(err, ConfigError::MissingReference { .. }),
        "{err:?}"
    );
}

#[test]
fn bad_scheme_csv_names_both_files_and_the_line() {
    let dir = tempfile::tempdir().expect("temp dir");
    std::fs::write(dir.path().join("s.csv"), "# c\n1,0,1,0,90\n2,0,0,0,90\n").expect("write csv");
    let seg = "[[motion.segment]]\nkind = \"scheme\"\nfile = \"s.csv\"\nrate_deg_per_s = 9.0\ndwell_s = 10.0\n";
    let path = dir.path().join("e.toml");
    std::fs::write(&path, experiment_text("", seg)).expect("write");
    let msg = load_experiment(&path).expect_err("zero axis").to_string();
    assert_mentions(
        &msg,
        &["e.toml", "motion.segment[0].file", "s.csv:3", "axis"],
    );
}

#[test]
fn missing_truth_file_and_bad_truth_are_reported_through_the_reference() {
    let text = experiment_text("", SEGMENTS)
        .replace(&exp_file("imu/paper_table1.toml"), "imu/missing.toml");
    let (_d, path) = write_temp("e.toml", &text);
    let msg = load_experiment(&path)
        .expect_err("missing truth")
        .to_string();
    assert_mentions(&msg, &["e.toml", "imu.truth", "missing.toml"]);

    let dir = tempfile::tempdir().expect("temp dir");
    let truth =
        std::fs::read_to_string(experiments_dir().join("imu/paper_table1.toml")).expect("truth");
    std::fs::write(
        dir.path().join("t.toml"),
        truth.replace("dK_y_ppm = 40.0\n", ""),
    )
    .expect("write");
    let text = experiment_text("", SEGMENTS).replace(&exp_file("imu/paper_table1.toml"), "t.toml");
    std::fs::write(dir.path().join("e.toml"), text).expect("write");
    let msg = load_experiment(dir.path().join("e.toml"))
        .expect_err("bad truth")
        .to_string();
    assert_mentions(&msg, &["e.toml", "imu.truth", "t.toml", "gyro.dK_y_ppm"]);
}

#[test]
fn semantic_checks_of_sampling_runs_and_patterns() {
    let text = experiment_text("", SEGMENTS)
        .replace("rate_hz = 200.0", "rate_hz = 200.0\nquadrature_nodes = 9");
    let (_d, path) = write_temp("q.toml", &text);
    let msg = load_experiment(&path).expect_err("9 nodes").to_string();
    assert_mentions(&msg, &["q.toml", "sampling.quadrature_nodes", "1..=8"]);

    let text = format!(
        "{}\n[[run]]\nname = \"r1\"\nseed = 2\n",
        experiment_text("", SEGMENTS)
    );
    let (_d, path) = write_temp("dup.toml", &text);
    let msg = load_experiment(&path)
        .expect_err("duplicate run")
        .to_string();
    assert_mentions(&msg, &["dup.toml", "run[1].name", "duplicate"]);

    let (msg, _) = experiment_error(
        "",
        "[[motion.segment]]\nkind = \"vibrate\"\npattern = 7\nduration_s = 10.0\n",
    );
    assert_mentions(&msg, &["motion.segment[0].pattern", "7"]);

    let (msg, _) = experiment_error(
        "",
        "[[motion.segment]]\nkind = \"vibrate\"\npattern = 1\namplitude_deg = [1, 1, 1]\nduration_s = 10.0\n",
    );
    assert_mentions(&msg, &["motion.segment[0]", "either"]);

    let (msg, _) = experiment_error(
        "",
        "[[motion.segment]]\nkind = \"scheme\"\nfile = \"x.csv\"\nrate_deg_per_s = 9.0\n",
    );
    assert_mentions(&msg, &["motion.segment[0]", "dwell_s"]);
}

#[test]
fn thermal_errors_name_the_chamber_segment() {
    let text = experiment_text("", SEGMENTS).replace(
        "rate_degc_per_h = 10.0",
        "rate_degc_per_h = 10.0\nslope = 1",
    );
    let (_d, path) = write_temp("th.toml", &text);
    let msg = load_experiment(&path).expect_err("unknown key").to_string();
    assert_mentions(&msg, &["th.toml", "slope", "thermal.chamber[0]"]);

    let text = experiment_text("", SEGMENTS).replace(
        "duration_h = 1.0\nrate_degc_per_h",
        "duration_h = -1.0\nrate_degc_per_h",
    );
    let (_d, path) = write_temp("th.toml", &text);
    let msg = load_experiment(&path).expect_err("negative").to_string();
    assert_mentions(&msg, &["th.toml", "thermal.chamber[0].duration_h"]);

    let text =
        experiment_text("", SEGMENTS).replace("[600.0, 600.0, 600.0]", "[600.0, 0.0, 600.0]");
    let (_d, path) = write_temp("th.toml", &text);
    let msg = load_experiment(&path).expect_err("zero tau").to_string();
    assert_mentions(&msg, &["thermal.accel_time_constant_s[1]"]);
}

// ---- parameter files ----

fn table1_text() -> String {
    std::fs::read_to_string(experiments_dir().join("imu/paper_table1.toml"))
        .expect("paper_table1.toml")
}

#[test]
fn missing_coefficient_is_named() {
    let text = table1_text().replace("TK_y_ppm_per_degc = 2.0\n", "");
    let err = parse_params_toml(&text, "p.toml").expect_err("missing");
    assert!(matches!(err, ConfigError::MissingKey { .. }), "{err:?}");
    assert_mentions(
        &err.to_string(),
        &["p.toml", "accel_temperature.TK_y_ppm_per_degc"],
    );
}

#[test]
fn unknown_coefficient_is_named() {
    let text = table1_text().replace("dK_x_ppm = 10.0\n", "dK_x_ppm = 10.0\ndK_w_ppm = 1.0\n");
    let err = parse_params_toml(&text, "p.toml").expect_err("unknown");
    assert!(matches!(err, ConfigError::UnknownKey { .. }), "{err:?}");
    assert_mentions(&err.to_string(), &["p.toml", "accel.dK_w_ppm"]);
    let text = table1_text().replace("model = ", "colour = 1\nmodel = ");
    let msg = parse_params_toml(&text, "p.toml")
        .expect_err("unknown top")
        .to_string();
    assert_mentions(&msg, &["p.toml", "colour"]);
}

#[test]
fn model_and_temperature_table_must_agree() {
    let text = table1_text().replace("model = \"42-state\"", "model = \"30-state\"");
    let msg = parse_params_toml(&text, "p30.toml")
        .expect_err("30 with temperature")
        .to_string();
    assert_mentions(&msg, &["p30.toml", "accel_temperature", "30-state"]);

    let cut = table1_text();
    let cut = &cut[..cut.find("[accel_temperature]").expect("section")];
    let msg = parse_params_toml(cut, "p42.toml")
        .expect_err("42 without temperature")
        .to_string();
    assert_mentions(&msg, &["p42.toml", "accel_temperature", "42-state"]);
    let ok = parse_params_toml(&cut.replace("42-state", "30-state"), "ok")
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ok.params.temperature, Default::default());

    let msg = parse_params_toml(&table1_text().replace("42-state", "36-state"), "m.toml")
        .expect_err("bad model")
        .to_string();
    assert_mentions(&msg, &["m.toml", "model", "36-state"]);
}

#[test]
fn non_finite_and_non_numeric_coefficients_are_rejected() {
    let msg = parse_params_toml(
        &table1_text().replace("B_y_ug = 1.0", "B_y_ug = nan"),
        "p.toml",
    )
    .expect_err("nan")
    .to_string();
    assert_mentions(&msg, &["p.toml", "accel.B_y_ug", "finite"]);
    let msg = parse_params_toml(
        &table1_text().replace("B_y_ug = 1.0", "B_y_ug = \"1\""),
        "p.toml",
    )
    .expect_err("string")
    .to_string();
    assert_mentions(&msg, &["p.toml", "B_y_ug"]);
    let json = r#"{"model": "30-state", "gyro": {"B_x_deg_per_h": "x"}, "accel": {}}"#;
    let msg = parse_params_json(json, "p.json")
        .expect_err("json string")
        .to_string();
    assert_mentions(&msg, &["p.json", "gyro.B_x_deg_per_h", "number"]);
    let msg = parse_params_json(
        r#"{"model": "30-state", "gyro": {}, "accel": {}, "extra": 1}"#,
        "p.json",
    )
    .expect_err("json unknown")
    .to_string();
    assert_mentions(&msg, &["p.json", "extra"]);
}

#[test]
fn negative_sigma_is_rejected_and_file_errors_name_the_path() {
    let sigma = table1_text()
        .replace("[gyro]", "[sigma.gyro]")
        .replace("[accel]", "[sigma.accel]");
    let sigma = sigma.replace("[accel_temperature]", "[sigma.accel_temperature]");
    let body = &sigma[sigma.find("[sigma.gyro]").expect("sigma")..];
    let text = format!(
        "{}\n{}",
        table1_text(),
        body.replace("dK_x_ppm = 20.0", "dK_x_ppm = -1.0")
    );
    let msg = parse_params_toml(&text, "s.toml")
        .expect_err("negative sigma")
        .to_string();
    assert_mentions(&msg, &["s.toml", "sigma.gyro.dK_x_ppm", "negative"]);
    let ok = format!(
        "{}\n{}",
        table1_text(),
        body.replace("-61.88", "61.88").replace("-20.63", "20.63")
    );
    let ok = ok
        .replace("-41.25", "41.25")
        .replace("-20.62", "20.62")
        .replace("-0.1\n", "0.1\n");
    let set =
        parse_params_toml(&ok.replace("-0.6\n", "0.6\n"), "s").unwrap_or_else(|e| panic!("{e}"));
    assert!(set.sigma.is_some());

    let msg = load_params("/nonexistent/dir/p.toml")
        .expect_err("no file")
        .to_string();
    assert_mentions(&msg, &["/nonexistent/dir/p.toml"]);
    let msg = load_params("/nonexistent/dir/p.yaml")
        .expect_err("format")
        .to_string();
    assert_mentions(&msg, &["p.yaml", ".toml or .json"]);
}
