#!/usr/bin/env python3
"""Issue 19, HA001 course: would moving the lower-back sensor's excursion to
the hip joints or to the centre of mass (rigid-body lever arms) remove the
pendulum's over-estimate on slow strides? (docs/RESULTS.md, "lowback-speed on
the shared HA001 recordings", "Lever arms of the sensor, tried").

For each of the three shared HA001 trials the script runs
`limbfuse estimate --method lowback-speed` and `limbfuse evaluate --strides`,
takes the estimator's own vertical acceleration (`diag_vertical_acc`) and
initial contacts (`diag_ic`), and recomputes every kept stride's speed:

* `shipped`: `step_excursion` of crates/limbfuse-estimators/src/lowback_speed
  rewritten in numpy (the step's mean `a_v` removed, zero-mean velocity,
  position detrended through its end point); it must reproduce the CLI's
  stride speeds (checked: the script stops otherwise);
* `+ obliquity W`: the excursion of the stance hip instead of the sensor,
  `z_hip = z_sensor + s W phi`, `phi` the integrated rate about the
  horizontal forward axis (detrended over the step like the position), `s` =
  +1 in left stance and -1 in right stance from the *reference* contacts,
  `W` the sensor's lateral distance from each hip joint;
* `+ tilt d`: `z = z_sensor - d theta`, `theta` the integrated rate about the
  horizontal left axis (up x forward), `d` the sensor's distance behind the
  point the pendulum describes (hip joints or centre of mass).

Signs are the rigid-body kinematics (positive `phi` lifts the left side,
positive `theta` pitches the top forward and lifts a point behind the pivot),
with forward = the sensor's z axis projected on the horizontal: the axis the
turns' centripetal acceleration gives (printed) and session 44's
energy-exchange estimate ([0.27-0.29, -0.14 to -0.16, 0.95]).

Pendulum pairs: `sensor` = l 0.964 m (the trials' sensor height) with
K = 4.587 / 4 (Mobilise-D, what limbfuse ships for these files); `leg` =
l = 0.530 x 1.59 m with K = 1.25 (Zijlstra & Hof 2003).

Then the same pitch correction where the geometry is known: the shared
independent simulator's three walks (`../shared/data/independent-sim`,
trunk IMU aligned to the trunk, 0.080 m behind and 0.100 m above the hip
joint, `# imu_mounts_m`; the hip joint's height is `com_y`): each kept
step's excursion of the sensor, of the hip joint (truth) and of the sensor
corrected by `d` = 0.08 m, and the stride speed MAE (bias) against
`evaluate`'s reference with the default pendulum (0.9275 m, K = 1.25).

Usage (numpy and scipy needed; `limbfuse` on PATH or LIMBFUSE_BIN):
    python3 scripts/lowback_lever_arms.py [../shared/data]
"""
import csv
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy.ndimage import uniform_filter1d

TRIALS = ["HA001-test5-trial1", "HA001-test5-trial2", "HA001-test11-trial1"]
DT = 0.01
PAIRS = {"sensor": (0.964, 4.587 / 4.0), "leg": (0.530 * 1.59, 1.25)}


def table(path):
    rows = [l for l in open(path) if not l.startswith("#")]
    hdr = rows[0].strip().split(",")
    data = np.genfromtxt(rows[1:], delimiter=",", missing_values="", filling_values=np.nan)
    return {h: data[:, i] for i, h in enumerate(hdr)}


def step_excursion_curve(a_v):
    """The position the shipped `step_excursion` takes max - min of."""
    a = a_v - a_v.mean()
    n = len(a)
    v = np.cumsum(a) * DT
    p = np.cumsum(v - v.mean()) * DT
    return p - p[-1] * np.arange(1, n + 1) / n


def detrended_angle(rate):
    """The rate integrated over the step, detrended through its end points."""
    ang = np.cumsum(rate) * DT
    ang = ang - ang[0]
    return ang - ang[-1] * np.arange(len(ang)) / (len(ang) - 1)


def axes(trial):
    acc = np.stack([trial["trunk_acc_" + c] for c in "xyz"], 1)
    gyr = np.stack([trial["trunk_gyr_" + c] for c in "xyz"], 1)
    mean = uniform_filter1d(acc, 200, axis=0)
    up = mean / np.linalg.norm(mean, axis=1)[:, None]
    z = np.array([0.0, 0.0, 1.0])
    fwd = z - (up @ z)[:, None] * up
    fwd /= np.linalg.norm(fwd, axis=1)[:, None]
    left = np.cross(up, fwd)
    return acc, gyr, up, (gyr * fwd).sum(1), (gyr * left).sum(1)


