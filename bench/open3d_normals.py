#!/usr/bin/python3
"""Open3D's estimate_normals(KDTreeSearchParamRadius(r)) on the cloud of
bench_smoothing: the comparison figure for the 3D-NDT smoothing layer in
docs/performance.md. Both build a k-d tree and do, per point, a radius query
and a 3x3 covariance with its eigen-decomposition.

Benchmark only, not a project dependency: needs Debian's python3-open3d for
/usr/bin/python3. Run with OMP_NUM_THREADS=2 (Open3D parallelises with
OpenMP) to match bench_smoothing's 2 TBB threads.

  bench_smoothing --write-cloud=/tmp/sphere.ply     # the exact cloud
  OMP_NUM_THREADS=2 bench/open3d_normals.py --cloud /tmp/sphere.ply

Without --cloud the script builds the cloud itself from the same formula
(Fibonacci sphere, splitmix64 radial noise); it then matches the C++ cloud to
the last bit wherever both use the same libm (Debian's glibc here).
"""

import argparse
import math
import os
import statistics
import sys
import time

import numpy as np
import open3d as o3d

POINTS = 1_000_000
SPHERE_RADIUS = 0.1
RADIUS_FACTOR = 4.0
MASK = (1 << 64) - 1


def mix(x):
    """splitmix64, as in bench_smoothing.cpp."""
    x = (x + 0x9E3779B97F4A7C15) & MASK
    x = ((x ^ (x >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    x = ((x ^ (x >> 27)) * 0x94D049BB133111EB) & MASK
    return x ^ (x >> 31)


def noisy_sphere(n=POINTS):
    golden_angle = math.pi * (3.0 - math.sqrt(5.0))
    spacing = math.sqrt(4.0 * math.pi / n) * SPHERE_RADIUS
    out = np.empty((n, 3))
    for i in range(n):
        z = 1.0 - (2.0 * i + 1.0) / n
        ring = math.sqrt(1.0 - z * z)
        phi = golden_angle * i
        unit_noise = (mix(i) >> 11) * 2.0 ** -53 * 2.0 - 1.0
        r = SPHERE_RADIUS + 0.2 * spacing * unit_noise
        out[i] = (r * ring * math.cos(phi), r * ring * math.sin(phi), r * z)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cloud", help="the cloud written by bench_smoothing --write-cloud (default: build it here)")
    parser.add_argument("--radius", type=float, help="window radius in metres (default: 4 x the median spacing)")
    parser.add_argument("--repetitions", type=int, default=5)
    args = parser.parse_args()

    if args.cloud:
        pcd = o3d.io.read_point_cloud(args.cloud)
        points = np.asarray(pcd.points)
    else:
        points = noisy_sphere()
    if len(points) == 0:
        sys.exit("no points read from %s" % args.cloud)

    base = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    median_spacing = float(np.median(np.asarray(base.compute_nearest_neighbor_distance())))
    radius = args.radius if args.radius else RADIUS_FACTOR * median_spacing

    times = []
    for _ in range(args.repetitions):
        cloud = o3d.geometry.PointCloud(base)  # fresh: no normals to orient against
        start = time.perf_counter()
        cloud.estimate_normals(o3d.geometry.KDTreeSearchParamRadius(radius))
        times.append(time.perf_counter() - start)
    median = statistics.median(times)
    print("open3d %s, OMP_NUM_THREADS=%s, %d points, median spacing %.9g m, r = %.9g m"
          % (o3d.__version__, os.environ.get("OMP_NUM_THREADS", "unset"), len(points), median_spacing, radius))
    print("estimate_normals: median %.1f ms of %d (min %.1f, max %.1f) -> %.3g points/s"
          % (median * 1e3, len(times), min(times) * 1e3, max(times) * 1e3, len(points) / median))


if __name__ == "__main__":
    main()
