#!/usr/bin/env bash
# End-to-end: meshes with vertices that no face uses (points left unmeshed, as
# in the Stanford bunny's bun_zipper.ply) through info, grasps, icr, evaluate
# and render. Those vertices keep their indices but are never a contact or in
# a region, their normals (zero, garbage) are never checked, and every result
# is that of the mesh without them, renumbered; naming one as a contact exits
# 2. With the shared data, the bunny itself goes through --compute-normals.
# Needs $ICRKIT.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"
icrkit="${ICRKIT:?set ICRKIT to the icrkit binary}"

# An ellipsoid (642 vertices) with exact normals, and the same with five
# strays: far away, on top of vertex 5, at the centre, on top of vertex 41,
# appended; as PLY with normals and as OBJ without.
py_meshes "
import json, math
p, n, f = testmeshes.icosphere(radius=0.04)
scale = (1.4, 1.0, 0.8)
n = [tuple(q[k] / scale[k] for k in range(3)) for q in n]
n = [tuple(x / math.sqrt(sum(y * y for y in q)) for x in q) for q in n]
p = [tuple(q[k] * scale[k] for k in range(3)) for q in p]
strays = {0: (1.0, 1.0, 1.0), 5: p[5], 300: (0.0, 0.0, 0.0), 41: p[41], len(p): p[0]}
garbage = [(0.0, 0.0, 0.0), (0.0, 0.0, 5.0)]
dp, dn, new_index, stray_index = [], [], [], []
for v in range(len(p) + 1):
    if v in strays:
        stray_index.append(len(dp))
        dp.append(strays[v])
        dn.append(garbage[len(stray_index) % 2])
    if v < len(p):
        new_index.append(len(dp))
        dp.append(p[v])
        dn.append(n[v])
df = [tuple(new_index[i] for i in t) for t in f]
testmeshes.write_ascii_ply('$work/clean.ply', p, n, f)
testmeshes.write_ascii_ply('$work/dirty.ply', dp, dn, df)
testmeshes.write_obj('$work/clean.obj', p, f)
testmeshes.write_obj('$work/dirty.obj', dp, df)
json.dump({'new_index': new_index, 'strays': stray_index}, open('$work/map.json', 'w'))
" || { echo "could not generate the test meshes" >&2; exit 1; }
clean="$work/clean.ply"
dirty="$work/dirty.ply"

# renumber JSON_LIST: the clean mesh's vertex indices in the dirty mesh's numbering.
renumber() {
  py "
import json
m = json.load(open('$work/map.json'))['new_index']
print(','.join(str(m[v]) for v in json.loads('$1')))"
}
stray() { py "import json; print(json.load(open('$work/map.json'))['strays'][$1])"; }

# --- info counts them.
expect_exit 0 "$icrkit" info "$dirty" --json
[ "$(json_field "['unreferenced_vertices']" <"$work/out")" = 5 ] || fail "info: expected 5 unreferenced vertices: $(cat "$work/out")"

# --- grasps: the clean mesh's grasps, renumbered; a stray is never drawn.
for m in clean dirty; do
  "$icrkit" grasps "$work/$m.ply" --count 6 --seed 3 -o "$work/$m.jsonl" --json -q >"$work/$m.grasps.json" 2>"$work/err" ||
    fail "grasps on $m failed: $(cat "$work/err")"
done
py "
import json
m = json.load(open('$work/map.json'))
clean = [json.loads(l) for l in open('$work/clean.jsonl')]
dirty = [json.loads(l) for l in open('$work/dirty.jsonl')]
assert len(dirty) == 6 and len(clean) == 6, (len(clean), len(dirty))
for c, d in zip(clean, dirty):
    assert d['contacts'] == [m['new_index'][v] for v in c['contacts']], (c, d)
    assert d['epsilon'] == c['epsilon'], (c, d)
    assert not set(d['contacts']) & set(m['strays']), d
