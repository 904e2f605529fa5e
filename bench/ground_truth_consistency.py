#!/usr/bin/python3
"""How far a recording's ground-truth poses can be trusted, measured by
Open3D alone (independent of icrkit's registration).

  bench/ground_truth_consistency.py VIEWS_DIR GROUND_TRUTH.txt [--partners 4]

VIEWS_DIR is what `icrkit reconstruct --write-registration-input` writes
(view_NNN.ply in each sensor's frame). Every view is registered to its next
`--partners` views (cyclically) by Open3D's point-to-plane ICP with a Tukey
kernel, started FROM THE GROUND TRUTH's own relative pose, at 6, 3 and
1.5 mm pairing distances. Two figures come out:

- how far the pairs move from the ground truth's relative poses (median
  rotation, degrees): what the data says against the ground truth;
- how well the pairs agree among themselves: the rotation left when three
  pairs are chained round a triangle of views (median, degrees).

Pairs that close their triangles to a small angle, yet all sit further
from the ground truth than that, mean the ground truth's relative poses
carry that much error: no pose error measured against it goes below it.
Prints one JSON object. Benchmark only: Debian python3-open3d.
"""
import argparse
import glob
import itertools
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from registration_measures import angle_of, read_tum  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("views")
    parser.add_argument("ground_truth")
    parser.add_argument("--partners", type=int, default=4)
    args = parser.parse_args()
    import open3d as o3d

    files = sorted(glob.glob(os.path.join(args.views, "view_*.ply")))
    truth = read_tum(args.ground_truth)
    if len(files) != len(truth) or len(files) < 3:
        sys.exit(f"{args.views}: {len(files)} views but {len(truth)} ground-truth poses (need the same, >= 3)")
    clouds = []
    for f in files:
        c = o3d.io.read_point_cloud(f)
        c.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=0.006, max_nn=30))
        clouds.append(c)
    n = len(clouds)
    icp = o3d.pipelines.registration
    measured = {}
    for i in range(n):
        for step in range(1, args.partners + 1):
            j = (i + step) % n
            a, b = min(i, j), max(i, j)
            if (a, b) in measured:
                continue
            start = np.linalg.inv(truth[a]) @ truth[b]
            pose = start
            for d in (0.006, 0.003, 0.0015):
                r = icp.registration_icp(clouds[b], clouds[a], d, pose,
                                         icp.TransformationEstimationPointToPlane(icp.TukeyLoss(k=d)),
                                         icp.ICPConvergenceCriteria(max_iteration=60))
                pose = r.transformation
            if r.fitness >= 0.15:
                measured[(a, b)] = pose

    def relative(a, b):
        return measured[(a, b)] if (a, b) in measured else None

    moved = [angle_of((np.linalg.inv(np.linalg.inv(truth[a]) @ truth[b]) @ m)[:3, :3]) for (a, b), m in measured.items()]
    cycles = []
    for a, b, c in itertools.combinations(range(n), 3):
        ab, bc, ac = relative(a, b), relative(b, c), relative(a, c)
        if ab is None or bc is None or ac is None:
            continue
        cycles.append(angle_of((ab @ bc @ np.linalg.inv(ac))[:3, :3]))
    print(json.dumps({
        "views": n,
        "pairs": len(measured),
        "pairs_from_ground_truth_median_deg": float(np.median(moved)),
        "pairs_from_ground_truth_max_deg": float(np.max(moved)),
        "triangles": len(cycles),
        "triangle_closure_median_deg": float(np.median(cycles)) if cycles else None,
        "open3d_version": o3d.__version__,
    }, indent=1))


if __name__ == "__main__":
    main()
