#!/usr/bin/python3
"""Open3D's ball-pivoting surface reconstruction on a point cloud with
normals, timed, with the edge statistics of its mesh: the comparison figure
for icrkit's own reconstruction.

Benchmark only, not a project dependency: needs Debian's python3-open3d for
/usr/bin/python3 (the python3 first on PATH may lack it). Open3D 0.16's
ball pivoting uses one thread (CPU time = wall time, whatever
OMP_NUM_THREADS), so compare it with a one-thread icrkit run.

  bench/open3d_ball_pivoting.py cloud.ply --radii 0.002,0.004 [--repeat 3]

Checked by hand on exact inputs: the 642 vertices of a level-3 icosphere
with radial normals give back its 1280 triangles, closed (0 boundary
edges); a jittered 20 x 20 grid gives 722 triangles, 76 boundary edges in 1
loop; two such grids apart give 2 loops.

Prints one JSON object on stdout:
  points              points read
  triangles           triangles made
  used_points         distinct input points that some triangle uses
  boundary_edges      undirected edges used by exactly one triangle
  non_manifold_edges  undirected edges used by three or more triangles
  boundary_loops      connected components of the boundary edges (two holes
                      that touch at a vertex count as one)
  time_s              best of --repeat runs of the reconstruction alone
                      (file loading and the statistics excluded)
  open3d_version
Edges are counted as icrkit's edgeStatistics does: a triangle with a
repeated vertex contributes no edge between the two equal corners.
"""

import argparse
import contextlib
import json
import os
import sys
import time

import numpy as np
import open3d as o3d


@contextlib.contextmanager
def stdout_to_stderr():
    """Open3D's C++ logger writes to file descriptor 1; while it runs, that
    descriptor points at stderr so stdout carries the JSON object alone."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        os.dup2(2, 1)
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)


def parse_radii(text):
    try:
        radii = [float(r) for r in text.split(",") if r.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError("expected comma-separated numbers, got %r" % text)
    if not radii or any(not np.isfinite(r) or r <= 0 for r in radii):
        raise argparse.ArgumentTypeError("expected positive radii, got %r" % text)
    return radii


def input_indices(mesh_vertices, points):
    """Input-point index of each mesh vertex. Open3D 0.16's ball pivoting
    copies the input points (and normals), in order, as the mesh vertices,
    so this is the identity; that is checked rather than assumed, and an
    output that differs is mapped back by exact coordinates."""
    if mesh_vertices.shape == points.shape and np.array_equal(mesh_vertices, points):
        return np.arange(len(points))
    lookup = {}
    for i, p in enumerate(map(tuple, points)):
        lookup.setdefault(p, i)  # the first of duplicate input points
    try:
        return np.array([lookup[tuple(v)] for v in mesh_vertices], dtype=np.int64)
    except KeyError:
        sys.exit("open3d_ball_pivoting: a mesh vertex is not one of the input points")


def count_components(edges, vertex_count):
    """Connected components of the graph of `edges` (E x 2), counting only
    vertices that some edge touches: union-find with path halving."""
    parent = list(range(vertex_count))

    def root(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for a, b in edges.tolist():
        ra, rb = root(a), root(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    touched = np.unique(edges)
    return len({root(v) for v in touched.tolist()})


def edge_statistics(triangles, vertex_count):
    """Boundary edges, non-manifold edges and boundary loops of a triangle
    list (T x 3 vertex indices)."""
    edges = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    edges = edges[edges[:, 0] != edges[:, 1]]
    edges.sort(axis=1)  # undirected: (min, max)
    if len(edges) == 0:
        return 0, 0, 0
    unique, uses = np.unique(edges, axis=0, return_counts=True)
    boundary = unique[uses == 1]
    return len(boundary), int(np.count_nonzero(uses >= 3)), count_components(boundary, vertex_count)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("cloud", help="PLY point cloud with normals")
    parser.add_argument("--radii", type=parse_radii, required=True, help="ball radii in metres, e.g. 0.002,0.004")
    parser.add_argument("--repeat", type=int, default=1, help="runs to time; the best counts (default 1)")
    args = parser.parse_args()
    if args.repeat < 1:
        parser.error("--repeat must be at least 1")
    if not os.path.isfile(args.cloud):
        parser.error("no such file: %s" % args.cloud)

    with stdout_to_stderr():
        pcd = o3d.io.read_point_cloud(args.cloud)
        points = np.asarray(pcd.points)
        if len(points) == 0:
            sys.exit("open3d_ball_pivoting: no points read from %s" % args.cloud)
        if not pcd.has_normals():
            sys.exit("open3d_ball_pivoting: %s has no normals, which ball pivoting needs" % args.cloud)
        radii = o3d.utility.DoubleVector(args.radii)
        best = float("inf")
        for _ in range(args.repeat):
            start = time.perf_counter()
            mesh = o3d.geometry.TriangleMesh.create_from_point_cloud_ball_pivoting(pcd, radii)
            best = min(best, time.perf_counter() - start)

    triangles = np.asarray(mesh.triangles, dtype=np.int64).reshape(-1, 3)
    to_input = input_indices(np.asarray(mesh.vertices), points)
    triangles = to_input[triangles] if len(triangles) else triangles
    boundary_edges, non_manifold_edges, boundary_loops = edge_statistics(triangles, len(points))
    print(json.dumps({
        "points": len(points),
        "triangles": len(triangles),
        "used_points": int(len(np.unique(triangles))),
        "boundary_edges": boundary_edges,
        "non_manifold_edges": non_manifold_edges,
        "boundary_loops": boundary_loops,
        "time_s": best,
        "open3d_version": o3d.__version__,
    }))


if __name__ == "__main__":
    main()
