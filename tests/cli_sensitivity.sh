#!/usr/bin/env bash
# End-to-end checks of `icrkit sensitivity` and of --preselection on the
# commands that take it: a small study on a simulated CAD object (files,
# JSON, the zero-noise row's sanity, shards merging into the same table),
# then exit code 2 with a one-line message for bad arguments. Needs $ICRKIT.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

expect_exit 0 "$ICRKIT" sensitivity --help
for option in --cad --object --spacing --noise --preselection --shard --mesh-kept-points-only; do
  grep -q -- "$option" "$work/out" || fail "sensitivity --help lacks $option"
done

# A small study: the bottle at 3 mm spacing, two noise levels, 4 fingers x 8 grasps.
args=(--object bottle --spacing 0.003 --noise 0,0.5 --fingers 4 --grasps 8)
"$ICRKIT" sensitivity "${args[@]}" -o "$work/s" --json -q >"$work/s.json" 2>"$work/err" ||
  fail "sensitivity failed: $(cat "$work/err")"
for f in sensitivity.md sensitivity.json sensitivity.svg sensitivity.png grasps.jsonl table1.md eligibility.json run.json; do
  [ -s "$work/s/$f" ] || fail "sensitivity did not write $f"
done
py "
import json
d = json.load(open('$work/s.json'))
t = json.load(open('$work/s/sensitivity.json'))
assert d['object'] == 'bottle' and abs(d['spacing_m'] - 0.003) < 1e-12, d
assert [r['rule'] for r in t['rows']] == ['default', 'paper-mean', 'none'] * 2, t['rows']
assert [r['noise_level'] for r in t['rows']] == [0] * 3 + [0.5] * 3
for r in t['rows']:
    assert r['grasps'] == 8, r
# the raw mesh is one per level: its eligibility agrees across the rules
# (its Int is over the grasps eligible on both meshes, so it may not)
for level in (0, 0.5):
    raw = {r['raw_eligible_percent'] for r in t['rows'] if r['noise_level'] == level}
    assert len(raw) == 1, raw
zero = [r for r in t['rows'] if r['noise_level'] == 0 and r['rule'] == 'none'][0]
assert zero['raw_eligible_percent'] >= 50 and zero['filtered_eligible_percent'] >= 50, zero
assert zero['evaluated'] > 0 and zero['filtered_intersection_percent'] > 0, zero
assert len(d['levels']) == 2 and all(l['built'] for l in d['levels'])
run = json.load(open('$work/s/run.json'))
assert run['command'] == 'sensitivity' and run['sensitivity']['rules'] == ['default', 'paper-mean', 'none']
assert open('$work/s/sensitivity.png', 'rb').read(8) == b'\x89PNG\r\n\x1a\n'
" || fail "sensitivity outputs inconsistent"

# Two shards merge into the same table.
for i in 0 1; do
  "$ICRKIT" sensitivity "${args[@]}" --shard $i/2 -o "$work/p$i" -q >/dev/null 2>"$work/err" ||
    fail "sensitivity --shard $i/2 failed: $(cat "$work/err")"
done
"$ICRKIT" merge "$work/p0" "$work/p1" -o "$work/m" -q >/dev/null 2>"$work/err" || fail "merge failed: $(cat "$work/err")"
cmp -s "$work/s/sensitivity.json" "$work/m/sensitivity.json" || fail "merged shards give another sensitivity table"
cmp -s "$work/s/grasps.jsonl" "$work/m/grasps.jsonl" || fail "merged shards give other grasp records"

# Bad input: exit 2, one line.
expect_input_error "noise" "$ICRKIT" sensitivity --object cup --noise 0,-0.5 -o "$work/bad"
expect_input_error "preselection" "$ICRKIT" sensitivity --object cup --preselection median -o "$work/bad"
expect_input_error "object" "$ICRKIT" sensitivity --object teapot -o "$work/bad"
expect_input_error "--window-normal-angle" "$ICRKIT" sensitivity --object cup --window-normal-angle -1 -o "$work/bad"
expect_input_error "cad" "$ICRKIT" sensitivity -o "$work/bad"
expect_exit 2 "$ICRKIT" smooth "$work/none.ply" -o "$work/x.ply" --preselection median
expect_exit 2 "$ICRKIT" evaluate --cad a.ply --raw b.ply --filtered c.ply -o "$work/e" --preselection mean

# --preselection on evaluate recomputes the flags from the mesh's attributes:
# a mesh without them is a one-line error naming the file.
make_evaluation_meshes "$ICRKIT" "$work/ev"
expect_input_error "filtered.ply.*cardinality" "$ICRKIT" evaluate --cad "$work/ev/sim/object.ply" \
  --raw "$work/ev/raw.ply" --filtered "$work/ev/filtered.ply" --preselection default --grasps 2 -o "$work/e2"

[ "$failures" -eq 0 ] || { echo "$failures check(s) failed" >&2; exit 1; }
echo "cli_sensitivity: all checks passed"
