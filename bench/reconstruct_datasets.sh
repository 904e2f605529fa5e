#!/usr/bin/env bash
# Timed `icrkit reconstruct` runs on the paper's nine simulated datasets
# (datasets/paper_datasets.json): registration error against the ground
# truth, fused cloud against the CAD mesh, stage times. Prints one
# Markdown table row per dataset (docs/performance.md). The SR4000 sets are
# run a second time with the camera's range error calibrated out
# (`icrkit calibrate-range` on a separate recording: another object, seed
# and exact poses, as a camera would be calibrated once before use).
#   [POSE_ERRORS="arm mobile"] bench/reconstruct_datasets.sh BUILD_DIR [WORK_DIR [NAME_FILTER]]
# NAME_FILTER (e.g. sr4000) keeps the datasets whose name contains it.
# POSE_ERRORS: the `--pose-error` models to simulate the robot's reported
# poses with, each a separate set of rows (default: arm, the paper's
# industrial arm; "arm mobile" adds the mobile manipulator's 3 mm / 0.5 deg
# per-view errors). A model other than arm names its rows and folders
# NAME_MODEL (cup_kinect_B_mobile, cup_kinect_B_5mm_1deg), as
# `icrkit datasets make` does.
set -euo pipefail
build="${1:?usage: $0 BUILD_DIR [WORK_DIR]}"
work="${2:-$(mktemp -d)}"
filter="${3:-}"
models="${POSE_ERRORS:-arm}"
icrkit="$build/apps/icrkit/icrkit"
mkdir -p "$work"
"$icrkit" datasets list --json >"$work/list.json"
names=$(/usr/bin/python3 -c "import json; print(' '.join(d['name'] for d in json.load(open('$work/list.json'))['datasets']))")
echo "| dataset | scans | reported: sensor mm / deg (median, aligned) | registered: sensor mm / deg (median) | max | pairs accepted | fused points | cloud -> CAD mean mm | modelled sigma mm | registration s | total s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
[ -f "$work/sr4000_calibration/scans.rawlog" ] ||
  "$icrkit" simulate --object paper_cup --sensor sr4000 --views 12 --seed 7 --perfect-poses \
    -o "$work/sr4000_calibration" -q >/dev/null
"$icrkit" calibrate-range "$work/sr4000_calibration/scans.rawlog" --scene "$work/sr4000_calibration/scene.ply" \
  -o "$work/sr4000_range.json" -q --json >/dev/null
# Each run is MODEL/DATASET[+range]; the dataset's folder is DATASET for the
# arm and DATASET_MODEL otherwise (the folder `icrkit datasets make` writes).
runs=""
for model in $models; do
  for name in $names; do
    case "$name" in *"$filter"*) ;; *) continue ;; esac
    runs="$runs $model/$name"
    case "$name" in *sr4000*) runs="$runs $model/$name+range" ;; esac
  done
done
for entry in $runs; do
  model="${entry%%/*}"
  run="${entry#*/}"
  name="${run%+range}"
  folder="$name"
  model_tag=$(echo "$model" | tr 'A-Z,' 'a-z_')
  [ "$model_tag" != arm ] && folder="${name}_$model_tag"
  extra=()
  [ "$run" != "$name" ] && extra=(--range-correction "$work/sr4000_range.json")
  run="$folder${run#"$name"}"
  [ -f "$work/$folder/scans.rawlog" ] ||
    "$icrkit" datasets make --only "$name" --pose-error "$model" -o "$work" -q >/dev/null
  "$icrkit" reconstruct "$work/$folder/scans.rawlog" -o "$work/$run.rec" --gt-poses "$work/$folder/ground_truth.txt" \
    "${extra[@]}" --json -q >"$work/$run.json"
  PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 - "$work/$run.json" "$work/$run.rec/cloud.ply" "$work/$folder/object.ply" "$run" <<'PY'
import json, sys
import numpy as np, open3d as o3d
d = json.load(open(sys.argv[1]))
e = d['registration_error']
reg, rep = e['registered']['aligned'], e['reported']['aligned']
# The cloud in the ground truth's frame (best-fit alignment of the trajectory), against the CAD mesh.
est = [l.split() for l in open(sys.argv[1].replace('.json', '.rec/poses.txt')) if l.strip() and not l.startswith('#')]
cloud = np.asarray(o3d.io.read_point_cloud(sys.argv[2]).points)
truth_file = sys.argv[3].replace('object.ply', 'ground_truth.txt')
gt = [l.split() for l in open(truth_file) if l.strip() and not l.startswith('#')]
A = np.array([[float(v) for v in p[1:4]] for p in est]); B = np.array([[float(v) for v in p[1:4]] for p in gt])
ca, cb = A.mean(0), B.mean(0)
U, S, Vt = np.linalg.svd((B - cb).T @ (A - ca))
D = np.diag([1, 1, np.sign(np.linalg.det(U @ Vt))])
R = U @ D @ Vt
aligned = (R @ (cloud - ca).T).T + cb
mesh = o3d.t.geometry.TriangleMesh.from_legacy(o3d.io.read_triangle_mesh(sys.argv[3]))
scene = o3d.t.geometry.RaycastingScene(); scene.add_triangles(mesh)
dist = scene.compute_distance(o3d.core.Tensor(aligned.astype(np.float32))).numpy()
# The simulator's SR4000 range noise for these very measurements (its model,
# libs/sim/src/sr4000_model.cpp: 4 mm at 2 m for amplitude 1, amplitude =
# reflectivity 0.6 x cos(incidence) x (2 m / range)^2), each point at its
# own range from its view's sensor and its incidence on the CAD surface;
# the median over the fused points. Not computed for the Kinect sets: they
# already meet the stricter bound, 1.5x the normal-incidence sigma at 0.7 m.
if 'sr4000' in sys.argv[4]:
    attributes = o3d.t.io.read_point_cloud(sys.argv[2]).point
    viewpoints = np.stack([attributes[k].numpy().reshape(-1) for k in ('viewpoint_x', 'viewpoint_y', 'viewpoint_z')], 1)
    viewpoints = (R @ (viewpoints - ca).T).T + cb
    closest = scene.compute_closest_points(o3d.core.Tensor(aligned.astype(np.float32)))
    normals = closest['primitive_normals'].numpy().astype(float)
    rays = aligned - viewpoints
    ranges = np.linalg.norm(rays, axis=1)
    cosines = np.clip(np.abs((normals * rays).sum(1)) / ranges, 1e-6, 1.0)
    sigma = np.median(0.004 * ranges ** 2 / (4.0 * 0.6 * cosines))
else:
    sigma = None
pairs = d['registration']
print(f"| {sys.argv[4]} | {d['scans']} | {rep['median_sensor_translation_mm']:.2f} / {rep['median_rotation_deg']:.3f} | "
      f"{reg['median_sensor_translation_mm']:.2f} / {reg['median_rotation_deg']:.3f} | "
      f"{reg['max_sensor_translation_mm']:.2f} / {reg['max_rotation_deg']:.3f} | {pairs['pairs_accepted']}/{pairs['pairs']} | "
      f"{d['cloud_points']} | {dist.mean() * 1e3:.2f} | {'–' if sigma is None else f'{sigma * 1e3:.2f}'} | "
      f"{d['time_ms']['registration'] / 1e3:.1f} | {d['time_ms']['total'] / 1e3:.1f} |")
PY
done
