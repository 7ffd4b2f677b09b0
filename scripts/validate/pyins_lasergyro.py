#!/usr/bin/env python3
"""Independent strapdown check of the PSINS laser-gyro log with pyins.

Reads the PSINS compact text SIMU file itself, navigates it with pyins'
strapdown integrator (pip package ``python-ins==1.0.1``) from the header's
position and attitude at rest, with no alignment and no sensor corrections,
and writes the horizontal track at 1 Hz.  With ``--compare`` it reports the
largest horizontal difference to a sinsbench ``errors.parquet`` (or a CSV
with the same columns) written by ``sinsbench navigate --start truth``.

File format (PSINS ``imufile.m``): ``%`` comment lines, then three header
lines, then one line of six integer counts per sample:

1. pitch0 roll0 yaw0 [deg] VE0 VN0 VU0 [m/s]; yaw counter-clockwise from
   north, C_enu_from_body = Rz(yaw) Rx(pitch) Ry(roll);
2. lat0 lon0 [deg] h0 [m] t0 [s] sampling interval [ms] g [m/s^2];
3. gyro scale [arcsec/count] x3, accel scale [ug*s/count] x3 (ug = 1e-6 g).

Body axes are x right, y forward, z up.

Time convention: PSINS ``imufile.m`` documents "t0 + ts = sampling time of the
first IMU record" and reads record k (1-based) at t0 + k*ts.  So t0 is the
START of the first sample's interval and each sample is stamped at the END of
its interval, which is sinsbench's convention: sample k (0-based) has
t_s = (k + 1) * dt.  All times here are measured from t0 (= 0 in this file).

Frames: pyins uses NED and a forward-right-down body frame.  The right-
forward-up counts are mapped to FRD by swapping x/y and negating z.

Vertical channel: by default the height is held at the header height (pyins
``Integrator(with_altitude=False)`` zeroes the down velocity and keeps the
altitude constant); ``--free-height`` integrates it instead (it diverges).
"""
import argparse
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
from pyins import earth, strapdown, transform

ARCSEC = np.pi / (180 * 3600)
DEFAULT_IMU = "../shared/realdata/psins-lasergyro/lasergyro.imu"
# Maps a right-forward-up vector to forward-right-down, and ENU to NED (self-inverse).
SWAP = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])


def read_psins(path):
    """Return (header dict, counts as an (n, 6) int64 array) of a PSINS .imu file."""
    header = []
    with open(path) as f:
        for line in f:
            if line.startswith("%") or not line.strip():
                continue
            header.append([float(v) for v in line.split()])
            if len(header) == 3:
                break
        counts = pd.read_csv(f, sep=r"\s+", header=None, dtype=np.int64).to_numpy()
    if counts.shape[1] != 6:
        raise ValueError(f"expected 6 columns per sample, found {counts.shape[1]}")
    (pitch, roll, yaw, ve, vn, vu), (lat, lon, h, t0, dt_ms, g), scales = header
    return dict(pitch=pitch, roll=roll, yaw=yaw, vel_enu=(ve, vn, vu), lat=lat, lon=lon,
                h=h, t0=t0, dt=dt_ms / 1000, g=g, gyro_scale=np.array(scales[:3]),
                accel_scale=np.array(scales[3:6])), counts


def rot(axis, deg):
    """Elementary rotation matrix about axis 0/1/2 by `deg` degrees."""
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    m = np.eye(3)
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
    return m


def navigate(hdr, counts, hold_height=True):
    """Run pyins' strapdown integrator; return its trajectory indexed by time from t0."""
    dt, n = hdr["dt"], len(counts)
    theta_rfu = counts[:, :3] * hdr["gyro_scale"] * ARCSEC           # rad
    dv_rfu = counts[:, 3:] * hdr["accel_scale"] * 1e-6 * hdr["g"]    # m/s
    # pyins' increment sensor model needs one sample "before" the first interval: a zero
    # sample at t0 (no coning/sculling term against an unknown previous interval).
    inc = np.vstack([np.zeros((1, 6)), np.hstack([theta_rfu @ SWAP, dv_rfu @ SWAP])])
    imu = pd.DataFrame(inc, index=np.arange(n + 1) * dt,
                       columns=["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"])
    increments = strapdown.compute_increments_from_imu(imu, "increment")

    c_enu_rfu = rot(2, hdr["yaw"]) @ rot(0, hdr["pitch"]) @ rot(1, hdr["roll"])
    roll, pitch, heading = transform.mat_to_rph(SWAP @ c_enu_rfu @ SWAP)
    ve, vn, vu = hdr["vel_enu"]
    pva = pd.Series(dict(lat=hdr["lat"], lon=hdr["lon"], alt=hdr["h"], VN=vn, VE=ve, VD=-vu,
                         roll=roll, pitch=pitch, heading=heading))
    integrator = strapdown.Integrator(pva, with_altitude=not hold_height)
    return integrator.integrate(increments)