def turn_forward(acc, gyr):
    """Forward from the turns: centripetal acceleration = w_up v (up x forward)."""
    from scipy.signal import butter, sosfiltfilt

    sos = butter(2, 0.5, fs=1 / DT, output="sos")
    a = sosfiltfilt(sos, acc, axis=0)
    w = sosfiltfilt(sos, gyr, axis=0)
    mean = uniform_filter1d(acc, 400, axis=0)
    up = mean / np.linalg.norm(mean, axis=1)[:, None]
    w_up = (w * up).sum(1)
    a_h = a - (a * up).sum(1)[:, None] * up
    lat = (w_up[:, None] * a_h).sum(0) / (w_up**2).sum()
    f = np.cross(lat, up.mean(0))
    return f / np.linalg.norm(f)


def strides(data_dir, name, work, exe):
    trial_path = os.path.join(data_dir, name + ".csv")
    est = os.path.join(work, name + ".est.csv")
    strides_csv = os.path.join(work, name + ".strides.csv")
    subprocess.run([exe, "estimate", "--method", "lowback-speed", trial_path, "-o", est],
                   check=True, capture_output=True)
    subprocess.run([exe, "evaluate", trial_path, est, "--strides", strides_csv],
                   check=True, capture_output=True)
    return table(trial_path), table(est), list(csv.DictReader(open(strides_csv)))


def kept_steps(est, rows):
    """(stride, its two steps as (start, end) rows) of every stride the
    estimator gave a speed with a reference, split at its middle contact."""
    ics = np.unique(est["diag_ic"][~np.isnan(est["diag_ic"])])
    for s in rows:
        if not s["speed_ref_m_s"] or s["speed_withheld"] or not s["speed_m_s"]:
            continue
        t0, t2 = float(s["ic_s"]), float(s["end_s"])
        mids = [x for x in ics if t0 + 0.2 < x < t2 - 0.2]
        if len(mids) == 1:
            i0, i1, i2 = (int(round(x / DT)) for x in (t0, mids[0], t2))
            yield s, ((i0, i1), (i1, i2))


def independent_walks(sim_dir, work, exe):
    """The pitch lever arm where the simulator states it (0.080 m behind the hip)."""
    l, K, d = 0.530 * 1.75, 1.25, 0.080
    print("\nindependent simulator's walks: step excursion (mm) and stride speed MAE (bias), m/s")
    print("| walk | sensor | hip joint (truth) | sensor + pitch | speed, shipped | speed, + pitch |")
    print("|---|---|---|---|---|---|")
    for walk in ("walk-v0.7-s300", "walk-v1.2-s301", "walk-v1.6-s302"):
        trial, est, rows = strides(sim_dir, walk, work, exe)
        a_v = np.nan_to_num(est["diag_vertical_acc"])
        pitch_rate = trial["trunk_gyr_z"]  # aligned trunk IMU: SPEC's sagittal rate
        excursions, errors = [], []
        for s, steps in kept_steps(est, rows):
            v_ref, v_cli = float(s["speed_ref_m_s"]), float(s["speed_m_s"])
            length = 0.0
            for a, b in steps:
                z = step_excursion_curve(a_v[a:b])
                # SPEC: theta counter-clockwise seen from the right; a point d
                # behind the hip moves down by d theta.
                zc = z + d * detrended_angle(pitch_rate[a:b])
                hip = detrended_angle(np.diff(trial["com_y"][a:b + 1]) / DT)
                excursions.append((np.ptp(z), np.ptp(hip), np.ptp(zc)))
                h = np.ptp(zc)
                length += K * 2.0 * np.sqrt(2.0 * l * h - h * h)
            errors.append((v_cli - v_ref, length / (float(s["end_s"]) - float(s["ic_s"])) - v_ref))
        x, e = 1000.0 * np.array(excursions).mean(0), np.array(errors)
        print("| %s | %.1f | %.1f | %.1f | %.3f (%+.3f) | %.3f (%+.3f) |" % (
            walk, x[0], x[1], x[2], np.abs(e[:, 0]).mean(), e[:, 0].mean(),
            np.abs(e[:, 1]).mean(), e[:, 1].mean()))


