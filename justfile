# sinsbench recipes. Everything runs in the release profile (15 h of physics in debug is too slow).
# `just` is optional: each recipe is one cargo command you can run by hand.

# Build the workspace.
build:
    cargo build --release --workspace

# Run the test suite (the same command as .ci/run and the README).
test:
    cargo test --release --workspace

# Default main job: simulate the paper's 15 h navigation experiment (three runs).
run:
    cargo run --release -- simulate

# Simulate any experiment definition into a directory.
simulate EXPERIMENT OUT="out/datasets":
    cargo run --release -- simulate {{EXPERIMENT}} --out {{OUT}}

# Benchmarks: simulation and replay speed and peak memory for a 15 h, 200 Hz dataset; error floor.
bench:
    cargo run --release -- bench

# Formatting and lints.
check:
    cargo fmt --all -- --check
    cargo clippy --release --workspace --all-targets
