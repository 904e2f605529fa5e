#!/usr/bin/env bash
# End-to-end checks of `icrkit icr` and `icrkit grasps`: outputs, JSON,
# exit codes and one-line errors on meshes generated here, then parity with
# the reference ICR library's regions on the shared sphere model. Needs
# $ICRKIT (the binary); exits 77 (skipped) after the self-contained checks
# when the shared ICR data is absent.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

for cmd in icr grasps; do
  expect_exit 0 "$ICRKIT" $cmd --help
done
"$ICRKIT" icr --help | grep -q "lowest" || fail "icr --help does not say which finger a shared vertex gets"

# --- Meshes generated here: an icosphere (radius 0.05 m, 642 vertices) as
# OBJ without normals, and as ASCII PLY with exact normals and an `excluded`
# attribute marking the cap z > 0.04.
py_meshes "
p, n, f = testmeshes.icosphere()
excluded = [1 if q[2] > 0.04 else 0 for q in p]
testmeshes.write_obj('$work/ico.obj', p, f)
testmeshes.write_ascii_ply('$work/ico.ply', p, n, f, excluded)
open('$work/excluded_count', 'w').write(str(sum(excluded)))
" || { echo "could not generate the test meshes" >&2; exit 1; }
ico_obj="$work/ico.obj"
ico_ply="$work/ico.ply"

# No normals: a one-line error naming the file, for the bundled tetrahedron
# and the generated OBJ, unless --compute-normals.
tet="$root/datasets/tetrahedron.obj"
expect_input_error "tetrahedron.obj.*normals" "$ICRKIT" icr "$tet" --contacts 0,1,2,3 -o "$work/tet.ply"
expect_input_error "ico.obj.*--compute-normals" "$ICRKIT" icr "$ico_obj" --contacts 0,1,2,3 -o "$work/ico_regions.ply"
expect_input_error "ico.obj.*normals" "$ICRKIT" grasps "$ico_obj" --count 1

# grasps -> icr on the generated sphere with computed normals
"$ICRKIT" grasps "$ico_obj" --compute-normals --count 1 --seed 3 --json >"$work/g.json" 2>"$work/err" ||
  fail "grasps on $ico_obj failed: $(cat "$work/err")"
[ "$(wc -l <"$work/g.json")" -eq 1 ] || fail "grasps --json printed more than one line"
for key in count attempts rejected_by_precheck hulls_built grasps_per_second time_ms grasps; do
  json_field "['$key']" <"$work/g.json" >/dev/null 2>&1 || fail "grasps --json lacks '$key'"
done
contacts=$(json_field "[\"grasps\"][0][\"contacts\"]" <"$work/g.json" | tr -d '[] ')
sampled_epsilon=$(json_field "['grasps'][0]['epsilon']" <"$work/g.json")
out="$work/ico_regions.ply"
"$ICRKIT" icr "$ico_obj" --compute-normals --contacts "$contacts" -o "$out" --json >"$work/icr.json" 2>"$work/err" ||
  fail "icr on $ico_obj with contacts $contacts failed: $(cat "$work/err")"
[ "$(wc -l <"$work/icr.json")" -eq 1 ] || fail "icr --json printed more than one line"
for key in epsilon lambda_m tws_radius gws_facets regions time_ms contacts model mesh output; do
  json_field "['$key']" <"$work/icr.json" >/dev/null 2>&1 || fail "icr --json lacks '$key'"
done
for key in hull zones growth total; do
  json_field "['time_ms']['$key']" <"$work/icr.json" >/dev/null 2>&1 || fail "icr --json lacks time_ms.$key"
done
py "
import json, sys
d = json.load(open('$work/icr.json'))
contacts = [int(c) for c in '$contacts'.split(',')]
assert d['contacts'] == contacts, d['contacts']
assert abs(d['epsilon'] - $sampled_epsilon) <= 1e-9 * $sampled_epsilon, (d['epsilon'], $sampled_epsilon)
assert abs(d['tws_radius'] - 0.5 * d['epsilon']) <= 1e-12
assert [r['finger'] for r in d['regions']] == list(range(len(contacts)))
for r, c in zip(d['regions'], contacts):
    assert r['contact'] == c and c in r['vertices'] and r['vertices'] == sorted(r['vertices']) and r['area_m2'] > 0, r
