"""limbfuse.estimate(trial, "mjls") in memory vs filterpy stepping a
KalmanFilter of the same size (8 states: angle + gyro bias of 4 segments;
7 measurements: 4 accelerometer inclinations + 3 joint encoders) over the
same 1-hour 100 Hz walking trial, side by side in one run.

    pip install ./python[bench]
    python python/benchmarks/filterpy_vs_limbfuse.py [--duration 3600] [--repeats 5]

Wall time and the process's CPU time are both reported: on a shared, loaded
machine the CPU time is the figure that does not depend on the load.
Only the filtering is timed on the filterpy side (its inputs, measurements
and matrices are prepared with numpy beforehand); the limbfuse figure is the
whole `estimate` call (trial arrays in, Estimate arrays out): the first call
and the median of `--repeats` calls (filterpy runs once: about 15 s of CPU).
"""

import argparse
import os
import platform
import time

import numpy as np

import limbfuse

SEGMENTS = ("trunk", "thigh", "shank", "foot")
JOINTS = (("hip", "trunk", "thigh"), ("knee", "thigh", "shank"), ("ankle", "shank", "foot"))


def filterpy_inputs(trial):
    """Gyro inputs u (N x 4), measurements z (N x 7), dt."""
    ch = trial.channels
    u = np.column_stack([np.ma.filled(ch[f"{s}_gyr_z"], 0.0) for s in SEGMENTS])
    incl = [np.arctan2(np.ma.filled(ch[f"{s}_acc_y"], 0.0), np.ma.filled(ch[f"{s}_acc_x"], 1.0)) for s in SEGMENTS]
    enc = [np.ma.filled(ch[f"{j}_enc"], 0.0) for j, _, _ in JOINTS]
    z = np.column_stack(incl + enc)
    dt = float(np.median(np.diff(trial.t)))
    return u, z, dt


def filterpy_filter(dt):
    from filterpy.kalman import KalmanFilter

    kf = KalmanFilter(dim_x=8, dim_z=7, dim_u=4)
    F = np.eye(8)
    B = np.zeros((8, 4))
    H = np.zeros((7, 8))
    for k in range(4):
        F[2 * k, 2 * k + 1] = -dt  # angle_k+1 = angle_k + dt (gyro - bias)
        B[2 * k, k] = dt
        H[k, 2 * k] = 1.0  # inclination measures the angle
    for r, (_, a, b) in enumerate(JOINTS):
        H[4 + r, 2 * SEGMENTS.index(a)] = 1.0  # encoder = proximal - distal
        H[4 + r, 2 * SEGMENTS.index(b)] = -1.0
    kf.F, kf.B, kf.H = F, B, H
    kf.Q = np.diag([1e-5, 1e-8] * 4)
    kf.R = np.diag([1e-2] * 4 + [1e-5] * 3)
    kf.P *= 0.1
    return kf


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration", type=float, default=3600.0, help="trial length (s), 100 Hz")
    ap.add_argument("--repeats", type=int, default=5, help="limbfuse calls (the first and the median are reported)")
    a = ap.parse_args()
    load_before = os.getloadavg()[0]
    trial = limbfuse.simulate("walking", duration=a.duration, seed=1)
    n = len(trial)
    limbfuse.estimate(limbfuse.simulate("walking", duration=5.0, seed=1), "mjls")  # warm-up

    # The first call on the trial is reported alone: it is the one that gets
    # its output memory fresh from the kernel (later calls may reuse pages).
    calls = []
    for _ in range(max(1, a.repeats)):
        c0, t0 = time.process_time(), time.perf_counter()
        est = limbfuse.estimate(trial, "mjls")
        calls.append((time.perf_counter() - t0, time.process_time() - c0))
        assert len(est) == n
        del est
    t_first, c_first = calls[0]
    t_lf, c_lf = (float(np.median([c[k] for c in calls])) for k in (0, 1))
    # The same call without the 38 diagnostic columns (`diagnostics="none"`,
    # the CLI's `--diagnostics none`): the estimates only.
    lean = []
    for _ in range(max(1, a.repeats)):
        c0, t0 = time.process_time(), time.perf_counter()
        est = limbfuse.estimate(trial, "mjls", diagnostics="none")
        lean.append((time.perf_counter() - t0, time.process_time() - c0))
        del est
    t_ln, c_ln = (float(np.median([c[k] for c in lean])) for k in (0, 1))

    u, z, dt = filterpy_inputs(trial)
    kf = filterpy_filter(dt)
    c0, t0 = time.process_time(), time.perf_counter()
    for i in range(n):
        kf.predict(u=u[i])
        kf.update(z[i])
    t_fp, c_fp = time.perf_counter() - t0, time.process_time() - c0

    import filterpy

    print(f"python {platform.python_version()}, numpy {np.__version__}, filterpy {filterpy.__version__}")
    print(f"trial: {a.duration:.0f} s walking at 100 Hz = {n} samples")
    print(f"load average before: {load_before:.1f} on {os.cpu_count()} CPUs")
    print(f"{'':40}{'wall s':>9}{'CPU s':>9}{'samples per CPU-s':>19}")
    print(f"{'limbfuse.estimate(trial, mjls), first':40}{t_first:>9.3f}{c_first:>9.3f}{n / c_first:>19.0f}")
    med = f"limbfuse.estimate, median of {len(calls)}"
    print(f"{med:40}{t_lf:>9.3f}{c_lf:>9.3f}{n / c_lf:>19.0f}")
    lean_label = f"diagnostics='none', median of {len(lean)}"
    print(f"{lean_label:40}{t_ln:>9.3f}{c_ln:>9.3f}{n / c_ln:>19.0f}")
    print(f"{'filterpy KalmanFilter 8x7':40}{t_fp:>9.3f}{c_fp:>9.3f}{n / c_fp:>19.0f}")
    print(f"speed-up, first call: {t_fp / t_first:.0f}x wall, {c_fp / c_first:.0f}x CPU time")
    print(f"speed-up, median:     {t_fp / t_lf:.0f}x wall, {c_fp / c_lf:.0f}x CPU time")
    print(f"speed-up, diagnostics='none', median: {t_fp / t_ln:.0f}x wall, {c_fp / c_ln:.0f}x CPU time")
    print(f"load average after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
