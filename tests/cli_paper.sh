#!/usr/bin/env bash
# End-to-end: `icrkit paper` on two small SR4000 datasets (6 views, 3 grasps
# per finger count): the outputs, 3 shards merged == the unsharded run,
# --reuse keeps the datasets and reconstructions, bad input exits 2.
set -uo pipefail
source "$(dirname "$0")/cli_common.sh"
icrkit="${ICRKIT:?set ICRKIT to the icrkit binary}"

small=(--datasets cup_sr4000_A,wooden_toy_2_sr4000_A --views 6 --grasps 3 --no-preselection)
expect_exit 0 "$icrkit" paper "${small[@]}" -o "$work/full" --json
py "
import json
s = json.load(open('$work/out'))
assert s['grasps'] == 12, s['grasps']
rows = json.load(open('$work/full/table1.json'))['rows']
assert [r['dataset'] for r in rows] == ['cup_sr4000_A', 'wooden_toy_2_sr4000_A'], rows
" || fail "paper summary or Table I rows"
for f in table1.md table1.csv table1.json table1.svg table1.png eligibility.json grasps.jsonl run.json \
         fig8_4fingers.svg fig8_5fingers.png datasets/cup_sr4000_A/scans.rawlog reconstructions/cup_sr4000_A/raw.ply \
         reconstructions/wooden_toy_2_sr4000_A/filtered.ply; do
  [ -s "$work/full/$f" ] || fail "paper did not write $f"
done

# Shards: contiguous blocks of the 12 grasps; shard 0 only needs the first dataset.
for i in 0 1 2; do
  expect_exit 0 "$icrkit" paper "${small[@]}" --shard "$i/3" -o "$work/shard$i" --quiet
done
[ ! -e "$work/shard0/datasets/wooden_toy_2_sr4000_A" ] || fail "shard 0 made a dataset outside its block"
expect_exit 0 "$icrkit" merge "$work/shard0" "$work/shard1" "$work/shard2" -o "$work/merged" --quiet
for f in table1.md table1.csv table1.json table1.svg eligibility.json grasps.jsonl fig8_4fingers.json fig8_5fingers.json; do
  cmp -s "$work/full/$f" "$work/merged/$f" || fail "merged paper shards differ from the unsharded run in $f"
done

# --reuse: the recordings and reconstructions are read, not made again.
before=$(stat -c %Y "$work/full/reconstructions/cup_sr4000_A/raw.ply")
sleep 1
expect_exit 0 "$icrkit" paper "${small[@]}" --reuse --alpha 0.7 -o "$work/full" --quiet
[ "$(stat -c %Y "$work/full/reconstructions/cup_sr4000_A/raw.ply")" = "$before" ] || fail "--reuse rebuilt a reconstruction"

expect_input_error "unknown dataset 'nope'" "$icrkit" paper --datasets nope -o "$work/bad1"
expect_input_error "views" "$icrkit" paper --views -3 -o "$work/bad2"
for b in bad1 bad2; do [ ! -e "$work/$b" ] || fail "a failed paper left $b behind"; done

[ "$failures" -eq 0 ] && echo "cli_paper: all checks passed" >&2
exit $((failures > 0))
