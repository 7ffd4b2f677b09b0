//! Every refusal names the run, the file and what to do (issue 30): a 42-state set on a run
//! without temperatures (`noise` as `diagnose`), a run too short for `diagnose`, data errors
//! without advice about the noise, a run name given twice, a parameter set given as
//! `--noise-from`, run names that cannot be file names (refused before any work), and a
//! campaign planned into another campaign's directory. Each exits 2.

use crate::common;
use common::{assert_refused, csv_without_temperatures, experiments, ideal30, run, s};
use std::time::{Duration, Instant};

/// The message after `error: ` on stderr.
fn error_line(o: &std::process::Output) -> String {
    let err = String::from_utf8_lossy(&o.stderr);
    err.lines()
        .find_map(|l| l.strip_prefix("error: "))
        .unwrap_or_default()
        .to_string()
}

/// `noise --params <42-state set>` on a run without temperatures is refused as `diagnose`
/// refuses it, in the same words, naming the run, the dataset, the set and what to do; no
/// output is written, also when a good run is pooled with it.
#[test]
fn noise_refuses_a_42_state_set_on_a_run_without_temperatures_as_diagnose_does() {
    let dir = tempfile::tempdir().expect("tempdir");
    // 70 s still: enough for the identification (before, it then exited 0 with an accelerometer
    // VRW of 0 and NaN stretch means).
    let csv = dir.path().join("nt.csv");
    csv_without_temperatures(&csv, 200 * 70);
    let set = experiments().join("imu/paper_truth.toml");
    let out = dir.path().join("noise");
    let o = run(&[
        "noise",
        "--dataset",
        &s(&csv),
        "--params",
        &s(&set),
        "--out",
        &s(&out),
    ]);
    let needles = [
        "run 'nt'",
        &s(&csv),
        &s(&set),
        "no accelerometer temperature columns",
        "42-state",
        "give a 30-state set with --params",
    ];
    assert_refused(&o, &needles);
    assert!(!out.exists(), "nothing written");
    let noise = error_line(&o);
    // Pooled with a good run (temperatures recorded), the run without them is named.
    let good = dir.path().join("good.csv");
    let with_temps = std::fs::read_to_string(&csv)
        .unwrap()
        .replace(
            "dv_z_mps\n",
            "dv_z_mps,temp_ax_degc,temp_ay_degc,temp_az_degc\n",
        )
        .replace(",0.049\n", ",0.049,20,20,20\n");
    std::fs::write(&good, with_temps).unwrap();
    let o = run(&[
        "noise",
        "--dataset",
        &s(&good),
        "--dataset",
        &s(&csv),
        "--params",
        &s(&set),
        "--out",
        &s(&out),
    ]);
    let err = assert_refused(&o, &needles);
    assert!(!err.contains("good"), "{err}");
    assert!(!out.exists(), "nothing written");
    let o = run(&[
        "diagnose",
        "--dataset",
        &s(&csv),
        "--params",
        &s(&set),
        "--out",
        &s(&dir.path().join("diag")),
    ]);
    assert_refused(&o, &needles);
    // The same words; noise alone may also be run without the set.
    assert_eq!(noise.replace(", or leave --params out", ""), error_line(&o));
}

/// A 2-row run in `diagnose` is refused before any work, naming the run, its file, its length
/// and the length it needs (before: "alignment needs 1200 s of data but the data end after
/// 0.01 s", no run, no file).
#[test]
fn diagnose_names_the_run_and_the_file_of_a_run_too_short() {
    let dir = tempfile::tempdir().expect("tempdir");
    let csv = dir.path().join("tiny.csv");
    csv_without_temperatures(&csv, 2);
    let o = run(&[
        "diagnose",
        "--dataset",
        &format!("short_run={}", s(&csv)),
        "--params",
        &s(&ideal30(dir.path())),
        "--noise-from",
        &s(&experiments().join("paper_navigation.toml")),
        "--out",
        &s(&dir.path().join("diag")),
    ]);
    assert_refused(
        &o,
        &[
            "run 'short_run'",
            &s(&csv),
            "2 samples",
            "give a recording of at least 1440 s",
        ],
    );
}