def ne_offsets(lat_deg, lon_deg, lat0_deg, lon0_deg, h0):
    """North/east offsets (m) from the start, linearised at the start as sinsbench does."""
    lat0 = np.radians(lat0_deg)
    x = 1 - earth.E2 * np.sin(lat0) ** 2
    r_m = earth.A * (1 - earth.E2) / x ** 1.5 + h0
    r_n = earth.A / x ** 0.5 + h0
    return (np.radians(lat_deg - lat0_deg) * r_m,
            np.radians(lon_deg - lon0_deg) * r_n * np.cos(lat0))


def read_errors(path):
    """sinsbench errors table: Parquet (needs pyarrow or fastparquet) or CSV."""
    path = Path(path)
    if path.suffix == ".csv":
        return pd.read_csv(path)
    try:
        return pd.read_parquet(path)
    except ImportError as e:
        sys.exit(f"reading {path}: {str(e).splitlines()[0]} `pip install pyarrow`, "
                 "or pass a CSV with the same columns")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("imu", nargs="?", default=DEFAULT_IMU, help="PSINS .imu file")
    p.add_argument("--out", required=True, help="CSV for the 1 Hz horizontal track")
    p.add_argument("--compare", metavar="ERRORS",
                   help="sinsbench errors.parquet (or .csv) to compare with")
    p.add_argument("--free-height", action="store_true",
                   help="integrate the vertical channel instead of holding the height")
    args = p.parse_args()

    t_start = time.perf_counter()
    hdr, counts = read_psins(args.imu)
    traj = navigate(hdr, counts, hold_height=not args.free_height)
    t_s = hdr["t0"] + np.arange(len(traj)) * hdr["dt"]  # exact grid, index 0 = t0
    north, east = ne_offsets(traj.lat.to_numpy(), traj.lon.to_numpy(),
                             hdr["lat"], hdr["lon"], hdr["h"])
    horiz = np.hypot(north, east)

    per_s = round(1 / hdr["dt"])
    sel = slice(0, None, per_s)  # t = 0, 1, 2, ... s from t0
    pd.DataFrame(dict(t_s=np.round(t_s[sel], 6), north_m=north[sel], east_m=east[sel],
                      lat_deg=traj.lat.to_numpy()[sel], lon_deg=traj.lon.to_numpy()[sel])
                 ).to_csv(args.out, index=False, float_format="%.9f")

    k = int(np.argmax(horiz))
    step = np.hypot(np.diff(north[sel]), np.diff(east[sel]))
    print(f"samples {len(counts)}, dt {hdr['dt']} s, duration {t_s[-1]:.2f} s, "
          f"height {'free' if args.free_height else 'held'}")
    print(f"pyins final offset: north {north[-1]:.1f} m, east {east[-1]:.1f} m, "
          f"horizontal {horiz[-1]:.1f} m")
    print(f"pyins max horizontal offset {horiz[k]:.1f} m at t {t_s[k]:.2f} s; "
          f"path length (1 Hz) {step.sum():.1f} m")
    print(f"pyins height: final {traj.alt.iloc[-1] - hdr['h']:+.1f} m, "
          f"max |dh| {np.abs(traj.alt - hdr['h']).max():.1f} m")
    print(f"wrote {args.out}; navigation wall time {time.perf_counter() - t_start:.1f} s")

    if args.compare:
        err = read_errors(args.compare)
        ts = err.t_s.to_numpy()
        ok = (ts >= t_s[0]) & (ts <= t_s[-1])
        ts = ts[ok]
        dn = np.interp(ts, t_s, north) - err.north_m.to_numpy()[ok]
        de = np.interp(ts, t_s, east) - err.east_m.to_numpy()[ok]
        d = np.hypot(dn, de)
        sb = np.hypot(err.north_m.to_numpy()[ok], err.east_m.to_numpy()[ok])
        j = int(np.argmax(d))
        print(f"compare: {ok.sum()} matched points, t {ts[0]:.2f}..{ts[-1]:.2f} s")
        print(f"max horizontal difference pyins - sinsbench {d[j]:.2f} m at t {ts[j]:.2f} s "
              f"(north {dn[j]:+.2f}, east {de[j]:+.2f}); final difference {d[-1]:.2f} m")
        print(f"scale: sinsbench max offset {sb.max():.1f} m, final {sb[-1]:.1f} m; "
              f"relative max difference {d[j] / max(sb.max(), 1e-9):.2%}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
