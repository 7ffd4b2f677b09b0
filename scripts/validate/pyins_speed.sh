#!/usr/bin/env bash
# The speed peer: sinsbench and pyins (python-ins 1.0.1) navigate the same simulated 15 h, 200 Hz
# file from the same true start, height held, no sensor corrections; each process is timed whole
# (wall time and peak RSS, GNU time), and the ratios printed. The file is the paper's navigation
# motion (5 h at rest, three 8/3 h angular vibration patterns up to 126 deg/s) with an ideal,
# noise-free IMU (experiments/error_free_navigation.toml). pyins' coning and sculling use the
# previous increment, so its track is compared with sinsbench's `--algorithm one-plus-previous`
# (the same job: both drift by about 217 km on this motion, the algorithm's own error);
# sinsbench's default 13-sample reconstruction stays within 0.3 m and is timed as well.
#   scripts/validate/pyins_speed.sh [EXPERIMENT RUN]   (default: error_free_navigation.toml error_free)
# Needs pip (installs python-ins 1.0.1 and pyarrow when missing), GNU time (/usr/bin/time) and
# about 1 GB of scratch space; pyins needs about 4 GB of memory. The binary is
# scripts/sinsbench-bin's ($SINSBENCH_BIN, else the release build).
set -euo pipefail
cd "$(dirname "$0")/../.."
EXPERIMENT=${1:-experiments/error_free_navigation.toml}
RUN=${2:-error_free}
SB=${SINSBENCH_BIN:-$(scripts/sinsbench-bin)}
python3 -c "import pyins, pyarrow" 2>/dev/null ||
    python3 -m pip install --quiet --disable-pip-version-check python-ins==1.0.1 pyarrow
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
"$SB" --quiet simulate "$EXPERIMENT" --run "$RUN" --reference --out "$TMP"
# Runs a command, its output in $TMP/out; "wall_s peak_kb" in $TMP/time. Stops the script when
# the command fails (not inside a subshell, so that `exit` ends the script).
timed() { /usr/bin/time -f "%e %M" -o "$TMP/time" "$@" >"$TMP/out" 2>&1 || { cat "$TMP/out"; exit 1; }; }
# sinsbench with pyins' algorithm (coning and sculling from the previous increment), whose track
# pyins must reproduce, then with its own default (the 13-sample reconstruction).
timed "$SB" --quiet navigate --dataset "$TMP/$RUN.parquet" --start truth \
    --params experiments/imu/ideal.toml --algorithm one-plus-previous --out "$TMP/nav"
read -r sb_s sb_kb <"$TMP/time"
grep "max horizontal error" "$TMP/out" | sed 's/^ */sinsbench, one-plus-previous: /'
timed "$SB" --quiet navigate --dataset "$TMP/$RUN.parquet" --start truth \
    --params experiments/imu/ideal.toml --out "$TMP/nav-reconstruct"
read -r rc_s rc_kb <"$TMP/time"
grep "max horizontal error" "$TMP/out" | sed 's/^ */sinsbench, reconstruct (default): /'
timed python3 scripts/validate/pyins_dataset.py "$TMP/$RUN.parquet" \
    --compare "$TMP/nav/errors.parquet"
read -r py_s py_kb <"$TMP/time"
cat "$TMP/out"
awk -v s="$sb_s" -v sk="$sb_kb" -v r="$rc_s" -v rk="$rc_kb" -v p="$py_s" -v pk="$py_kb" 'BEGIN {
    printf "sinsbench navigate, one-plus-previous: %.2f s wall, %.0f MB peak RSS\n", s, sk / 1024;
    printf "sinsbench navigate, reconstruct:       %.2f s wall, %.0f MB peak RSS\n", r, rk / 1024;
    printf "pyins:                                 %.2f s wall, %.0f MB peak RSS\n", p, pk / 1024;
    printf "pyins / sinsbench, same algorithm: %.1fx the time, %.1fx the memory\n", p / s, pk / sk;
    printf "pyins / sinsbench, default:        %.1fx the time, %.1fx the memory\n", p / r, pk / rk }'