/// A data error in `diagnose` names the run and the file and carries no advice about
/// `--noise-from` (before, it started with "no --noise-from was given, so the noise is
/// identified from the data (give --noise-from FILE ...)"); a failed noise identification
/// still gets that advice, after the error.
#[test]
fn diagnose_gives_noise_advice_only_for_noise_errors() {
    let dir = tempfile::tempdir().expect("tempdir");
    let params = ideal30(dir.path());
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "not a dataset\n").unwrap();
    let o = run(&[
        "diagnose",
        "--dataset",
        &s(&bad),
        "--params",
        &s(&params),
        "--out",
        &s(&dir.path().join("diag")),
    ]);
    let err = assert_refused(&o, &["run 'bad'", &s(&bad), "not a sinsbench dataset"]);
    assert!(!err.contains("noise"), "{err}");

    // 1500 s labelled `turning` throughout: no stationary segment to identify the noise from.
    let lab = dir.path().join("turning.csv");
    let mut text = String::from(
        "# sinsbench.schema_version = 1\n# sinsbench.sample_rate_hz = 100\n# sinsbench.site_latitude_deg = 28.22\n\
         # sinsbench.site_longitude_deg = 112.99\n# sinsbench.site_height_m = 60\n# sinsbench.description = labelled\n\
         t_s,dtheta_x_rad,dtheta_y_rad,dtheta_z_rad,dv_x_mps,dv_y_mps,dv_z_mps,segment\n",
    );
    for k in 1..=150_000 {
        text.push_str(&format!(
            "{},0,6e-7,3.4e-7,0,0,0.098,turning\n",
            k as f64 / 100.0
        ));
    }
    std::fs::write(&lab, text).unwrap();
    let o = run(&[
        "diagnose",
        "--dataset",
        &s(&lab),
        "--params",
        &s(&params),
        "--out",
        &s(&dir.path().join("diag")),
    ]);
    let err = assert_refused(
        &o,
        &[&s(&lab), "not enough stationary data", "--noise-from FILE"],
    );
    let line = error_line(&o);
    assert!(
        line.find("not enough stationary data") < line.find("--noise-from"),
        "the error first, then the advice: {err}"
    );
}

/// `--dataset a=X --dataset a=Y` says that the run name is given twice, naming both files
/// (before: "two runs are named 'a'; name them with NAME=PATH", though they were named).
#[test]
fn a_run_name_given_twice_is_named_with_both_files() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (x, y) = (dir.path().join("x.csv"), dir.path().join("y.csv"));
    for p in [&x, &y] {
        csv_without_temperatures(p, 10);
    }
    for cmd in ["noise", "diagnose"] {
        let o = run(&[
            cmd,
            "--dataset",
            &format!("a={}", s(&x)),
            "--dataset",
            &format!("a={}", s(&y)),
            "--params",
            &s(&ideal30(dir.path())),
            "--out",
            &s(&dir.path().join("out")),
        ]);
        let err = assert_refused(
            &o,
            &[
                "the run name 'a' is given twice",
                &s(&x),
                &s(&y),
                "give each run its own name",
            ],
        );
        assert!(!err.contains("NAME=PATH"), "{cmd}: {err}");
    }
}

/// A parameter set given as `--noise-from` is named as such, with the fix (before:
/// "ideal30.toml:17:2: `accel`: unknown field `accel`, expected one of `schema`, ...").
#[test]
fn a_parameter_set_given_as_noise_from_is_named_as_such() {
    let dir = tempfile::tempdir().expect("tempdir");
    let csv = dir.path().join("nt.csv");
    csv_without_temperatures(&csv, 10);
    let params = ideal30(dir.path());
    let o = run(&[
        "diagnose",
        "--dataset",
        &s(&csv),
        "--params",
        &s(&params),
        "--noise-from",
        &s(&params),
        "--out",
        &s(&dir.path().join("diag")),
    ]);
    let err = assert_refused(
        &o,
        &[&format!(
            "{} is a parameter set (calibrate's output), not a noise file (noise's output); pass it as --params",
            s(&params)
        )],
    );
    assert!(!err.contains("unknown field"), "{err}");
}

