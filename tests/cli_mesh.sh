#!/usr/bin/env bash
# End-to-end checks of `icrkit mesh`: a sphere sampled here meshes into a
# closed, consistently oriented surface whose vertices are the input points;
# the JSON summary agrees with the file; thread-count independence; normal
# estimation when the input has none; exit code 2 with a one-line message for
# bad arguments and inputs; then the raw scan bun000.ply when present. Needs
# $ICRKIT; exits 77 (skipped) after the self-contained checks without it.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

# check_mesh JSON OUTPUT_PLY INPUT_POINTS: the summary against the file.
check_mesh() {
  local json="$1" ply="$2" points="$3"
  [ "$(wc -l <"$json")" -eq 1 ] || fail "mesh --json printed more than one line: $(head -c 300 "$json")"
  cmp -s "$json" "${ply%.*}.json" || fail "${ply%.*}.json differs from the --json summary"
  PYTHONPATH="$here" py "
import json
from collections import Counter
from plyfile import read
d = json.load(open('$json'))
for key in ('points', 'median_spacing_m', 'radii_m', 'passes', 'triangles', 'used_points', 'unused_points',
            'duplicate_points', 'closed_holes', 'boundary_edges', 'boundary_loops', 'non_manifold_edges',
            'components', 'euler_characteristic', 'normals', 'time_ms'):
    assert key in d, 'summary lacks ' + key
assert d['points'] == $points, (d['points'], $points)
assert d['radii_m'] == sorted(d['radii_m']) and d['radii_m'][0] > 0, d['radii_m']
assert len(d['passes']) == len(d['radii_m'])
v, faces = read('$ply')
assert len(v['x'][1]) == d['points'], 'vertices are not the input points'
assert all(k in v for k in ('nx', 'ny', 'nz')), 'the mesh has no vertex normals'
assert len(faces) == d['triangles'], (len(faces), d['triangles'])
used = set(i for f in faces for i in f)
assert len(used) == d['used_points'] and d['used_points'] + d['unused_points'] == d['points']
directed = Counter((f[k], f[(k + 1) % 3]) for f in faces for k in range(3))
assert max(directed.values()) == 1, 'a directed edge appears twice: inconsistent orientation'
undirected = Counter(tuple(sorted(e)) for e in directed.elements())
assert max(undirected.values()) <= 2 and d['non_manifold_edges'] == 0, 'non-manifold edge'
assert sum(1 for c in undirected.values() if c == 1) == d['boundary_edges']
assert d['euler_characteristic'] == len(used) - len(undirected) + len(faces)
" || fail "mesh summary or output inconsistent for $ply"
}

expect_exit 0 "$ICRKIT" mesh --help
grep -q -- "--radii" "$work/out" && grep -q -- "--estimate-normals" "$work/out" || fail "mesh --help lacks its options"

# --- A sphere generated here: 2000 points on a Fibonacci spiral, radius 5 cm,
# with their exact outward normals, as ASCII PLY.
py "
import math
n = 2000
with open('$work/sphere.ply', 'w') as out:
    out.write('ply\nformat ascii 1.0\nelement vertex %d\n' % n)
    out.write(''.join('property double %s\n' % p for p in ('x', 'y', 'z', 'nx', 'ny', 'nz')))
    out.write('end_header\n')
    for i in range(n):
        z = 1 - (2 * i + 1) / n
        r, phi = math.sqrt(1 - z * z), i * math.pi * (3 - math.sqrt(5))
        x, y = r * math.cos(phi), r * math.sin(phi)
        out.write('%.17g %.17g %.17g %.17g %.17g %.17g\n' % (0.05 * x, 0.05 * y, 0.05 * z, x, y, z))
" || { echo "could not generate the test cloud" >&2; exit 1; }
sphere="$work/sphere.ply"

"$ICRKIT" mesh "$sphere" -o "$work/sphere_mesh.ply" --json >"$work/sphere.json" 2>"$work/err" ||
  fail "mesh on $sphere failed: $(cat "$work/err")"
check_mesh "$work/sphere.json" "$work/sphere_mesh.ply" 2000
PYTHONPATH="$here" py "
import json
from plyfile import read
d = json.load(open('$work/sphere.json'))
assert d['normals'] == 'input'
assert d['used_points'] == 2000 and d['boundary_edges'] == 0 and d['components'] == 1, d
assert d['euler_characteristic'] == 2, d['euler_characteristic']
# the default radii on an evenly sampled surface: 1.5 and 2.5 times the median spacing
assert [round(r / d['median_spacing_m'], 9) for r in d['radii_m']] == [1.5, 2.5], d['radii_m']
v, faces = read('$work/sphere_mesh.ply')
src = [l.split() for l in open('$work/sphere.ply').read().split('end_header\n')[1].splitlines()]
assert all(float(s[0]) == x for s, x in zip(src, v['x'][1])), 'vertex order or values changed'
# outward winding: each face's normal points away from the centre
for a, b, c in faces:
    p = [(v['x'][1][i], v['y'][1][i], v['z'][1][i]) for i in (a, b, c)]
    u = [p[1][k] - p[0][k] for k in range(3)]
    w = [p[2][k] - p[0][k] for k in range(3)]
    n = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
    assert sum(n[k] * p[0][k] for k in range(3)) > 0, 'inward face'
