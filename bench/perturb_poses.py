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

import numpy as np


def quat_to_matrix(q):
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def matrix_to_quat(r):
    # Shepperd's method: stable for every rotation.
    t = np.trace(r)
    if t > 0:
        s = 2 * np.sqrt(1 + t)
        q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2 * np.sqrt(1 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0, 0.0, 0.0, (r[k, j] - r[j, k]) / s]
        q[i] = s / 4
        q[j] = (r[j, i] + r[i, j]) / s
        q[k] = (r[k, i] + r[i, k]) / s
    q = np.array(q)
    return q / np.linalg.norm(q)


def rotation_vector_to_matrix(w):
    angle = np.linalg.norm(w)
    if angle == 0:
        return np.eye(3)
    k = w / angle
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("ground_truth")
    ap.add_argument("output")
    ap.add_argument("--sigma-translation", type=float, default=0.005, help="metres per axis")
    ap.add_argument("--sigma-rotation-deg", type=float, default=1.0, help="degrees per axis")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    lines = []
    for line in open(a.ground_truth):
        f = line.split()
        if not f or f[0].startswith("#"):
            continue
        t = np.array(list(map(float, f[1:4])))
        r = quat_to_matrix(np.array(list(map(float, f[4:8]))))
        v = rng.normal(0.0, a.sigma_translation, 3)
        w = rng.normal(0.0, np.radians(a.sigma_rotation_deg), 3)
        r2 = r @ rotation_vector_to_matrix(w)
        t2 = t + r @ v
        q = matrix_to_quat(r2)
        lines.append(f"{f[0]} {t2[0]:.9f} {t2[1]:.9f} {t2[2]:.9f} {q[0]:.9f} {q[1]:.9f} {q[2]:.9f} {q[3]:.9f}")
    with open(a.output, "w") as out:
        out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