/// Run names that cannot be file names are refused before any work (the dataset is not even
/// read), naming the name and the rule: `--dataset ../../x=F`, a name with a newline, a file
/// stem with a space, and an experiment's `[[run]] name`; nothing is written.
#[test]
fn run_names_are_checked_before_any_work() {
    let dir = tempfile::tempdir().expect("tempdir");
    let params = ideal30(dir.path());
    let missing = dir.path().join("never_read.csv");
    let rule = "[A-Za-z0-9_.-]";
    for (cmd, arg, shown) in [
        ("noise", format!("../../x={}", s(&missing)), "'../../x'"),
        ("diagnose", format!("../../x={}", s(&missing)), "'../../x'"),
        ("noise", format!("a\nb={}", s(&missing)), "'a\\nb'"),
        ("diagnose", format!("a\nb={}", s(&missing)), "'a\\nb'"),
        ("noise", s(&dir.path().join("my run.csv")), "'my run'"),
    ] {
        let out = dir.path().join("out");
        let started = Instant::now();
        let o = run(&[
            cmd,
            "--dataset",
            &arg,
            "--params",
            &s(&params),
            "--out",
            &s(&out),
        ]);
        let err = assert_refused(&o, &[shown, rule, "run name"]);
        assert!(
            !err.contains("cannot read"),
            "{cmd} {arg:?}: before any read: {err}"
        );
        assert!(started.elapsed() < Duration::from_secs(5), "{cmd}: at once");
        assert!(!out.exists(), "{cmd} {arg:?}: nothing written");
    }
    // An experiment file's run name.
    let exp = std::fs::read_to_string(experiments().join("paper_navigation.toml")).unwrap();
    let first = exp
        .lines()
        .find(|l| l.trim_start().starts_with("name = \"nav"))
        .expect("a run name")
        .to_string();
    let bad = dir.path().join("bad_names.toml");
    std::fs::write(
        &bad,
        exp.replacen(&first, "name = \"../nav1\"", 1)
            .replace("\"imu/", &format!("\"{}/imu/", experiments().display()))
            .replace(
                "\"schemes/",
                &format!("\"{}/schemes/", experiments().display()),
            ),
    )
    .unwrap();
    let out = dir.path().join("sim");
    let o = run(&["simulate", &s(&bad), "--out", &s(&out)]);
    assert_refused(&o, &[&s(&bad), "run[0].name", "'../nav1'", rule]);
    assert!(!out.exists(), "nothing simulated");
}

/// Planning a second campaign into the directory of a first says which campaign is there and
/// where it was planned from, and what to do (before: "the campaign's inputs changed since it
/// was planned ...: c_two.toml or a file it reads was edited").
#[test]
fn planning_another_campaign_into_a_planned_directory_names_the_one_there() {
    let dir = tempfile::tempdir().expect("tempdir");
    let cfg = |name: &str| {
        let p = dir.path().join(format!("c_{name}.toml"));
        std::fs::write(
            &p,
            format!(
                "schema = 1\nname = \"{name}\"\nkind = \"calibration-mc\"\nseed = 3\njobs_per_shard = 2\n[calibration_mc]\nseeds = 3\nexperiment = \"{}\"\nmax_duration_s = 1500.0\n",
                experiments().join("paper_calibration.toml").display()
            ),
        )
        .unwrap();
        p
    };
    let (one, two) = (cfg("one"), cfg("two"));
    let out = dir.path().join("camp");
    let o = run(&["campaign", "plan", &s(&one), "--out", &s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let manifest = std::fs::read(out.join("manifest.json")).unwrap();
    let o = run(&["campaign", "plan", &s(&two), "--out", &s(&out)]);
    let err = assert_refused(
        &o,
        &[
            &s(&out),
            "already holds campaign 'one'",
            &format!("planned from {}", s(&one)),
            "pick another --out",
            "or remove",
        ],
    );
    assert!(!err.contains("edited"), "{err}");
    assert_eq!(
        std::fs::read(out.join("manifest.json")).unwrap(),
        manifest,
        "left as it was"
    );
}
