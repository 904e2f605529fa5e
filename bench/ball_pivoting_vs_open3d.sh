#!/usr/bin/env bash
# Ball pivoting, icrkit against Open3D's create_from_point_cloud_ball_pivoting
# on the same points, normals and radii (timed CLI runs, best of N). The
# figures in docs/performance.md come from this script on an idle machine:
#
#   bench/ball_pivoting_vs_open3d.sh [BUILD_DIR] [WORK_DIR] [REPEAT]
#
# Inputs: the bun_zipper points with normals estimated by icrkit (radius 3x
# the median spacing), and 1M points sampled uniformly on bun_zipper with
# interpolated vertex normals (bench/sample_mesh_cloud.py, seed 1). The radii
# are icrkit's automatic ones (BUNNY_RADII / MILLION_RADII, e.g. 2x,3x,4.5x,
# override them); icrkit reports them in metres and Open3D gets exactly those.
# Then the real fused cloud of the PrimeSense recording (see the end).
# Open3D is a benchmark-only dependency (Debian python3-open3d for
# /usr/bin/python3); its BPA runs on one thread, icrkit uses --threads.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="${1:-$here/../build}"
work="${2:-$build/bench/ball_pivoting}"
repeat="${3:-3}"
threads="${ICRKIT_THREADS:-2}"  # 1 for a one-thread comparison
icrkit="$build/apps/icrkit/icrkit"
bunny="$here/../../shared/data/stanford-bunny/bun_zipper.ply"
mkdir -p "$work"
[ -f "$bunny" ] || { echo "shared data not found: $bunny" >&2; exit 2; }

"$icrkit" mesh "$bunny" -o "$work/bunny.ply" --estimate-normals --quiet >/dev/null
[ -f "$work/bunny_1m.ply" ] || "$here/sample_mesh_cloud.py" "$bunny" "$work/bunny_1m.ply" --points 1000000 --seed 1

run_case() {
  local name="$1" cloud="$2" factors="$3"
  shift 3  # further arguments go to icrkit mesh
  local best=""
  local radii_option=()
  [ -z "$factors" ] || radii_option=(--radii "$factors")
  for _ in $(seq "$repeat"); do
    "$icrkit" mesh "$cloud" -o "$work/$name.icrkit.ply" "${radii_option[@]}" "$@" --threads "$threads" --json --quiet >"$work/$name.icrkit.run.json"
    best=$(/usr/bin/python3 - "$work/$name.icrkit.run.json" "$best" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))["time_ms"]["total"] / 1000.0  # the whole command: read, mesh, write
print(min(t, float(sys.argv[2])) if sys.argv[2] else t)
PY
)
  done
  cp "$work/$name.icrkit.run.json" "$work/$name.icrkit.json"
  # The radii icrkit used, in metres (JSON keeps every digit).
  local radii
  radii=$(/usr/bin/python3 -c 'import json,sys; print(",".join(repr(r) for r in json.load(open(sys.argv[1]))["radii_m"]))' "$work/$name.icrkit.json")
  "$here/open3d_ball_pivoting.py" "$cloud" --radii "$radii" --repeat "$repeat" >"$work/$name.open3d.json"
  /usr/bin/python3 - "$name" "$best" "$work/$name.icrkit.json" "$work/$name.open3d.json" <<'PY'
import json, sys
name, best = sys.argv[1], float(sys.argv[2])
ours, o3d = json.load(open(sys.argv[3])), json.load(open(sys.argv[4]))
factors = ', '.join('%.2f' % (r / ours['median_spacing_m']) for r in ours['radii_m'])
print(f"| {name} | {ours['points']} | {factors} | icrkit | {best:.3f} | {ours['used_points']} | {ours['triangles']} "
      f"| {ours['boundary_edges']} | {ours['boundary_loops']} | {ours['non_manifold_edges']} |")
print(f"| {name} | {o3d['points']} | {factors} | Open3D {o3d['open3d_version']} | {o3d['time_s']:.3f} | {o3d['used_points']} "
      f"| {o3d['triangles']} | {o3d['boundary_edges']} | {o3d['boundary_loops']} | {o3d['non_manifold_edges']} |")
print(f"| {name} | | | speed-up | {o3d['time_s'] / best:.2f}x | | | | | |")
PY
}

echo "| cloud | points | radii (x median spacing) | program | time (s) | used points | triangles | boundary edges | boundary loops | non-manifold edges |"
echo "|---|---|---|---|---|---|---|---|---|---|"
run_case bun_zipper "$work/bunny.ply" "${BUNNY_RADII:-}"
run_case bunny_1m "$work/bunny_1m.ply" "${MILLION_RADII:-}"

# The real fused cloud: `icrkit reconstruct` of the PrimeSense recording,
# its cloud.ply (points and the fusion's normals) meshed as it is. icrkit's
# default thins the noise layer for the pivoting and puts the thinned
# points back; Open3D gets the same points, normals and radii (slow: its
# ball falls into the layer at radii of the thinned spacing). Then both at
# the radii of the unthinned cloud's own spacing (icrkit --thinning 0).
# REAL_FUSED=0 skips these rows.
real="$here/../../shared/data/primesense-bunny/scans.rawlog"
if [ "${REAL_FUSED:-1}" != "0" ] && [ -f "$real" ]; then
  [ -f "$work/real_fused/cloud.ply" ] ||
    "$icrkit" reconstruct "$real" -o "$work/real_fused" --no-meshes --quiet >/dev/null
  run_case real_fused "$work/real_fused/cloud.ply" ""
  run_case real_fused_unthinned "$work/real_fused/cloud.ply" "" --thinning 0
fi