s = json.load(open('$work/dirty.grasps.json'))
assert s['unreferenced_vertices'] == 5 and s['vertices'] == 647, s
" || fail "grasps on the mesh with strays differ from the clean mesh's"

# --- icr: the clean mesh's regions, renumbered, in both growth modes; the
# strays' `region` is -1.
contacts=$(py "import json; print(','.join(map(str, json.loads(open('$work/clean.jsonl').readline())['contacts'])))")
dirty_contacts=$(renumber "[$contacts]")
for mode in bfs full; do
  expect_exit 0 "$icrkit" icr "$clean" --contacts "$contacts" --mode "$mode" -o "$work/clean_$mode.ply" --quiet
  expect_exit 0 "$icrkit" icr "$dirty" --contacts "$dirty_contacts" --mode "$mode" -o "$work/dirty_$mode.ply" --quiet
  py_meshes "
import json, plyfile
m = json.load(open('$work/map.json'))
clean = json.load(open('$work/clean_$mode.json'))
dirty = json.load(open('$work/dirty_$mode.json'))
assert dirty['epsilon'] == clean['epsilon'] and dirty['lambda_m'] == clean['lambda_m'], (clean, dirty)
assert dirty['unreferenced_vertices'] == 5, dirty
for c, d in zip(clean['regions'], dirty['regions']):
    assert d['vertices'] == [m['new_index'][v] for v in c['vertices']], d['finger']
    assert d['area_m2'] == c['area_m2'], d['finger']
v, _ = plyfile.read('$work/dirty_$mode.ply')
region = v['region'][1]
assert all(region[s] == -1 for s in m['strays']), [region[s] for s in m['strays']]
" || fail "icr --mode $mode on the mesh with strays differs from the clean mesh's"
done

# A stray as a contact: exit 2, naming the vertex.
bad_contacts="$(echo "$dirty_contacts" | cut -d, -f1-2),$(stray 2),$(echo "$dirty_contacts" | cut -d, -f4)"
expect_input_error "vertex $(stray 2)" "$icrkit" icr "$dirty" --contacts "$bad_contacts" -o "$work/bad.ply"
grep -q "no face" "$work/err" || fail "the refusal does not say the vertex is used by no face: $(cat "$work/err")"
[ ! -e "$work/bad.ply" ] || fail "a refused icr wrote its output"

# --contact-points snap to vertices of faces only: on a mesh where every
# vertex has a stray on top of it, listed first, the grasp's own positions
# snap to the vertices of faces.
py_meshes "
import json
m = json.load(open('$work/map.json'))
p, n, f = testmeshes.icosphere(radius=0.04)
p = [tuple(q[k] * s for k, s in enumerate((1.4, 1.0, 0.8))) for q in p]
dp = [q for q in p for _ in (0, 1)]
dn = [r for q in n for r in ((0.0, 0.0, 0.0), q)]
testmeshes.write_ascii_ply('$work/doubled.ply', dp, dn, [tuple(2 * i + 1 for i in t) for t in f])
print(';'.join('%.17g,%.17g,%.17g' % p[int(c)] for c in '$contacts'.split(',')))
" >"$work/points" || fail "could not write the doubled mesh"
expect_exit 0 "$icrkit" icr "$work/doubled.ply" --contact-points "$(cat "$work/points")" -o "$work/snap.ply" --json -q
py "
import json
d = json.load(open('$work/out'))
assert d['contacts'] == [2 * int(c) + 1 for c in '$contacts'.split(',')], d['contacts']
assert max(d['contact_snap_distance_m']) == 0, d['contact_snap_distance_m']
" || fail "--contact-points snapped onto a vertex no face uses: $(cat "$work/out")"

