"""limbfuse.cohort.run over a generated cohort: same metrics as the serial
loop of estimate + evaluate, and the time of each way, side by side.

    pip install ./python[cohort]
    python python/benchmarks/cohort_scaling.py [--trials 200] [--duration 30] [--method mjls] [--repeats 3]

Trials are simulated walking (seed = index, speed 0.8-1.6 m/s), written to
a temporary folder first; the timings are read + estimate + evaluate.
"""

import argparse
import os
import resource
import statistics
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
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        paths = []
        for k in range(a.trials):
            p = os.path.join(d, f"s{k:03}.csv")
            limbfuse.simulate("walking", duration=a.duration, seed=k, speed=0.8 + 0.8 * k / max(1, a.trials - 1)).write(p)
            paths.append(p)

        def serial_loop():
            rows = []
            for p in paths:
                tr = limbfuse.read_trial(p)
                rows += cohort.rows_of(p, limbfuse.evaluate(tr, limbfuse.estimate(tr, a.method)))
            return pd.DataFrame(rows, columns=list(cohort.COLUMNS))

        from distributed import Client, LocalCluster

        def cpu():
            r = resource.getrusage(resource.RUSAGE_SELF)
            return r.ru_utime + r.ru_stime

        times = {"serial": [], "threads": [], "cluster": []}
        cpus = {"serial": [], "threads": [], "cluster": []}
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cl, Client(cl) as client:
            client.run(lambda: __import__("limbfuse"))  # workers import limbfuse before the clock starts
            # The ways alternate, `--repeats` times: the load of a shared
            # machine changes from minute to minute.
            for _ in range(a.repeats):
                t0, c0 = time.perf_counter(), time.process_time()
                serial = serial_loop()
                times["serial"].append(time.perf_counter() - t0)
                cpus["serial"].append(time.process_time() - c0)

                t0, c0 = time.perf_counter(), time.process_time()
                threads = cohort.run(paths, a.method)
                times["threads"].append(time.perf_counter() - t0)
                cpus["threads"].append(time.process_time() - c0)

                w0 = client.run(cpu)
                t0, c0 = time.perf_counter(), time.process_time()
                dist = cohort.run(paths, a.method, client=client)
                times["cluster"].append(time.perf_counter() - t0)
                w1 = client.run(cpu)
                cpus["cluster"].append(time.process_time() - c0 + sum(w1[w] - w0[w] for w in w0))
                pd.testing.assert_frame_equal(threads, serial, check_exact=True)
                pd.testing.assert_frame_equal(dist, serial, check_exact=True)

    med = statistics.median
    print(f"{a.trials} trials x {a.duration:.0f} s walking at 100 Hz, method {a.method}, {os.cpu_count()} CPUs")
    print("metrics: identical (exact) for the three ways")
    print(f"load average at the end: {os.getloadavg()}")
    print(f"medians of {a.repeats} alternating runs; CPU = all processes (client, scheduler, workers)")
    print(f"{'way':36}{'wall':>8}  {'vs serial':>9}  {'CPU':>7}")
    names = {"serial": "serial loop", "threads": "cohort.run, local threads", "cluster": "cohort.run, LocalCluster 2 workers"}
    for k, label in names.items():
        print(f"{label:36}{med(times[k]):8.2f} s {med(times['serial']) / med(times[k]):8.2f}x  {med(cpus[k]):6.2f} s"
              f"   (walls: {', '.join(f'{t:.2f}' for t in times[k])})")

if __name__ == "__main__":
    main()
