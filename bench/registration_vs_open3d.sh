#!/usr/bin/env bash
# icrkit's registration against Open3D's multiway registration on the real
# PrimeSense bunny recording, side by side in one run: the same views, crops
# and starting poses (icrkit reconstruct --write-registration-input), the
# same error measures (bench/registration_measures.py: poses after the best
# rigid fit of the camera centres, clouds after a rigid fit to the reference
# surface, both fused by icrkit's OctoMap fusion). Cases: the rawlog's own
# reported poses (3 mm / 0.5 deg per view) and seeded 5 mm / 1 deg per-axis
# errors on its ground truth. Prints a Markdown table (docs/performance.md).
#   bench/registration_vs_open3d.sh BUILD_DIR [WORK_DIR] [SEEDS]
# Open3D is a benchmark-only dependency (Debian python3-open3d, /usr/bin/python3).
set -euo pipefail
build="${1:?usage: $0 BUILD_DIR [WORK_DIR] [SEEDS]}"
work="${2:-$(mktemp -d)}"
seeds="${3:-1 2 3}"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
icrkit="$build/apps/icrkit/icrkit"
data="$here/../../shared/data"
bunny="$data/primesense-bunny"
reference="$data/stanford-bunny/bun_zipper.ply"
[ -f "$bunny/scans.rawlog" ] || { echo "shared data not found: $bunny" >&2; exit 77; }
mkdir -p "$work"
echo "| case | tool | registration s | pose error at the object, aligned: median mm / deg (max mm) | raw median mm / deg | views worse than start by > 0.5 mm | cloud -> reference mean mm, fitted (as is) |"
echo "|---|---|---|---|---|---|---|"
cases="reported"
for s in $seeds; do cases="$cases seeded$s"; done
for case in $cases; do
  poses=()
  if [ "$case" != reported ]; then
    "$here/perturb_poses.py" "$bunny/ground_truth.txt" "$work/$case.start.txt" --sigma-translation 0.005 \
      --sigma-rotation-deg 1 --seed "${case#seeded}"
    poses=(--poses "$work/$case.start.txt")
  fi
  "$icrkit" reconstruct "$bunny/scans.rawlog" "${poses[@]}" --gt-poses "$bunny/ground_truth.txt" --no-meshes \
    --write-registration-input "$work/$case.views" -o "$work/$case.icrkit" --json -q >"$work/$case.icrkit.json"
  "$here/open3d_multiway.py" "$work/$case.views" -o "$work/$case.open3d.txt" >"$work/$case.open3d.json"
  # Open3D's poses fused exactly like icrkit's own.
  "$icrkit" reconstruct "$bunny/scans.rawlog" --poses "$work/$case.open3d.txt" --no-registration --no-meshes \
    -o "$work/$case.open3d" --json -q >/dev/null
  for tool in icrkit open3d; do
    if [ $tool = icrkit ]; then est="$work/$case.icrkit/poses.txt"; else est="$work/$case.open3d.txt"; fi
    PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 - "$case" "$tool" "$est" "$bunny/ground_truth.txt" \
      "$work/$case.views/start.txt" "$work/$case.icrkit.json" "$work/$case.open3d.json" \
      "$work/$case.$tool/cloud.ply" "$reference" "$here" <<'PY'
import json, sys
case, tool, est, truth, start, ij, oj, cloud, reference, here = sys.argv[1:]
sys.path.insert(0, here)
import numpy as np
from registration_measures import read_tum, pose_errors, surface_errors, read_points
d = json.load(open(ij))
point = np.array(d['registration_error']['object_point_m'])
gt = read_tum(truth)
e = pose_errors(read_tum(est), gt, point)
s = pose_errors(read_tum(start), gt, point)
worse = sum(1 for a, b in zip(e['aligned']['object_translation_mm'], s['aligned']['object_translation_mm']) if a > b + 0.5)
t = d['time_ms']['registration'] / 1e3 if tool == 'icrkit' else json.load(open(oj))['time_s']
c = surface_errors(read_points(cloud), reference)
a, r = e['aligned'], e['raw']
print(f"| {case} (start {s['aligned']['median_object_translation_mm']:.2f} mm / {s['aligned']['median_rotation_deg']:.2f} deg) | {tool} | {t:.2f} | "
      f"{a['median_object_translation_mm']:.2f} / {a['median_rotation_deg']:.3f} ({a['max_object_translation_mm']:.2f}) | "
      f"{r['median_object_translation_mm']:.2f} / {r['median_rotation_deg']:.3f} | {worse} | {c['fitted_mean_mm']:.2f} ({c['mean_mm']:.2f}) |")
PY
  done
done
