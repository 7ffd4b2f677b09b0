//! The crate layers of ARCHITECTURE.md, checked against the dependency graph cargo resolves:
//! a numeric crate that gains a file-format, plotting, logging or CLI dependency (directly or
//! through another crate) fails this test, naming the path that brought it in.

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
    "sins-files",
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

/// The layer table of ARCHITECTURE.md (the text block under "## Layers"), top layer first: each
/// layer's workspace crates (tokens `sins…`; an indented line continues the layer above).
fn architecture_layers() -> Vec<(String, Vec<String>)> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../ARCHITECTURE.md");
    let text = std::fs::read_to_string(path).expect("ARCHITECTURE.md reads");
    let section = text.split("## Layers").nth(1).expect("a Layers section");
    let block = section
        .split("```text")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("a text block in the Layers section");
    let mut layers: Vec<(String, Vec<String>)> = Vec::new();
    for line in block.lines().filter(|l| !l.trim().is_empty()) {
        let body = line.split('(').next().unwrap_or("");
        let mut words = body.split_whitespace().peekable();
        let crates = |w: &mut dyn Iterator<Item = &str>| -> Vec<String> {
            w.filter(|t| t.starts_with("sins"))
                .map(str::to_string)
                .collect()
        };
        if line.starts_with("  ") && !layers.is_empty() {
            let more = crates(&mut words);
            if let Some(last) = layers.last_mut() {
                last.1.extend(more);
            }
        } else if let Some(name) = words.next() {
            layers.push((name.to_string(), crates(&mut words)));
        }
    }
    layers
}

/// The CLI is thin: it parses arguments and calls the library crates, which own every frame,
/// file format and log. It depends on no data-frame, Parquet or Rerun library directly
/// (through sins-report and sins-data it does).
#[test]
fn the_cli_builds_no_frame_and_writes_no_format_itself() {
    let direct: Vec<String> = tree("sinsbench")
        .into_iter()
        .filter(|(d, n)| *d == 1 && banned(n, &["polars", "arrow", "parquet", "rerun"]))
        .map(|(_, n)| n)
        .collect();
    assert!(
        direct.is_empty(),
        "sinsbench depends directly on {direct:?}"
    );
    // The check itself sees a direct dependency that is there.
    assert!(
        tree("sins-report")
            .iter()
            .any(|(d, n)| *d == 1 && n == "polars")
    );
}

/// The workspace crates a crate depends on directly (normal and build edges).
fn direct_workspace_deps(krate: &str, members: &BTreeSet<String>) -> BTreeSet<String> {
    tree(krate)
        .into_iter()
        .filter(|(d, n)| *d == 1 && members.contains(n))
        .map(|(_, n)| n)
        .collect()
}

#[test]
fn the_architecture_table_names_every_crate_and_every_arrow_points_down() {
    let layers = architecture_layers();
    let rank: BTreeMap<String, usize> = layers
        .iter()
        .enumerate()
        .flat_map(|(i, (_, cs))| cs.iter().map(move |c| (c.clone(), i)))
        .collect();
    let crates_dir = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let members: BTreeSet<String> = std::fs::read_dir(crates_dir)
        .expect("crates/ lists")
        .filter_map(|e| {
            let e = e.ok()?;
            e.path()
                .join("Cargo.toml")
                .exists()
                .then(|| e.file_name().to_string_lossy().into_owned())
        })
        .collect();
    assert!(
        members.len() >= 19 && members.contains("sins-nav"),
        "{members:?}"
    );
    let missing: Vec<&String> = members.iter().filter(|m| !rank.contains_key(*m)).collect();
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md's layer table does not name {missing:?} (layers: {layers:?})"
    );
    let mut up = Vec::new();
    for m in &members {
        for d in direct_workspace_deps(m, &members) {
            if rank[&d] < rank[m] {
                up.push(format!(
                    "{m} ({}) depends on {d} ({}), a layer above it",
                    layers[rank[m]].0, layers[rank[&d]].0
                ));
            }
        }
    }
    assert!(up.is_empty(), "arrows that point up:\n{}", up.join("\n"));
}
