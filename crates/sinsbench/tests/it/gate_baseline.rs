//! `gate --baseline`: a `reports` campaign over noise seeds, compared with a candidate's. The
//! same release passes against itself, a release whose parameter set is worse fails on that
//! set's cells only, and campaigns that cannot be compared are refused (exit 2).

use crate::common;
use common::{assert_refused, exe, experiments, s};
use std::path::{Path, PathBuf};

/// A report configuration `name`: the short calibration run calibrated with the 30-state
/// filter ("cal30") and the parameter file `truth` ("truth"), replayed on the short navigation
/// runs (three runs: six cells).
fn config(dir: &Path, name: &str, truth: &Path) -> PathBuf {
    let cal = common::short_calibration_experiment(dir);
    let nav = common::short_navigation_experiment(dir, "short_nav.toml", 900.0, 120.0, 60.0);
    let p = dir.join(format!("{name}.toml"));
    std::fs::write(
        &p,
        format!(
            "schema = 1\nname = \"{name}\"\n\
             [calibration]\nexperiment = \"{}\"\nrun = \"cal1\"\n\
             [[parameter_set]]\nkey = \"cal30\"\ncalibrate = 30\n\
             [[parameter_set]]\nkey = \"truth\"\nfile = \"{}\"\n\
             [navigation]\nexperiment = \"{}\"\n\
             [replay]\nalignment_s = 450.0\n",
            cal.display(),
            truth.display(),
            nav.display()
        ),
    )
    .unwrap();
    p
}