def main():
    data = sys.argv[1] if len(sys.argv) > 1 else "../shared/data"
    data_dir = os.path.join(data, "mobgap-lowerback")
    exe = os.environ.get("LIMBFUSE_BIN", "limbfuse")
    variants = [("shipped", "sensor", 0.0, 0.0)]
    for pair in ("sensor", "leg"):
        if pair == "leg":
            variants.append(("no lever arm", pair, 0.0, 0.0))
        for w in (0.085,):
            variants.append(("obliquity W %.3f" % w, pair, w, 0.0))
        for d in (0.06, 0.08, 0.10, 0.12):
            variants.append(("tilt d %.2f" % d, pair, 0.0, d))
        variants.append(("obliquity 0.085 + tilt 0.10", pair, 0.085, 0.10))
    errors = {v: {} for v in range(len(variants))}
    with tempfile.TemporaryDirectory() as work:
        for name in TRIALS:
            trial, est, rows = strides(data_dir, name, work, exe)
            acc, gyr, _, w_fwd, w_left = axes(trial)
            print("%s: forward from the turns %s" % (name, np.round(turn_forward(acc, gyr), 2)))
            a_v = np.nan_to_num(est["diag_vertical_acc"])
            ics = np.unique(est["diag_ic"][~np.isnan(est["diag_ic"])])
            left_ref = trial["contact_left_ref"]
            humps, agree = 0, 0
            for s in rows:
                if not s["speed_ref_m_s"] or s["speed_withheld"] or not s["speed_m_s"]:
                    continue
                t0, t2 = float(s["ic_s"]), float(s["end_s"])
                mids = [x for x in ics if t0 + 0.2 < x < t2 - 0.2]
                if len(mids) != 1:
                    continue
                i0, i1, i2 = (int(round(x / DT)) for x in (t0, mids[0], t2))
                v_ref, v_cli = float(s["speed_ref_m_s"]), float(s["speed_m_s"])
                for k, (label, pair, w, d) in enumerate(variants):
                    l, K = PAIRS[pair]
                    length = 0.0
                    for a, b in ((i0, i1), (i1, i2)):
                        z = step_excursion_curve(a_v[a:b])
                        m = (a + b) // 2
                        side = 0.0 if np.isnan(left_ref[m]) else (1.0 if left_ref[m] == 1 else -1.0)
                        phi = detrended_angle(w_fwd[a:b])
                        if k == 0 and side != 0.0:
                            humps += 1
                            agree += (phi.mean() > 0) == (side > 0)
                        z = z + side * w * phi - d * detrended_angle(w_left[a:b])
                        h = z.max() - z.min()
                        length += K * 2.0 * np.sqrt(2.0 * l * h - h * h)
                    v = length / (t2 - t0)
                    if k == 0 and abs(v - v_cli) > 1e-9:
                        sys.exit("%s %.2f s: recomputed %.6f, CLI %.6f m/s" % (name, t0, v, v_cli))
                    errors[k].setdefault(name, []).append((v - v_ref, v_ref))
            print("  steps whose roll hump (phi > 0: left side up) matches left stance: %d of %d"
                  % (agree, humps))
    print()
    print("MAE m/s (bias, strides); last column: the course's MAE with K scaled so that the two")
    print("straight walks have no mean error (what a K refitted on straight walking would give)")
    print("| variant | pendulum | " + " | ".join(t.replace("HA001-", "") for t in TRIALS)
          + " | slope of error vs speed | course, K for unbiased straight walks |")
    print("|---|---|" + "---|" * len(TRIALS) + "---|---|")
    for k, (label, pair, _, _) in enumerate(variants):
        cells, allerr = [], []
        for name in TRIALS:
            e = np.array(errors[k][name])
            allerr.append(e)
            cells.append("%.3f (%+.3f, %d)" % (np.abs(e[:, 0]).mean(), e[:, 0].mean(), len(e)))
        e = np.vstack(allerr)
        slope = np.polyfit(e[:, 1], e[:, 0], 1)[0]
        straight = np.vstack(allerr[:2])
        scale = straight[:, 1].sum() / (straight[:, 0] + straight[:, 1]).sum()
        course = allerr[2]
        rescaled = np.abs(scale * (course[:, 0] + course[:, 1]) - course[:, 1]).mean()
        print("| %s | %s | %s | %.3f | %.3f (x %.3f) |"
              % (label, pair, " | ".join(cells), slope, rescaled, scale))
    with tempfile.TemporaryDirectory() as work:
        independent_walks(os.path.join(data, "independent-sim"), work, exe)


if __name__ == "__main__":
    main()
