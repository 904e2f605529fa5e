#!/usr/bin/python3
"""Uniform random points on a triangle mesh with interpolated vertex normals,
written as a binary PLY point cloud: the large input of the ball pivoting
benchmark (bench/ball_pivoting_vs_open3d.sh). Triangles are drawn with
probability proportional to their area and points uniformly inside them
(numpy's PCG64 with an explicit seed, so the cloud is the same on every run).

Benchmark only: needs Debian's python3-open3d and python3-numpy for
/usr/bin/python3.

  bench/sample_mesh_cloud.py MESH.ply OUT.ply --points 1000000 --seed 1
"""

import argparse

import numpy as np
import open3d as o3d


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mesh")
    parser.add_argument("output")
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()

    mesh = o3d.io.read_triangle_mesh(args.mesh)
    mesh.compute_vertex_normals()
    vertices = np.asarray(mesh.vertices)
    normals = np.asarray(mesh.vertex_normals)
    triangles = np.asarray(mesh.triangles)
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)

    rng = np.random.default_rng(args.seed)
    chosen = rng.choice(len(triangles), size=args.points, p=area / area.sum())
    u, v = rng.random(args.points), rng.random(args.points)
    flip = u + v > 1.0  # fold the square onto the triangle
    u[flip], v[flip] = 1.0 - u[flip], 1.0 - v[flip]
    w = 1.0 - u - v
    t = triangles[chosen]
    points = w[:, None] * vertices[t[:, 0]] + u[:, None] * vertices[t[:, 1]] + v[:, None] * vertices[t[:, 2]]
    point_normals = w[:, None] * normals[t[:, 0]] + u[:, None] * normals[t[:, 1]] + v[:, None] * normals[t[:, 2]]
    point_normals /= np.linalg.norm(point_normals, axis=1, keepdims=True)

    cloud = o3d.geometry.PointCloud()
    cloud.points = o3d.utility.Vector3dVector(points)
    cloud.normals = o3d.utility.Vector3dVector(point_normals)
    if not o3d.io.write_point_cloud(args.output, cloud, write_ascii=False):
        raise SystemExit(f"cannot write {args.output}")


if __name__ == "__main__":
    main()