/// Run a `reports` campaign of `config` over `seeds` noise seeds into `out`.
fn campaign(dir: &Path, config: &Path, seeds: u64, out: &Path) {
    let file = dir.join(format!("c{seeds}.toml"));
    std::fs::write(
        &file,
        format!(
            "schema = 1\nname = \"seeds\"\nkind = \"reports\"\n[reports]\nconfigs = [\"{}\"]\nnoise_seeds = {seeds}\n",
            config.display()
        ),
    )
    .unwrap();
    let o = exe()
        .args(["campaign", "local", &s(&file), "--out", &s(out)])
        .args(["--threads", "2", "--quiet"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn gate(base: &Path, cand: &Path) -> std::process::Output {
    exe()
        .args(["gate", "--baseline", &s(base), "--candidate", &s(cand)])
        .output()
        .unwrap()
}

#[test]
fn a_release_is_judged_against_the_run_to_run_spread_of_its_baseline() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let truth = experiments().join("imu").join("paper_truth.toml");
    let base_cfg = config(dir, "release", &truth);
    let base = dir.join("base");
    campaign(dir, &base_cfg, 5, &base);
    let list = sins_config::read_report_list(&base).unwrap();
    assert_eq!(list.len(), 5);
    let seeds: Vec<Option<u64>> = list.iter().map(|r| r.noise_seed).collect();
    assert_eq!(seeds, [Some(1), Some(2), Some(3), Some(4), Some(5)]);
    assert!(list.iter().all(|r| r.name == "release"));
    // Each seed is another draw: the calibrated set's error differs from seed to seed.
    let cal30: Vec<f64> = list
        .iter()
        .map(|r| r.experiments[0].results["cal30"].max_horizontal_nmi)
        .collect();
    assert!(cal30.windows(2).all(|w| w[0] != w[1]), "{cal30:?}");
    // Each seed's report has its own directory.
    assert!(
        base.join("reports")
            .join("release-seed5")
            .join("summary.json")
            .is_file()
    );

    // The same campaign against itself: every shift is 0, six PASS lines, exit 0.
    let o = gate(&base, &base);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(out.matches("PASS ").count(), 6, "{out}");

    // A release whose "truth" set has gyro z's scale factor 500 ppm off: its cells fail,
    // naming the set and the shift; the calibrated set's cells pass.
    let text = std::fs::read_to_string(&truth)
        .unwrap()
        .replace("dK_z_ppm = 60.0", "dK_z_ppm = 560.0");
    let worse = dir.join("worse_truth.toml");
    std::fs::write(&worse, text).unwrap();
    let cand_cfg = {
        let sub = dir.join("cand");
        std::fs::create_dir_all(&sub).unwrap();
        config(&sub, "release", &worse)
    };
    let cand = dir.join("cand_out");
    campaign(dir, &cand_cfg, 5, &cand);
    let o = gate(&base, &cand);
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{out}");
    let fails: Vec<&str> = out.lines().filter(|l| l.starts_with("FAIL")).collect();
    assert!(
        !fails.is_empty() && fails.iter().all(|l| l.contains(" truth: ")),
        "{out}"
    );
    assert!(
        out.lines()
            .filter(|l| l.contains(" cal30: "))
            .all(|l| l.starts_with("PASS"))
    );

    // Bad input: another configuration, other seed counts, too few seeds.
    let other_cfg = config(dir, "other", &truth);
    let other = dir.join("other_out");
    campaign(dir, &other_cfg, 4, &other);
    assert_refused(&gate(&base, &other), &["'release'", "'other'"]);
    let four = dir.join("four");
    campaign(dir, &base_cfg, 4, &four);
    assert_refused(&gate(&base, &four), &["5 noise seeds", "4"]);
    // Six cells at 0.95 family-wise need 5 seeds a side (P(U = 0) = 1/70 > 0.05/6 at 4).
    assert_refused(&gate(&four, &four), &["at least 5"]);

    power(dir, &base);
}

/// `gate --power` on a campaign of 10 seeds made from the 5 real ones (each again with its
/// errors 0.5 % larger): the truth set made 10 times worse is caught in every draw, the table
/// says so, and sides larger than half the campaign or an unknown set are refused.
fn power(dir: &Path, base: &Path) {
    let text = std::fs::read_to_string(base.join("summary.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let reports = v["reports"].as_array_mut().unwrap();
    let mut more = reports.clone();
    for r in &mut more {
        for e in r["experiments"].as_array_mut().unwrap() {
            for (_, cell) in e["results"].as_object_mut().unwrap() {
                for key in ["max_horizontal_nmi", "max_horizontal_m"] {
                    cell[key] = (cell[key].as_f64().unwrap() * 1.005).into();
                }
            }
        }
    }
    // A candidate whose reports lack one cell is bad input naming the cell.
    let mut lacking = serde_json::json!({ "reports": reports.clone() });
    for r in lacking["reports"].as_array_mut().unwrap() {
        r["experiments"][1]["results"]
            .as_object_mut()
            .unwrap()
            .remove("truth");
    }
    let lacking_path = dir.join("lacking.json");
    std::fs::write(&lacking_path, serde_json::to_string(&lacking).unwrap()).unwrap();
    assert_refused(&gate(base, &lacking_path), &["lacks cell nav2 / truth"]);
    reports.extend(more);
    let ten = dir.join("ten.json");
    std::fs::write(&ten, serde_json::to_string(&v).unwrap()).unwrap();
    let power = |extra: &[&str]| {
        exe()
            .args(["gate", "--power", &s(&ten), "--draws", "20"])
            .args(extra)
            .output()
            .unwrap()
    };
    let o = power(&[
        "--seeds-per-side",
        "5",
        "--worsen-set",
        "truth",
        "--worsen-percent",
        "900",
    ]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.contains("over 10 noise seeds"), "{out}");
    assert!(out.contains("| 5 | 900 % | 20 of 20 |"), "{out}");
    assert!(
        out.contains("5 seeds a side: the smallest worsening caught in 90 % of the draws is 900 %"),
        "{out}"
    );
    assert_refused(
        &power(&["--seeds-per-side", "6", "--worsen-set", "truth"]),
        &["12 distinct seeds", "has 10"],
    );
    assert_refused(&power(&["--worsen-set", "nine"]), &["'nine'"]);
}
