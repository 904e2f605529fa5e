#!/usr/bin/env bash
# End-to-end checks of `icrkit simulate` and `icrkit datasets`: a small
# simulated recording's files and JSON summary, byte-identical output for
# the same seed, and exit code 2 with a one-line message and nothing left
# behind for bad arguments. Needs $ICRKIT.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

expect_exit 0 "$ICRKIT" simulate --help
grep -q -- "--sensor" "$work/out" && grep -q -- "--setup" "$work/out" || fail "simulate --help lacks its options"
grep -q -- "--pose-error" "$work/out" || fail "simulate --help lacks --pose-error"

"$ICRKIT" simulate --object cup --sensor kinect --setup B --views 2 --seed 3 -o "$work/cup" --json \
  >"$work/cup.json" 2>"$work/err" || fail "simulate failed: $(cat "$work/err")"
for f in scans.rawlog ground_truth.txt reported_poses.txt object.ply scene.ply manifest.json; do
  [ -s "$work/cup/$f" ] || fail "simulate did not write $f"
done
py "
import json
d = json.load(open('$work/cup.json'))
assert d['name'] == 'cup_kinect_B' and d['views'] == 2 and d['seed'] == 3, d
assert 0 < d['object_pixel_fraction'] <= d['valid_pixel_fraction'] <= 1, d
m = json.load(open('$work/cup/manifest.json'))
assert m['sensor']['range_is_depth'] is True and m['sensor']['width'] == 640 and m['setup'] == 'B', m['sensor']
assert len(m['views_detail']) == 2
lines = [l for l in open('$work/cup/ground_truth.txt') if l.strip() and not l.startswith('#')]
assert len(lines) == 2 and len(lines[0].split()) == 8, lines
" || fail "simulate summary or manifest wrong"
# gzip magic: a compressed MRPT rawlog
[ "$(head -c 2 "$work/cup/scans.rawlog" | od -An -tx1 | tr -d ' ')" = "1f8b" ] || fail "scans.rawlog is not gzip"

"$ICRKIT" simulate --object cup --sensor kinect --setup B --views 2 --seed 3 -o "$work/cup2" -q >/dev/null ||
  fail "second simulate failed"
cmp -s "$work/cup/scans.rawlog" "$work/cup2/scans.rawlog" || fail "same seed gave a different rawlog"

# --- Pose-error models: the arm is the default (same bytes as no option);
# mobile and explicit sigmas change the reported poses only, and the
# manifest names the model.
"$ICRKIT" simulate --object cup --sensor kinect --setup B --views 2 --seed 3 --pose-error arm -o "$work/cup_arm" -q \
  >/dev/null || fail "simulate --pose-error arm failed"
for f in scans.rawlog ground_truth.txt reported_poses.txt; do
  cmp -s "$work/cup/$f" "$work/cup_arm/$f" || fail "--pose-error arm changed $f"
done
"$ICRKIT" simulate --object cup --sensor kinect --setup B --views 2 --seed 3 --pose-error mobile -o "$work/cup_mobile" \
  --json -q >"$work/cup_mobile.json" 2>"$work/err" || fail "simulate --pose-error mobile failed: $(cat "$work/err")"
"$ICRKIT" simulate --object cup --sensor kinect --setup B --views 2 --seed 3 --pose-error 5mm,1deg -o "$work/cup_5mm" \
  -q >/dev/null 2>"$work/err" || fail "simulate --pose-error 5mm,1deg failed: $(cat "$work/err")"
