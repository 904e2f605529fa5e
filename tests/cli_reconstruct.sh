#!/usr/bin/env bash
# End-to-end checks of `icrkit reconstruct`: a small simulated Kinect
# recording (the simulator's default robot pose errors) reconstructed with
# its ground truth, the five output files and the JSON summary, and exit
# code 2 with one line naming the file and scan, and nothing written, for
# bad input. Needs $ICRKIT.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

expect_exit 0 "$ICRKIT" reconstruct --help
for option in --poses --gt-poses --crop --no-registration --voxel --smoothing-radius --board-square --board-origin; do
  grep -q -- "$option" "$work/out" || fail "reconstruct --help lacks $option"
done
expect_exit 0 "$ICRKIT" --help
grep -q -- "reconstruct" "$work/out" && grep -q -- "--json" "$work/out" && grep -q -- "--quiet" "$work/out" ||
  fail "icrkit --help lacks reconstruct or the global --json / --quiet"

"$ICRKIT" simulate --object cup --sensor kinect --views 8 -o "$work/cup" -q >/dev/null 2>"$work/err" ||
  { echo "simulate failed: $(cat "$work/err")" >&2; exit 1; }

"$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/rec" --gt-poses "$work/cup/ground_truth.txt" --json \
  >"$work/rec.json" 2>"$work/err" || fail "reconstruct failed: $(cat "$work/err")"
for f in cloud.ply raw.ply filtered.ply poses.txt reconstruction.json; do
  [ -s "$work/rec/$f" ] || fail "reconstruct did not write $f"
done
[ -z "$(ls -A "$work/rec" | grep -v -E '^(cloud|raw|filtered)\.ply$|^poses\.txt$|^reconstruction\.json$')" ] ||
  fail "unexpected files left in the output: $(ls "$work/rec")"
PYTHONPATH="$here" py "
import json
from plyfile import read
d = json.load(open('$work/rec.json'))
assert d == json.load(open('$work/rec/reconstruction.json')), 'stdout and reconstruction.json differ'
assert d['scans'] == 8 and len(d['per_scan']) == 8, d['scans']
assert d['crop_box_automatic'] is True
assert all(s['object_points'] > 1000 and s['support_plane_found'] for s in d['per_scan']), d['per_scan'][0]
e = d['registration_error']['registered']['aligned']
assert e['median_sensor_translation_mm'] <= 1.0 and e['median_rotation_deg'] <= 0.3, e
assert d['registration']['pose_graph']['converged'], d['registration']
for k in ('read', 'filters', 'registration', 'fusion', 'raw_mesh', 'smoothing', 'filtered_mesh', 'total'):
    assert d['time_ms'][k] >= 0, k
poses = [l.split() for l in open('$work/rec/poses.txt') if l.strip() and not l.startswith('#')]
truth = [l.split() for l in open('$work/cup/ground_truth.txt') if l.strip() and not l.startswith('#')]
assert len(poses) == 8 and all(len(p) == 8 for p in poses), poses
assert [p[0] for p in poses] == [t[0] for t in truth], 'time stamps differ from the rawlog'
cloud, _ = read('$work/rec/cloud.ply')
assert len(cloud['x'][1]) == d['cloud_points'], (len(cloud['x'][1]), d['cloud_points'])
for name in ('nx', 'view', 'pixel', 'viewpoint_x'):
    assert name in cloud, name
assert set(cloud['view'][1]) == set(range(8)), sorted(set(cloud['view'][1]))
raw, raw_faces = read('$work/rec/raw.ply')
filtered, filtered_faces = read('$work/rec/filtered.ply')
assert len(raw['x'][1]) == d['cloud_points'] == len(filtered['x'][1])
assert len(raw_faces) == d['raw_mesh']['triangles'] > 0 and len(filtered_faces) == d['filtered_mesh']['triangles'] > 0
assert 'excluded' in filtered and sum(filtered['excluded'][1]) == d['smoothing']['excluded'], 'excluded flags'
" || fail "reconstruct outputs or summary wrong"

# The same result on one thread (pairs, NDT, fusion and normals are parallel)
"$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/one_thread" --threads 1 --no-meshes -q --json \
  >/dev/null 2>"$work/err" || fail "reconstruct --threads 1 failed: $(cat "$work/err")"
cmp -s "$work/rec/poses.txt" "$work/one_thread/poses.txt" || fail "poses differ between 1 and 2 threads"
cmp -s "$work/rec/cloud.ply" "$work/one_thread/cloud.ply" || fail "fused cloud differs between 1 and 2 threads"

# --no-registration keeps the reported poses exactly
"$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/plain" --no-registration --no-meshes --json -q \
  >"$work/plain.json" 2>"$work/err" || fail "reconstruct --no-registration failed: $(cat "$work/err")"
[ ! -e "$work/plain/raw.ply" ] || fail "--no-meshes still wrote raw.ply"
py "
reported = [l.split()[1:] for l in open('$work/cup/reported_poses.txt') if l.strip() and not l.startswith('#')]
written = [l.split()[1:] for l in open('$work/plain/poses.txt') if l.strip() and not l.startswith('#')]
assert len(reported) == len(written) == 8
for r, w in zip(reported, written):
    assert all(abs(float(a) - float(b)) < 1e-9 for a, b in zip(r[:3], w[:3])), (r, w)
" || fail "--no-registration changed the poses"

