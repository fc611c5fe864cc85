#!/usr/bin/env python3
"""End-to-end comparison (issue 18, "Done when"): what a Python user would
write to do the job of `limbfuse estimate --method mjls` (pandas
`read_csv`, a filterpy `KalmanFilter` of the size of mjls stepped over every
sample, `to_csv`), timed side by side with the limbfuse binary on the same
trial, interleaved, in one run.

Usage (docs/PERFORMANCE.md):
    python3 -m venv target/pyvenv && target/pyvenv/bin/pip install pandas filterpy pyarrow
    target/release/limbfuse simulate walking --duration 1200 --seed 1 -o target/walk1200.csv
    target/release/limbfuse simulate walking --duration 1200 --seed 1 -o target/walk1200.arrow
    target/pyvenv/bin/python scripts/python_comparison.py target/release/limbfuse \
        target/walk1200.csv 3 target/walk1200.arrow

With the optional Arrow trial (the same trial as an Arrow IPC file,
docs/ARROW.md; needs pyarrow), two more pairs are timed in the same loop:
limbfuse reading and writing Arrow (`.arrow` in, `.arrow` out), and the
Python script reading and writing Feather (`pd.read_feather`,
`DataFrame.to_feather`, the same Arrow IPC format), so that the binary
format is compared with both the CSV script and the script given the same
binary format.

The Python filter has the size of mjls (8 states: angle and gyro bias of
trunk, thigh, shank and foot; 7 measurement rows: 4 accelerometer
inclinations and 3 encoder joint angles, `filterpy.kalman.KalmanFilter`
with `dim_x=8, dim_z=7, dim_u=4`); the inclinations are computed
vectorised with numpy before the loop, as a careful user would. It writes
t, 7 angles and 8 standard deviations (16 columns); limbfuse writes its
46 by default (t, 7 angles and 38 diagnostics), so the Python side writes less.
Each limbfuse run is therefore timed twice: with its default columns, and
like for like with `--diagnostics` naming 8 diagnostics (the 4 angle
standard deviations and the 4 gyro bias estimates), i.e. the same 16
columns as the Python script (`like` in the report).

Reported per tool: the median over the repeats of wall time and CPU time
(the machine may be shared: CPU time is what one core spent). Python's
times cover read_csv -> filter -> to_csv (not the interpreter start nor the
imports, which are reported apart); limbfuse's cover the whole process.
"""

import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

T_IMPORT = time.perf_counter()
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from filterpy.kalman import KalmanFilter  # noqa: E402

IMPORT_SECONDS = time.perf_counter() - T_IMPORT

SEGMENTS = ["trunk", "thigh", "shank", "foot"]
# limbfuse's 16 columns like the Python script's: t, 7 angles, 8 diagnostics.
LIKE_FOR_LIKE = ["--diagnostics", ",".join(
    [f"sd_{s}" for s in ["trunk", "thigh", "shank", "foot"]]
    + [f"bias_{s}" for s in ["trunk", "thigh", "shank", "foot"]])]
JOINTS = ["hip", "knee", "ankle"]


def python_estimate(trial, out, feather=False):
    """read_csv -> 8-state KF over every sample -> to_csv (or Feather both ends)."""
    df = pd.read_feather(trial) if feather else pd.read_csv(trial, comment="#")
    t = df["t"].to_numpy()
    gyro = np.stack([df[f"{s}_gyr_z"].to_numpy() for s in SEGMENTS], axis=1)
    incl = np.stack(
        [np.arctan2(df[f"{s}_acc_x"].to_numpy(), df[f"{s}_acc_y"].to_numpy()) for s in SEGMENTS],
        axis=1,
    )
    enc = np.stack([df[f"{j}_enc"].to_numpy() for j in JOINTS], axis=1)
    z_all = np.concatenate([incl, enc], axis=1)

    kf = KalmanFilter(dim_x=8, dim_z=7, dim_u=4)
    H = np.zeros((7, 8))
    for i in range(4):
        H[i, 2 * i] = 1.0
    for j in range(3):  # joint = distal segment - proximal segment
        H[4 + j, 2 * (j + 1)] = 1.0
        H[4 + j, 2 * j] = -1.0
    kf.H = H
    kf.R = np.diag([0.2**2] * 4 + [0.005**2] * 3)
    kf.P = np.eye(8) * 0.05**2
    kf.x = np.zeros((8, 1))
    for i in range(4):
        kf.x[2 * i, 0] = incl[0, i]
    # A uniform time base (checked): F, B and Q are set once, as a user
    # with a 100 Hz recording would (cheaper than rebuilding them per step).
    dts = np.diff(t)
    dt = float(np.median(dts))
    assert np.allclose(dts, dt, rtol=1e-6), "the script assumes a uniform time base"
    F = np.eye(8)
    B = np.zeros((8, 4))
    for i in range(4):
        F[2 * i, 2 * i + 1] = -dt
        B[2 * i, i] = dt
    kf.F, kf.B = F, B
    kf.Q = np.diag([(0.01 * dt) ** 2, (1e-4 * dt) ** 2] * 4)
    n = len(t)
    angles = np.empty((n, 4))
    sds = np.empty((n, 8))
    for k in range(n):
        kf.predict(u=gyro[k].reshape(4, 1))
        kf.update(z_all[k].reshape(7, 1))
        angles[k] = kf.x[0::2, 0]
        sds[k] = np.sqrt(np.diag(kf.P))
    out_df = pd.DataFrame({"t": t})
    for i, s in enumerate(SEGMENTS):
        out_df[s] = angles[:, i]
    for j, name in enumerate(JOINTS):
        out_df[name] = angles[:, j + 1] - angles[:, j]
    for i in range(8):
        out_df[f"diag_sd_{i}"] = sds[:, i]
    if feather:
        out_df.to_feather(out)
    else:
        out_df.to_csv(out, index=False)
    return n


