#!/usr/bin/env bash
# End-to-end checks of `icrkit render`: the ICRs of a generated sphere drawn
# to PNG (size from the command line, several views, JSON summary), the
# comparison of a mesh with itself (intersection everywhere, no false
# positives), byte-identical reruns, and exit code 2 with a one-line message
# and nothing written for bad input. Needs $ICRKIT; self-contained.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

expect_exit 0 "$ICRKIT" render --help
for option in --regions --compare --compare-regions --size --views --camera; do
  grep -q -- "$option" "$work/out" || fail "render --help lacks $option"
done

# An icosphere (radius 0.05 m, 642 vertices) as ASCII PLY with exact normals,
# and the same without normals as OBJ.
py_meshes "
p, n, f = testmeshes.icosphere()
testmeshes.write_ascii_ply('$work/ico.ply', p, n, f)
testmeshes.write_obj('$work/ico.obj', p, f)
" || { echo "could not generate the test meshes" >&2; exit 1; }
ico="$work/ico.ply"

# Regions from `icrkit icr`, for a sampled force-closure grasp.
"$ICRKIT" grasps "$ico" --count 1 --seed 3 --json -q >"$work/g.json" 2>"$work/err" ||
  { echo "grasps failed: $(cat "$work/err")" >&2; exit 1; }
contacts=$(json_field "[\"grasps\"][0][\"contacts\"]" <"$work/g.json" | tr -d '[] ')
"$ICRKIT" icr "$ico" --contacts "$contacts" -o "$work/regions.ply" --json -q >/dev/null 2>"$work/err" ||
  { echo "icr failed: $(cat "$work/err")" >&2; exit 1; }
regions="$work/regions.json"

# png_size FILE: "WIDTH HEIGHT" from the IHDR chunk, after checking the signature.
png_size() {
  py "
import struct, sys
data = open('$1', 'rb').read(24)
assert data[:8] == b'\x89PNG\r\n\x1a\n' and data[12:16] == b'IHDR', 'not a PNG'
print(*struct.unpack('>II', data[16:24]))"
}

# --- Regions, four automatic views of 320x240 in 2 columns, plus a legend.
"$ICRKIT" render "$ico" --regions "$regions" --size 320x240 -o "$work/single.png" --json >"$work/single.json" \
  2>"$work/err" || fail "render --regions failed: $(cat "$work/err")"
[ "$(wc -l <"$work/single.json")" -eq 1 ] || fail "render --json printed more than one line"
size=$(png_size "$work/single.png") || fail "single.png is not a PNG"
py "
import json
d = json.load(open('$work/single.json'))
w, h = map(int, '$size'.split())
assert d['views'] == 4 and d['columns'] == 2 and d['view_size'] == [320, 240], d
assert [c['name'] for c in d['cameras']] == ['front', 'right', 'back', 'left'], d['cameras']
assert d['image_size'] == [w, h], (d['image_size'], w, h)
assert w == 2 * 320 and 2 * 240 < h < 2 * 240 + 100, (w, h)
contacts = [int(c) for c in '$contacts'.split(',')]
assert [r['finger'] for r in d['regions']] == list(range(len(contacts)))
assert [r['contact'] for r in d['regions']] == contacts
regions = json.load(open('$regions'))['regions']
for r, s in zip(d['regions'], regions):
    assert r['vertices'] == len(s['vertices']) and r['central_point'] in s['vertices'], (r, s['contact'])
" || fail "render summary wrong: $(cat "$work/single.json")"

# Same input, same bytes; regions change the picture.
"$ICRKIT" render "$ico" --regions "$regions" --size 320x240 -o "$work/again.png" -q >/dev/null ||
  fail "second render failed"
cmp -s "$work/single.png" "$work/again.png" || fail "the same render gave different bytes"
"$ICRKIT" render "$ico" --size 320x240 -o "$work/plain.png" -q >/dev/null || fail "render without regions failed"
cmp -s "$work/single.png" "$work/plain.png" && fail "regions did not change the render"

# Explicit cameras: two views in one row (--columns), each 200x100.
"$ICRKIT" render "$ico" --regions "$regions" --camera 0,0,0.3 --camera 0.3,0,0,0,0,0 --size 200x100 --columns 2 \
  -o "$work/cams.png" --json -q >"$work/cams.json" 2>"$work/err" || fail "render --camera failed: $(cat "$work/err")"
size=$(png_size "$work/cams.png") || fail "cams.png is not a PNG"
py "
import json
d = json.load(open('$work/cams.json'))
w, h = map(int, '$size'.split())
assert d['views'] == 2 and d['image_size'] == [w, h] and w == 400 and h > 100, (d, w, h)
assert d['cameras'][0]['eye'] == [0, 0, 0.3] and d['cameras'][1]['target'] == [0, 0, 0], d['cameras']
" || fail "render --camera summary wrong: $(cat "$work/cams.json")"

