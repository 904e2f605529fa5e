#!/usr/bin/python3
"""Registration under poor poses, icrkit against Open3D's multiway
registration on identical points: the sweep of docs/reconstruction.md.

  bench/registration_sweep.py BUILD_DIR WORK_DIR [--seeds 20] [--classes 3:0.5,5:1,8:2]
                              [--datasets ps18,ps12,ps9,stanford,sim_paper_cup,sim_toy2] [--sim-seed 41]

Each dataset's views are prepared once (each view's object points in its
sensor frame, as `icrkit reconstruct --write-registration-input` writes
them, made from the true poses so that no seed changes a crop): the shared
PrimeSense recording (its 18 views, and subsets of 12 and 9), the ten
Stanford laser scans (bun.conf) and two simulated recordings by default
(more by name: SIMULATED below, e.g. sim_toy2_kinect, or
sim_toy2_kinect_corr with the Kinect's noise correlated). For every
error class (sigma per axis and view: millimetres : degrees) and seed the
true poses get seeded per-view errors (bench/perturb_poses.py's model, in
the sensor frame), and both tools register the same views from the same
starting poses: `bench_register_views` (icrkit's registration stage with
`icrkit reconstruct`'s parameters) and bench/open3d_multiway.py.

The measure, gauge-free: place each view's points by the pose set, fuse
them (1 mm voxel centroids, the same for both tools), fit the fused cloud
rigidly to the reference surface (bench/registration_measures.py's fit)
and take the mean distance; with the same fit, each view's own mean
distance (the worst view is reported). Pose errors against the truth (and
the refined truth of the real recording) are reported beside, never a gate.

Writes WORK_DIR/runs.jsonl (one line per run and tool, appended; a run
already there is not redone) and prints a Markdown summary.
Benchmark only (Debian python3-open3d and the system interpreter).
"""
import argparse
import shlex
import glob
import json
import os
import shutil
import subprocess
import sys
import zlib

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
from registration_measures import angle_of, fit_to_surface, pose_errors, quaternion_to_matrix, read_tum, write_tum  # noqa: E402
from perturb_poses import perturb  # noqa: E402

data = os.path.abspath(os.path.join(here, "..", "..", "shared", "data"))


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, stdout=subprocess.PIPE, text=True, **kw).stdout


def link_views(source_dir, indices, target_dir, truth, truths_extra=None):
    os.makedirs(target_dir, exist_ok=True)
    for k, i in enumerate(indices):
        dst = os.path.join(target_dir, f"view_{k:03d}.ply")
        if not os.path.exists(dst):
            os.symlink(os.path.abspath(os.path.join(source_dir, f"view_{i:03d}.ply")), dst)
    write_tum(os.path.join(target_dir, "truth.txt"), [f"{k:.6f}" for k in range(len(indices))], [truth[i] for i in indices])
    for name, poses in (truths_extra or {}).items():
        write_tum(os.path.join(target_dir, name), [f"{k:.6f}" for k in range(len(indices))], [poses[i] for i in indices])


# Simulated recordings (36 views): the two of the sweep, and the
# other objects of the nine datasets for checks across object sizes.
SIMULATED = {
    "sim_paper_cup": ("paper_cup", "kinect"), "sim_toy2": ("wooden_toy_2", "sr4000"),
    "sim_cup": ("cup", "kinect"), "sim_bottle": ("bottle", "kinect"), "sim_coffee_pot": ("coffee_pot", "kinect"),
    "sim_toy1": ("wooden_toy_1", "kinect"), "sim_toy2_kinect": ("wooden_toy_2", "kinect"),
    "sim_cup_sr4000": ("cup", "sr4000"), "sim_toy1_sr4000": ("wooden_toy_1", "sr4000"),
    # The Kinect's depth noise shared between neighbouring pixels as the real
    # recording's is (docs/sensors.md, "Correlated depth noise").
    "sim_toy2_kinect_corr": ("wooden_toy_2", "kinect", "--correlated-noise", "0.75,3"),
    "sim_paper_cup_corr": ("paper_cup", "kinect", "--correlated-noise", "0.75,3"),
}