" || fail "the sphere did not mesh into a closed outward surface"

# human output; the same file whatever the thread count
"$ICRKIT" mesh "$sphere" -o "$work/t1.ply" --threads 1 >"$work/human" 2>/dev/null || fail "mesh --threads 1 failed"
grep -q '^boundary_loops: ' "$work/human" || fail "human summary lacks boundary_loops: $(cat "$work/human")"
cmp -s "$work/sphere_mesh.ply" "$work/t1.ply" || fail "mesh gave different outputs on 1 thread and on all cores"

# explicit radii, in metres and relative
"$ICRKIT" mesh "$sphere" -o "$work/m.ply" --radii 0.004,0.008 --json -q >"$work/m.json" || fail "mesh --radii metres failed"
py "
import json
d = json.load(open('$work/m.json'))
assert d['radii_m'] == [0.004, 0.008], d['radii_m']
" || fail "--radii in metres not in the summary"
"$ICRKIT" mesh "$sphere" -o "$work/r.ply" --radii 3x,1.5x --json -q >"$work/r.json" || fail "mesh --radii 3x,1.5x failed"
py "
import json
d = json.load(open('$work/r.json'))
assert [round(r / d['median_spacing_m'], 9) for r in d['radii_m']] == [1.5, 3], d['radii_m']
" || fail "relative --radii not sorted or not relative to the spacing"

# no normals in the input: estimated, said on stderr
py "
for line in open('$work/sphere.ply').read().split('end_header\n')[1].splitlines():
    print(' '.join(line.split()[:3]))
" >"$work/sphere.xyz"
"$ICRKIT" mesh "$work/sphere.xyz" -o "$work/est.ply" --json >"$work/est.json" 2>"$work/err" ||
  fail "mesh of a cloud without normals failed: $(cat "$work/err")"
grep -q "no normals: estimating" "$work/err" || fail "no note about estimated normals: $(cat "$work/err")"
check_mesh "$work/est.json" "$work/est.ply" 2000
py "
import json
d = json.load(open('$work/est.json'))
assert d['normals'] == 'estimated' and d['boundary_edges'] == 0 and d['euler_characteristic'] == 2, d
" || fail "estimated normals did not give the closed sphere"

# a fused cloud's per-point viewpoints orient the estimated normals
py "
import math
pts = [(0.002 * i, 0.002 * j, 0.0002 * math.sin(i * j)) for i in range(40) for j in range(40)]
with open('$work/fused.ply', 'w') as out:
    out.write('ply\nformat ascii 1.0\nelement vertex %d\n' % len(pts))
    out.write(''.join('property double %s\n' % p for p in ('x', 'y', 'z', 'viewpoint_x', 'viewpoint_y', 'viewpoint_z')))
    out.write('end_header\n')
    for x, y, z in pts:
        out.write('%r %r %r 0.04 0.04 %r\n' % (x, y, z, -0.5 if x < 0.04 else -0.6))
"
"$ICRKIT" mesh "$work/fused.ply" -o "$work/fused_mesh.ply" --json -q >"$work/fused.json" 2>"$work/err" ||
  fail "mesh of a fused cloud failed: $(cat "$work/err")"
PYTHONPATH="$here" py "
import json
from plyfile import read
d = json.load(open('$work/fused.json'))
assert d['normals'].startswith('estimated, facing'), d['normals']
v, faces = read('$work/fused_mesh.ply')
assert max(v['nz'][1]) < 0, 'a normal does not face its viewpoint below the plane'
assert d['used_points'] > 0.95 * d['points'], d
" || fail "per-point viewpoints did not orient the normals"

# --- A noise layer (a sphere whose points are moved along their normals by
# Gaussian noise of half the spacing, as many overlapping views leave it):
# thinned for the pivoting, the thinned points put back into the faces, so
# the mesh is closed and nearly every point a vertex; --no-reinsert leaves
# them unused.
py "
import math, random
random.seed(4)
n = 6000
with open('$work/layer.ply', 'w') as out:
    out.write('ply\nformat ascii 1.0\nelement vertex %d\n' % n)
    out.write(''.join('property double %s\n' % p for p in ('x', 'y', 'z', 'nx', 'ny', 'nz')))
    out.write('end_header\n')
    spacing = 0.05 * math.sqrt(4 * math.pi / n)
    for i in range(n):
        z = 1 - (2 * i + 1) / n
        r, phi = math.sqrt(1 - z * z), i * math.pi * (3 - math.sqrt(5))
        x, y = r * math.cos(phi), r * math.sin(phi)
        h = 0.05 + random.gauss(0.0, 0.5 * spacing)
        out.write('%.17g %.17g %.17g %.17g %.17g %.17g\n' % (h * x, h * y, h * z, x, y, z))