cmp -s "$work/cup/ground_truth.txt" "$work/cup_mobile/ground_truth.txt" || fail "the mobile model moved the ground truth"
cmp -s "$work/cup/reported_poses.txt" "$work/cup_mobile/reported_poses.txt" && fail "the mobile model reported the arm's poses"
py "
import json, math
assert json.load(open('$work/cup.json'))['pose_error'] == 'arm'
assert json.load(open('$work/cup_mobile.json'))['pose_error'] == 'mobile'
m = json.load(open('$work/cup/manifest.json'))['pose_errors']
assert m['model'] == 'arm' and m['noise_translation_m'] == 0.0003 and m['hand_eye_translation_m'] == 0.002, m
m = json.load(open('$work/cup_mobile/manifest.json'))['pose_errors']
assert m['model'] == 'mobile' and m['noise_translation_m'] == 0.003, m
assert abs(m['noise_rotation_rad'] - math.radians(0.5)) < 1e-15 and m['hand_eye_translation_m'] == 0 and m['drift_rotation_rad_per_view'] == 0, m
m = json.load(open('$work/cup_5mm/manifest.json'))['pose_errors']
assert m['model'] == 'custom' and m['noise_translation_m'] == 0.005 and abs(m['noise_rotation_rad'] - math.radians(1)) < 1e-15, m
" || fail "pose-error model not recorded"
# --- Correlated Kinect depth noise: 0 is the default's bytes; a share
# changes the ranges only, and the manifest and summary name it.
"$ICRKIT" simulate --object cup --sensor kinect --setup B --views 2 --seed 3 --correlated-noise 0 -o "$work/cup_cn0" -q \
  >/dev/null || fail "simulate --correlated-noise 0 failed"
cmp -s "$work/cup/scans.rawlog" "$work/cup_cn0/scans.rawlog" || fail "--correlated-noise 0 changed the rawlog"
"$ICRKIT" simulate --object cup --sensor kinect --setup B --views 2 --seed 3 --correlated-noise 0.75,3 -o "$work/cup_cn" \
  --json -q >"$work/cup_cn.json" 2>"$work/err" || fail "simulate --correlated-noise 0.75,3 failed: $(cat "$work/err")"
cmp -s "$work/cup/scans.rawlog" "$work/cup_cn/scans.rawlog" && fail "--correlated-noise 0.75,3 left the rawlog as it was"
cmp -s "$work/cup/ground_truth.txt" "$work/cup_cn/ground_truth.txt" || fail "--correlated-noise moved the ground truth"
py "
import json
assert json.load(open('$work/cup_cn.json'))['correlated_depth_noise'] == {'share': 0.75, 'length_px': 3.0}
assert json.load(open('$work/cup_cn/manifest.json'))['sensor']['correlated_depth_noise'] == {'share': 0.75, 'length_px': 3.0}
assert 'correlated_depth_noise' not in json.load(open('$work/cup/manifest.json'))['sensor']
" || fail "correlated noise not recorded"
expect_input_error "--correlated-noise.*only the Kinect" "$ICRKIT" simulate --views 1 --sensor sr4000 --correlated-noise 0.5 \
  -o "$work/bad"
expect_input_error "--correlated-noise.*\\[0, 1\\]" "$ICRKIT" simulate --views 1 --correlated-noise 1.5 -o "$work/bad"
expect_input_error "--correlated-noise.*\\[1, 64\\]" "$ICRKIT" simulate --views 1 --correlated-noise 0.5,0.5 -o "$work/bad"
expect_input_error "--correlated-noise.*\\[0, 1\\]" "$ICRKIT" simulate --views 1 --correlated-noise -0.1 -o "$work/bad"
expect_input_error "--correlated-noise.*SHARE" "$ICRKIT" simulate --views 1 --correlated-noise 0.5,x -o "$work/bad"
expect_input_error "--correlated-noise.*SHARE" "$ICRKIT" simulate --views 1 --correlated-noise 0.5,3,1 -o "$work/bad"
expect_input_error "--pose-error.*>= 0" "$ICRKIT" simulate --views 1 --pose-error -3mm,1deg -o "$work/bad"
expect_input_error "--pose-error.*>= 0" "$ICRKIT" simulate --views 1 --pose-error 3mm,-1deg -o "$work/bad"
expect_input_error "--pose-error.*wobbly" "$ICRKIT" simulate --views 1 --pose-error wobbly -o "$work/bad"
expect_input_error "--pose-error.*'5,1deg'" "$ICRKIT" simulate --views 1 --pose-error 5,1deg -o "$work/bad"
expect_input_error "--pose-error" "$ICRKIT" simulate --views 1 --pose-error 5mm -o "$work/bad"
expect_input_error "--perfect-poses excludes --pose-error" "$ICRKIT" simulate --views 1 --perfect-poses --pose-error mobile \
  -o "$work/bad"
