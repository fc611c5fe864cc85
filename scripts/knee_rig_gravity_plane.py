#!/usr/bin/env python3
"""How much gravity lies in the joint plane of each segment of a knee trial,
measured without trusting the accelerometer's offsets (knee31 finding).

Two poses of a segment turned by `dtheta` about its joint axis `j` differ in
the joint plane by `|g_perp| * 2 sin(dtheta / 2)`, whatever constant offset
the accelerometer adds: the mean specific force projected off `j` is taken
over 0.5 s bins where the segment turns slowly (mean |gyro| < 0.5 rad/s, so
the motion's accelerations are small against g), `theta` is the gyro angle
about `j` (the principal axis of the segment's gyro), and `|g_perp|` is the
least-squares slope over every pair of bins turned by more than 15 deg.
Also prints the mean of the specific force along `j`: near +-1 g on the
shared knee rig although `|g_perp|` is 1.00 g there, i.e. the ~1 g along the
joint axis is an accelerometer offset, not gravity.

Usage (numpy needed):
    limbfuse import --format knee-rig ../shared/data/knee-rig/Trial_03.csv -o rig03.csv
    python3 scripts/knee_rig_gravity_plane.py rig03.csv
"""
import sys

import numpy as np

G = 9.81


def load(path):
    rows = [l for l in open(path) if not l.startswith("#")]
    hdr = rows[0].strip().split(",")
    data = np.genfromtxt(rows[1:], delimiter=",")
    return hdr, data


def segment(hdr, data, name):
    acc = data[:, [hdr.index(f"{name}_acc_{c}") for c in "xyz"]]
    gyr = data[:, [hdr.index(f"{name}_gyr_{c}") for c in "xyz"]]
    ok = ~(np.isnan(acc).any(1) | np.isnan(gyr).any(1))
    t = data[ok, 0]
    acc, gyr = acc[ok], gyr[ok]
    _, vecs = np.linalg.eigh(gyr.T @ gyr)
    j = vecs[:, -1]
    theta = np.cumsum((gyr @ j) * np.diff(t, prepend=t[0]))
    perp = acc - np.outer(acc @ j, j)
    bins = []
    for t0 in np.arange(t[0], t[-1] - 0.5, 0.5):
        m = (t >= t0) & (t < t0 + 0.5)
        if m.sum() > 10 and np.linalg.norm(gyr[m], axis=1).mean() < 0.5:
            bins.append((theta[m].mean(), perp[m].mean(0)))
    x, y = [], []
    for i in range(len(bins)):
        for k in range(i + 1, len(bins)):
            d = abs(bins[i][0] - bins[k][0])
            if d > np.radians(15):
                x.append(2 * np.sin(d / 2))
                y.append(np.linalg.norm(bins[i][1] - bins[k][1]))
    x, y = np.array(x), np.array(y)
    if len(x) == 0:
        return j, float("nan"), float("nan"), (acc @ j).mean(), len(bins)
    g_perp = (x @ y) / (x @ x)
    misfit = np.sqrt(((y - g_perp * x) ** 2).mean())
    return j, g_perp, misfit, (acc @ j).mean(), len(bins)


def main():
    for path in sys.argv[1:]:
        hdr, data = load(path)
        print(path)
        for name in ("thigh", "shank"):
            j, g_perp, misfit, along, n = segment(hdr, data, name)
            print(
                f"  {name}: j {np.round(j, 3)}, {n} slow bins: |g_perp| {g_perp:.2f} m/s^2 "
                f"= {g_perp / G:.2f} g (rms misfit {misfit:.2f} m/s^2); mean specific force along j {along:.2f} m/s^2"
            )


if __name__ == "__main__":
    main()