# --- The mesh compared with itself: I_n is the whole CAD region, no false
# positives. Two rows (CAD, reconstructed) of three views.
"$ICRKIT" render "$ico" --regions "$regions" --compare "$ico" --compare-regions "$regions" --views 3 --size 240x180 \
  -o "$work/compare.png" --json -q >"$work/compare.json" 2>"$work/err" || fail "render --compare failed: $(cat "$work/err")"
size=$(png_size "$work/compare.png") || fail "compare.png is not a PNG"
py "
import json
d = json.load(open('$work/compare.json'))
w, h = map(int, '$size'.split())
assert d['image_size'] == [w, h] and w == 3 * 240 and 2 * 180 < h < 2 * 180 + 100, (d['image_size'], w, h)
fingers = d['compare']['fingers']
assert [f['finger'] for f in fingers] == list(range(len('$contacts'.split(','))))
for f in fingers:
    assert abs(f['intersection_percent'] - 100.0) < 1e-9, f
    assert f['false_positive_area_m2'] == 0.0 and f['false_positive_percent'] == 0.0, f
    assert f['unmapped_vertices'] == 0, f
" || fail "render --compare of a mesh with itself: $(cat "$work/compare.json")"
# One finger only.
"$ICRKIT" render "$ico" --regions "$regions" --compare "$ico" --compare-regions "$regions" --finger 1 --views 1 \
  --size 120x90 -o "$work/finger.png" --json -q >"$work/finger.json" 2>"$work/err" || fail "render --finger failed: $(cat "$work/err")"
[ "$(json_field "['compare']['fingers'][0]['finger']" <"$work/finger.json")" = 1 ] &&
  [ "$(py "import json; print(len(json.load(open('$work/finger.json'))['compare']['fingers']))")" = 1 ] ||
  fail "--finger 1 did not keep finger 1 only"

# --- Bad input: exit 2, one line naming the problem, nothing written.
rm -f "$work/bad.png"
expect_input_error "missing.ply" "$ICRKIT" render "$work/missing.ply" -o "$work/bad.png"
expect_input_error "missing.json" "$ICRKIT" render "$ico" --regions "$work/missing.json" -o "$work/bad.png"
py "
import json
d = json.load(open('$regions'))
d['regions'][1]['vertices'].append(100000)
json.dump(d, open('$work/far.json', 'w'))
json.dump({'grasps': []}, open('$work/noregions.json', 'w'))
"
expect_input_error "far.json.*regions\[1\].*out of range" "$ICRKIT" render "$ico" --regions "$work/far.json" -o "$work/bad.png"
expect_input_error "noregions.json.*regions" "$ICRKIT" render "$ico" --regions "$work/noregions.json" -o "$work/bad.png"
printf '{"regions": [' >"$work/broken.json"
expect_input_error "broken.json.*JSON" "$ICRKIT" render "$ico" --regions "$work/broken.json" -o "$work/bad.png"
for bad_size in 0x100 800 100x 12.5x10 -3x4; do
  expect_input_error "size" "$ICRKIT" render "$ico" --size "$bad_size" -o "$work/bad.png"
done
expect_input_error "\.png" "$ICRKIT" render "$ico" -o "$work/bad.jpg"
expect_input_error "camera" "$ICRKIT" render "$ico" --camera 0,0 -o "$work/bad.png"
expect_input_error "camera.*target" "$ICRKIT" render "$ico" --camera 0,0,0.3,0,0,0.3 -o "$work/bad.png"
expect_input_error "compare-regions" "$ICRKIT" render "$ico" --regions "$regions" --compare "$ico" -o "$work/bad.png"
expect_input_error "contacts" "$ICRKIT" render "$ico" --contacts 0,700 -o "$work/bad.png"
expect_input_error "finger 7" "$ICRKIT" render "$ico" --regions "$regions" --finger 7 -o "$work/bad.png"
# The CAD side of a comparison needs normals; the OBJ has none.
expect_input_error "ico.obj.*--compute-normals" "$ICRKIT" render "$work/ico.obj" --regions "$regions" \
  --compare "$ico" --compare-regions "$regions" -o "$work/bad.png"
expect_exit 0 "$ICRKIT" render "$work/ico.obj" --compute-normals --regions "$regions" --compare "$ico" \
  --compare-regions "$regions" --views 1 --size 80x60 -o "$work/computed.png" -q
[ ! -e "$work/bad.png" ] && [ ! -e "$work/bad.jpg" ] || fail "a failed render left an output behind"
[ -z "$(ls -A "$work" | grep '\.tmp')" ] || fail "a temporary file was left behind"

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi
echo "all render CLI checks passed"
