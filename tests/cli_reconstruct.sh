#!/usr/bin/env bash
# End-to-end checks of `icrkit reconstruct`: a small simulated Kinect
# recording (the simulator's default robot pose errors) reconstructed with
# its ground truth, the five output files and the JSON summary, and exit
# code 2 with one line naming the file and scan, and nothing written, for
# bad input. Needs $ICRKIT.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

expect_exit 0 "$ICRKIT" reconstruct --help
for option in --poses --gt-poses --crop --no-registration --voxel --smoothing-radius --board-square --board-origin \
  --intrinsics --depth-scale --camera --max-time-difference --rotation-tolerance --no-joint-refinement; do
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
# The filters' totals (mixed pixels: jump_edges) are the per-scan counts summed.
for k, total in d['removed'].items():
    assert total == sum(s['removed'][k] for s in d['per_scan']), (k, total)
assert d['removed']['jump_edges'] > 0, d['removed']
assert d['registration']['model_alignment']['views_kept'][-1] >= 6, d['registration']['model_alignment']
e = d['registration_error']['registered']['aligned']
assert e['median_sensor_translation_mm'] <= 1.0 and e['median_rotation_deg'] <= 0.3, e
assert d['registration']['pose_graph']['converged'], d['registration']
j = d['registration']['joint_refinement']
# Kept exactly when its face-on matches link 0.75 pairs of views per graph pair.
assert j['enabled'] and j['iterations'] > 0 and j['graph_view_pairs'] > 0, j
assert j['applied'] == (j['linked_view_pairs'] >= 0.75 * j['graph_view_pairs']), j
assert j['applied'] == (j['rejection'] == ''), j
st = d['registration']['stage_time_ms']
assert all(st[k] >= 0 for k in ('prepare', 'model_alignment', 'pairs', 'graph', 'joint_refinement')), st
assert sum(st.values()) <= d['time_ms']['registration'] + 1, (st, d['time_ms'])
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
expect_input_error "--register-as-scans-arrive" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad13" \
  --register-as-scans-arrive --no-registration
expect_input_error "--joint-refinement" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad14" \
  --joint-refinement --no-joint-refinement
expect_input_error "missing.rawlog" "$ICRKIT" reconstruct "$work/missing.rawlog" -o "$work/bad1"
expect_input_error "--window-normal-angle" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad12" \
  --window-normal-angle 0
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

# --- TUM RGB-D folders: a synthetic one (a sphere seen from four sides,
# rendered here as 16-bit PNGs), read directly and through its rawlog.
tum_py() { py "
import math, struct, zlib, os
def png(path, rows, bits=16):
    h, w = len(rows), len(rows[0])
    raw = b''.join(b'\x00' + (struct.pack('>%dH' % w, *row) if bits == 16 else bytes(row)) for row in rows)
    chunk = lambda t, d: struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    ihdr = struct.pack('>IIBBBBB', w, h, bits, 0, 0, 0, 0)
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', ihdr) + chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))
def cross(a, b): return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]
def unit(a): n = math.sqrt(sum(x*x for x in a)); return [x / n for x in a]
def quaternion(R):  # columns x, y, z -> qx qy qz qw
    m = [[R[c][r] for c in range(3)] for r in range(3)]
    w = math.sqrt(max(0, 1 + m[0][0] + m[1][1] + m[2][2])) / 2
    x = math.copysign(math.sqrt(max(0, 1 + m[0][0] - m[1][1] - m[2][2])) / 2, m[2][1] - m[1][2])
    y = math.copysign(math.sqrt(max(0, 1 - m[0][0] + m[1][1] - m[2][2])) / 2, m[0][2] - m[2][0])
    z = math.copysign(math.sqrt(max(0, 1 - m[0][0] - m[1][1] + m[2][2])) / 2, m[1][0] - m[0][1])
    return x, y, z, w
