#!/usr/bin/python3
"""Arrays both ways between Open3D and icrkit.

    open3d_interop.py [-o mesh.ply]

Open3D makes a sphere (its vertices, with noise, are the cloud) and estimates
the normals; icrkit smooths the
cloud (3D-NDT layer) and meshes it (ball pivoting); the mesh goes back to
Open3D, which measures it."""

import argparse

import numpy as np
import open3d as o3d

import icrkit


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", default="mesh.ply")
    args = parser.parse_args()
    sphere = o3d.geometry.TriangleMesh.create_sphere(radius=0.05, resolution=60)
    points = np.asarray(sphere.vertices)
    rng = np.random.default_rng(1)
    points = points + 0.0005 * rng.standard_normal(points.shape) * (points / np.linalg.norm(points, axis=1, keepdims=True))
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(16))
    cloud.orient_normals_towards_camera_location(np.zeros(3))
    normals = -np.asarray(cloud.normals)  # outwards

    # Open3D -> icrkit: plain float64 (N, 3) arrays.
    smoothed = icrkit.smooth(np.ascontiguousarray(points), np.ascontiguousarray(normals), preselection="none")
    mesh = icrkit.ball_pivoting(smoothed)
    print(f"icrkit: {len(smoothed)} points smoothed (mean normal_sigma "
          f"{np.degrees(smoothed.attributes['normal_sigma'].mean()):.2f} deg), {len(mesh.faces)} triangles")

    # icrkit -> Open3D: the same arrays (views; Open3D copies them).
    out = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(mesh.vertices), o3d.utility.Vector3iVector(mesh.faces))
    out.vertex_normals = o3d.utility.Vector3dVector(mesh.normals)
    area = out.get_surface_area()
    print(f"Open3D: area {area * 1e4:.1f} cm^2 (sphere {4 * np.pi * 0.05 ** 2 * 1e4:.1f} cm^2), "
          f"edge manifold {out.is_edge_manifold()}")
    icrkit.write_mesh(args.output, mesh)
    print("wrote", args.output)


if __name__ == "__main__":
    main()
