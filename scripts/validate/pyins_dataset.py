"""pyins on a sinsbench dataset: the same job as `sinsbench navigate --start truth`, for speed.

Reads a sinsbench Parquet dataset with reference columns (``sinsbench simulate ...
--reference``), navigates it with pyins' strapdown integrator (``python-ins==1.0.1``) from the
first row's reference state, height held, no sensor corrections, and prints the horizontal
offset it reaches. With ``--compare ERRORS`` it also prints the largest horizontal difference
to the track of ``sinsbench navigate --start truth --params <ideal> --algorithm
one-plus-previous`` (its ``errors.parquet``; pyins' coning and sculling corrections use the
previous increment too), so that the two programs are seen to do the same work. Timing is the caller's
(``scripts/validate/pyins_speed.sh`` times both processes whole).

Frames: sinsbench's body frame is right-forward-up with ``C_enu_from_body = Rz(yaw) Rx(pitch)
Ry(roll)`` (the PSINS convention, as in pyins_lasergyro.py); pyins uses forward-right-down and
NED. Sample k is stamped at the end of its interval in both.
"""
import argparse
import sys

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
from pyins import strapdown, transform

from pyins_lasergyro import SWAP, ne_offsets, read_errors, rot

INCREMENTS = ["dtheta_x_rad", "dtheta_y_rad", "dtheta_z_rad", "dv_x_mps", "dv_y_mps", "dv_z_mps"]
REFERENCE = ["ref_lat_rad", "ref_lon_rad", "ref_height_m", "ref_vel_n_mps", "ref_vel_e_mps",
             "ref_vel_d_mps", "ref_pitch_rad", "ref_roll_rad", "ref_yaw_rad"]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("dataset", help="sinsbench Parquet dataset with reference columns")
    p.add_argument("--compare", metavar="ERRORS", help="sinsbench errors.parquet")
    args = p.parse_args()

    table = pq.read_table(args.dataset, columns=["t_s"] + INCREMENTS)
    t = table.column("t_s").to_numpy()
    inc = np.column_stack([table.column(c).to_numpy() for c in INCREMENTS])
    del table
    # The start state: the reference columns of the first row only.
    first = pq.ParquetFile(args.dataset).read_row_group(0, columns=REFERENCE)
    ref0 = {c: first.column(c)[0].as_py() for c in REFERENCE}
    dt = float(np.median(np.diff(t[:1000])))
    t0 = t[0] - dt  # the start of the first sample's interval
    frd = np.vstack([np.zeros((1, 6)), np.hstack([inc[:, :3] @ SWAP, inc[:, 3:] @ SWAP])])
    del inc
    imu = pd.DataFrame(frd, index=np.concatenate([[t0], t]) - t0,
                       columns=["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"])
    increments = strapdown.compute_increments_from_imu(imu, "increment")
    deg = np.degrees
    c_enu_rfu = (rot(2, deg(ref0["ref_yaw_rad"])) @ rot(0, deg(ref0["ref_pitch_rad"]))
                 @ rot(1, deg(ref0["ref_roll_rad"])))
    roll, pitch, heading = transform.mat_to_rph(SWAP @ c_enu_rfu @ SWAP)
    lat0, lon0, h0 = deg(ref0["ref_lat_rad"]), deg(ref0["ref_lon_rad"]), ref0["ref_height_m"]
    pva = pd.Series(dict(lat=lat0, lon=lon0, alt=h0, VN=ref0["ref_vel_n_mps"],
                         VE=ref0["ref_vel_e_mps"], VD=ref0["ref_vel_d_mps"],
                         roll=roll, pitch=pitch, heading=heading))
    traj = strapdown.Integrator(pva, with_altitude=False).integrate(increments)
    north, east = ne_offsets(traj.lat.to_numpy(), traj.lon.to_numpy(), lat0, lon0, h0)
    horiz = np.hypot(north, east)
    t_s = traj.index.to_numpy() + t0
    print(f"pyins: {len(t)} samples, {t_s[-1] / 3600:.2f} h; horizontal offset max "
          f"{horiz.max():.3f} m, final {horiz[-1]:.3f} m")
    if args.compare:
        err = read_errors(args.compare)
        ts = err.t_s.to_numpy()
        ok = (ts >= t_s[0]) & (ts <= t_s[-1])
        dn = np.interp(ts[ok], t_s, north) - err.north_m.to_numpy()[ok]
        de = np.interp(ts[ok], t_s, east) - err.east_m.to_numpy()[ok]
        d = np.hypot(dn, de)
        print(f"pyins - sinsbench: max horizontal difference {d.max():.3f} m over {ok.sum()} "
              f"points (sinsbench's own max offset "
              f"{np.hypot(err.north_m, err.east_m).max():.3f} m)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
