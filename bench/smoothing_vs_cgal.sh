#!/usr/bin/env bash
# Issue 34's anchor, side by side on the same fused clouds (docs/smoothing.md):
# icrkit's 3D-NDT smoothing (the feature-preserving default, 30 deg one-sided
# windows, and the paper's window) against CGAL's bilateral_smooth_point_set
# (edge-aware) and jet_smooth_point_set, same neighbourhood (icrkit's radius
# from reconstruction.json; CGAL's k = the median window count recorded
# there), each meshed by `icrkit mesh`, rigidly fitted to the CAD mesh (the
# issue's protocol; ALIGN=none measures in the simulator's frame) and
# measured against it (`icrkit evaluate`'s surface.jsonl: distance, normal
# error near sharp edges and elsewhere). Prints one Markdown row per dataset
# and method.
#   [ALIGN=icp|none] bench/smoothing_vs_cgal.sh BUILD_DIR WORK_DIR DATASET...
# WORK_DIR/DATASET.rec/{cloud.ply, reconstruction.json} (icrkit reconstruct)
# and the reference WORK_DIR/DATASET/object.ply (the CAD mesh) must exist;
# bench/plan_acceptance.sh makes them. For its real recording
# (primesense_bunny) the reference is ../shared/data/stanford-bunny/
# bun_zipper.ply (ICRKIT_DATA overrides the data folder), whose vertex
# normals are derived from its faces. Needs Debian's libcgal-dev for BUILD_DIR/bench/cgal_smooth.
set -euo pipefail
build="$(cd "${1:?usage: $0 BUILD_DIR WORK_DIR DATASET...}" && pwd)"
work="${2:?usage: $0 BUILD_DIR WORK_DIR DATASET...}"
shift 2
icrkit="$build/apps/icrkit/icrkit"
cgal="$build/bench/cgal_smooth"
align="${ALIGN:-icp}"
data="${ICRKIT_DATA:-$(cd "$(dirname "$0")/.." && pwd)/../shared/data}"
reference() {  # DATASET: its reference surface
  if [ ! -f "$1/object.ply" ] && [ "$1" = primesense_bunny ]; then
    echo "$data/stanford-bunny/bun_zipper.ply"
  else
    echo "$1/object.ply"
  fi
}
[ -x "$cgal" ] || { echo "no $cgal: install libcgal-dev and rebuild" >&2; exit 77; }
cd "$work"
mkdir -p cgal_runs
echo "| dataset | method | time s | mean distance mm | normal error near edges deg | elsewhere deg |"
echo "|---|---|---:|---:|---:|---:|"
for n in "$@"; do
  rec="$n.rec"
  read -r radius k < <(/usr/bin/python3 -c "
import json, sys
s = json.load(open(sys.argv[1]))['smoothing']
print(s['radius_m'], max(8, int(round(s['preselection']['statistics']['median_cardinality']))))" "$rec/reconstruction.json")
  echo "| $n | (window radius $radius m, CGAL k = $k) | | | | |"
  for method in feature paper bilateral jet; do
    out="cgal_runs/$n.$method"
    start=$(date +%s.%N)
    case "$method" in
      feature) "$icrkit" smooth "$rec/cloud.ply" -o "$out.cloud.ply" --radius "$radius" --window-normal-angle 0.5236 -q >/dev/null ;;
      paper) "$icrkit" smooth "$rec/cloud.ply" -o "$out.cloud.ply" --radius "$radius" -q >/dev/null ;;
      bilateral) "$cgal" "$rec/cloud.ply" "$out.cloud.ply" bilateral "$k" 2 25 >/dev/null ;;
      jet) "$cgal" "$rec/cloud.ply" "$out.cloud.ply" jet "$k" 1 >/dev/null ;;
    esac
    seconds=$(/usr/bin/python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.1f}')" "$start" "$(date +%s.%N)")
    "$icrkit" mesh "$out.cloud.ply" -o "$out.mesh.ply" -q >/dev/null
    "$icrkit" evaluate --cad "$(reference "$n")" --raw "$out.mesh.ply" --filtered "$out.mesh.ply" --name "$n" --fingers 4 \
      --grasps 1 --plan-top 0 --renders 0 --preselection none --align "$align" --compute-normals -o "$out.eval" -q >/dev/null
    /usr/bin/python3 - "$n" "$method"  "$seconds" "$out.eval/surface.jsonl" <<'PY'
import json, sys
name, method, seconds, path = sys.argv[1:5]
f = json.loads(open(path).readline())['filtered']
angle = lambda g: f"{f[g]['median_normal_error_deg']:.1f}" if f[g]['vertices'] else '–'
print(f"| {name} | {method} | {seconds} | {1e3 * f['all']['mean_distance_m']:.2f} | {angle('near_edges')} | {angle('elsewhere')} |")
PY
  done
done
