"""`limbfuse.estimate(trial, METHOD)` called again and again on one
simulated walking trial: a process to profile the package's estimate path
(`perf record ... python python/benchmarks/estimate_loop.py`) and the CPU
time of each call.

    python python/benchmarks/estimate_loop.py [--duration 600] [--calls 20] [--method mjls]
    python python/benchmarks/estimate_loop.py --trial FILE [--calls 20]   # a trial file instead
    python python/benchmarks/estimate_loop.py --duration 3600 --calls 4 --per-call

`--per-call` prints each call's wall, CPU and system time and minor page
faults (Unix): where the first call's extra time goes (docs/PERFORMANCE.md).
"""

import argparse
import statistics
import time

try:
    import resource
except ImportError:  # not on Windows
    resource = None

import limbfuse


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration", type=float, default=600.0, help="trial length (s), 100 Hz")
    ap.add_argument("--calls", type=int, default=20)
    ap.add_argument("--method", default="mjls")
    ap.add_argument("--trial", help="read this trial file instead of simulating one")
    ap.add_argument("--per-call", action="store_true", help="print every call's times and page faults")
    a = ap.parse_args()
    if a.trial:
        trial = limbfuse.read_trial(a.trial)
    else:
        trial = limbfuse.simulate("walking", duration=a.duration, seed=1)
    n = len(trial)
    cpu = []
    for k in range(max(1, a.calls)):
        r0 = resource.getrusage(resource.RUSAGE_SELF) if resource else None
        c0, t0 = time.process_time(), time.perf_counter()
        est = limbfuse.estimate(trial, a.method)
        cpu.append(time.process_time() - c0)
        if a.per_call:
            line = f"call {k}: wall {time.perf_counter() - t0:.3f} s, CPU {cpu[-1]:.3f} s"
            if resource:
                r1 = resource.getrusage(resource.RUSAGE_SELF)
                line += (f" (system {r1.ru_stime - r0.ru_stime:.3f} s), "
                         f"{r1.ru_minflt - r0.ru_minflt} minor page faults")
            print(line)
        del est
    med = statistics.median(cpu)
    print(f"{a.method} over {n} samples, {len(cpu)} calls: CPU first {cpu[0]:.3f} s, "
          f"median {med:.3f} s = {med / n * 1e6:.3f} us per sample")


if __name__ == "__main__":
    main()
