#!/usr/bin/env bash
# (Re)generate the fuzz seed corpora in fuzz/seeds/<target>/ from the shipped files and from a
# 0.2 s simulated experiment (fuzz/fixtures/tiny_experiment.toml). The seeds are small (a few KB
# each) and committed; run this after a change of the dataset, experiment or parameter formats.
#   fuzz/seed.sh                      # uses target/release/sinsbench, builds it if missing
#   SINSBENCH=/path/to/sinsbench fuzz/seed.sh
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
S=fuzz/seeds
SB=${SINSBENCH:-}
if [ -z "$SB" ]; then
    SB=${CARGO_TARGET_DIR:-$ROOT/target}/release/sinsbench
    [ -x "$SB" ] || cargo build --release -p sinsbench
fi
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

for t in dataset_parquet dataset_csv experiment params report_config gate_thresholds gate_summary shard_result; do
    rm -rf "${S:?}/$t"
    mkdir -p "$S/$t"
done

# Datasets: 10 rows at 50 Hz, with and without the reference columns, Parquet and CSV.
"$SB" simulate fuzz/fixtures/tiny_experiment.toml --out "$TMP/pq" --quiet >/dev/null
"$SB" simulate fuzz/fixtures/tiny_experiment.toml --out "$TMP/pq_ref" --reference --quiet >/dev/null
"$SB" simulate fuzz/fixtures/tiny_experiment.toml --out "$TMP/csv" --format csv --quiet >/dev/null
"$SB" simulate fuzz/fixtures/tiny_experiment.toml --out "$TMP/csv_ref" --format csv --reference --quiet >/dev/null
cp "$TMP/pq/tiny1.parquet" "$S/dataset_parquet/tiny.parquet"
cp "$TMP/pq_ref/tiny1.parquet" "$S/dataset_parquet/tiny_reference.parquet"
cp "$TMP/csv/tiny1.csv" "$S/dataset_csv/tiny.csv"
cp "$TMP/csv_ref/tiny1.csv" "$S/dataset_csv/tiny_reference.csv"
# The smallest CSV the reader accepts: metadata, the required columns, three rows.
cat > "$S/dataset_csv/minimal.csv" <<'CSV'
# sinsbench.schema_version = 1
# sinsbench.sample_rate_hz = 100
# sinsbench.site_latitude_deg = 28.22
# sinsbench.site_longitude_deg = 112.99
# sinsbench.site_height_m = 60
t_s,dtheta_x_rad,dtheta_y_rad,dtheta_z_rad,dv_x_mps,dv_y_mps,dv_z_mps
0.01,0,0,0,0,0,0.098
0.02,1e-7,0,0,0,0,0.098
0.03,0,-1e-7,0,0.001,0,0.098
CSV

# Experiments: the shipped ones (their references resolve inside the fuzz target's copy of
# experiments/), the tiny one with its references rewritten to that layout, and an effects list.
for f in experiments/*.toml; do cp "$f" "$S/experiment/"; done
sed -e 's|"../../experiments/|"|' fuzz/fixtures/tiny_experiment.toml > "$S/experiment/tiny.toml"
sed -n '/let text = r#"$/,/^"#;$/p' crates/sins-config/tests/effects.rs 2>/dev/null | sed '1d;$d' > "$S/experiment/effects.toml" || true
[ -s "$S/experiment/effects.toml" ] || rm -f "$S/experiment/effects.toml"

# Parameter files: the shipped truths and a calibrated set with sigmas (TOML), and the same as JSON.
for f in experiments/imu/*.toml fuzz/fixtures/params_42-state_calibrated.toml; do
    b=$(basename "$f" .toml)
    cp "$f" "$S/params/$b.toml"
    python3 -c 'import json,sys,tomllib; print(json.dumps(tomllib.load(open(sys.argv[1],"rb")), indent=1))' "$f" > "$S/params/$b.json"
done

# Report configuration, thresholds, summary.
cp experiments/harness/report_paper.toml "$S/report_config/"
cat > "$S/report_config/datasets.toml" <<'TOML'
schema = 1
name = "own_data"
description = "two parameter files replayed on two datasets"
gate = "gate_paper.toml"

[[parameter_set]]
key = "30-state"
file = "../imu/paper_table1.toml"

[[parameter_set]]
key = "42-state"
label = "with temperature compensation"
file = "../imu/paper_truth.toml"

[[navigation.dataset]]
name = "run1"
path = "data/run1.parquet"

[[navigation.dataset]]
name = "run2"
path = "data/run2.csv"

[comparison]
baseline = "30-state"
compensated = "42-state"

[replay]
algorithm = "two-sample"
alignment_s = 300.0
TOML
cp experiments/harness/gate_paper.toml "$S/gate_thresholds/"
cat > "$S/gate_thresholds/per_experiment.toml" <<'TOML'
schema = 1
[default]
max_horizontal_nmi = { "30-state" = 5.0, "42-state" = 3.0 }
min_improvement_percent = 0.0
[experiment.nav2]
max_horizontal_nmi = { "42-state" = 2.5 }
min_improvement_percent = 10.0
TOML
cp fuzz/fixtures/summary.json "$S/gate_summary/paper_replica.json"
python3 - "$S/gate_summary" <<'PY'
import json, sys
d = sys.argv[1]
s = json.load(open(f"{d}/paper_replica.json"))
# One experiment, one segment per set: a small seed the mutator can work on.
s["experiments"] = s["experiments"][:1]
for r in s["experiments"][0]["results"].values():
    r["segments"] = r["segments"][:1]
json.dump(s, open(f"{d}/one_experiment.json", "w"), indent=1)
PY

# Shard results of the manifest in fuzz_targets/shard_result.rs (its hash computed as the
# manifest computes it: SHA-256 of its compact JSON with an empty manifest_sha256): both
# shards whole, and one whose per-seed arrays are cut short (a damaged result).
python3 - "$S/shard_result" <<'PY'
import hashlib, json, sys
d = sys.argv[1]
m = {"format": "sinsbench-campaign/1", "campaign": "fuzz", "kind": "calibration-mc",
     "source": "fuzz.toml", "experiments_dir": "experiments", "jobs": 4, "jobs_per_shard": 2,
     "shards": 2, "config_sha256": "0" * 64, "binary": {"version": "fuzz", "sha256": "0" * 64},
     "manifest_sha256": ""}
h = hashlib.sha256(json.dumps(m, separators=(",", ":")).encode()).hexdigest()
def outcome(seed, n=33, states=42):
    return {"outcome": {"seed": seed, "estimate": [1.5] * n, "error": [0.25] * n,
                        "sigma": [0.5] * n, "nees": 33.0, "sigma_ratio": [0.05] * states,
                        "max_normalized_innovation": 1.0},
            "initial_sigma_si": [1e-3] * states, "final_sigma_si": [5e-5] * states,
            "estimate_si": [1e-6] * n}
def shard(s, outcomes):
    return {"manifest_sha256": h, "shard": s, "jobs": [2 * s, 2 * s + 2], "host": "fuzz",
            "wall_s": 1.0, "outcomes": outcomes}
json.dump(shard(0, [outcome(5), outcome(6)]), open(f"{d}/shard0.json", "w"))
json.dump(shard(1, [outcome(7), outcome(1)]), open(f"{d}/shard1.json", "w"))
json.dump(shard(1, [outcome(7, n=30), outcome(1)]), open(f"{d}/short_arrays.json", "w"))
PY
du -sh "$S"
