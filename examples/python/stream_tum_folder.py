#!/usr/bin/python3
"""Streams a TUM RGB-D folder frame by frame into icrkit.Reconstructor, then plans grasps.

    stream_tum_folder.py [FOLDER] [--intrinsics FX,FY,CX,CY] [--depth-scale S]
                         [--poses FILE] [--top N] [--as-they-arrive] [-o DIR]

As a robot would: each depth image is decoded into a NumPy array and handed
over with its camera pose (a 4x4 camera-to-object matrix, optical axes) as if
a driver had just delivered it; nothing is read back from files by icrkit.
After the last frame it asks for the meshes, writes what `icrkit reconstruct`
writes (and plan.json) to DIR, and prints the best grasps on the filtered mesh.
With --as-they-arrive each frame is also registered with the earlier ones
as it is handed over, so that the meshes come sooner after the last one
(docs/python.md). Without FOLDER: the shared PrimeSense bunny recording
(../shared/data)."""

import argparse
import json
import os
import sys
import time

import numpy as np
from PIL import Image

import icrkit

HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = os.path.join(HERE, "..", "..", "..", "shared", "data", "primesense-bunny", "tum")


def read_list(path):
    """`timestamp filename` lines of a TUM list ('#' comments)."""
    rows = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line and not line.startswith("#"):
                stamp, rest = line.split(maxsplit=1)
                rows.append((float(stamp), rest.split()[0]))
    return rows


def pose_for(frames, poses, i):
    """By order when there are as many poses as frames, else the nearest in time."""
    stamps, matrices = poses
    if len(stamps) == len(frames):
        return matrices[i]
    k = int(np.argmin(np.abs(stamps - frames[i][0])))
    if abs(stamps[k] - frames[i][0]) > 0.02:
        sys.exit(f"no pose within 20 ms of frame {i} (t = {frames[i][0]:.6f})")
    return matrices[k]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", nargs="?", default=SHARED)
    parser.add_argument("--intrinsics", default=None, help="fx,fy,cx,cy in pixels (default: FOLDER/camera.json, "
                        "or the shared bunny's 542,540.5,320,240)")
    parser.add_argument("--depth-scale", type=float, default=None, help="depth counts per metre (default 1000)")
    parser.add_argument("--poses", default=None, help="TUM trajectory (default FOLDER/reported.txt)")
    parser.add_argument("--top", type=int, default=5, help="grasps to print")
    parser.add_argument("--as-they-arrive", action="store_true",
                        help="register each frame with the earlier ones as it is handed over")
    parser.add_argument("-o", "--output", default="stream_out")
    args = parser.parse_args()

    camera = {}
    if os.path.exists(os.path.join(args.folder, "camera.json")):
        with open(os.path.join(args.folder, "camera.json")) as f:
            camera = json.load(f)
    if args.intrinsics:
        intrinsics = [float(x) for x in args.intrinsics.split(",")]
    elif "fx" in camera:
        intrinsics = [camera["fx"], camera["fy"], camera["cx"], camera["cy"]]
    else:
        intrinsics = [542.0, 540.5, 320.0, 240.0]
    depth_scale = args.depth_scale or camera.get("depth_scale", 1000.0)
    frames = read_list(os.path.join(args.folder, "depth.txt"))
    poses = icrkit.read_tum_poses(args.poses or os.path.join(args.folder, "reported.txt"))

    show = sys.stderr.isatty()
    reconstructor = icrkit.Reconstructor(register_as_scans_arrive=args.as_they_arrive)
    start = time.perf_counter()
    for i, (stamp, name) in enumerate(frames):
        depth = np.asarray(Image.open(os.path.join(args.folder, name)), dtype=np.uint16)  # the driver's frame
        reconstructor.add_depth(depth, intrinsics, pose_for(frames, poses, i), timestamp=stamp,
                                depth_scale=depth_scale)
        if show:
            print(f"\rscan {i + 1}/{len(frames)}", end="", file=sys.stderr, flush=True)
    fed = time.perf_counter()

    def progress(stage, done, total):
        if show:
            print(f"\r{stage} {done}/{total}" if total else f"\r{stage}", end="      ", file=sys.stderr, flush=True)

    raw, filtered = reconstructor.meshes(progress)
    meshed = time.perf_counter()
    if show:
        print(file=sys.stderr)
    reconstructor.write(args.output)
    print(f"{len(reconstructor)} scans fed in {fed - start:.1f} s; meshes {meshed - fed:.1f} s after the last scan: "
          f"raw {len(raw.faces)} faces, filtered {len(filtered.faces)} faces")

    plan = icrkit.plan(filtered, fingers=[4], top=args.top, candidates=300, mesh_path="filtered.ply")
    with open(os.path.join(args.output, "plan.json"), "w") as f:
        json.dump(plan, f, indent=1)
    for g in plan["grasps"][: args.top]:
        aims = [r["recommended"]["vertex"] for r in g["regions"]]
        print(f"grasp {g['rank']}: score {g['score']:.2f}, epsilon {g['epsilon']:.3f}, aim at vertices {aims}")
    print("wrote", args.output)


if __name__ == "__main__":
    main()
