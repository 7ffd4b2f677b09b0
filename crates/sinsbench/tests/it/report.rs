//! `sinsbench report` and `sinsbench gate` end to end: the built-in replica of the paper's
//! Table 5, the gate's three outcomes, bad input and the atomic report directory.

use crate::common;
use common::{
    csv_without_temperatures, experiments, run, s, short_calibration_experiment, simulate_into,
    verify_rrd,
};

/// The default report (no arguments besides the output directory): three experiments, each
/// better with temperature compensation, every file present, every .rrd readable by Rerun,
/// then the gate passes on it, fails on tighter thresholds and refuses a malformed summary.
#[test]
fn replica_report_then_gate() {
    let dir = tempfile::tempdir().expect("tempdir");
    let o = run(&["report", "--reports-dir", &s(dir.path())]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = dir.path().join("paper_replica");
    for f in [
        "report.md",
        "summary.json",
        "params_30-state.toml",
        "params_42-state.toml",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let exps = summary["experiments"].as_array().expect("experiments");
    assert_eq!(exps.len(), 3);
    for e in exps {
        let name = e["name"].as_str().unwrap();
        let with = e["results"]["42-state"]["max_horizontal_nmi"]
            .as_f64()
            .unwrap();
        let without = e["results"]["30-state"]["max_horizontal_nmi"]
            .as_f64()
            .unwrap();
        let imp = e["improvement_percent"].as_f64().unwrap();
        assert!(
            with < without,
            "{name}: {with} nmi with vs {without} without"
        );
        assert!((imp - 100.0 * (without - with) / without).abs() < 1e-9);
        assert!(e["paper"]["improvement_percent"].as_f64().is_some());
        // 15 h of data, navigated after the 20 min alignment
        let nav_h = e["results"]["42-state"]["navigated_s"].as_f64().unwrap() / 3600.0;
        assert!((nav_h - (15.0 - 1.0 / 3.0)).abs() < 1e-3, "{nav_h}");
        for png in ["errors", "temperature"] {
            let p = out.join(format!("{name}_{png}.png"));
            let bytes = std::fs::read(&p).unwrap_or_else(|_| panic!("missing {}", p.display()));
            assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        }
        assert!(out.join(format!("{name}_errors.parquet")).is_file());
        assert!(out.join(format!("{name}_segments.parquet")).is_file());
        verify_rrd(&out.join(format!("{name}.rrd")));
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("| nav1 |") && md.contains("37.6 %"),
        "Table 5 layout with the paper's column"
    );
    // The other calibration condition as variant rows, the headline's reason, and Table 5 as a
    // prediction from the shipped study (experiments/replica/study), per calibration condition.
    assert!(md.contains("| nav1 (variant: `30-state-ramp`) |"), "{md}");
    assert!(md.contains("Why \"without\" is `30-state`: "), "{md}");
    assert!(md.contains("## Table 5 as a prediction"), "{md}");
    assert!(md.contains("| exp1 without |") && md.contains("stable: ") && md.contains("ramp: "));
    assert!(md.contains("replica/study/summary.json"), "{md}");
    for e in exps {
        let ramp = e["results"]["30-state-ramp"]["max_horizontal_nmi"]
            .as_f64()
            .unwrap();
        assert!(ramp.is_finite() && ramp > 0.0);
    }

    let summary_path = out.join("summary.json");
    let gate = experiments().join("harness/gate_paper.toml");
    let o = run(&[
        "gate",
        "--summary",
        &s(&summary_path),
        "--thresholds",
        &s(&gate),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stdout));

    let tight = dir.path().join("tight.toml");
    std::fs::write(
        &tight,
        "schema = 1\n[default]\nmax_horizontal_nmi = { \"42-state\" = 0.01 }\n",
    )
    .unwrap();
    let junit = dir.path().join("gate.xml");
    let o = run(&[
        "gate",
        "--summary",
        &s(&summary_path),
        "--thresholds",
        &s(&tight),
        "--junit",
        &s(&junit),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        text.lines().filter(|l| l.starts_with("FAIL")).count(),
        3,
        "{text}"
    );
    assert!(
        text.contains("nav1: max horizontal error with '42-state' is"),
        "{text}"
    );
    assert!(text.contains("(limit 0.010 nmi)"), "{text}");
    let xml = std::fs::read_to_string(&junit).unwrap();
    assert_eq!(xml.matches("<failure").count(), 3);

    let broken = dir.path().join("broken.json");
    let json = std::fs::read_to_string(&summary_path).unwrap();
    std::fs::write(
        &broken,
        json.replacen("\"max_horizontal_nmi\"", "\"max_horizontal\"", 1),
    )
    .unwrap();
    let o = run(&["gate", "--summary", &s(&broken), "--thresholds", &s(&gate)]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("broken.json") && err.contains("max_horizontal_nmi"),
        "{err}"
    );
}

/// A report on datasets: a 42-state set with a dataset that has no temperatures is refused
/// before anything is written, and an existing report stays as it was.
#[test]
fn bad_dataset_leaves_the_existing_report_untouched() {
    let dir = tempfile::tempdir().expect("tempdir");
    let csv = dir.path().join("nt.csv");
    csv_without_temperatures(&csv, 400);
    let imu = experiments().join("imu/paper_truth.toml");
    let config = dir.path().join("mine.toml");
    std::fs::write(
        &config,
        format!(
            "schema = 1\nname = \"mine\"\n[[parameter_set]]\nkey = \"42-state\"\nfile = \"{}\"\n\
             [navigation]\ndataset = [{{ name = \"run1\", path = \"nt.csv\" }}]\n",
            imu.display()
        ),
    )
    .unwrap();
    let reports = dir.path().join("reports");
    std::fs::create_dir_all(reports.join("mine")).unwrap();
    std::fs::write(reports.join("mine/report.md"), "the good old report\n").unwrap();
    let o = run(&[
        "report",
        "--config",
        &s(&config),
        "--reports-dir",
        &s(&reports),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("nt.csv") && err.contains("temperature") && err.contains("42-state"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(reports.join("mine/report.md")).unwrap(),
        "the good old report\n"
    );
    let names: Vec<_> = std::fs::read_dir(&reports)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "no partial report may remain: {names:?}");
}

/// Malformed report configuration and parameter files name the file and the key.
/// `report --config CONFIG` into `dir`: its exit code and standard error.
fn refused(config: &std::path::Path, dir: &std::path::Path) -> (Option<i32>, String) {
    let o = run(&["report", "--config", &s(config), "--reports-dir", &s(dir)]);
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn malformed_config_and_params_name_the_key() {
    let dir = tempfile::tempdir().expect("tempdir");
    let config = dir.path().join("c.toml");
    std::fs::write(
        &config,
        "schema = 1\nname = \"x\"\n[[parameter_set]]\nkey = \"a\"\ncalibrate = 42\n[navigation]\nexperiment = \"n.toml\"\n",
    )
    .unwrap();
    let (_, err) = refused(&config, dir.path());
    assert!(
        err.contains("c.toml") && err.contains("[calibration]"),
        "{err}"
    );

    let text = std::fs::read_to_string(experiments().join("imu/paper_truth.toml")).unwrap();
    let bad = dir.path().join("p.toml");
    std::fs::write(&bad, text.replace("TB_y_ug_per_degc", "TB_w_ug_per_degc")).unwrap();
    std::fs::write(
        &config,
        format!(
            "schema = 1\nname = \"x\"\n[[parameter_set]]\nkey = \"a\"\nfile = \"p.toml\"\n[navigation]\nexperiment = \"{}\"\n",
            experiments().join("paper_navigation.toml").display()
        ),
    )
    .unwrap();
    let (code, err) = refused(&config, dir.path());
    assert_eq!(code, Some(2));
    assert!(
        err.contains("p.toml") && err.contains("TB_w_ug_per_degc"),
        "{err}"
    );

    // A set calibrated on a run the calibration experiment does not have: refused before
    // anything is simulated, naming the configuration, the run and the experiment.
    std::fs::write(
        &config,
        format!(
            "schema = 1\nname = \"x\"\n[calibration]\nexperiment = \"{}\"\n[[parameter_set]]\nkey = \"a\"\ncalibrate = 30\ncalibration_run = \"truth_cal_cold\"\n[navigation]\nexperiment = \"{}\"\n",
            experiments().join("paper_truth_calibration.toml").display(),
            experiments().join("paper_navigation.toml").display()
        ),
    )
    .unwrap();
    let (code, err) = refused(&config, dir.path());
    assert_eq!(code, Some(2));
    assert!(
        err.contains("c.toml")
            && err.contains("calibration run 'truth_cal_cold' is not a run of")
            && err.contains("paper_truth_calibration.toml"),
        "{err}"
    );
}

/// A report on the user's own files: a dataset and two parameter files (the truth and an ideal
/// IMU). Compensating with the truth must beat not compensating at all.
#[test]
fn report_on_own_datasets_and_parameter_files() {
    let dir = tempfile::tempdir().expect("tempdir");
    let exp = short_calibration_experiment(dir.path());
    simulate_into(&exp, &dir.path().join("data"));
    let imu = experiments().join("imu");
    let config = dir.path().join("own.toml");
    std::fs::write(
        &config,
        format!(
            "schema = 1\nname = \"own\"\n\
             [[parameter_set]]\nkey = \"none\"\nfile = \"{}\"\n\
             [[parameter_set]]\nkey = \"truth\"\nfile = \"{}\"\n\
             [navigation]\ndataset = [{{ name = \"cal\", path = \"data/cal1.parquet\" }}]\n\
             [comparison]\nbaseline = \"none\"\ncompensated = \"truth\"\n",
            imu.join("ideal.toml").display(),
            imu.join("paper_table1.toml").display()
        ),
    )
    .unwrap();
    let reports = dir.path().join("reports");
    let o = run(&[
        "report",
        "--config",
        &s(&config),
        "--reports-dir",
        &s(&reports),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = sins_config::read_summary(&reports.join("own/summary.json")).expect("summary");
    let e = &summary.experiments[0];
    let none = e.results["none"].max_horizontal_m;
    let truth = e.results["truth"].max_horizontal_m;
    assert!(
        truth < 0.5 * none,
        "truth {truth} m vs uncompensated {none} m"
    );
    assert!(e.improvement_percent.unwrap() > 50.0);
    verify_rrd(&reports.join("own/cal.rrd"));
}

/// A report computes its simulated runs side by side (two calibration runs, then three
/// navigation runs); the results do not depend on the thread count: `summary.json`, the
/// calibrated parameter files and the error tracks are byte-identical with 1 and 3 threads.
#[test]
fn report_results_do_not_depend_on_the_thread_count() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cal = short_calibration_experiment(dir.path());
    // A second calibration run of the same scheme, its own seed.
    let mut text = std::fs::read_to_string(&cal).unwrap();
    text.push_str("\n[[run]]\nname = \"cal2\"\nseed = 2\n");
    std::fs::write(&cal, text).unwrap();
    let nav = common::short_navigation_experiment(dir.path(), "short_nav.toml", 900.0, 120.0, 60.0);
    let config = dir.path().join("threads.toml");
    std::fs::write(
        &config,
        format!(
            "schema = 1\nname = \"threads\"\n\
             [calibration]\nexperiment = \"{}\"\nrun = \"cal1\"\n\
             [[parameter_set]]\nkey = \"42-state\"\ncalibrate = 42\n\
             [[parameter_set]]\nkey = \"30-state\"\ncalibrate = 30\ncalibration_run = \"cal2\"\n\
             [navigation]\nexperiment = \"{}\"\n\
             [replay]\nalignment_s = 450.0\n",
            cal.display(),
            nav.display()
        ),
    )
    .unwrap();
    let out = |threads: &str| {
        let d = dir.path().join(format!("t{threads}"));
        let o = run(&[
            "report",
            "--config",
            &s(&config),
            "--threads",
            threads,
            "--reports-dir",
            &s(&d),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        d.join("threads")
    };
    let (one, three) = (out("1"), out("3"));
    let mut files = vec![
        "summary.json".to_string(),
        "params_42-state.toml".to_string(),
        "params_30-state.toml".to_string(),
    ];
    for run in ["nav1", "nav2", "nav3"] {
        files.push(format!("{run}_errors.parquet"));
        files.push(format!("{run}_segments.parquet"));
    }
    for f in &files {
        let (a, b) = (std::fs::read(one.join(f)), std::fs::read(three.join(f)));
        assert!(
            a.is_ok() && a.ok() == b.ok(),
            "{f} differs between 1 and 3 threads"
        );
    }
    // The two sets were calibrated on different runs.
    let summary = std::fs::read_to_string(one.join("summary.json")).unwrap();
    assert!(
        summary.contains("'cal1'") && summary.contains("'cal2'"),
        "{summary}"
    );
}