def timed_python(trial, out, feather=False):
    w0, c0 = time.perf_counter(), time.process_time()
    n = python_estimate(trial, out, feather)
    return time.perf_counter() - w0, time.process_time() - c0, n


def timed_limbfuse(binary, trial, out, extra=()):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    w0 = time.perf_counter()
    subprocess.run(
        [binary, "-q", "estimate", "--method", "mjls", *extra, trial, "-o", out],
        check=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    wall = time.perf_counter() - w0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return wall, cpu


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    binary, trial = sys.argv[1], sys.argv[2]
    repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    arrow = sys.argv[4] if len(sys.argv) > 4 else None
    size = os.path.getsize(trial)
    keys = ["py", "lf", "lf_like", "py_feather", "lf_arrow", "lf_arrow_like"]
    times = {k: ([], []) for k in keys}

    def add(key, wall, cpu):
        times[key][0].append(wall)
        times[key][1].append(cpu)

    sizes = {}
    with tempfile.TemporaryDirectory() as d:
        out = {
            "py": os.path.join(d, "py.csv"),
            "lf": os.path.join(d, "lf.csv"),
            "lf_like": os.path.join(d, "lf_like.csv"),
            "py_feather": os.path.join(d, "py.feather"),
            "lf_arrow": os.path.join(d, "lf.arrow"),
            "lf_arrow_like": os.path.join(d, "lf_like.arrow"),
        }
        for _ in range(repeats):
            add("lf", *timed_limbfuse(binary, trial, out["lf"]))
            add("lf_like", *timed_limbfuse(binary, trial, out["lf_like"], LIKE_FOR_LIKE))
            w, c, n = timed_python(trial, out["py"])
            add("py", w, c)
            if arrow:
                add("lf_arrow", *timed_limbfuse(binary, arrow, out["lf_arrow"]))
                add("lf_arrow_like",
                    *timed_limbfuse(binary, arrow, out["lf_arrow_like"], LIKE_FOR_LIKE))
                w, c, _ = timed_python(arrow, out["py_feather"], feather=True)
                add("py_feather", w, c)
        for k, p in out.items():
            if os.path.exists(p):
                sizes[k] = os.path.getsize(p)
    med = statistics.median

    def wall(k):
        return med(times[k][0])

    def cpu(k):
        return med(times[k][1])

    print(f"trial: {trial} ({size / 1e6:.1f} MB, {n} samples); load average {os.getloadavg()}")
    if arrow:
        print(f"arrow trial: {arrow} ({os.path.getsize(arrow) / 1e6:.1f} MB)")
    print(f"python imports (not counted): {IMPORT_SECONDS:.2f} s")
    labels = {
        "py": "python  (pandas csv + filterpy)",
        "py_feather": "python  (pandas feather + filterpy)",
        "lf": "limbfuse estimate mjls, csv",
        "lf_like": "limbfuse, csv, like for like",
        "lf_arrow": "limbfuse estimate mjls, arrow",
        "lf_arrow_like": "limbfuse, arrow, like for like",
    }
    for k, label in labels.items():
        if times[k][0]:
            print(f"{label:36}: wall {wall(k):.3f} s, cpu {cpu(k):.3f} s, "
                  f"output {sizes[k] / 1e6:.1f} MB")
    pairs = [("py", "lf", "csv vs csv"), ("py", "lf_like", "csv vs csv, like for like")]
    if arrow:
        pairs += [("py", "lf_arrow", "python csv vs limbfuse arrow"),
                  ("py", "lf_arrow_like", "python csv vs limbfuse arrow, like for like"),
                  ("py_feather", "lf_arrow", "python feather vs limbfuse arrow"),
                  ("py_feather", "lf_arrow_like",
                   "python feather vs limbfuse arrow, like for like")]
    for p, l, what in pairs:
        print(f"speed-up, {what}: wall {wall(p) / wall(l):.1f}x, cpu {cpu(p) / cpu(l):.1f}x "
              f"(medians of {repeats})")


if __name__ == "__main__":
    main()