W, H, F, C = 160, 120, 150.0, (79.5, 59.5)
$1
"; }
make_tum_folder() {  # make_tum_folder DIR: 4 views, camera-to-object optical poses in DIR/poses.txt
  tum_py "
d = '$1'
os.makedirs(d + '/depth', exist_ok=True)
lst, poses = open(d + '/depth.txt', 'w'), open(d + '/poses.txt', 'w')
lst.write('# depth maps\n# timestamp filename\n')
poses.write('# timestamp tx ty tz qx qy qz qw (optical axes, camera to object)\n')
for k in range(4):
    a = k * math.pi / 2 + 0.3
    c = [0.5 * math.cos(a), 0.5 * math.sin(a), 0.15]
    z = unit([-x for x in c]); x = unit(cross(z, [0, 0, 1])); y = cross(z, x)
    rows = []
    for v in range(H):
        row = []
        for u in range(W):
            r = [(u - C[0]) / F, (v - C[1]) / F, 1.0]
            dv = [x[i] * r[0] + y[i] * r[1] + z[i] * r[2] for i in range(3)]
            # |c + s dv| = 0.05: the sphere at the origin.
            A = sum(q * q for q in dv); B = 2 * sum(p * q for p, q in zip(c, dv)); Cc = sum(p * p for p in c) - 0.05 ** 2
            disc = B * B - 4 * A * Cc
            row.append(int(round(1000 * (-B - math.sqrt(disc)) / (2 * A))) if disc > 0 else 0)
        rows.append(row)
    name = 'depth/%d.000000.png' % (100 + k)
    png(d + '/' + name, rows)
    lst.write('%d.000000 %s\n' % (100 + k, name))
    poses.write('%d.000000 %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n' % ((100 + k,) + tuple(c) + quaternion([x, y, z])))
"
}
tum="$work/tum"
make_tum_folder "$tum" || { echo "FAIL: writing the synthetic TUM folder" >&2; exit 1; }
camera_flags=(--intrinsics 150,150,79.5,59.5 --depth-scale 1000)
fast_flags=(--crop -0.1,-0.1,-0.1,0.1,0.1,0.1 --no-plane-removal --no-registration --no-meshes)
"$ICRKIT" reconstruct "$tum" -o "$work/tum_rec" "${camera_flags[@]}" --poses "$tum/poses.txt" "${fast_flags[@]}" \
  --gt-poses "$tum/poses.txt" --json >"$work/tum_rec.json" 2>"$work/err" ||
  fail "reconstruct of a TUM folder failed: $(cat "$work/err")"
"$ICRKIT" convert "$tum" "$work/tum.rawlog" "${camera_flags[@]}" --poses "$tum/poses.txt" --json \
  >"$work/tum_convert.json" 2>"$work/err" || fail "convert of a TUM folder failed: $(cat "$work/err")"
"$ICRKIT" reconstruct "$work/tum.rawlog" -o "$work/tum_rawlog_rec" "${fast_flags[@]}" --json \
  >"$work/tum_rawlog_rec.json" 2>"$work/err" || fail "reconstruct of the converted rawlog failed: $(cat "$work/err")"
cmp -s "$work/tum_rec/poses.txt" "$work/tum_rawlog_rec/poses.txt" || fail "poses.txt differs between folder and rawlog"
cmp -s "$work/tum_rec/cloud.ply" "$work/tum_rawlog_rec/cloud.ply" || fail "cloud.ply differs between folder and rawlog"
PYTHONPATH="$here" py "
import json, math
d = json.load(open('$work/tum_rec.json'))
assert d['input_format'] == 'tum_folder' and d['scans'] == 4 and d['pose_matching'] == 'order', d['input_format']
assert d['cloud_points'] > 1000, d['cloud_points']
k = d['depth_camera']
assert (k['width'], k['height'], k['fx'], k['cy'], k['depth_scale']) == (160, 120, 150, 59.5, 1000), k
assert d['registration_error']['reported']['raw']['max_sensor_translation_mm'] < 1e-6, d['registration_error']
c = json.load(open('$work/tum_convert.json'))
assert c['format'] == 'rawlog' and c['scans'] == 4, c
r = json.load(open('$work/tum_rawlog_rec.json'))
assert r['input_format'] == 'rawlog' and r['poses_orthonormalised'] == 0 and r['cloud_points'] == d['cloud_points'], r
# Every fused point on the sphere (1 mm depth steps).
from plyfile import read
cloud, _ = read('$work/tum_rec/cloud.ply')
xs, ys, zs = cloud['x'][1], cloud['y'][1], cloud['z'][1]
worst = max(abs(math.sqrt(x * x + y * y + z * z) - 0.05) for x, y, z in zip(xs, ys, zs))
assert worst < 0.002, worst
" || fail "TUM folder reconstruction summary or geometry wrong"

