"""icrkit.Reconstructor fed the shared TUM folder frame by frame against `icrkit reconstruct` on the folder:
wall time of each (alternating, 3 runs) and byte equality of the four files (docs/performance.md).
Run from the repository root: /usr/bin/python3 bench/python_reconstructor_vs_cli.py"""
import os, sys, time, subprocess, numpy as np
sys.path.insert(0, "build/python")  # run from the repository root
import icrkit
from PIL import Image
T = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data", "primesense-bunny", "tum")
K = [542.0, 540.5, 320.0, 240.0]
rows = [l.split() for l in open(T + "/depth.txt") if l.strip() and not l.startswith("#")]
for rep in range(3):
    t0 = time.perf_counter()
    subprocess.run(["build/apps/icrkit/icrkit", "reconstruct", T, "--intrinsics", "542,540.5,320,240", "--depth-scale", "1000",
                    "--poses", T + "/reported.txt", "-o", "/tmp/pt_cli", "--quiet"], check=True, capture_output=True)
    cli = time.perf_counter() - t0
    t0 = time.perf_counter()
    _, poses = icrkit.read_tum_poses(T + "/reported.txt")
    rec = icrkit.Reconstructor()
    for (stamp, name), pose in zip(rows, poses):
        rec.add_depth(np.asarray(Image.open(os.path.join(T, name)), dtype=np.uint16), K, pose, timestamp=float(stamp))
    fed = time.perf_counter()
    rec.write("/tmp/pt_py")
    py = time.perf_counter() - t0
    print(f"cli {cli:.2f} s  python {py:.2f} s (after last frame {time.perf_counter() - fed:.2f} s)  ratio {py / cli:.3f}")
for f in ("cloud.ply", "raw.ply", "filtered.ply", "poses.txt"):
    print(f, open("/tmp/pt_cli/" + f, "rb").read() == open("/tmp/pt_py/" + f, "rb").read())
