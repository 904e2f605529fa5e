#!/usr/bin/env bash
# End-to-end checks of `icrkit smooth`: the JSON summary, the output's
# per-point properties, that a noisy plane gets flatter, thread-count
# independence, and exit code 2 with a one-line message for bad arguments
# and inputs; then the shared real scans (bun000.ply, the PCL views) when
# present. Needs $ICRKIT (the binary); exits 77 (skipped) after the
# self-contained checks when none of the shared scans is there.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

# check_summary JSON OUTPUT_PLY POINTS: the summary's fields, the file next to
# the output, and the output's properties agreeing with the summary.
check_summary() {
  local json="$1" ply="$2" points="$3"
  [ "$(wc -l <"$json")" -eq 1 ] || fail "smooth --json printed more than one line: $(head -c 300 "$json")"
  cmp -s "$json" "${ply%.*}.json" || fail "${ply%.*}.json differs from the --json summary"
  PYTHONPATH="$here" py "
import json, math, sys
from plyfile import vertex_properties
d = json.load(open('$json'))
for key in ('points', 'radius_m', 'median_spacing_m', 'passes', 'small_windows', 'mean_cardinality',
            'mean_flatness', 'thresholds', 'excluded', 'mean_displacement_m', 'max_displacement_m', 'time_ms'):
    assert key in d, 'summary lacks ' + key
assert d['points'] == $points, (d['points'], $points)
assert d['radius_m'] > 0 and d['median_spacing_m'] > 0 and d['passes'] >= 1
assert 0 <= d['small_windows'] <= d['points']
e = d['excluded']
for key in ('total', 'cardinality_only', 'flatness_only', 'both'):
    assert key in e, 'excluded lacks ' + key
assert e['total'] == e['cardinality_only'] + e['flatness_only'] + e['both'] <= d['points'], e
assert 'cardinality' in d['thresholds'] and 'flatness' in d['thresholds']
assert 0 <= d['mean_displacement_m'] <= d['max_displacement_m']
assert d['time_ms']['total'] >= d['time_ms']['smooth'] > 0
p = vertex_properties('$ply')
want = {'x': 'double', 'y': 'double', 'z': 'double', 'nx': 'double', 'ny': 'double', 'nz': 'double',
        'cardinality': 'int', 'flatness': 'float', 'displacement': 'float', 'excluded': 'uchar'}
for name, t in want.items():
    assert name in p, '$ply lacks property ' + name
    assert p[name][0] == t, (name, p[name][0], t)
n = len(p['x'][1])
assert n == d['points'], (n, d['points'])
card, flat, disp, excl = (p[k][1] for k in ('cardinality', 'flatness', 'displacement', 'excluded'))
assert abs(sum(card) / n - d['mean_cardinality']) <= 1e-9 * d['mean_cardinality'], 'cardinality vs summary'
assert sum(excl) == e['total'] and set(excl) <= {0, 1}, 'excluded vs summary'
assert abs(max(disp) - d['max_displacement_m']) <= 1e-6 * d['max_displacement_m'] + 1e-12, 'displacement vs summary'
assert sum(1 for c in card if c < 3) == d['small_windows'], 'small windows vs cardinality'
# every point with a full window has a unit normal
for i in range(n):
    if card[i] >= 3:
        norm = math.sqrt(p['nx'][1][i] ** 2 + p['ny'][1][i] ** 2 + p['nz'][1][i] ** 2)
        assert abs(norm - 1) < 1e-9, ('normal', i, norm)
" || fail "smooth summary or output inconsistent for $ply"
}

expect_exit 0 "$ICRKIT" smooth --help
grep -q -- "--radius" "$work/out" && grep -q -- "--viewpoint" "$work/out" || fail "smooth --help lacks its options"

# --- A noisy plane generated here: 60 x 60 points 2 mm apart in z = 0 with
# deterministic pseudo-noise of up to 0.5 mm in z.
py "
import math
with open('$work/plane.xyz', 'w') as out:
    for i in range(60):
        for j in range(60):
            k = i * 60 + j
            noise = 0.0005 * (math.sin(k * 12.9898) * 43758.5453 % 1.0 * 2 - 1)
            out.write('%.9g %.9g %.9g\n' % (0.002 * i, 0.002 * j, noise))
" || { echo "could not generate the test cloud" >&2; exit 1; }

plane="$work/plane.xyz"
"$ICRKIT" smooth "$plane" -o "$work/plane.ply" --viewpoint 0.06,0.06,1 --json >"$work/plane.json" 2>"$work/err" ||
  fail "smooth on $plane failed: $(cat "$work/err")"