# A camera.json in the folder replaces the flags; a quaternion off unit
# length (0.9999) is normalised and counted.
printf '{"fx": 150, "fy": 150, "cx": 79.5, "cy": 59.5, "depth_scale": 1000}\n' >"$tum/camera.json"
py "
lines = open('$tum/poses.txt').read().splitlines()
f = lines[2].split(); q = [float(v) * 0.9999 for v in f[4:]]
lines[2] = ' '.join(f[:4] + ['%.12f' % v for v in q])
open('$work/poses_q.txt', 'w').write('\n'.join(lines) + '\n')
"
"$ICRKIT" reconstruct "$tum" -o "$work/tum_camera" --poses "$work/poses_q.txt" "${fast_flags[@]}" --json \
  >"$work/tum_camera.json" 2>"$work/err" || fail "reconstruct with camera.json failed: $(cat "$work/err")"
py "
import json
d = json.load(open('$work/tum_camera.json'))
assert d['depth_camera']['intrinsics_source'].endswith('camera.json'), d['depth_camera']
assert d['depth_camera']['depth_scale_source'].endswith('camera.json'), d['depth_camera']
assert d['poses_orthonormalised'] >= 1, d['poses_orthonormalised']
" || fail "camera.json or quaternion normalisation not reported"
rm "$tum/camera.json"

# Bad folders: exit 2, one line naming the file (and line or scan).
expect_input_error "intrinsics" "$ICRKIT" reconstruct "$tum" -o "$work/bad_t1" --poses "$tum/poses.txt"
expect_input_error "--intrinsics" "$ICRKIT" reconstruct "$work/cup/scans.rawlog" -o "$work/bad_t2" \
  --intrinsics 1,1,1,1
expect_input_error "--intrinsics" "$ICRKIT" reconstruct "$tum" -o "$work/bad_t3" --intrinsics 150,150,79.5
head -n 4 "$tum/poses.txt" >"$work/three_poses.txt"
sed -i 's/^103.000000 /109.000000 /' "$tum/depth.txt"
expect_input_error "three_poses.txt:scan 3" "$ICRKIT" reconstruct "$tum" -o "$work/bad_t4" "${camera_flags[@]}" \
  --poses "$work/three_poses.txt"
[ ! -e "$work/bad_t4" ] || fail "a run with unmatched poses created its output directory"
mv "$tum/depth/101.000000.png" "$work/moved.png"
expect_input_error "depth.txt:line 4" "$ICRKIT" reconstruct "$tum" -o "$work/bad_t5" "${camera_flags[@]}"
tum_py "png('$tum/depth/101.000000.png', [[100] * W for _ in range(H)], bits=8)"
expect_input_error "expected a 16-bit depth image" "$ICRKIT" reconstruct "$tum" -o "$work/bad_t6" "${camera_flags[@]}"
grep -q "101.000000.png" "$work/err" || fail "the 8-bit image is not named: $(cat "$work/err")"
expect_input_error "101.000000.png" "$ICRKIT" convert "$tum" "$work/bad.rawlog" "${camera_flags[@]}"
[ ! -e "$work/bad.rawlog" ] || fail "a failed conversion left a rawlog behind"
rm "$tum/depth.txt"
expect_input_error "depth.txt" "$ICRKIT" reconstruct "$tum" -o "$work/bad_t7" "${camera_flags[@]}"
expect_input_error "rawlog" "$ICRKIT" convert "$tum" "$work/bad.ply" "${camera_flags[@]}"
expect_input_error "only a TUM RGB-D folder" "$ICRKIT" convert "$work/cup/scans.rawlog" "$work/cup.rawlog"

# --- The shared bunny recording: its TUM folder and its rawlog.
data="${ICRKIT_SHARED_DATA_DIR:-}"
bunny="$data/primesense-bunny"
if [ -z "$data" ] || [ ! -f "$bunny/tum/depth.txt" ] || [ ! -f "$bunny/scans.rawlog" ]; then
  echo "note: shared primesense-bunny data not found under '${data}'; its checks skipped" >&2
