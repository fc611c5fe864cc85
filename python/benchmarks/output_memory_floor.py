"""The memory floor of an estimate's output: the CPU time of writing
`--columns` float64 columns of a `--duration` s, 100 Hz trial into fresh
memory (numpy `empty` + one `fill`, the kernel zeroing each page first) and
into memory already mapped (a second `fill`), per sample; the median of
`--repeats`. Whatever the package does, `limbfuse.estimate` hands back
that much fresh memory (mjls: 46 columns).

    python python/benchmarks/output_memory_floor.py [--duration 3600] [--columns 46] [--repeats 5]
"""

import argparse
import os
import statistics
import time

import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--duration", type=float, default=3600.0, help="trial length (s), 100 Hz")
    ap.add_argument("--columns", type=int, default=46)
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args()
    n = int(round(a.duration * 100))
    fresh, mapped = [], []
    for _ in range(max(1, a.repeats)):
        c0 = time.process_time()
        block = np.empty((a.columns, n))
        block.fill(1.0)
        c1 = time.process_time()
        block.fill(2.0)
        c2 = time.process_time()
        fresh.append(c1 - c0)
        mapped.append(c2 - c1)
        del block
    mb = a.columns * n * 8 / 1e6
    print(f"{a.columns} columns x {n} samples = {mb:.0f} MB, load average {os.getloadavg()[0]:.1f}")
    for name, v in (("fresh memory", fresh), ("mapped memory", mapped)):
        m = statistics.median(v)
        print(f"{name}: median {m * 1e3:.1f} ms CPU = {m / n * 1e6:.3f} us per sample ({mb / 1e3 / m:.1f} GB/s)")


if __name__ == "__main__":
    main()
