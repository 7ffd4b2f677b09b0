//! `sinsbench campaign` end to end: `local` and shard-by-shard runs in reverse order give the
//! same bytes; `status --missing` speaks Slurm array syntax; bad input is refused with exit 2,
//! a message naming the problem, and nothing half-written.

use crate::common;
use common::{experiments, run, s};
use std::path::{Path, PathBuf};

/// A calibration Monte Carlo of 3 seeds cut to 25 min (4 jobs, 2 per shard).
fn campaign_file(dir: &Path) -> PathBuf {
    let p = dir.join("c.toml");
    std::fs::write(
        &p,
        format!(
            "schema = 1\nname = \"cli\"\nkind = \"calibration-mc\"\nseed = 3\njobs_per_shard = 2\n[calibration_mc]\nseeds = 3\nexperiment = \"{}\"\nmax_duration_s = 1500.0\n",
            experiments().join("paper_calibration.toml").display()
        ),
    )
    .unwrap();
    p
}

fn ok(args: &[String]) -> String {
    let o = run(args);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn refused(args: &[String], needle: &str) {
    let o = run(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: {err}");
}

fn a(v: &[&str]) -> Vec<String> {
    v.iter().map(|x| x.to_string()).collect()
}

#[test]
fn local_and_shard_by_shard_give_the_same_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = s(&campaign_file(tmp.path()));
    let (one, many) = (tmp.path().join("one"), tmp.path().join("many"));
    ok(&a(&[
        "campaign",
        "local",
        &cfg,
        "--out",
        &s(&one),
        "--threads",
        "2",
    ]));
    let plan = ok(&a(&["campaign", "plan", &cfg, "--out", &s(&many)]));
    assert!(plan.contains("4 jobs in 2 shards"), "{plan}");
    assert_eq!(
        ok(&a(&["campaign", "status", &s(&many), "--missing"])),
        "0-1\n"
    );
    refused(
        &a(&["campaign", "reduce", &s(&many)]),
        "2 of 2 shards have no result",
    );
    refused(
        &a(&["campaign", "shard", &s(&many), "--index", "2"]),
        "shard index 2 is out of range",
    );
    ok(&a(&["campaign", "shard", &s(&many), "--index", "1"]));
    assert_eq!(
        ok(&a(&["campaign", "status", &s(&many), "--missing"])),
        "0\n"
    );
    ok(&a(&["campaign", "shard", &s(&many), "--index", "0"]));
    let again = ok(&a(&["campaign", "shard", &s(&many), "--index", "0"]));
    assert!(again.contains("was already done"), "{again}");
    assert_eq!(
        ok(&a(&["campaign", "status", &s(&many), "--missing"])),
        "\n"
    );
    ok(&a(&["campaign", "reduce", &s(&many)]));
    for f in ["summary.json", "report.md"] {
        assert_eq!(
            std::fs::read(one.join(f)).unwrap(),
            std::fs::read(many.join(f)).unwrap(),
            "{f}"
        );
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(one.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["seeds"], serde_json::json!([3, 4, 5]));
    // Re-planning the same campaign is a no-op; a tampered manifest is refused.
    let again = ok(&a(&["campaign", "plan", &cfg, "--out", &s(&many)]));
    assert!(again.contains("already planned"), "{again}");
    let m = many.join("manifest.json");
    let text = std::fs::read_to_string(&m).unwrap();
    std::fs::write(&m, text.replace("\"jobs\": 4", "\"jobs\": 5")).unwrap();
    refused(
        &a(&["campaign", "shard", &s(&many), "--index", "0"]),
        "modified after planning",
    );
}

#[test]
fn an_unknown_kind_is_refused_before_anything_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("bad.toml");
    std::fs::write(&cfg, "schema = 1\nname = \"x\"\nkind = \"sweep\"\n").unwrap();
    let out = tmp.path().join("out");
    refused(
        &a(&["campaign", "plan", &s(&cfg), "--out", &s(&out)]),
        "kind = 'sweep' is not a campaign kind (one of: blind, calibration-mc, replica-uq, reports)",
    );
    assert!(!out.exists());
    refused(
        &a(&["campaign", "shard", &s(&out), "--index", "0"]),
        "no campaign planned",
    );
}

#[test]
fn the_shipped_campaign_files_load() {
    let dir = experiments().join("campaigns");
    for entry in std::fs::read_dir(&dir).unwrap() {
        let p = entry.unwrap().path();
        let c = sins_campaign::load_campaign(&p, &experiments())
            .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        assert!(!c.name.is_empty());
    }
}

/// A `reports` campaign: each configuration's report is the one `sinsbench report` writes
/// (summary byte for byte), the campaign's summary gathers them, and two reports of one name
/// are refused at planning.
#[test]
fn a_reports_campaign_writes_the_reports_report_writes() {
    let tmp = tempfile::tempdir().unwrap();
    let exp = common::short_calibration_experiment(tmp.path());
    common::simulate_into(&exp, &tmp.path().join("data"));
    let imu = experiments().join("imu");
    let config = |name: &str, compensated: &str| {
        let p = tmp.path().join(format!("{name}.toml"));
        std::fs::write(
            &p,
            format!(
                "schema = 1\nname = \"{name}\"\n\
                 [[parameter_set]]\nkey = \"none\"\nfile = \"{}\"\n\
                 [[parameter_set]]\nkey = \"set\"\nfile = \"{}\"\n\
                 [navigation]\ndataset = [{{ name = \"cal\", path = \"data/cal1.parquet\" }}]\n\
                 [comparison]\nbaseline = \"none\"\ncompensated = \"set\"\n",
                imu.join("ideal.toml").display(),
                imu.join(compensated).display()
            ),
        )
        .unwrap();
        p
    };
    let (a1, a2) = (
        config("truth", "paper_table1.toml"),
        config("other", "paper_truth.toml"),
    );
    let cfg = tmp.path().join("reports.toml");
    let list = |x: &Path, y: &Path| {
        format!(
            "schema = 1\nname = \"two\"\nkind = \"reports\"\n[reports]\nconfigs = [\"{}\", \"{}\"]\n",
            x.display(),
            y.display()
        )
    };
    std::fs::write(&cfg, list(&a1, &a2)).unwrap();
    let out = tmp.path().join("campaign");
    ok(&a(&[
        "campaign",
        "local",
        &s(&cfg),
        "--out",
        &s(&out),
        "--threads",
        "2",
    ]));
    let reports = tmp.path().join("reports");
    for (name, path) in [("truth", &a1), ("other", &a2)] {
        ok(&a(&[
            "report",
            "--config",
            &s(path),
            "--reports-dir",
            &s(&reports),
        ]));
        assert_eq!(
            std::fs::read(out.join("reports").join(name).join("summary.json")).unwrap(),
            std::fs::read(reports.join(name).join("summary.json")).unwrap(),
            "{name}"
        );
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["reports"][1]["name"], "other");
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("| truth | - | cal | set |") && md.contains("| other | - | cal | none |"),
        "{md}"
    );
    let dup = tmp.path().join("dup.toml");
    std::fs::write(&dup, list(&a1, &a1)).unwrap();
    refused(
        &a(&[
            "campaign",
            "plan",
            &s(&dup),
            "--out",
            &s(&tmp.path().join("d")),
        ]),
        "every report of a campaign needs its own name",
    );
}
