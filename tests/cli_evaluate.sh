#!/usr/bin/env bash
# End-to-end: `icrkit evaluate` on a CAD mesh, a noisy copy (raw) and an exact
# copy with a few excluded vertices (filtered); 3 shards merged by `icrkit
# merge` equal the unsharded run byte for byte; one thread equals two; bad
# input exits 2 and writes nothing.
set -uo pipefail
source "$(dirname "$0")/cli_common.sh"
icrkit="${ICRKIT:?set ICRKIT to the icrkit binary}"

make_evaluation_meshes "$icrkit" "$work"

args=(--cad "$work/sim/object.ply" --raw "$work/raw.ply" --filtered "$work/filtered.ply" --name toy --grasps 4)
expect_exit 0 "$icrkit" evaluate "${args[@]}" -o "$work/full" --json
py "import json; json.load(open('$work/out'))" || fail "evaluate --json did not print one JSON object"
for f in table1.md table1.csv table1.json table1.svg table1.png eligibility.json grasps.jsonl run.json fig8_4fingers.svg fig8_4fingers.png \
         fig8_5fingers.svg fig8_5fingers.png fig8_4fingers.json; do
  [ -s "$work/full/$f" ] || fail "evaluate did not write $f"
done
[ "$(wc -l <"$work/full/grasps.jsonl")" -eq 8 ] || fail "expected 8 grasp records"
# The filtered mesh is the CAD mesh itself: every evaluated region is found whole.
py "
import json
rows = json.load(open('$work/full/table1.json'))['rows']
assert rows[0]['dataset'] == 'toy', rows
f = rows[0]['filtered']
if rows[0]['evaluated_grasps'] > 0:
    assert abs(f['median_intersection_percent'] - 100.0) < 1e-6, f
    assert f['median_false_positive_percent'] == 0.0, f
" || fail "identical filtered mesh did not give Int = 100 %, FP = 0"

# Shards merged == one run; one thread == two.
for i in 0 1 2; do
  expect_exit 0 "$icrkit" evaluate "${args[@]}" --shard "$i/3" -o "$work/shard$i" --quiet
done
expect_exit 0 "$icrkit" merge "$work/shard0" "$work/shard1" "$work/shard2" -o "$work/merged" --quiet
for f in table1.md table1.csv table1.json table1.svg table1.png eligibility.json grasps.jsonl fig8_4fingers.svg fig8_4fingers.png \
         fig8_4fingers.json fig8_5fingers.svg fig8_5fingers.png fig8_5fingers.json planned.jsonl planned.md \
         surface.jsonl surface.md; do
  cmp -s "$work/full/$f" "$work/merged/$f" || fail "merged shards differ from the unsharded run in $f"
done
# The planned grasps (--plan-top, default 10) beside the random ones: one
# study for the dataset, made by the shard holding its first grasp. The
# filtered mesh is the CAD mesh itself: every aimed grasp and pick holds.
[ -s "$work/shard0/planned.jsonl" ] && [ ! -e "$work/shard1/planned.jsonl" ] ||
  fail "the planned grasps were not made by shard 0 alone"
py "
import json
lines = open('$work/full/planned.jsonl').read().splitlines()
assert len(lines) == 1, lines
s = json.loads(lines[0])
assert s['dataset'] == 'toy' and s['fingers'] == 4 and s['tws_radius'] > 0, s
f = s['filtered']
assert 'error' not in f and len(f['grasps']) > 0, f
assert f['aimed_held_fraction'] == 1.0 and f['picks_held_fraction'] == 1.0, f
assert 'filtered_random' in s and 'raw_random' in s
run = json.load(open('$work/full/run.json'))
assert run['plan']['top'] == 10, run.get('plan')
" || fail "evaluate: planned.jsonl wrong"
grep -q "| toy | filtered | " "$work/full/planned.md" || fail "planned.md has no filtered row"
# Surface accuracy: the filtered mesh is the CAD mesh itself (distance 0).
py "
import json
s = json.loads(open('$work/full/surface.jsonl').readline())
assert s['dataset'] == 'toy' and s['filtered']['all']['mean_distance_m'] < 1e-9, s
assert s['raw']['all']['mean_distance_m'] > 0, s
" || fail "evaluate: surface.jsonl wrong"
expect_exit 0 "$icrkit" evaluate "${args[@]}" --plan-top 0 -o "$work/unplanned" --quiet
[ ! -e "$work/unplanned/planned.jsonl" ] || fail "--plan-top 0 still planned"
expect_exit 0 "$icrkit" --threads 1 evaluate "${args[@]}" -o "$work/one_thread" --quiet
cmp -s "$work/full/grasps.jsonl" "$work/one_thread/grasps.jsonl" || fail "one thread changed the records"

# The patch-contact study beside the plain one: its rows in conservative.md,
# its config in run.json, the plain records unchanged.
expect_exit 0 "$icrkit" evaluate "${args[@]}" --patch-radius 0.0012 -o "$work/patch" --quiet
grep -q "| toy | patch 1.2 mm |" "$work/patch/conservative.md" || fail "evaluate --patch-radius wrote no patch row"
py "
import json
run = json.load(open('$work/patch/run.json'))
assert run['config']['patch']['radius_m'] == 0.0012, run['config']
full = [json.loads(l) for l in open('$work/full/grasps.jsonl')]
patch = [json.loads(l) for l in open('$work/patch/grasps.jsonl')]
assert [('patch' in r) for r in patch] == [r['evaluated'] for r in patch], 'patch study on other grasps than the evaluated'
for r in patch: r.pop('patch', None)
assert patch == full, 'the patch study changed the plain records'
" || fail "evaluate --patch-radius: records or run.json wrong"
for bad in 0 -0.001 nan; do
  expect_input_error "patch-radius" "$icrkit" evaluate "${args[@]}" --patch-radius "$bad" -o "$work/bad_patch"
  [ ! -e "$work/bad_patch" ] || fail "a failed evaluate --patch-radius $bad left output behind"
done

# Bad input: exit 2, one line naming the problem, nothing written.
expect_input_error "missing.ply" "$icrkit" evaluate --cad "$work/missing.ply" --raw "$work/raw.ply" \
  --filtered "$work/filtered.ply" -o "$work/bad1"
[ ! -e "$work/bad1" ] || fail "a failed evaluate left $work/bad1 behind"
expect_input_error "shard" "$icrkit" evaluate "${args[@]}" --shard 3/3 -o "$work/bad2"
expect_input_error "alpha" "$icrkit" evaluate "${args[@]}" --alpha 1.5 -o "$work/bad3"
touch "$work/a_file"
expect_input_error "not a directory" "$icrkit" evaluate "${args[@]}" -o "$work/a_file"
expect_input_error "shards missing: 2" "$icrkit" merge "$work/shard0" "$work/shard1" -o "$work/bad4"
expect_exit 0 "$icrkit" evaluate "${args[@]}" --seed 2 --shard 2/3 -o "$work/other_seed" --quiet
expect_input_error "differ" "$icrkit" merge "$work/shard0" "$work/shard1" "$work/other_seed" -o "$work/bad5"
expect_input_error "given twice" "$icrkit" merge "$work/shard0" "$work/shard0" "$work/shard2" -o "$work/bad6"
for b in bad2 bad3 bad4 bad5 bad6; do [ ! -e "$work/$b" ] || fail "a failed command left $b behind"; done
expect_input_error "run.json" "$icrkit" merge "$work/sim" -o "$work/bad7"

[ "$failures" -eq 0 ] && echo "cli_evaluate: all checks passed" >&2
exit $((failures > 0))
