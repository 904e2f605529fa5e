#!/usr/bin/python3
"""Independent Contact Regions on a mesh, plotted with matplotlib.

    icr_on_a_mesh.py [MESH] [-o regions.png]

Samples one 4-finger force-closure grasp (seeded), grows its regions, prints
them and plots the mesh vertices grey, each region in its colour and each
recommended contact as a black star. Without MESH it uses a UV sphere."""

import argparse

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt
import numpy as np

import icrkit


def ellipsoid(n=30, axes=(0.06, 0.045, 0.035)):
    theta, phi = np.meshgrid(np.linspace(0, np.pi, n + 1)[1:-1], np.linspace(0, 2 * np.pi, 2 * n, endpoint=False), indexing="ij")
    ring = np.column_stack([np.sin(theta).ravel() * np.cos(phi).ravel(), np.sin(theta).ravel() * np.sin(phi).ravel(), np.cos(theta).ravel()])
    unit = np.vstack([[0, 0, 1], ring, [0, 0, -1]])
    v = unit * np.array(axes)
    normals = unit / np.array(axes)  # the gradient of x^2/a^2 + y^2/b^2 + z^2/c^2
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    idx = lambda i, j: 1 + i * 2 * n + (j % (2 * n))
    f = [(0, idx(0, j), idx(0, j + 1)) for j in range(2 * n)]
    for i in range(n - 2):
        for j in range(2 * n):
            f += [(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)), (idx(i, j), idx(i + 1, j + 1), idx(i, j + 1))]
    f += [(idx(n - 2, j), len(v) - 1, idx(n - 2, j + 1)) for j in range(2 * n)]
    return icrkit.TriangleMesh(v, np.array(f, dtype=np.int32), normals)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh", nargs="?", help="mesh with vertex normals (.ply, .obj)")
    parser.add_argument("-o", "--output", default="regions.png")
    args = parser.parse_args()
    mesh = icrkit.read_mesh(args.mesh) if args.mesh else ellipsoid()
    grasp = icrkit.sample_grasps(mesh, fingers=4, count=1, seed=1, min_epsilon=0.05)[0]
    result = icrkit.independent_contact_regions(mesh, grasp["contacts"], alpha=0.5)
    print(f"epsilon {result['epsilon']:.4f}, TWS radius {result['tws_radius']:.4f}")
    v = mesh.vertices
    fig = plt.figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="3d")
    ax.scatter(v[:, 0], v[:, 1], v[:, 2], s=1, c="0.8")
    for region in result["regions"]:
        r = region["vertices"]
        print(f"finger {region['finger']}: {len(r)} vertices, {region['area_m2'] * 1e4:.2f} cm^2, "
              f"aim at vertex {region['recommended']['vertex']} ({region['recommended']['depth_m'] * 1e3:.1f} mm deep)")
        ax.scatter(v[r, 0], v[r, 1], v[r, 2], s=6)
        aim = region["recommended"]["vertex"]
        if aim >= 0:
            ax.scatter(*v[aim], s=80, c="k", marker="*")
    ax.set_box_aspect(np.ptp(v, axis=0))
    fig.savefig(args.output, dpi=100)
    print("wrote", args.output)


if __name__ == "__main__":
    main()
