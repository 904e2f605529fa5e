#!/usr/bin/python3
"""Seeded per-view pose errors on a TUM trajectory: the mobile-manipulator
error class of docs/reconstruction.md, made on a recording's ground truth.

  bench/perturb_poses.py GROUND_TRUTH.txt OUT.txt --sigma-translation 0.005 --sigma-rotation-deg 1 --seed 1

Each pose T (sensor -> object) becomes T * [Exp(w), v] with v and w drawn
independently per view and per axis from N(0, sigma^2) (metres, radians),
in the sensor's own frame, as a robot's camera-pose error is. Quaternions
are written normalised with 9 decimals.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from registration_measures import read_tum, write_tum  # noqa: E402


def rotation_vector_to_matrix(w):
    angle = np.linalg.norm(w)
    if angle == 0:
        return np.eye(3)
    k = w / angle
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def perturb(poses, sigma_translation, sigma_rotation_deg, seed):
    """Each pose T times [Exp(w), v], v and w drawn per view and axis (metres, degrees)."""
    rng = np.random.default_rng(seed)
    out = []
    for pose in poses:
        v = rng.normal(0.0, sigma_translation, 3)
        w = rng.normal(0.0, np.radians(sigma_rotation_deg), 3)
        step = np.eye(4)
        step[:3, :3], step[:3, 3] = rotation_vector_to_matrix(w), v
        out.append(pose @ step)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("ground_truth")
    ap.add_argument("output")
    ap.add_argument("--sigma-translation", type=float, default=0.005, help="metres per axis")
    ap.add_argument("--sigma-rotation-deg", type=float, default=1.0, help="degrees per axis")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    stamps = [l.split()[0] for l in open(a.ground_truth) if l.split() and not l.startswith("#")]
    write_tum(a.output, stamps, perturb(read_tum(a.ground_truth), a.sigma_translation, a.sigma_rotation_deg, a.seed))

if __name__ == "__main__":
    main()