# --compute-normals on the OBJ: no zero normal is written, strays included.
expect_exit 0 "$icrkit" icr "$work/dirty.obj" --compute-normals --contacts "$dirty_contacts" -o "$work/computed.ply" --quiet
py_meshes "
import math, plyfile
v, _ = plyfile.read('$work/computed.ply')
lengths = [math.sqrt(a * a + b * b + c * c) for a, b, c in zip(v['nx'][1], v['ny'][1], v['nz'][1])]
assert len(lengths) == 647 and all(abs(l - 1) < 1e-5 for l in lengths), min(lengths)
" || fail "--compute-normals left a normal that is not unit"

# --- evaluate, from the OBJs with --compute-normals (the bunny's failure):
# the same records, renumbered, and the same tables.
for m in clean dirty; do
  expect_exit 0 "$icrkit" evaluate --cad "$work/$m.obj" --raw "$work/$m.obj" --filtered "$work/$m.obj" --name sphere \
    --compute-normals --grasps 3 --fingers 4 -o "$work/eval_$m" --quiet
done
py "
import json
m = json.load(open('$work/map.json'))['new_index']
clean = [json.loads(l) for l in open('$work/eval_clean/grasps.jsonl')]
dirty = [json.loads(l) for l in open('$work/eval_dirty/grasps.jsonl')]
assert len(clean) == 3 and any(r['evaluated'] for r in clean), clean
for r in clean:
    r['cad_contacts'] = [m[v] for v in r['cad_contacts']]
    for side in ('raw', 'filtered'):
        r[side]['contacts'] = [m[v] for v in r[side]['contacts']]
assert dirty == clean, (clean, dirty)
" || fail "evaluate on meshes with strays gave other records"
cmp -s "$work/eval_clean/table1.json" "$work/eval_dirty/table1.json" || fail "evaluate on meshes with strays gave another table1.json"

# --- render: the same picture, and a self-comparison without false positives.
for m in clean dirty; do
  expect_exit 0 "$icrkit" render "$work/$m.ply" --regions "$work/${m}_bfs.json" --size 160x120 -o "$work/$m.png" --quiet
done
cmp -s "$work/clean.png" "$work/dirty.png" || fail "render of the mesh with strays differs from the clean mesh's"
expect_exit 0 "$icrkit" render "$clean" --regions "$work/clean_bfs.json" --compare "$dirty" \
  --compare-regions "$work/dirty_bfs.json" --size 160x120 -o "$work/compare.png" --json -q
py "
import json
for f in json.load(open('$work/out'))['compare']['fingers']:
    assert abs(f['intersection_percent'] - 100) < 1e-9 and f['false_positive_percent'] == 0, f
" || fail "render --compare against the mesh with strays is not a perfect match: $(cat "$work/out")"
expect_input_error "vertex $(stray 0)" "$icrkit" render "$dirty" --contacts "$(stray 0)" -o "$work/bad.png"

# --- The Stanford bunny as distributed (1,113 strays, no normals).
bunny="${ICRKIT_SHARED_DATA_DIR:-$root/../shared/data}/stanford-bunny/bun_zipper.ply"
if [ -f "$bunny" ]; then
  expect_exit 0 "$icrkit" grasps "$bunny" --compute-normals --count 2 --seed 1 --json -q
  py "
import json
d = json.load(open('$work/out'))
assert len(d['grasps']) == 2 and d['unreferenced_vertices'] == 1113, d
" || fail "grasps on the bunny: $(cat "$work/out")"
  expect_exit 0 "$icrkit" evaluate --cad "$bunny" --raw "$bunny" --filtered "$bunny" --compute-normals --grasps 1 \
    --fingers 4 -o "$work/bunny" --quiet
  [ "$(wc -l <"$work/bunny/grasps.jsonl")" -eq 1 ] || fail "evaluate on the bunny wrote no record"
else
  echo "cli_unreferenced: $bunny not found, the bunny checks are skipped" >&2
fi

[ "$failures" -eq 0 ] && echo "cli_unreferenced: all checks passed" >&2
exit $((failures > 0))
