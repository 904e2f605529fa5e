#!/usr/bin/python3
"""Open3D's multiway registration on the views icrkit registered: the
comparison figure for icrkit's registration stage (docs/performance.md).

  bench/open3d_multiway.py VIEWS_DIR -o POSES.txt [--voxel 0.002] [--partners 3]

VIEWS_DIR is what `icrkit reconstruct --write-registration-input` writes:
view_NNN.ply (each scan's object points in its sensor frame) and start.txt
(the starting poses, TUM, sensor -> object). The recipe is Open3D's own
multiway-registration tutorial, started from the reported poses instead of
odometry: views reduced to `--voxel` cubes, normals from a hybrid search
(radius 2.5 voxels, 30 neighbours), each view registered to its next
`--partners` views by point-to-plane ICP (a coarse pass at 15 voxels, a
fine one at 1.5 voxels, from the relative reported pose), information
from the fine correspondences, consecutive views as odometry edges, the
others as uncertain loop closures, the graph solved by Levenberg-Marquardt
(global optimisation with line-process pruning, reference node 0), then
every pose moved so that the mean of the result fits the starting poses
(the same gauge as icrkit's reported-pose priors).

Benchmark only: Debian python3-open3d for /usr/bin/python3. Prints one JSON
object: views, pairs, time_s (registration only: reduction, normals,
pairs and graph; file loading excluded), open3d_version, threads.
"""
import argparse
import glob
import json
import os
import sys
import time

import numpy as np
import open3d as o3d

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from registration_measures import read_tum, umeyama_rigid, write_tum  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("views")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--voxel", type=float, default=0.002)
    ap.add_argument("--partners", type=int, default=3)
    a = ap.parse_args()
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)
    files = sorted(glob.glob(os.path.join(a.views, "view_*.ply")))
    starts = read_tum(os.path.join(a.views, "start.txt"))
    stamps = [l.split()[0] for l in open(os.path.join(a.views, "start.txt")) if l.strip() and not l.startswith("#")]
    if len(files) != len(starts):
        raise SystemExit(f"{len(files)} views but {len(starts)} starting poses")
    clouds = [o3d.io.read_point_cloud(f) for f in files]

    t0 = time.perf_counter()
    reduced = []
    for c in clouds:
        d = c.voxel_down_sample(a.voxel)
        d.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=2.5 * a.voxel, max_nn=30))
        reduced.append(d)
    coarse, fine = 15 * a.voxel, 1.5 * a.voxel
    graph = o3d.pipelines.registration.PoseGraph()
    for s in starts:
        graph.nodes.append(o3d.pipelines.registration.PoseGraphNode(s))
    pairs = 0
    n = len(reduced)
    for i in range(n):
        for j in range(i + 1, min(n, i + 1 + a.partners)):
            guess = np.linalg.inv(starts[i]) @ starts[j]  # pose of j in i's frame
            p2l = o3d.pipelines.registration.TransformationEstimationPointToPlane()
            r1 = o3d.pipelines.registration.registration_icp(reduced[j], reduced[i], coarse, guess, p2l)
            r2 = o3d.pipelines.registration.registration_icp(reduced[j], reduced[i], fine, r1.transformation, p2l)
            info = o3d.pipelines.registration.get_information_matrix_from_point_clouds(
                reduced[j], reduced[i], fine, r2.transformation)
            # Open3D's edge (source, target) holds T with target = T source, in
            # its node-pose convention T_node maps node -> world.
            graph.edges.append(o3d.pipelines.registration.PoseGraphEdge(
                j, i, r2.transformation, info, uncertain=(j != i + 1)))
            pairs += 1
    option = o3d.pipelines.registration.GlobalOptimizationOption(
        max_correspondence_distance=fine, edge_prune_threshold=0.25, reference_node=0)
    o3d.pipelines.registration.global_optimization(
        graph, o3d.pipelines.registration.GlobalOptimizationLevenbergMarquardt(),
        o3d.pipelines.registration.GlobalOptimizationConvergenceCriteria(), option)
    poses = [np.array(node.pose) for node in graph.nodes]
    # Open3D holds node 0; move the whole result onto the starting poses'
    # least-squares frame (camera centres), as icrkit's priors place it.
    fit = umeyama_rigid(np.array([p[:3, 3] for p in poses]), np.array([s[:3, 3] for s in starts]))
    poses = [fit @ p for p in poses]
    elapsed = time.perf_counter() - t0

    write_tum(a.output, stamps, poses)
    json.dump({"views": n, "pairs": pairs, "time_s": elapsed, "open3d_version": o3d.__version__,
               "threads": os.cpu_count()}, sys.stdout)
    print()


if __name__ == "__main__":
    main()