check_summary "$work/plane.json" "$work/plane.ply" 3600
PYTHONPATH="$here" py "
import json
from plyfile import vertex_properties
d = json.load(open('$work/plane.json'))
# default radius: 4 x the median spacing (2 mm)
assert abs(d['median_spacing_m'] - 0.002) < 1e-4, d['median_spacing_m']
assert abs(d['radius_m'] - 4 * d['median_spacing_m']) < 1e-12, d['radius_m']
assert d['passes'] == 1 and d['small_windows'] == 0
# the default rule: robust thresholds, far below the means on a clean plane
assert d['preselection'] == 'default', d['preselection']
assert d['thresholds']['flatness_source'] == 'robust', d['thresholds']
assert d['thresholds']['flatness'] < d['mean_flatness'] and d['excluded']['total'] < 0.05 * d['points'], d
before = [float(l.split()[2]) for l in open('$work/plane.xyz')]
p = vertex_properties('$work/plane.ply')
after = p['z'][1]
rms = lambda v: (sum(x * x for x in v) / len(v)) ** 0.5
assert rms(after) < 0.6 * rms(before), ('not flatter', rms(before), rms(after))
# the viewpoint is above the plane: every normal points up
assert min(p['nz'][1]) > 0.9, min(p['nz'][1])
# points move along z only (the plane's normal), by at most the noise
assert max(abs(a - b) for a, b in zip(p['x'][1], [0.002 * (k // 60) for k in range(3600)])) < 1e-4
" || fail "smoothing did not flatten the noisy plane as expected"

# human output: key: value lines, nothing but the summary on stdout
"$ICRKIT" smooth "$plane" -o "$work/human.ply" >"$work/human" 2>/dev/null || fail "smooth without --json failed"
grep -q '^radius_m: ' "$work/human" && grep -q '^excluded.flatness_only: ' "$work/human" ||
  fail "human summary lacks radius_m or excluded.flatness_only: $(cat "$work/human")"

# the same result whatever the thread count
"$ICRKIT" smooth "$plane" -o "$work/t1.ply" --threads 1 -q >/dev/null || fail "smooth --threads 1 failed"
cmp -s "$work/human.ply" "$work/t1.ply" || fail "smooth gave different outputs on 1 thread and on all cores"

# options: metres, passes, explicit thresholds, no preselection, other output formats
"$ICRKIT" smooth "$plane" -o "$work/opt.ply" --radius 0.005 --passes 3 --cardinality-threshold 10 \
  --flatness-threshold 2.5 --json -q >"$work/opt.json" || fail "smooth with explicit options failed"
py "
import json
d = json.load(open('$work/opt.json'))
assert d['radius_m'] == 0.005 and d['passes'] == 3, d
assert d['thresholds']['cardinality'] == 10 and d['thresholds']['flatness'] == 2.5, d['thresholds']
" || fail "explicit --radius/--passes/thresholds not in the summary"
"$ICRKIT" smooth "$plane" -o "$work/side.ply" --window-normal-angle 1.5708 --json -q >"$work/side.json" ||
  fail "smooth --window-normal-angle failed"
py "
import json
d = json.load(open('$work/side.json'))
assert d['window_normal_angle_rad'] == 1.5708, d
" || fail "--window-normal-angle not in the summary"
"$ICRKIT" smooth "$plane" -o "$work/f.ply" --radius 2x --json -q >"$work/f.json" || fail "smooth --radius 2x failed"
py "
import json
d = json.load(open('$work/f.json'))
assert abs(d['radius_m'] - 2 * d['median_spacing_m']) < 1e-12, d
" || fail "--radius 2x is not twice the median spacing"
"$ICRKIT" smooth "$plane" -o "$work/nopre.ply" --no-preselection -q >/dev/null || fail "smooth --no-preselection failed"
# One spelling (issue 20): the older --no-preselect is a usage error now.
"$ICRKIT" smooth "$plane" -o "$work/nopre_old.ply" --no-preselect -q >/dev/null 2>&1
status=$?
[ "$status" -eq 2 ] || fail "smooth --no-preselect exited $status, expected 2 (usage error)"
head -c 1000 "$work/nopre.ply" | grep -aq "property uchar excluded" && fail "--no-preselection still wrote 'excluded'"
"$ICRKIT" smooth "$plane" -o "$work/none.ply" --preselection none -q >/dev/null || fail "smooth --preselection none failed"
head -c 1000 "$work/none.ply" | grep -aq "property uchar excluded" && fail "--preselection none still wrote 'excluded'"
"$ICRKIT" smooth "$plane" -o "$work/paper.ply" --preselection paper-mean --json -q >"$work/paper.json" ||
  fail "smooth --preselection paper-mean failed"
py "
import json
d = json.load(open('$work/paper.json'))
assert d['preselection'] == 'paper-mean' and d['thresholds']['flatness_source'] == 'mean', d
assert abs(d['thresholds']['cardinality'] - d['mean_cardinality']) < 1e-12
assert abs(d['thresholds']['flatness'] - d['mean_flatness']) < 1e-12
" || fail "--preselection paper-mean: thresholds are not the means"
expect_exit 2 "$ICRKIT" smooth "$plane" -o "$work/x.ply" --preselection mean
head -c 1000 "$work/nopre.ply" | grep -aq "property int cardinality" || fail "--no-preselection lost 'cardinality'"
"$ICRKIT" smooth "$plane" -o "$work/out.pcd" -q >/dev/null || fail "smooth to .pcd failed"
head -c 300 "$work/out.pcd" | grep -aq "^FIELDS .*cardinality flatness displacement normal_sigma position_sigma excluded" ||
  fail "the .pcd output lacks the attributes"
"$ICRKIT" smooth "$plane" -o "$work/out.xyz" -q >/dev/null || fail "smooth to .xyz failed"
[ "$(wc -l <"$work/out.xyz")" -eq 3600 ] || fail "the .xyz output does not hold 3600 points"
[ -f "$work/out.json" ] || fail "no summary next to out.xyz"

# --- Bad arguments and inputs: exit 2, one line, no output left behind
: >"$work/empty.xyz"
rm -f "$work/bad.ply" "$work/bad.json"
expect_input_error "--radius.*positive" "$ICRKIT" smooth "$plane" -o "$work/bad.ply" --radius 0
expect_input_error "--radius.*positive" "$ICRKIT" smooth "$plane" -o "$work/bad.ply" --radius -1x
expect_input_error "--radius.*positive" "$ICRKIT" smooth "$plane" -o "$work/bad.ply" --radius 0x
expect_input_error "--radius.*expected metres" "$ICRKIT" smooth "$plane" -o "$work/bad.ply" --radius 4y
expect_input_error "--passes" "$ICRKIT" smooth "$plane" -o "$work/bad.ply" --passes 0
expect_input_error "--viewpoint" "$ICRKIT" smooth "$plane" -o "$work/bad.ply" --viewpoint 1,2
expect_input_error "--flatness-threshold" "$ICRKIT" smooth "$plane" -o "$work/bad.ply" --flatness-threshold -1
expect_input_error "--window-normal-angle.*> 0" "$ICRKIT" smooth "$plane" -o "$work/bad.ply" --window-normal-angle 0
expect_input_error "--window-normal-angle.*> 0" "$ICRKIT" smooth "$plane" -o "$work/bad.ply" --window-normal-angle -1
expect_input_error "empty.xyz.*empty" "$ICRKIT" smooth "$work/empty.xyz" -o "$work/bad.ply"
expect_input_error "missing.xyz" "$ICRKIT" smooth "$work/missing.xyz" -o "$work/bad.ply"
expect_input_error "bad.txt" "$ICRKIT" smooth "$plane" -o "$work/bad.txt"
[ ! -e "$work/bad.ply" ] && [ ! -e "$work/bad.json" ] || fail "a failed smooth left an output behind"
[ -z "$(ls -A "$work" | grep '\.tmp')" ] || fail "a temporary file was left behind"

# --- The shared real scans
data="${ICRKIT_SHARED_DATA_DIR:-}"
found=0
for scan in "$data/stanford-bunny/bun000.ply" "$data"/pcl-views/*.pcd; do
  if [ -z "$data" ] || [ ! -f "$scan" ]; then
    echo "note: $scan not found; skipped" >&2
    continue
  fi
  found=$((found + 1))
  name="$(basename "$scan")"
  points=$("$ICRKIT" info "$scan" --json -q | py "import json, sys; print(json.load(sys.stdin)['vertices'])")
  out="$work/real_${name%.*}.ply"
  "$ICRKIT" smooth "$scan" -o "$out" --json -q >"$work/real.json" 2>"$work/err" ||
    { fail "smooth on $scan failed: $(cat "$work/err")"; continue; }
  check_summary "$work/real.json" "$out" "$points"
done

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi
if [ "$found" -eq 0 ]; then
  echo "note: no shared scans under '${data}'; generated-cloud checks passed, real-data checks skipped" >&2
  exit 77
fi
echo "all smooth CLI checks passed"
