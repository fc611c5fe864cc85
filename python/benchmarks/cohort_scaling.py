"""limbfuse.cohort.run over a generated cohort: same metrics as the serial
loop of estimate + evaluate, and the time of each way, side by side.

    pip install ./python[cohort]
    python python/benchmarks/cohort_scaling.py [--trials 200] [--duration 30] [--method mjls]

Trials are simulated walking (seed = index, speed 0.8-1.6 m/s), written to
a temporary folder first; the timings are read + estimate + evaluate.
"""

import argparse
import os
import resource
import tempfile
import time

import pandas as pd

import limbfuse
from limbfuse import cohort


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--trials", type=int, default=200)
    ap.add_argument("--duration", type=float, default=30.0)
    ap.add_argument("--method", default="mjls")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        paths = []
        for k in range(a.trials):
            p = os.path.join(d, f"s{k:03}.csv")
            limbfuse.simulate("walking", duration=a.duration, seed=k, speed=0.8 + 0.8 * k / max(1, a.trials - 1)).write(p)
            paths.append(p)

        t0, c0 = time.perf_counter(), time.process_time()
        rows = []
        for p in paths:
            tr = limbfuse.read_trial(p)
            rows += cohort.rows_of(p, limbfuse.evaluate(tr, limbfuse.estimate(tr, a.method)))
        serial = pd.DataFrame(rows, columns=list(cohort.COLUMNS))
        t_serial, c_serial = time.perf_counter() - t0, time.process_time() - c0

        t0, c0 = time.perf_counter(), time.process_time()
        threads = cohort.run(paths, a.method)
        t_threads, c_threads = time.perf_counter() - t0, time.process_time() - c0

        from distributed import Client, LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cl, Client(cl) as client:
            client.run(lambda: __import__("limbfuse"))  # workers import limbfuse before the clock starts
            def cpu():
                r = resource.getrusage(resource.RUSAGE_SELF)
                return r.ru_utime + r.ru_stime

            w0 = client.run(cpu)
            t0, c0 = time.perf_counter(), time.process_time()
            dist = cohort.run(paths, a.method, client=client)
            t_dist, c_main = time.perf_counter() - t0, time.process_time() - c0
            w1 = client.run(cpu)
            c_workers = {w: w1[w] - w0[w] for w in w0}

    pd.testing.assert_frame_equal(threads, serial, check_exact=True)
    pd.testing.assert_frame_equal(dist, serial, check_exact=True)
    print(f"{a.trials} trials x {a.duration:.0f} s walking at 100 Hz, method {a.method}, {os.cpu_count()} CPUs")
    print("metrics: identical (exact) for the three ways")
    print(f"load average at the end: {os.getloadavg()}")
    print(f"{'way':36}{'wall':>8}  {'vs serial':>9}  CPU (s)")
    print(f"{'serial loop':36}{t_serial:8.2f} s {1:9.2f}x  {c_serial:.2f}")
    print(f"{'cohort.run, local threads':36}{t_threads:8.2f} s {t_serial / t_threads:9.2f}x  {c_threads:.2f}")
    workers = " + ".join(f"{c:.2f}" for c in c_workers.values())
    print(f"{'cohort.run, LocalCluster 2 workers':36}{t_dist:8.2f} s {t_serial / t_dist:9.2f}x  "
          f"{c_main:.2f} (client + scheduler) + {workers} (workers)")


if __name__ == "__main__":
    main()