" || { echo "could not generate the noisy layer" >&2; exit 1; }
"$ICRKIT" mesh "$work/layer.ply" -o "$work/layer_mesh.ply" --json -q >"$work/layer.json" 2>"$work/err" ||
  fail "mesh of the noisy layer failed: $(cat "$work/err")"
check_mesh "$work/layer.json" "$work/layer_mesh.ply" 6000
"$ICRKIT" mesh "$work/layer.ply" -o "$work/layer_bare.ply" --no-reinsert --json -q >"$work/layer_bare.json" \
  2>"$work/err" || fail "mesh --no-reinsert failed: $(cat "$work/err")"
check_mesh "$work/layer_bare.json" "$work/layer_bare.ply" 6000
py "
import json
d = json.load(open('$work/layer.json'))
bare = json.load(open('$work/layer_bare.json'))
assert d['thinned_points'] > 3000 and d['reinserted_points'] >= 0.8 * d['thinned_points'], d
assert d['used_points'] >= 0.85 * d['points'], d
assert d['boundary_loops'] == 0 and d['components'] == 1 and d['euler_characteristic'] == 2, d
assert bare['reinserted_points'] == 0 and bare['used_points'] == d['used_points'] - d['reinserted_points'], bare
assert bare['boundary_loops'] == 0 and bare['euler_characteristic'] == 2, bare
" || fail "the noise layer did not mesh closed with its thinned points put back: $(cat "$work/layer.json")"

# --- Bad arguments and inputs: exit 2, one line, no output left behind
printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n0 0 0 0 0 1\n1 0 0 0 0 1\n' >"$work/two.ply"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n0 0 0 0 0 1\n1 0 0 0 0 0\n0 1 0 0 0 1\n' >"$work/zero_normal.ply"
rm -f "$work/bad.ply" "$work/bad.json"
expect_input_error "--radii.*positive" "$ICRKIT" mesh "$sphere" -o "$work/bad.ply" --radii 0
expect_input_error "--radii.*positive" "$ICRKIT" mesh "$sphere" -o "$work/bad.ply" --radii 0.004,-1
expect_input_error "--radii.*expected metres" "$ICRKIT" mesh "$sphere" -o "$work/bad.ply" --radii abc
expect_input_error "--radii.*in metres or all as multiples" "$ICRKIT" mesh "$sphere" -o "$work/bad.ply" --radii 2x,0.004
expect_input_error "--viewpoint" "$ICRKIT" mesh "$sphere" -o "$work/bad.ply" --viewpoint 1,2
expect_input_error "two.ply.*at least 3 points" "$ICRKIT" mesh "$work/two.ply" -o "$work/bad.ply"
expect_input_error "zero_normal.ply.*at least 3 points with a non-zero normal" "$ICRKIT" mesh "$work/zero_normal.ply" -o "$work/bad.ply"
expect_input_error "missing.ply" "$ICRKIT" mesh "$work/missing.ply" -o "$work/bad.ply"
expect_input_error "bad.json" "$ICRKIT" mesh "$sphere" -o "$work/bad.json"
[ ! -e "$work/bad.ply" ] && [ ! -e "$work/bad.json" ] || fail "a failed mesh left an output behind"
[ -z "$(ls -A "$work" | grep '\.tmp')" ] || fail "a temporary file was left behind"

# --- The raw scan bun000 (normals estimated towards the scanner at the origin)
data="${ICRKIT_SHARED_DATA_DIR:-}"
scan="$data/stanford-bunny/bun000.ply"
if [ -z "$data" ] || [ ! -f "$scan" ]; then
  echo "note: $scan not found; real-data checks skipped" >&2
  [ "$failures" -eq 0 ] || { echo "$failures check(s) failed" >&2; exit 1; }
  exit 77
fi
"$ICRKIT" mesh "$scan" -o "$work/bun000.ply" --viewpoint 0,0,0 --json -q >"$work/bun000.json" 2>"$work/err" ||
  fail "mesh on $scan failed: $(cat "$work/err")"
check_mesh "$work/bun000.json" "$work/bun000.ply" 40256
py "
import json
d = json.load(open('$work/bun000.json'))
assert d['used_points'] >= 0.97 * d['points'], d['used_points']
assert d['boundary_loops'] <= 100, d['boundary_loops']
" || fail "bun000 meshed poorly: $(cat "$work/bun000.json")"

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi
echo "all mesh CLI checks passed"
