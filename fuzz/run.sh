#!/usr/bin/env bash
# Run the libFuzzer targets one at a time (`just fuzz [TARGET] [SECS]`):
#   fuzz/run.sh                      # every target, 600 s each
#   fuzz/run.sh dataset_csv 60       # one target, 60 s
#   fuzz/run.sh "params experiment"  # these two, 600 s each
# Each target starts from its committed seeds (fuzz/seeds/TARGET, read only) and keeps what it
# finds in fuzz/corpus/TARGET; crashes go to fuzz/artifacts/TARGET, the log to fuzz/logs/TARGET.log.
# Needs cargo-fuzz (`cargo install cargo-fuzz`) and a nightly toolchain (FUZZ_TOOLCHAIN, default
# nightly). Builds go to fuzz/target unless CARGO_TARGET_DIR says otherwise. Extra libFuzzer
# options can be given in FUZZ_ARGS (e.g. FUZZ_ARGS="-rss_limit_mb=4096"), cargo-fuzz build options
# in FUZZ_BUILD_ARGS (e.g. FUZZ_BUILD_ARGS=--no-default-features: the parser targets without polars).
set -euo pipefail
cd "$(dirname "$0")"
TARGET=${1:-}
SECS=${2:-600}
TC=${FUZZ_TOOLCHAIN:-nightly}
if [ -n "$TARGET" ]; then
    read -r -a targets <<<"$TARGET" # one target or several, space-separated
else
    mapfile -t targets < <(cargo "+$TC" fuzz list)
fi
mkdir -p logs
# shellcheck disable=SC2086
for t in "${targets[@]}"; do cargo "+$TC" fuzz build ${FUZZ_BUILD_ARGS:-} "$t"; done
status=0
summary=()
for t in "${targets[@]}"; do
    mkdir -p "corpus/$t"
    echo "== $t: ${SECS} s" >&2
    # One process (no -jobs/-fork): the machines this runs on are small and shared.
    # -timeout: an input that takes 20 s is a hang; -rss_limit_mb: 2 GB is a runaway allocation.
    # shellcheck disable=SC2086
    if cargo "+$TC" fuzz run ${FUZZ_BUILD_ARGS:-} "$t" "corpus/$t" "seeds/$t" -- \
        -max_total_time="$SECS" -print_final_stats=1 -timeout=20 -rss_limit_mb=2048 \
        ${FUZZ_ARGS:-} 2>&1 | tee "logs/$t.log" >&2; then
        result=ok
    else
        result="CRASH (see artifacts/$t/, logs/$t.log)"
        status=1
    fi
    execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "logs/$t.log" | tail -1 | grep -o '[0-9]*$' || true)
    cov=$(grep -o 'cov: [0-9]* ft: [0-9]*' "logs/$t.log" | tail -1 || true)
    summary+=("$t: $result, ${execs:-?} execs, ${cov:-no coverage line}")
done
echo "== summary (${SECS} s per target)" >&2
printf '%s\n' "${summary[@]}" >&2
exit $status