def prepare(name, build, work, sim_seed):
    """WORK/prep/NAME/{view_NNN.ply, truth.txt[, refined.txt], reference}."""
    icrkit = os.path.join(build, "apps", "icrkit", "icrkit")
    out = os.path.join(work, "prep", name)
    if os.path.exists(os.path.join(out, "reference")):
        return out
    tmp = out + ".tmp"
    shutil.rmtree(tmp, ignore_errors=True)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    if name.startswith("ps"):
        bunny = os.path.join(data, "primesense-bunny")
        full = os.path.join(work, "prep", "ps_all")
        if not os.path.exists(os.path.join(full, "start.txt")):
            run([icrkit, "reconstruct", os.path.join(bunny, "scans.rawlog"), "--poses",
                 os.path.join(bunny, "ground_truth.txt"), "--no-meshes", "--write-registration-input", full,
                 "-o", full + ".rec", "-q"])
        truth = read_tum(os.path.join(full, "start.txt"))
        refined = read_tum(os.path.join(bunny, "ground_truth_refined.txt"))
        n = len(truth)
        indices = {"ps18": range(n), "ps12": [i for i in range(n) if i % 3 != 2], "ps9": range(0, n, 2)}[name]
        link_views(full, list(indices), tmp, truth, {"refined.txt": refined})
        reference = os.path.join(data, "stanford-bunny", "bun_zipper.ply")
    elif name == "stanford":
        # bun.conf: a scan point p lies at R(q)^T p + t in the reference frame.
        order = ["bun000.ply", "bun045.ply", "bun090.ply", "bun180.ply", "bun270.ply", "bun315.ply", "chin.ply",
                 "ear_back.ply", "top2.ply", "top3.ply"]
        conf = {}
        for line in open(os.path.join(data, "stanford-bunny", "bun.conf")):
            f = line.split()
            if f and f[0] == "bmesh":
                m = np.eye(4)
                m[:3, :3] = quaternion_to_matrix(list(map(float, f[5:9]))).T
                m[:3, 3] = list(map(float, f[2:5]))
                conf[f[1]] = m
        # The scans are in the scanner's frame with the bunny at its origin;
        # icrkit takes a view's points in its sensor's frame (the sensor at
        # the origin, x forward, z up), as a depth camera gives them. The
        # scanner saw every scan from +z (a height field along z): place it
        # 0.6 m up that axis from the bunny, looking down -z, y up.
        import open3d as o3d
        sensor = np.eye(4)  # sensor frame -> scan frame
        sensor[:3, :3] = np.array([[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]).T
        sensor[:3, 3] = [-0.017, 0.11, 0.6]
        to_sensor = np.linalg.inv(sensor)
        os.makedirs(tmp)
        for k, scan in enumerate(order):
            cloud = o3d.io.read_point_cloud(os.path.join(data, "stanford-bunny", scan))
            cloud.transform(to_sensor)
            o3d.io.write_point_cloud(os.path.join(tmp, f"view_{k:03d}.ply"), cloud)
        write_tum(os.path.join(tmp, "truth.txt"), [f"{k:.6f}" for k in range(len(order))],
                  [conf[s] @ sensor for s in order])
        reference = os.path.join(data, "stanford-bunny", "bun_zipper.ply")
    elif name.startswith("sim_"):
        if name not in SIMULATED:
            raise SystemExit(f"unknown dataset {name} (simulated: {', '.join(sorted(SIMULATED))})")
        obj, sensor, *options = SIMULATED[name]
        sim = os.path.join(work, "prep", name + ".sim")
        if not os.path.exists(os.path.join(sim, "manifest.json")):
            run([icrkit, "simulate", "--object", obj, "--sensor", sensor, "--seed", str(sim_seed), "-o", sim, "-q"]
                + list(options))
        views = os.path.join(work, "prep", name + ".views")
        if not os.path.exists(os.path.join(views, "start.txt")):
            run([icrkit, "reconstruct", os.path.join(sim, "scans.rawlog"), "--poses",
                 os.path.join(sim, "ground_truth.txt"), "--no-meshes", "--write-registration-input", views,
                 "-o", views + ".rec", "-q"])
        truth = read_tum(os.path.join(views, "start.txt"))
        link_views(views, list(range(len(truth))), tmp, truth)
        reference = os.path.join(sim, "object.ply")
    else:
        raise SystemExit(f"unknown dataset {name}")
    with open(os.path.join(tmp, "reference"), "w") as f:
        f.write(os.path.abspath(reference) + "\n")
    os.rename(tmp, out)
    return out


class Judge:
    """The reference surface and the views' points of one dataset."""

    def __init__(self, prep):
        import open3d as o3d
        self.o3d = o3d
        reference = open(os.path.join(prep, "reference")).read().strip()
        mesh = o3d.io.read_triangle_mesh(reference)
        mesh.remove_unreferenced_vertices()
        self.scene = o3d.t.geometry.RaycastingScene()
        self.scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(mesh))
        self.views = []
        for f in sorted(glob.glob(os.path.join(prep, "view_*.ply"))):
            p = np.asarray(o3d.io.read_point_cloud(f).points)
            self.views.append(p)
        self.truth = read_tum(os.path.join(prep, "truth.txt"))
        refined = os.path.join(prep, "refined.txt")
        self.refined = read_tum(refined) if os.path.exists(refined) else None
        fused = self.fuse(self.truth)
        self.object_point = fused.mean(0)
        self.truth_measure = self.measure(self.truth)

    def fuse(self, poses, voxel=0.001):
        pts = np.vstack([(p[:3, :3] @ v.T).T + p[:3, 3] for p, v in zip(poses, self.views)])
        keys = np.floor(pts / voxel).astype(np.int64)
        _, inverse, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
        sums = np.zeros((len(counts), 3))
        np.add.at(sums, inverse.reshape(-1), pts)
        return sums / counts[:, None]

    def distances(self, p):
        t = self.o3d.core.Tensor(p.astype(np.float32))
        return self.scene.compute_distance(t).numpy().astype(float)

    def fit(self, points):
        return fit_to_surface(self.scene, points)

    def measure(self, poses):
        fused = self.fuse(poses)
        m = self.fit(fused)
        d = self.distances((m[:3, :3] @ fused.T).T + m[:3, 3])
        per_view = []
        for p, v in zip(poses, self.views):
            v = v[:: max(1, len(v) // 4000)]
            a = m @ p
            per_view.append(float(self.distances((a[:3, :3] @ v.T).T + a[:3, 3]).mean() * 1e3))
        return {"fused_mean_mm": float(d.mean() * 1e3), "view_mean_mm": per_view,
                "worst_view_mm": float(max(per_view)), "fit_translation_mm": float(np.linalg.norm(m[:3, 3]) * 1e3),
                "fit_rotation_deg": angle_of(m[:3, :3])}

    def pose_errors(self, poses):
        out = {}
        for label, truth in (("truth", self.truth), ("refined", self.refined)):
            if truth is None:
                continue
            e = pose_errors(poses, truth, self.object_point)["aligned"]
            out[label] = {k: e[k] for k in ("median_object_translation_mm", "max_object_translation_mm",
                                            "median_rotation_deg", "max_rotation_deg")}
        return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build")
    ap.add_argument("work")
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--classes", default="3:0.5,5:1,8:2")
    ap.add_argument("--datasets", default="ps18,ps12,ps9,stanford,sim_paper_cup,sim_toy2")
    ap.add_argument("--sim-seed", type=int, default=41)
    ap.add_argument("--tools", default="icrkit,open3d")
    ap.add_argument("--tag", default="", help="a label for icrkit's runs (a variant being tried)")
    ap.add_argument("--icrkit-flag", default="", help="passed to bench_register_views (e.g. --no-model-alignment, '--set incremental=1')")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    log_path = os.path.join(a.work, "runs.jsonl")
    done = set()
    if os.path.exists(log_path):
        for line in open(log_path):
            r = json.loads(line)
            done.add((r["dataset"], r["class"], r["seed"], r["tool"]))
    classes = [tuple(map(float, c.split(":"))) for c in a.classes.split(",")]
    for name in a.datasets.split(","):
        prep = prepare(name, a.build, a.work, a.sim_seed)
        judge = None
        for mm, deg in classes:
            label = f"{mm:g}mm/{deg:g}deg"
            for seed in range(a.first_seed, a.first_seed + a.seeds):
                tools = [t if t != "icrkit" or not a.tag else "icrkit:" + a.tag for t in a.tools.split(",")]
                todo = [t for t in tools if (name, label, seed, t) not in done]
                if not todo:
                    continue
                if judge is None:
                    judge = Judge(prep)
                rundir = os.path.join(a.work, "runs", name, label.replace("/", "_"), f"seed{seed}")
                os.makedirs(rundir, exist_ok=True)
                for f in glob.glob(os.path.join(prep, "view_*.ply")):
                    dst = os.path.join(rundir, os.path.basename(f))
                    if not os.path.lexists(dst):
                        os.symlink(os.path.realpath(f), dst)
                # Seeds differ per dataset and class, so no two runs share their errors.
                start = perturb(judge.truth, mm * 1e-3, deg, seed * 1000 + int(mm * 10) + zlib.crc32(name.encode()) % 997)
                write_tum(os.path.join(rundir, "start.txt"), [f"{k:.6f}" for k in range(len(start))], start)
                start_record = {"measure": judge.measure(start), "poses": judge.pose_errors(start)}
                for tool in todo:
                    poses_file = os.path.join(rundir, tool.replace(":", "_") + ".txt")
                    if tool.startswith("icrkit"):
                        summary = json.loads(run([os.path.join(a.build, "bench", "bench_register_views"), rundir,
                                                  "-o", poses_file] + shlex.split(a.icrkit_flag)))
                    else:
                        summary = json.loads(run([os.path.join(here, "open3d_multiway.py"), rundir, "-o", poses_file],
                                                 env=dict(os.environ, PYTHONDONTWRITEBYTECODE="1")))
                    poses = read_tum(poses_file)
                    record = {"dataset": name, "class": label, "seed": seed, "tool": tool, "time_s": summary["time_s"],
                              "summary": summary,
                              "measure": judge.measure(poses), "poses": judge.pose_errors(poses),
                              "start": start_record, "truth_measure": judge.truth_measure}
                    with open(log_path, "a") as f:
                        f.write(json.dumps(record) + "\n")
                    print(f"{name} {label} seed {seed} {tool}: fused {record['measure']['fused_mean_mm']:.3f} mm, "
                          f"worst view {record['measure']['worst_view_mm']:.2f} mm, {summary['time_s']:.2f} s",
                          file=sys.stderr, flush=True)
    summarize(log_path)


def summarize(log_path):
    rows = [json.loads(line) for line in open(log_path)]
    keys = sorted({(r["dataset"], r["class"]) for r in rows}, key=lambda k: (k[0], float(k[1].split("mm")[0])))
    tools = sorted({r["tool"] for r in rows})
    print("| dataset | class | tool | runs | fused mean mm: median (worst) | worst view mm: median (max) | "
          "runs not above Open3D | pose err vs truth mm / deg (median) | time s (median) | Open3D time / tool time |")
    print("|---|---|---|---:|---|---|---:|---|---|---:|")
    for dataset, label in keys:
        by = {(r["tool"], r["seed"]): r for r in rows if r["dataset"] == dataset and r["class"] == label}
        for tool in tools:
            mine = {s: r for (t, s), r in by.items() if t == tool}
            if not mine:
                continue
            fused = [r["measure"]["fused_mean_mm"] for r in mine.values()]
            worst = [r["measure"]["worst_view_mm"] for r in mine.values()]
            pt = [r["poses"]["truth"]["median_object_translation_mm"] for r in mine.values()]
            pr = [r["poses"]["truth"]["median_rotation_deg"] for r in mine.values()]
            times = [r["time_s"] for r in mine.values()]
            wins, ratios = "", ""
            if tool != "open3d":
                paired = [(r, by[("open3d", s)]) for s, r in mine.items() if ("open3d", s) in by]
                wins = f"{sum(1 for r, o in paired if r['measure']['fused_mean_mm'] <= o['measure']['fused_mean_mm'])}/{len(paired)}"
                if paired:
                    ratios = f"{np.median([o['time_s'] / r['time_s'] for r, o in paired]):.2f}"
            print(f"| {dataset} | {label} | {tool} | {len(mine)} | {np.median(fused):.3f} ({max(fused):.3f}) | "
                  f"{np.median(worst):.2f} ({max(worst):.2f}) | {wins} | {np.median(pt):.2f} / {np.median(pr):.2f} | "
                  f"{np.median(times):.2f} | {ratios} |")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--summary":
        summarize(sys.argv[2])
    else:
        main()