else
  bunny_flags=(--intrinsics 542,540.5,320,240 --depth-scale 1000)
  # Without a pose file every view sits at the same pose: say what is missing.
  expect_input_error "give the camera poses (--poses, a TUM file) or the object.s region (--crop)" "$ICRKIT" reconstruct "$bunny/tum" -o "$work/bunny_noposes" \
    "${bunny_flags[@]}"
  "$ICRKIT" reconstruct "$bunny/tum" -o "$work/bunny_folder" "${bunny_flags[@]}" --poses "$bunny/tum/reported.txt" \
    --gt-poses "$bunny/tum/groundtruth.txt" --no-registration --no-meshes --json >"$work/bunny_folder.json" \
    2>"$work/err" || fail "reconstruct of the bunny folder failed: $(cat "$work/err")"
  "$ICRKIT" convert "$bunny/tum" "$work/bunny.rawlog" "${bunny_flags[@]}" --poses "$bunny/tum/reported.txt" -q \
    >/dev/null 2>"$work/err" || fail "convert of the bunny folder failed: $(cat "$work/err")"
  "$ICRKIT" reconstruct "$work/bunny.rawlog" -o "$work/bunny_rawlog" --gt-poses "$bunny/ground_truth.txt" \
    --no-registration --no-meshes --json >"$work/bunny_rawlog.json" 2>"$work/err" ||
    fail "reconstruct of the converted bunny rawlog failed: $(cat "$work/err")"
  cmp -s "$work/bunny_folder/poses.txt" "$work/bunny_rawlog/poses.txt" || fail "bunny poses.txt: folder != rawlog"
  cmp -s "$work/bunny_folder/cloud.ply" "$work/bunny_rawlog/cloud.ply" || fail "bunny cloud.ply: folder != rawlog"
  py "
import json
f = json.load(open('$work/bunny_folder.json')); r = json.load(open('$work/bunny_rawlog.json'))
assert f['scans'] == r['scans'] == 18, (f['scans'], r['scans'])
assert f['poses_orthonormalised'] == 18, f['poses_orthonormalised']  # 9-digit quaternions
# The same ground truth in optical (folder) and MRPT (rawlog) axes.
ef, er = f['registration_error']['reported']['raw'], r['registration_error']['reported']['raw']
for k in ef:
    assert abs(ef[k] - er[k]) < 1e-4, (k, ef[k], er[k])
" || fail "bunny folder and rawlog summaries disagree"
  # The recorded rawlog: its sensorPose matrices are either within the
  # documented tolerance (loaded and counted) or refused naming the scan.
  "$ICRKIT" reconstruct "$bunny/scans.rawlog" -o "$work/bunny_recorded" --no-registration --no-meshes --json \
    >"$work/bunny_recorded.json" 2>"$work/err"
  code=$?
  if [ "$code" -eq 0 ]; then
    [ "$(json_field "['poses_orthonormalised']" <"$work/bunny_recorded.json")" -eq 18 ] ||
      fail "the bunny rawlog's rounded poses were not counted"
  else
    [ "$code" -eq 2 ] && grep -q "scans.rawlog:scan 0: the rotation matrix is not orthonormal" "$work/err" ||
      fail "the bunny rawlog failed without naming the scan: $(cat "$work/err")"
    "$ICRKIT" reconstruct "$bunny/scans.rawlog" -o "$work/bunny_recorded" --no-registration --no-meshes --json \
      --rotation-tolerance 0.01 >"$work/bunny_recorded.json" 2>"$work/err" ||
      fail "--rotation-tolerance 0.01 did not load the bunny rawlog: $(cat "$work/err")"
    [ "$(json_field "['poses_orthonormalised']" <"$work/bunny_recorded.json")" -eq 18 ] ||
      fail "the bunny rawlog's projected poses were not counted"
  fi
fi

[ "$failures" -eq 0 ] || { echo "$failures check(s) failed" >&2; exit 1; }
echo "cli_reconstruct: all checks passed"
