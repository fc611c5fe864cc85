"""Two builds of the package side by side: `limbfuse.estimate(trial, METHOD)`
of the installed `limbfuse` and of another build, imported as
`limbfuse_base` from `--base-dir`, called in alternation (ABBA order) in one
process on the same simulated trial; the CPU time per sample of each
(minimum, median, first call). On a loaded machine the alternation keeps
both builds under the same load, which separate runs minutes apart do not.

    # the other build: a copy of an installed `limbfuse` package directory
    # (e.g. from `pip install --target DIR ./python` at another commit),
    # renamed `limbfuse_base`
    cp -r OTHER/limbfuse BASE_DIR/limbfuse_base
    python python/benchmarks/estimate_ab.py --base-dir BASE_DIR [--duration 3600] [--rounds 12]
"""

import argparse
import importlib
import os
import statistics
import sys
import time

import limbfuse


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--base-dir", required=True, help="directory holding the other build as `limbfuse_base`")
    ap.add_argument("--duration", type=float, default=3600.0, help="trial length (s), 100 Hz")
    ap.add_argument("--rounds", type=int, default=12)
    ap.add_argument("--method", default="mjls")
    a = ap.parse_args()
    sys.path.insert(0, a.base_dir)
    base = importlib.import_module("limbfuse_base")
    builds = {"base": base, "installed": limbfuse}
    trials = {k: m.simulate("walking", duration=a.duration, seed=1) for k, m in builds.items()}
    n = len(trials["installed"])
    cpu = {k: [] for k in builds}
    load = os.getloadavg()[0]
    for r in range(max(1, a.rounds)):
        order = ("base", "installed") if r % 2 == 0 else ("installed", "base")
        for k in order:
            c0 = time.process_time()
            est = builds[k].estimate(trials[k], a.method)
            cpu[k].append(time.process_time() - c0)
            del est
    print(f"{a.method} over {n} samples, {a.rounds} rounds, load average {load:.1f} -> {os.getloadavg()[0]:.1f}")
    for k, v in cpu.items():
        us = [c / n * 1e6 for c in v]
        print(f"{k:>9}: CPU per sample min {min(us):.3f} us, median {statistics.median(us):.3f} us, first {us[0]:.3f} us")


if __name__ == "__main__":
    main()
