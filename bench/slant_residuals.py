#!/usr/bin/python3
"""Signed residuals of depth views against their reference surface, by the
angle at which the camera saw the surface: the slant behaviour that the
joint refinement's face-on targets answer (docs/reconstruction.md,
"Stop 55").

  bench/slant_residuals.py PREP_DIR [--poses truth.txt]

PREP_DIR: a dataset prepared by bench/registration_sweep.py
(WORK/prep/NAME: view_NNN.ply, each view's object points in its sensor
frame; truth.txt and, for the real recording, refined.txt; `reference`
naming the reference mesh). Each view's points are placed by the poses and
matched to the nearest of 1.5 M points sampled on the reference (within 4
mm); the residual is along that point's normal turned towards the camera,
positive behind the surface, the incidence the angle between that normal
and the camera's ray. Prints a Markdown table per 10 deg of incidence:
count, mean, median, standard deviation (mm).
Benchmark only (Debian python3-open3d, python3-scipy; the system
interpreter).
"""
import argparse
import glob
import os
import sys

import numpy as np
import open3d as o3d
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from registration_measures import read_tum  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("prep")
    ap.add_argument("--poses", default="truth.txt")
    a = ap.parse_args()
    reference = open(os.path.join(a.prep, "reference")).read().strip()
    mesh = o3d.io.read_triangle_mesh(reference)
    mesh.compute_triangle_normals()
    samples = mesh.sample_points_uniformly(1500000, use_triangle_normal=True)
    surface, normals = np.asarray(samples.points), np.asarray(samples.normals)
    tree = cKDTree(surface)
    poses = read_tum(os.path.join(a.prep, a.poses))
    views = sorted(glob.glob(os.path.join(a.prep, "view_*.ply")))
    if len(views) != len(poses):
        raise SystemExit(f"{a.prep}: {len(views)} views but {len(poses)} poses in {a.poses}")
    edges = np.arange(0, 90, 10)
    residuals = [[] for _ in edges]
    for path, pose in zip(views, poses):
        local = np.asarray(o3d.io.read_point_cloud(path).points)
        if len(local) == 0:
            continue
        points = local @ pose[:3, :3].T + pose[:3, 3]
        distance, nearest = tree.query(points)
        near = distance < 0.004
        p, q, n = points[near], surface[nearest[near]], normals[nearest[near]]
        ray = p - pose[:3, 3]
        ray /= np.linalg.norm(ray, axis=1)[:, None]
        n = n * np.sign(-(n * ray).sum(1))[:, None]
        incidence = np.degrees(np.arccos(np.clip(-(n * ray).sum(1), 0, 1)))
        behind = -((p - q) * n).sum(1) * 1e3
        for i, low in enumerate(edges):
            residuals[i].extend(behind[(incidence >= low) & (incidence < low + 10)])
    print("| incidence | points | mean mm | median mm | sd mm |\n|---|---:|---:|---:|---:|")
    for low, r in zip(edges, residuals):
        if r:
            r = np.asarray(r)
            print(f"| {low}-{low + 10} deg | {len(r)} | {r.mean():+.3f} | {np.median(r):+.3f} | {r.std():.3f} |")


if __name__ == "__main__":
    main()
