# sinsbench recipes. Everything runs in the release profile (15 h of physics in debug is too slow).
# `just` is optional: each recipe is one cargo command you can run by hand.

# Build the workspace.
build:
    cargo build --release --workspace

# Run the test suite (the same command as .ci/run and the README; installs rerun-sdk for the
# .rrd checks).
test:
    scripts/test

# Default main job: the paper's Table 5 replicated end to end into reports/paper_replica/.
run:
    cargo run --release -- report

# Release gate on the replica's summary.
gate:
    cargo run --release -- gate --summary reports/paper_replica/summary.json --thresholds experiments/harness/gate_paper.toml

# A report on your own parameter sets and datasets.
report CONFIG:
    cargo run --release -- report --config {{CONFIG}}

# Simulate any experiment definition into a directory.
simulate EXPERIMENT OUT="out/datasets":
    cargo run --release -- simulate {{EXPERIMENT}} --out {{OUT}}

# Benchmarks: simulation and replay speed and peak memory for a 15 h, 200 Hz dataset; error floor.
bench:
    cargo run --release -- bench

# Formatting and lints.
check:
    cargo fmt --all -- --check
    cargo clippy --release --workspace --all-targets -- -D warnings
    RUSTDOCFLAGS="-D warnings" cargo doc --release --workspace --no-deps

# Fuzz the readers and parsers (cargo-fuzz, nightly): every target for SECS seconds one after the
# other, or only TARGET. `cargo install cargo-fuzz` first; see README.md, "Fuzzing".
fuzz TARGET="" SECS="600":
    fuzz/run.sh "{{TARGET}}" "{{SECS}}"
