//! `sinsbench campaign` with damaged shard results: a truncated result counts as missing in
//! `status` and `status --missing` (what the Slurm retry resubmits), `shard --index I` keeps it
//! aside and runs the shard again, `local` does the same; a result whose per-seed arrays are cut
//! short is named by `reduce` (exit 2), never a panic.

use crate::common;
use common::{experiments, run, s};
use std::path::Path;

/// Runs sinsbench with `args`; returns exit code, stdout, stderr.
fn sb(args: &[&str]) -> (Option<i32>, String, String) {
    let o = run(args);
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn ok(args: &[&str]) -> (String, String) {
    let (code, out, err) = sb(args);
    assert_eq!(code, Some(0), "{args:?}: {err}");
    (out, err)
}

fn refused(args: &[&str], needles: &[&str]) {
    let (code, _, err) = sb(args);
    assert_eq!(code, Some(2), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "'{n}' missing from {args:?}: {err}");
    }
}

fn shard_file(dir: &Path, s: usize) -> std::path::PathBuf {
    dir.join(format!("shards/shard-{s:05}.json"))
}

/// Plans and runs a 2-shard calibration-mc campaign named `name` in `tmp` (one seed and the
/// noise-free run, cut to 25 min: 2 jobs, one per shard); returns its file and directory.
fn two_shard_campaign(tmp: &Path, name: &str) -> (String, std::path::PathBuf) {
    let cfg = tmp.join("c.toml");
    std::fs::write(
        &cfg,
        format!(
            "schema = 1\nname = \"{name}\"\nkind = \"calibration-mc\"\nseed = 3\njobs_per_shard = 1\n[calibration_mc]\nseeds = 1\nexperiment = \"{}\"\nmax_duration_s = 1500.0\n",
            experiments().join("paper_calibration.toml").display()
        ),
    )
    .unwrap();
    let (cfg, dir) = (s(&cfg), tmp.join("run"));
    let d = s(&dir);
    ok(&["campaign", "plan", &cfg, "--out", &d]);
    ok(&["campaign", "shard", &d, "--index", "0"]);
    ok(&["campaign", "shard", &d, "--index", "1"]);
    (cfg, dir)
}

#[test]
fn damaged_results_are_missing_for_status_run_again_and_named_by_reduce() {
    let tmp = tempfile::tempdir().unwrap();
    let (cfg, dir) = two_shard_campaign(tmp.path(), "damaged");
    let d = s(&dir);
    assert_eq!(ok(&["campaign", "status", &d, "--missing"]).0, "\n");

    // Truncated (a copy cut off): missing for status, named by reduce, run again by shard.
    let text = std::fs::read_to_string(shard_file(&dir, 1)).unwrap();
    let cut = &text[..text.len() / 2];
    std::fs::write(shard_file(&dir, 1), cut).unwrap();
    assert_eq!(ok(&["campaign", "status", &d, "--missing"]).0, "1\n");
    let (status, _) = ok(&["campaign", "status", &d]);
    assert!(
        status.contains("1 done, 1 missing (1)")
            && status.contains("shard 1 counts as missing: ")
            && status.contains("shard-00001.json is truncated or not a shard result"),
        "{status}"
    );
    refused(
        &["campaign", "reduce", &d],
        &[
            "shard-00001.json is truncated",
            "are damaged and were not used",
        ],
    );
    let (out, err) = ok(&["campaign", "shard", &d, "--index", "1"]);
    assert!(out.starts_with("shard 1 (noise-free run) done in"), "{out}");
    let kept = dir.join("shards/shard-00001.json.damaged-1");
    assert!(
        err.starts_with("note: ")
            && err.contains("shard-00001.json is truncated")
            && err.contains(&format!("kept as {}, shard 1 runs again", kept.display())),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&kept).unwrap(), cut);
    assert_eq!(ok(&["campaign", "status", &d, "--missing"]).0, "\n");
    ok(&["campaign", "reduce", &d]);
    let summary = std::fs::read(dir.join("summary.json")).unwrap();

    // Valid JSON whose per-seed arrays are cut short: named by reduce, no panic.
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(shard_file(&dir, 0)).unwrap()).unwrap();
    let error = json["outcomes"][0]["outcome"]["error"]
        .as_array_mut()
        .unwrap();
    error.truncate(30);
    std::fs::write(shard_file(&dir, 0), json.to_string()).unwrap();
    refused(
        &["campaign", "reduce", &d],
        &[
            "shard-00000.json",
            "shard-00000.json holds an unusable outcome of job 0: error has 30 values where a 42-state calibration has 33",
        ],
    );
    assert_eq!(ok(&["campaign", "status", &d, "--missing"]).0, "0\n");
    // `local` keeps it aside too, runs the shard again and reduces to the same bytes.
    let (_, err) = ok(&["campaign", "local", &cfg, "--out", &d, "--threads", "1"]);
    assert!(
        err.contains("shard-00000.json holds an unusable outcome of job 0: error has 30 values")
            && err.contains("shard-00000.json.damaged-1, shard 0 runs again"),
        "{err}"
    );
    assert_eq!(std::fs::read(dir.join("summary.json")).unwrap(), summary);
}

/// Issue 30, no panic anywhere in the reduce: a shard result of the right shape whose numbers
/// are extreme (±1e308, 0, −1, the largest integers; a seed repeated) is reduced or refused
/// with exit 0 or 2, never a panic (exit 101). One edit per reduce, at every numeric field of an
/// outcome (the first and the last element of each array).
#[test]
fn extreme_numbers_in_a_whole_result_never_panic_the_reduce() {
    let tmp = tempfile::tempdir().unwrap();
    let (_, dir) = two_shard_campaign(tmp.path(), "extreme");
    let d = s(&dir);
    let original = std::fs::read_to_string(shard_file(&dir, 0)).unwrap();
    let json: serde_json::Value = serde_json::from_str(&original).unwrap();
    // Every numeric leaf of the outcome (arrays: first and last element).
    fn leaves(v: &serde_json::Value, path: String, out: &mut Vec<String>) {
        match v {
            serde_json::Value::Object(m) => {
                for (k, x) in m {
                    leaves(x, format!("{path}/{k}"), out);
                }
            }
            serde_json::Value::Array(a) if !a.is_empty() => {
                for i in [0, a.len() - 1] {
                    leaves(&a[i], format!("{path}/{i}"), out);
                }
            }
            serde_json::Value::Number(_) => out.push(path),
            _ => {}
        }
    }
    let mut paths = Vec::new();
    leaves(&json["outcomes"][0], "/outcomes/0".into(), &mut paths);
    paths.dedup();
    assert!(paths.len() >= 15, "{paths:?}");
    let values = [
        serde_json::json!(1e308),
        serde_json::json!(-1e308),
        serde_json::json!(0),
        serde_json::json!(-1),
        serde_json::json!(u64::MAX),
    ];
    let (mut reduced, mut refused_n) = (0, 0);
    for (i, p) in paths.iter().enumerate() {
        let mut v = json.clone();
        *v.pointer_mut(p).unwrap() = values[i % values.len()].clone();
        std::fs::write(shard_file(&dir, 0), v.to_string()).unwrap();
        let (code, _, err) = sb(&["campaign", "reduce", &d]);
        assert!(
            matches!(code, Some(0 | 2)) && !err.contains("panicked"),
            "{p} = {}: exit {code:?}: {err}",
            values[i % values.len()]
        );
        if code == Some(0) {
            reduced += 1;
        } else {
            refused_n += 1;
        }
    }
    eprintln!(
        "{} extreme values: {reduced} reduced, {refused_n} refused, 0 panics",
        paths.len()
    );
}
