#!/usr/bin/env bash
# The PSINS laser-gyro recording read as it comes, navigated by sinsbench and by pyins from the
# same start (the header's attitude, at rest, height held), and the two tracks compared.
#   scripts/validate/lasergyro.sh [LASERGYRO_IMU]
# Needs pip (installs python-ins 1.0.1 and pyarrow when missing). The binary is
# scripts/sinsbench-bin's ($SINSBENCH_BIN, else the release build).
set -euo pipefail
cd "$(dirname "$0")/../.."
IMU=${1:-../shared/realdata/psins-lasergyro/lasergyro.imu}
SB=${SINSBENCH_BIN:-$(scripts/sinsbench-bin)}
python3 -c "import pyins, pyarrow" 2>/dev/null ||
    python3 -m pip install --quiet --disable-pip-version-check python-ins==1.0.1 pyarrow
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
"$SB" import "$IMU" --format psins --out "$TMP/lasergyro.parquet" --quiet
"$SB" navigate --dataset "$TMP/lasergyro.parquet" --start truth --out "$TMP/nav" --quiet
python3 scripts/validate/pyins_lasergyro.py "$IMU" --out "$TMP/pyins.csv" --compare "$TMP/nav/errors.parquet"