assert d['model']['type'] == 'frictional' and d['model']['mu'] == 0.8 and d['model']['edges'] == 8
" || fail "icr summary on the generated sphere is inconsistent"
# the summary file next to the PLY holds exactly what --json printed
cmp -s "$work/icr.json" "${out%.ply}.json" || fail "${out%.ply}.json differs from the --json summary"
head -c 2000 "$out" | grep -aq "property int region" || fail "$out has no int 'region' vertex property"
head -c 2000 "$out" | grep -aq "property uchar red" || fail "$out has no vertex colours"
"$ICRKIT" info "$out" --json | json_field "['attributes']" | grep -q "region" || fail "icrkit info does not see 'region'"
# recommended contacts: in the JSON (a region vertex) and marked in the PLY
py "
import json
d = json.load(open('$work/icr.json'))
for r in d['regions']:
    rec = r['recommended']
    assert rec['vertex'] in r['vertices'] and rec['depth_m'] >= 0, r
assert d['conservative'] is None and d['patch'] is None
" || fail "icr summary: recommended contacts missing or outside their regions"
head -c 2000 "$out" | grep -aq "property int recommended" || fail "$out has no int 'recommended' vertex property"

# conservative growth: fixed bounds on a mesh without sigmas; refused clearly
# without them, for K < 0 and for a patch radius <= 0
"$ICRKIT" icr "$ico_obj" --compute-normals --contacts "$contacts" --normal-uncertainty 0.005 --position-uncertainty 0.0001 \
  -o "$work/cons.ply" --json >"$work/cons.json" 2>"$work/err" || fail "icr with fixed uncertainty bounds failed: $(cat "$work/err")"
py "
import json
plain = json.load(open('$work/icr.json'))
cons = json.load(open('$work/cons.json'))
assert cons['conservative'] == {'sigmas': 1.0, 'normal_uncertainty_rad': 0.005, 'position_uncertainty_m': 0.0001}, cons['conservative']
for p, c in zip(plain['regions'], cons['regions']):
    assert set(c['vertices']) <= set(p['vertices']), (len(p['vertices']), len(c['vertices']))
assert sum(len(c['vertices']) for c in cons['regions']) < sum(len(p['vertices']) for p in plain['regions'])
" || fail "conservative regions are not smaller subsets of the plain ones"
expect_input_error "normal_sigma and position_sigma" "$ICRKIT" icr "$ico_obj" --compute-normals --contacts "$contacts" \
  --conservative -o "$work/x.ply"
expect_input_error "--conservative.*>= 0" "$ICRKIT" icr "$ico_obj" --compute-normals --contacts "$contacts" \
  --conservative=-1 --normal-uncertainty 0.01 --position-uncertainty 0.0001 -o "$work/x.ply"
expect_input_error "--patch-radius.*> 0" "$ICRKIT" icr "$ico_obj" --compute-normals --contacts "$contacts" \
  --patch-radius 0 -o "$work/x.ply"
[ ! -e "$work/x.ply" ] || fail "a refused icr left an output behind"
"$ICRKIT" icr "$ico_obj" --compute-normals --contacts "$contacts" --patch-radius 0.012 -o "$work/patch.ply" --json \
  >"$work/patch.json" 2>"$work/err" || fail "icr --patch-radius failed: $(cat "$work/err")"
json_field "['patch']['radius_m']" <"$work/patch.json" | grep -q "0.012" || fail "icr --patch-radius: no patch in the summary"

# human output: one line per finger
"$ICRKIT" icr "$ico_obj" --compute-normals --contacts "$contacts" -o "$out" >"$work/human" 2>&1 ||
  fail "icr without --json failed"
[ "$(grep -c '^finger ' "$work/human")" -eq 4 ] || fail "human summary lacks one line per finger: $(cat "$work/human")"

