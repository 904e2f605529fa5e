#!/usr/bin/python3
"""The error measures of docs/reconstruction.md for real recordings, shared
by the registration benchmarks so that icrkit and Open3D are judged alike.

  bench/registration_measures.py poses EST.txt TRUTH.txt --object-point x,y,z
  bench/registration_measures.py surface CLOUD_OR_MESH.ply REFERENCE.ply [--no-fit]

`poses`: per view, the displacement of the object point and the rotation
angle, as estimated and after the best rigid fit of the camera centres to
the true ones (Umeyama without scale; the same as icrkit's
trajectoryError), medians and maxima, in mm and degrees.

`surface`: mean and median distance of the points (a mesh's vertices that
some face uses) to the reference surface, as they are and after a rigid
best fit to it (point-to-plane ICP with a Tukey kernel and a shrinking
pairing distance, 10 -> 2 mm, from the identity: the clouds are already in
the reference frame to a few mm).

Benchmark only (Debian python3-open3d, /usr/bin/python3). Prints JSON.
"""
import argparse
import json
import sys

import numpy as np


def quaternion_to_matrix(q):
    """The rotation of a quaternion (x, y, z, w), normalised first."""
    x, y, z, w = np.array(q, dtype=float) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def read_tum(path):
    poses = []
    for line in open(path):
        f = line.split()
        if not f or f[0].startswith("#"):
            continue
        m = np.eye(4)
        m[:3, :3], m[:3, 3] = quaternion_to_matrix(list(map(float, f[4:8]))), list(map(float, f[1:4]))
        poses.append(m)
    return poses


def matrix_to_quat(r):
    """(x, y, z, w) of a rotation matrix, normalised (Shepperd's method)."""
    t = np.trace(r)
    if t > 0:
        s = 2 * np.sqrt(1 + t)
        q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2 * np.sqrt(1 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0, 0.0, 0.0, (r[k, j] - r[j, k]) / s]
        q[i], q[j], q[k] = s / 4, (r[j, i] + r[i, j]) / s, (r[k, i] + r[i, k]) / s
    return np.array(q) / np.linalg.norm(q)


def write_tum(path, stamps, poses):
    """TUM lines `stamp tx ty tz qx qy qz qw` (4 x 4 pose matrices)."""
    with open(path, "w") as out:
        for stamp, p in zip(stamps, poses):
            q = matrix_to_quat(p[:3, :3])
            out.write(f"{stamp} {p[0, 3]:.9f} {p[1, 3]:.9f} {p[2, 3]:.9f} {q[0]:.9f} {q[1]:.9f} {q[2]:.9f} {q[3]:.9f}\n")


def umeyama_rigid(src, dst):
    """The rotation and translation taking src (N x 3) onto dst, no scale."""
    cs, cd = src.mean(0), dst.mean(0)
    u, _, vt = np.linalg.svd((dst - cd).T @ (src - cs))
    d = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))])
    r = u @ d @ vt
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = r, cd - r @ cs
    return m


def angle_of(r):
    return float(np.degrees(np.arccos(np.clip((np.trace(r) - 1) / 2, -1.0, 1.0))))


def series(est, truth, alignment, point):
    obj, rot = [], []
    p = np.append(point, 1.0)
    for e, t in zip(est, truth):
        a = alignment @ e
        moved = a @ np.linalg.inv(t)
        obj.append(float(np.linalg.norm((moved @ p)[:3] - point)) * 1e3)
        rot.append(angle_of(t[:3, :3].T @ a[:3, :3]))
    return {"object_translation_mm": obj, "rotation_deg": rot,
            "median_object_translation_mm": float(np.median(obj)), "max_object_translation_mm": float(np.max(obj)),
            "median_rotation_deg": float(np.median(rot)), "max_rotation_deg": float(np.max(rot))}


def pose_errors(est, truth, point):
    if len(est) != len(truth):
        raise SystemExit(f"{len(est)} estimated poses but {len(truth)} true ones")
    alignment = umeyama_rigid(np.array([e[:3, 3] for e in est]), np.array([t[:3, 3] for t in truth]))
    return {"raw": series(est, truth, np.eye(4), point), "aligned": series(est, truth, alignment, point)}


def fit_to_surface(scene, points):
    """The rigid motion (4 x 4) fitting `points` to the surface of an Open3D
    RaycastingScene: point-to-plane ICP with a Tukey kernel and a shrinking
    pairing distance, 10 -> 2 mm, from the identity."""
    import open3d as o3d
    m = np.eye(4)
    for limit in (0.010, 0.006, 0.004, 0.003, 0.002, 0.002, 0.002, 0.002):
        p = (m[:3, :3] @ points.T).T + m[:3, 3]
        closest = scene.compute_closest_points(o3d.core.Tensor(p.astype(np.float32)))
        q = closest["points"].numpy().astype(float)
        n = closest["primitive_normals"].numpy().astype(float)
        r = ((p - q) * n).sum(1)
        gap = np.linalg.norm(p - q, axis=1)
        w = np.where(gap < limit, (1 - (r / limit) ** 2) ** 2, 0.0)
        j = np.hstack([n, np.cross(p, n)])
        h = (j * w[:, None]).T @ j + 1e-12 * np.eye(6)
        x = -np.linalg.solve(h, (j * (w * r)[:, None]).sum(0))
        angle = np.linalg.norm(x[3:])
        k = x[3:] / angle if angle > 0 else np.zeros(3)
        kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        step = np.eye(4)
        step[:3, :3] = np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx
        step[:3, 3] = x[:3]
        m = step @ m
    return m


def surface_errors(points, reference_path, fit=True):
    import open3d as o3d
    mesh = o3d.io.read_triangle_mesh(reference_path)
    mesh.remove_unreferenced_vertices()
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(mesh))

    def distances(p):
        return scene.compute_distance(o3d.core.Tensor(p.astype(np.float32))).numpy().astype(float)

    out = {"points": int(len(points))}
    d = distances(points)
    out["mean_mm"], out["median_mm"] = float(d.mean() * 1e3), float(np.median(d) * 1e3)
    if fit:
        m = fit_to_surface(scene, points)
        p = (m[:3, :3] @ points.T).T + m[:3, 3]
        d = distances(p)
        out["fitted_mean_mm"], out["fitted_median_mm"] = float(d.mean() * 1e3), float(np.median(d) * 1e3)
        out["fit_translation_mm"] = float(np.linalg.norm(m[:3, 3]) * 1e3)
        out["fit_rotation_deg"] = angle_of(m[:3, :3])
    return out


def read_points(path):
    import open3d as o3d
    mesh = o3d.io.read_triangle_mesh(path)
    if len(mesh.triangles) > 0:
        used = np.unique(np.asarray(mesh.triangles).reshape(-1))
        return np.asarray(mesh.vertices)[used]
    return np.asarray(o3d.io.read_point_cloud(path).points)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="what", required=True)
    p = sub.add_parser("poses")
    p.add_argument("estimated")
    p.add_argument("truth")
    p.add_argument("--object-point", required=True)
    s = sub.add_parser("surface")
    s.add_argument("points")
    s.add_argument("reference")
    s.add_argument("--no-fit", action="store_true")
    a = ap.parse_args()
    if a.what == "poses":
        point = np.array(list(map(float, a.object_point.split(","))))
        json.dump(pose_errors(read_tum(a.estimated), read_tum(a.truth), point), sys.stdout)
    else:
        json.dump(surface_errors(read_points(a.points), a.reference, not a.no_fit), sys.stdout)
    print()


if __name__ == "__main__":
    main()