# Setup B: the cup stands on the simulator's plate (2 cm squares, lines on
# the object frame's axes, 0.1 mm below the base); its poses anchor the registration.
"$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/board" --no-meshes --json -q --board-square 0.02 \
  --board-origin 0,0,-0.0001 --gt-poses "$work/cup/ground_truth.txt" >"$work/board.json" 2>"$work/err" ||
  fail "reconstruct --board-square failed: $(cat "$work/err")"
py "
import json
s = json.load(open('$work/board.json'))
b = s['board']
assert b['square_m'] == 0.02 and b['origin_m'] == [0, 0, -0.0001], b
assert b['poses_from_board'] >= 6, b
used = [scan['board']['used'] for scan in s['per_scan']]
assert sum(used) == b['poses_from_board'] and len(used) == 8, used
assert all(scan['board']['found'] for scan in s['per_scan'] if scan['board']['used'])
assert all(scan['board']['corners'] >= 12 for scan in s['per_scan'] if scan['board']['found'])
plain = json.load(open('$work/rec.json'))
assert plain['board'] is None and 'board' not in plain['per_scan'][0]
" || fail "--board-square summary wrong"

# Bad input: one line naming the file (and scan), exit 2, no output directory.
expect_input_error "--board-square" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad8" --board-square -0.02
expect_input_error "--board-origin" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad9" \
  --board-square 0.02 --board-origin 0,0
expect_input_error "--board-origin" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad10" --board-origin 0,0,0
expect_input_error "--no-registration" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad11" \
  --board-square 0.02 --no-registration
expect_input_error "missing.rawlog" "$ICRKIT" reconstruct "$work/missing.rawlog" -o "$work/bad1"
[ ! -e "$work/bad1" ] || fail "a failed run created its output directory"
head -c 20000 "$work/cup/scans.rawlog" >"$work/truncated.rawlog"
expect_input_error "truncated.rawlog" "$ICRKIT" reconstruct "$work/truncated.rawlog" -o "$work/bad2"
[ ! -e "$work/bad2" ] || fail "a failed run created its output directory"
grep -v '^#' "$work/cup/ground_truth.txt" | head -n 3 >"$work/short.txt"
expect_input_error "scan 3" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad3" --poses "$work/short.txt"
expect_input_error "scan 3" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad4" --no-meshes \
  --gt-poses "$work/short.txt"
[ ! -e "$work/bad4" ] || fail "a run with a short ground truth wrote its outputs"
expect_input_error "scan 0" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad5" --crop 5,5,5,6,6,6
expect_input_error "--crop" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad6" --crop 0,0,0,1,1
touch "$work/a_file"
expect_input_error "not a directory" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/a_file"
printf 'not a rawlog\n' >"$work/text.rawlog"
expect_input_error "text.rawlog" "$ICRKIT" reconstruct "$work/text.rawlog" -o "$work/bad7"

# ToF range calibration: a reference recording at exact poses, the model,
# and its use by reconstruct.
"$ICRKIT" simulate --object paper_cup --sensor sr4000 --views 4 --perfect-poses -o "$work/tof" -q >/dev/null 2>&1 ||
  fail "simulate sr4000 failed"
expect_exit 0 "$ICRKIT" calibrate-range --help
"$ICRKIT" calibrate-range "$work/tof/scans.rawlog" --scene "$work/tof/scene.ply" -o "$work/range.json" --json \
  >"$work/range_summary.json" 2>"$work/err" || fail "calibrate-range failed: $(cat "$work/err")"
py "
import json
s = json.load(open('$work/range_summary.json'))
m = json.load(open('$work/range.json'))
assert m['format'] == 'icrkit range error model 1' and m['wavelength_m'] == 1.249, m
assert s['samples'] > 1000 and s['rms_after_mm'] < s['rms_before_mm'], s
assert 3 < s['periodic_amplitude_mm'] < 10, s  # the simulated SR4000 wiggles by 5 mm
" || fail "calibrate-range outputs wrong"
"$ICRKIT" reconstruct "$work/tof/scans.rawlog" -o "$work/tof_rec" --range-correction "$work/range.json" --no-meshes \
  --json -q >"$work/tof_rec.json" 2>"$work/err" || fail "reconstruct --range-correction failed: $(cat "$work/err")"
py "
import json
d = json.load(open('$work/tof_rec.json'))
assert d['range_correction'] == '$work/range.json' and d['scans'] == 4, d['range_correction']
" || fail "reconstruct --range-correction summary wrong"
expect_input_error "missing.ply" "$ICRKIT" calibrate-range "$work/tof/scans.rawlog" --scene "$work/missing.ply" \
  -o "$work/r2.json"
expect_input_error "r2.txt" "$ICRKIT" calibrate-range "$work/tof/scans.rawlog" --scene "$work/tof/scene.ply" \
  -o "$work/r2.txt"
printf '{"format": "something else"}\n' >"$work/bad_model.json"
expect_input_error "bad_model.json" "$ICRKIT" reconstruct "$work/tof/scans.rawlog" -o "$work/bad8" \
  --range-correction "$work/bad_model.json"
[ ! -e "$work/bad8" ] || fail "a run with a bad range model created its output directory"

[ "$failures" -eq 0 ] || { echo "$failures check(s) failed" >&2; exit 1; }
echo "cli_reconstruct: all checks passed"