# The same grasp given as points, slightly off the vertices, snaps back to it.
points=$(py "
lines = [l.split() for l in open('$ico_obj') if l.startswith('v ')]
print(';'.join(','.join('%.9g' % (float(x) * 1.001) for x in lines[int(c)][1:]) for c in '$contacts'.split(',')))")
"$ICRKIT" icr "$ico_obj" --compute-normals --contact-points "$points" -o "$work/points.ply" --json >"$work/points.json" 2>"$work/err" ||
  fail "icr --contact-points failed: $(cat "$work/err")"
[ "$(json_field "['contacts']" <"$work/points.json" | tr -d '[] ')" = "$contacts" ] ||
  fail "--contact-points did not snap to contacts $contacts"
expect_input_error "contact-points" "$ICRKIT" icr "$ico_obj" --compute-normals --contact-points "1,2;3,4,5" -o "$work/x.ply"

# Exclusion: the `excluded` attribute of the PLY is used by itself; a mask
# file overrides it; a grasp on an excluded vertex is refused.
"$ICRKIT" grasps "$ico_ply" --count 20 --json -q >"$work/gx.json" 2>"$work/err" || fail "grasps on $ico_ply failed: $(cat "$work/err")"
py "
import json
d = json.load(open('$work/gx.json'))
assert d['exclusion'] == 'attribute' and d['excluded_vertices'] == $(cat "$work/excluded_count"), d
excluded = {i for i, l in enumerate(open('$ico_ply').read().split('end_header\n')[1].splitlines()[:642]) if l.split()[6] == '1'}
assert not any(c in excluded for g in d['grasps'] for c in g['contacts'])
" || fail "grasps on $ico_ply ignored the 'excluded' attribute"
cap_vertex=$(py "print(next(i for i, l in enumerate(open('$ico_ply').read().split('end_header\n')[1].splitlines()) if l.split()[6] == '1'))")
expect_input_error "ico.ply.*excluded" "$ICRKIT" icr "$ico_ply" --contacts "$cap_vertex,1,2,3" -o "$work/x.ply"
py "print('\n'.join(['0'] * 642))" >"$work/none.mask"
"$ICRKIT" grasps "$ico_ply" --count 1 --exclude "$work/none.mask" --json -q | json_field "['excluded_vertices']" | grep -qx 0 ||
  fail "--exclude did not override the 'excluded' attribute"
printf '0\n1\n' >"$work/short.mask"
expect_input_error "short.mask" "$ICRKIT" grasps "$ico_ply" --exclude "$work/short.mask"
printf '0\n2\n' >"$work/bad.mask"
expect_input_error "bad.mask:line 2" "$ICRKIT" grasps "$ico_ply" --exclude "$work/bad.mask"

# grasps: same seed, same file (whatever the thread count); another seed, another file
"$ICRKIT" grasps "$ico_ply" --count 30 --seed 7 -o "$work/s7a.jsonl" -q >/dev/null || fail "grasps --seed 7 failed"
"$ICRKIT" grasps "$ico_ply" --count 30 --seed 7 -o "$work/s7b.jsonl" -q --threads 1 >/dev/null || fail "grasps --threads 1 failed"
"$ICRKIT" grasps "$ico_ply" --count 30 --seed 8 -o "$work/s8.jsonl" -q >/dev/null || fail "grasps --seed 8 failed"
cmp -s "$work/s7a.jsonl" "$work/s7b.jsonl" || fail "grasps with one seed gave different files"
cmp -s "$work/s7a.jsonl" "$work/s8.jsonl" && fail "grasps with different seeds gave the same file"
py "
lines = open('$work/s7a.jsonl').read().splitlines()
import json
assert len(lines) == 30
for l in lines:
    g = json.loads(l)
    assert sorted(g) == ['contacts', 'epsilon'] and len(set(g['contacts'])) == 4 and g['epsilon'] > 0, g
" || fail "grasps.jsonl is not 30 lines of {contacts, epsilon}"
expect_exit 2 "$ICRKIT" grasps "$ico_ply" --fingers 1
expect_exit 2 "$ICRKIT" grasps "$ico_ply" --count 0
[ -z "$(ls -A "$work" | grep '\.tmp')" ] || fail "a temporary file was left behind"

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi

# --- The shared sphere model and the reference library's regions
data="${ICRKIT_SHARED_DATA_DIR:-}"
sphere="$data/icr-models/sphere.obj"
reference="$data/icr-reference/sphere__frictional_mu0.8_L8_f4_a0.5.json"
if [ -z "$data" ] || [ ! -f "$sphere" ] || [ ! -f "$reference" ]; then
  echo "note: shared ICR data not found under '${data}'; generated-mesh checks passed, reference checks skipped" >&2
  exit 77
fi

contacts=$(py "import json; print(','.join(map(str, json.load(open('$reference'))['grasps'][0]['contacts'])))")
for mode in bfs full; do
  "$ICRKIT" icr "$sphere" --contacts "$contacts" --alpha 0.5 --mode $mode -o "$work/sphere_$mode.ply" --json \
    >"$work/sphere_$mode.json" 2>"$work/err" || fail "icr on $sphere ($mode) failed: $(cat "$work/err")"
  py "
import json
ref = json.load(open('$reference'))['grasps'][0]
d = json.load(open('$work/sphere_$mode.json'))
got = [r['vertices'] for r in d['regions']]
assert got == ref['regions_$mode'], 'regions differ from the reference'
assert d['gws_facets'] == ref['gws_facets'], (d['gws_facets'], ref['gws_facets'])
assert abs(d['epsilon'] - ref['epsilon']) <= 1e-5 * ref['epsilon'], (d['epsilon'], ref['epsilon'])
" || fail "icr --mode $mode on $sphere does not match $reference"
done
# the region property: each vertex carries the lowest finger whose region holds it
"$ICRKIT" convert "$work/sphere_bfs.ply" "$work/sphere_ascii.ply" --ascii -q >/dev/null || fail "could not convert the region PLY"
py "
import json
text = open('$work/sphere_ascii.ply').read()
header, body = text.split('end_header\n')
props = [l.split()[-1] for l in header.splitlines() if l.startswith('property') and 'list' not in l]
n = int([l for l in header.splitlines() if l.startswith('element vertex')][0].split()[2])
col = props.index('region')
region = [int(l.split()[col]) for l in body.splitlines()[:n]]
d = json.load(open('$work/sphere_bfs.json'))
want = [-1] * n
for r in reversed(d['regions']):
    for v in r['vertices']:
        want[v] = r['finger']
assert region == want
" || fail "the 'region' property of the output PLY disagrees with the summary"

# bad grasps: exit 2 with a one-line message, no output written
rm -f "$work/bad.ply"
expect_input_error "at least 2 contacts" "$ICRKIT" icr "$sphere" --contacts 89 -o "$work/bad.ply"
expect_input_error "used by contacts" "$ICRKIT" icr "$sphere" --contacts 89,89,918,375 -o "$work/bad.ply"
expect_input_error "expected 0\.\.1177" "$ICRKIT" icr "$sphere" --contacts 89,267,918,5000 -o "$work/bad.ply"
expect_input_error "alpha" "$ICRKIT" icr "$sphere" --contacts "$contacts" --alpha 1.5 -o "$work/bad.ply"
expect_input_error "TWS must lie inside" "$ICRKIT" icr "$sphere" --contacts "$contacts" --tws-radius 1000 -o "$work/bad.ply"
# four vertices of two neighbouring triangles: all normals nearly parallel
adjacent=$(py "
faces = [tuple(int(t.split('/')[0]) - 1 for t in l.split()[1:4]) for l in open('$sphere') if l.startswith('f ')]
a = faces[0]
b = next(f for f in faces[1:] if len(set(f) & set(a)) == 2)
print(','.join(map(str, list(a) + [v for v in b if v not in a])))")
expect_input_error "not force closure" "$ICRKIT" icr "$sphere" --contacts "$adjacent" -o "$work/bad.ply"
[ ! -e "$work/bad.ply" ] && [ ! -e "$work/bad.json" ] || fail "a failed icr left an output behind"

# grasps on the sphere, then the regions of the first one
"$ICRKIT" grasps "$sphere" --count 5 -o "$work/sphere.jsonl" --json >"$work/sg.json" 2>"$work/err" ||
  fail "grasps on $sphere failed: $(cat "$work/err")"
[ "$(wc -l <"$work/sphere.jsonl")" -eq 5 ] || fail "grasps --count 5 did not write 5 lines"
first=$(head -1 "$work/sphere.jsonl" | json_field "['contacts']" | tr -d '[] ')
expect_exit 0 "$ICRKIT" icr "$sphere" --contacts "$first" -o "$work/first.ply"

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi
echo "all icr/grasps CLI checks passed"