# datasets make under another model writes NAME_MODEL beside the arm's NAME
"$ICRKIT" datasets make --only wooden_toy_2_sr4000_A --pose-error mobile -o "$work/ds" --json -q >"$work/ds.json" \
  2>"$work/err" || fail "datasets make --pose-error mobile failed: $(cat "$work/err")"
py "
import json
d = json.load(open('$work/ds.json'))
assert d['pose_error'] == 'mobile' and len(d['datasets']) == 1, d
x = d['datasets'][0]
assert x['name'] == 'wooden_toy_2_sr4000_A' and x['directory'].endswith('/wooden_toy_2_sr4000_A_mobile'), x
assert json.load(open('$work/ds/wooden_toy_2_sr4000_A_mobile/manifest.json'))['pose_errors']['model'] == 'mobile'
" || fail "datasets make --pose-error mobile: wrong folder or model"
expect_input_error "--pose-error.*wobbly" "$ICRKIT" datasets make --only cup_kinect_B --pose-error wobbly -o "$work/bad"

# the SR4000 defaults to setup A; a user mesh can be scanned
"$ICRKIT" simulate --mesh "$root/datasets/tetrahedron.obj" --sensor sr4000 --views 1 -o "$work/tet" --json -q \
  >"$work/tet.json" 2>"$work/err" || fail "simulate --mesh failed: $(cat "$work/err")"
py "
import json
d = json.load(open('$work/tet.json'))
assert d['setup'] == 'A' and d['sensor'] == 'sr4000', d
" || fail "sr4000 did not default to setup A"

"$ICRKIT" datasets list --json >"$work/list.json" || fail "datasets list failed"
py "
import json
d = json.load(open('$work/list.json'))['datasets']
f = json.load(open('$root/datasets/paper_datasets.json'))['datasets']
assert [x['name'] for x in d] == [x['name'] for x in f] and len(d) == 9, d
" || fail "datasets list differs from datasets/paper_datasets.json"

# --- Bad arguments: exit 2, one line, nothing left behind
expect_input_error "--object.*teapot" "$ICRKIT" simulate --object teapot -o "$work/bad"
expect_input_error "--sensor.*lidar" "$ICRKIT" simulate --sensor lidar -o "$work/bad"
expect_input_error "--setup.*C" "$ICRKIT" simulate --setup C -o "$work/bad"
expect_input_error "--views" "$ICRKIT" simulate --views 0 -o "$work/bad"
expect_input_error "--views" "$ICRKIT" simulate --views -3 -o "$work/bad"
expect_input_error "missing.ply" "$ICRKIT" simulate --mesh "$work/missing.ply" -o "$work/bad"
expect_input_error "--only.*nope" "$ICRKIT" datasets make --only nope -o "$work/bad"
[ ! -e "$work/bad" ] && [ ! -e "$work/bad.partial" ] || fail "a failed simulate left an output behind"
mkdir -p "$work/theirs" && echo mine >"$work/theirs/notes.txt"
expect_input_error "theirs.*no earlier simulation" "$ICRKIT" simulate --views 1 -o "$work/theirs"
[ -f "$work/theirs/notes.txt" ] || fail "simulate touched a folder it does not own"
expect_input_error "cannot create" "$ICRKIT" simulate --views 1 -o /proc/icrkit_no_such_place

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi
echo "all simulate CLI checks passed"
