"""`limbfuse.estimate(trial, METHOD)` called again and again on one
simulated walking trial: a process to profile the package's estimate path
(`perf record ... python python/benchmarks/estimate_loop.py`) and the CPU
time of each call.

    python python/benchmarks/estimate_loop.py [--duration 600] [--calls 20] [--method mjls]
    python python/benchmarks/estimate_loop.py --trial FILE [--calls 20]   # a trial file instead
"""

import argparse
import statistics
import time

import limbfuse


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration", type=float, default=600.0, help="trial length (s), 100 Hz")
    ap.add_argument("--calls", type=int, default=20)
    ap.add_argument("--method", default="mjls")
    ap.add_argument("--trial", help="read this trial file instead of simulating one")
    a = ap.parse_args()
    if a.trial:
        trial = limbfuse.read_trial(a.trial)
    else:
        trial = limbfuse.simulate("walking", duration=a.duration, seed=1)
    n = len(trial)
    cpu = []
    for _ in range(max(1, a.calls)):
        c0 = time.process_time()
        est = limbfuse.estimate(trial, a.method)
        cpu.append(time.process_time() - c0)
        del est
    med = statistics.median(cpu)
    print(f"{a.method} over {n} samples, {len(cpu)} calls: CPU first {cpu[0]:.3f} s, "
          f"median {med:.3f} s = {med / n * 1e6:.3f} us per sample")


if __name__ == "__main__":
    main()
