//! The crate layers of ARCHITECTURE.md, checked against the dependency graph cargo resolves:
//! a numeric crate that gains a file-format, plotting, logging or CLI dependency (directly or
//! through another crate) fails this test, naming the path that brought it in.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test or an example is its failure message

use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

/// Numeric crates: physics, filters, diagnosis. No file formats, no outputs, no CLI.
const NUMERIC: &[&str] = &[
    "sins-nav",
    "sins-imu",
    "sins-sim",
    "sins-kf",
    "sins-replay",
    "sins-harness",
    "sins-diag",
    "sins-noiseid",
    "sins-uq",
];

/// What a numeric crate must not reach: the format and output crates of the workspace and the
/// I/O libraries they wrap.
const IO: &[&str] = &[
    "sins-config",
    "sins-data",
    "sins-plot",
    "sins-viz",
    "sins-report",
    "sins-gap",
    "sins-campaign",
    "sinsbench",
    "toml",
    "serde_json",
    "csv",
    "polars",
    "arrow",
    "parquet",
    "rerun",
    "png",
    "image",
    "clap",
    "indicatif",
];

/// Crates of the outer layers with what each must still not reach (arrows point one way:
/// formats know nothing of studies or outputs; studies nothing of datasets or outputs; plots
/// know nothing of Rerun or Parquet).
const OUTER: &[(&str, &[&str])] = &[
    (
        "sins-config",
        &[
            "sins-data",
            "sins-calstudy",
            "sins-plot",
            "sins-viz",
            "sins-report",
            "polars",
            "rerun",
        ],
    ),
    (
        "sins-data",
        &[
            "sins-calstudy",
            "sins-plot",
            "sins-viz",
            "sins-report",
            "rerun",
        ],
    ),
    (
        "sins-import",
        &[
            "sins-calstudy",
            "sins-plot",
            "sins-viz",
            "sins-report",
            "rerun",
        ],
    ),
    (
        "sins-calstudy",
        &[
            "sins-data",
            "sins-plot",
            "sins-viz",
            "sins-report",
            "polars",
            "rerun",
        ],
    ),
    (
        "sins-plot",
        &["polars", "rerun", "sins-data", "sins-config"],
    ),
    ("sins-viz", &["polars", "sins-data", "sins-report"]),
];

/// A dependency name matches a banned one exactly or as its family (`polars-core` for `polars`).
fn banned(name: &str, list: &[&str]) -> bool {
    list.iter().any(|b| {
        name == *b || name.starts_with(&format!("{b}-")) || name.starts_with(&format!("{b}_"))
    })
}

/// `cargo tree -e normal,build -p crate` as (depth, name) lines.
fn tree(krate: &str) -> Vec<(usize, String)> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .args([
            "tree",
            "-e",
            "normal,build",
            "--prefix",
            "depth",
            "-p",
            krate,
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo tree runs");
    assert!(
        out.status.success(),
        "cargo tree -p {krate}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| {
            let digits = l.chars().take_while(char::is_ascii_digit).count();
            let depth = l[..digits].parse().ok()?;
            let name = l[digits..].split_whitespace().next()?.to_string();
            Some((depth, name))
        })
        .collect()
}

/// Every banned crate reachable from `krate`, with the path that reaches it.
fn violations(krate: &str, list: &[&str]) -> BTreeMap<String, String> {
    let mut path: Vec<String> = Vec::new();
    let mut found = BTreeMap::new();
    for (depth, name) in tree(krate) {
        path.truncate(depth);
        path.push(name.clone());
        if depth > 0 && banned(&name, list) {
            found.entry(name).or_insert_with(|| path.join(" -> "));
        }
    }
    found
}

/// Every rule broken, one line each with the path that breaks it.
fn assert_layers(rules: &[(&str, &[&str])]) {
    let mut report = BTreeSet::new();
    for (krate, list) in rules {
        for (dep, path) in violations(krate, list) {
            report.insert(format!("{krate} reaches {dep}: {path}"));
        }
    }
    assert!(
        report.is_empty(),
        "layering broken (see ARCHITECTURE.md):\n{}",
        report.into_iter().collect::<Vec<_>>().join("\n")
    );
}

#[test]
fn numeric_crates_reach_no_file_format_output_or_cli_crate() {
    let rules: Vec<(&str, &[&str])> = NUMERIC.iter().map(|&k| (k, IO)).collect();
    assert_layers(&rules);
}

#[test]
fn outer_layers_point_one_way() {
    assert_layers(OUTER);
}

#[test]
fn the_check_sees_a_known_dependency() {
    // The check would pass vacuously if the tree came back empty or misparsed: sins-diag
    // reaches nalgebra and sins-nav.
    let names: BTreeSet<String> = tree("sins-diag").into_iter().map(|(_, n)| n).collect();
    assert!(
        names.contains("nalgebra") && names.contains("sins-nav"),
        "{names:?}"
    );
    assert!(banned("polars-parquet", IO) && !banned("serde", IO));
}
