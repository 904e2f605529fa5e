#!/usr/bin/python3
"""What the Python package adds to a 1M-point smoothing (issue 21: <= 5 %).

    PYTHONPATH=build/python /usr/bin/python3 bench/python_smoothing_overhead.py build [repeats]

Runs bench_smoothing's BM_SmoothPointCloud/viewpoint:0 (C++, the cloud
copied outside the timing) and icrkit.smooth on the same cloud (the same
Fibonacci sphere and radial noise, rebuilt here; the radius as the C++
fixture computes it, read from its counters) in one run, alternating, and
prints the medians and their ratio. Both use two threads."""

import json
import os
import statistics
import subprocess
import sys
import time

import numpy as np

import icrkit

K_POINTS = 1_000_000
K_RADIUS = 0.1


def mix(x):
    m = np.uint64(0xFFFFFFFFFFFFFFFF)
    x = (x + np.uint64(0x9E3779B97F4A7C15)) & m
    x = ((x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)) & m
    x = ((x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)) & m
    return x ^ (x >> np.uint64(31))


def noisy_sphere():
    i = np.arange(K_POINTS, dtype=np.uint64)
    golden = np.pi * (3.0 - np.sqrt(5.0))
    spacing = np.sqrt(4.0 * np.pi / K_POINTS) * K_RADIUS
    z = 1.0 - (2.0 * i.astype(np.float64) + 1.0) / K_POINTS
    ring = np.sqrt(1.0 - z * z)
    phi = golden * i.astype(np.float64)
    with np.errstate(over="ignore"):
        unit = (mix(i) >> np.uint64(11)).astype(np.float64) * 2.0 ** -53 * 2.0 - 1.0
    r = K_RADIUS + 0.2 * spacing * unit
    return np.ascontiguousarray(np.column_stack([r * ring * np.cos(phi), r * ring * np.sin(phi), r * z]))


def cpp_run(build):
    out = subprocess.run([os.path.join(build, "bench", "bench_smoothing"), "--benchmark_filter=BM_SmoothPointCloud/viewpoint:0/",
                          "--benchmark_repetitions=1", "--benchmark_format=json"], check=True, capture_output=True, text=True)
    b = json.loads(out.stdout)["benchmarks"][0]
    return b["real_time"] / 1e3, b["radius_mm"] / 1e3  # seconds, metres


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    points = noisy_sphere()
    os.environ.setdefault("TBB_NUM_THREADS", "2")
    cpp, py = [], []
    radius = None
    for _ in range(repeats):
        seconds, radius = cpp_run(build)
        cpp.append(seconds)
        start = time.perf_counter()
        smoothed = icrkit.smooth(points, radius=radius, preselection="default")
        py.append(time.perf_counter() - start)
        assert len(smoothed) == K_POINTS
    c, p = statistics.median(cpp), statistics.median(py)
    print(f"1M points, r = {radius * 1e3:.3f} mm: C++ {c:.3f} s, Python {p:.3f} s, ratio {p / c:.3f} "
          f"(runs: C++ {[round(x, 3) for x in cpp]}, Python {[round(x, 3) for x in py]})")


if __name__ == "__main__":
    main()
