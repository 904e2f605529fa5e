#!/usr/bin/env bash
# End-to-end checks of `icrkit plan` on an icosphere generated here: the
# three outputs, plan.json's format, --json, and exit 2 with nothing written
# for bad input. Needs $ICRKIT (the binary).
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

expect_exit 0 "$ICRKIT" plan --help
py_meshes "
p, n, f = testmeshes.icosphere()
testmeshes.write_obj('$work/ico.obj', p, f)
testmeshes.write_ascii_ply('$work/ico.ply', p, n, f, [0] * len(p))
" || { echo "could not generate the test meshes" >&2; exit 1; }

"$ICRKIT" plan "$work/ico.ply" -o "$work/plan.json" --top 3 --candidates 200 --json >"$work/summary.json" 2>"$work/err" ||
  fail "plan failed: $(cat "$work/err")"
for f in plan.json plan.ply plan.png; do [ -s "$work/$f" ] || fail "plan wrote no $f"; done
py "
import json
plan = json.load(open('$work/plan.json'))
assert plan['mesh'].endswith('ico.ply'), plan['mesh']
for key in ('type', 'mu', 'mu_t', 'edges'): assert key in plan['model'], key
assert len(plan['torque_reference_m']) == 3 and plan['lambda_m'] > 0
assert [g['rank'] for g in plan['grasps']] == [1, 2, 3]
for g in plan['grasps']:
    assert g['fingers'] == 4 and len(g['regions']) == 4 and g['tws_radius'] > 0
    for r in g['regions']:
        assert r['recommended']['vertex'] in r['vertices'] and len(r['recommended']['position']) == 3
        assert r['area_m2'] > 0
summary = json.load(open('$work/summary.json'))
assert summary['grasps'][0]['rank'] == 1 and summary['output'].endswith('plan.json')
" || fail "plan.json or the summary is not as specified"

# Patch fingers: plan.json says so.
"$ICRKIT" plan "$work/ico.ply" -o "$work/patch.json" --top 2 --candidates 200 --patch-radius 0.004 --renders 0 -q \
  2>"$work/err" || fail "plan --patch-radius failed: $(cat "$work/err")"
py "
import json
plan = json.load(open('$work/patch.json'))
assert plan['patch'] == {'radius_m': 0.004, 'filter_border': True}, plan['patch']
assert len(plan['grasps']) == 2
assert json.load(open('$work/plan.json'))['patch'] is None
" || fail "plan.json of a patch plan"

# Bad input: one line, exit 2, nothing written.
rm -f "$work"/bad.*
expect_input_error "--patch-radius" "$ICRKIT" plan "$work/ico.ply" -o "$work/bad.json" --patch-all-points
expect_input_error "--patch-radius" "$ICRKIT" plan "$work/ico.ply" -o "$work/bad.json" --patch-radius 0.004 --conservative
expect_input_error "ico.obj.*--compute-normals" "$ICRKIT" plan "$work/ico.obj" -o "$work/bad.json"
expect_input_error "--top" "$ICRKIT" plan "$work/ico.ply" -o "$work/bad.json" --top 0
expect_input_error "no candidate meets the task" "$ICRKIT" plan "$work/ico.ply" -o "$work/bad.json" --tws-radius 5 --candidates 50
expect_exit 2 "$ICRKIT" plan "$work/ico.ply" -o "$work/bad.json" --model sticky
expect_input_error "no force-closure grasp among 50 candidates" "$ICRKIT" plan "$work/ico.ply" -o "$work/bad.json" \
  --model frictionless --fingers 2 --candidates 50
ls "$work"/bad.* >/dev/null 2>&1 && fail "a failed plan left files: $(ls "$work"/bad.*)"

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi
echo "all plan CLI checks passed"
