#!/usr/bin/env bash
# The planner's acceptance run (issue 33, docs/planning.md): the nine
# simulated datasets made with --pose-error mobile and a seed of our own,
# reconstructed; per object R = half the median epsilon of 200 random
# 4-finger force-closure grasps on the CAD mesh; `icrkit plan --fingers 4
# --top 10 --tws-radius R` on the filtered mesh, executed on the CAD mesh by
# the independent Python executor (tests/executor/execute_plan.py, by touch)
# and by `icrkit evaluate`'s planned-grasp study (eq. (3), with the random
# baseline beside). Prints one Markdown row per dataset.
# Then the real PrimeSense bunny recording (when ../shared/data is there),
# reconstructed, aligned to bun_zipper.ply by evaluate's ICP; the executor
# gets that alignment (--transform).
#   [PLAN_DATASETS="paper_cup:kinect ..."] bench/plan_acceptance.sh BUILD_DIR [WORK_DIR [SEED]]
set -euo pipefail
build="${1:?usage: $0 BUILD_DIR [WORK_DIR [SEED]]}"
work="${2:-$(mktemp -d)}"
seed="${3:-11}"
icrkit="$(cd "$build" && pwd)/apps/icrkit/icrkit"
root="$(cd "$(dirname "$0")/.." && pwd)"
executor="$root/tests/executor/execute_plan.py"
data="${ICRKIT_DATA:-$root/../shared/data}"
mkdir -p "$work"
cd "$work"
echo "| dataset | R | executor: aimed / picks / 3 mm placement held % | evaluate (eq. 3): aimed / picks / placement % | median region mm² | random baseline (evaluate): aimed / picks / placement % | baseline area mm² |"
echo "|---|---:|---|---|---:|---|---:|"
report_row() {  # NAME R: the row from plans/NAME.exec.json and ev_NAME/planned.jsonl
  /usr/bin/python3 - "$1" "$2" "plans/$1.exec.json" "ev_$1/planned.jsonl" <<'PY'
import json, sys
name, R, executed, planned = sys.argv[1], float(sys.argv[2]), json.load(open(sys.argv[3])), json.loads(open(sys.argv[4]).readline())
s = executed['summary']
pct = lambda x: f'{100 * x:.1f}'
def study(m):
    if 'error' in m:
        return 'no plan', '–'
    return (f"{pct(m['aimed_held_fraction'])} / {pct(m['picks_held_fraction'])} / {pct(m['placements_held_fraction'])}",
            f"{m['median_region_area_m2'] * 1e6:.0f}")
ev, _ = study(planned['filtered'])
base, base_area = study(planned['filtered_random'])
print(f"| {name} | {R:.4f} | {pct(s['aimed_held_fraction'])} / {pct(s['picks_held_fraction'])} / "
      f"{pct(s['placement_held_fraction'])} | {ev} | {s['median_region_area_m2'] * 1e6:.0f} | {base} | {base_area} |")
PY
}
median_half() {  # half the median epsilon of a grasps.jsonl
  /usr/bin/python3 -c "
import json, statistics, sys
print(0.5 * statistics.median(json.loads(l)['epsilon'] for l in open(sys.argv[1])))" "$1"
}
all="cup:sr4000 wooden_toy_1:sr4000 wooden_toy_2:sr4000 cup:kinect wooden_toy_1:kinect wooden_toy_2:kinect
  bottle:kinect paper_cup:kinect coffee_pot:kinect real"
# PLAN_DATASETS: a subset, e.g. "paper_cup:kinect bottle:kinect" ("real": the PrimeSense bunny).
datasets="${PLAN_DATASETS:-$all}"
for spec in $datasets; do
  [ "$spec" = real ] && continue
  object=${spec%%:*}
  sensor=${spec##*:}
  n=${object}_${sensor}
  [ -f "$n/manifest.json" ] ||
    "$icrkit" simulate --object "$object" --sensor "$sensor" --seed "$seed" --pose-error mobile -o "$n" -q >/dev/null
  [ -f "$n.rec/filtered.ply" ] || "$icrkit" reconstruct "$n/scans.rawlog" -o "$n.rec" -q --json >"$n.rec.json"
  [ -f "$n.cad_grasps.jsonl" ] ||
    "$icrkit" grasps "$n/object.ply" --torque-reference centroid --fingers 4 --count 200 --seed 5 \
      -o "$n.cad_grasps.jsonl" -q >/dev/null
  R=$(median_half "$n.cad_grasps.jsonl")
  mkdir -p plans
  "$icrkit" plan "$n.rec/filtered.ply" --fingers 4 --top 10 --tws-radius "$R" -o "plans/$n.json" -q --json \
    >"plans/$n.summary.json"
  /usr/bin/python3 "$executor" "plans/$n.json" --cad "$n/object.ply" --json "plans/$n.exec.json" >/dev/null
  [ -f "ev_$n/planned.jsonl" ] ||
    "$icrkit" evaluate --cad "$n/object.ply" --raw "$n.rec/raw.ply" --filtered "$n.rec/filtered.ply" --name "$n" \
      --fingers 4 --grasps 100 --renders 0 -o "ev_$n" -q --json >"ev_$n.json"
  report_row "$n" "$R"
done

# The real recording: its reconstruction is in the camera's frame, the CAD
# bunny in its own; evaluate aligns them (ICP) and the executor reuses that.
rawlog="$data/primesense-bunny/scans.rawlog"
cad="$data/stanford-bunny/bun_zipper.ply"
if [ -f "$rawlog" ] && [ -f "$cad" ] && [[ " $datasets " == *" real "* ]]; then
  n=primesense_bunny
  [ -f "$n.rec/filtered.ply" ] || "$icrkit" reconstruct "$rawlog" -o "$n.rec" -q --json >"$n.rec.json"
  [ -f "$n.cad_grasps.jsonl" ] ||
    "$icrkit" grasps "$cad" --compute-normals --torque-reference centroid --fingers 4 --count 200 --seed 5 \
      -o "$n.cad_grasps.jsonl" -q >/dev/null
  R=$(median_half "$n.cad_grasps.jsonl")
  [ -f "ev_$n/planned.jsonl" ] ||
    "$icrkit" evaluate --cad "$cad" --compute-normals --raw "$n.rec/raw.ply" --filtered "$n.rec/filtered.ply" \
      --align icp --name "$n" --fingers 4 --grasps 100 --renders 0 -o "ev_$n" -q --json >"ev_$n.json"
  /usr/bin/python3 -c "
import json, sys
for a in json.load(open(sys.argv[1]))['datasets'][0]['alignment']:
    if a['mesh'].endswith('filtered.ply'):
        json.dump({'matrix': a['matrix']}, open(sys.argv[2], 'w'))" "ev_$n/run.json" "$n.to_cad.json"
  mkdir -p plans
  "$icrkit" plan "$n.rec/filtered.ply" --fingers 4 --top 10 --tws-radius "$R" -o "plans/$n.json" -q --json \
    >"plans/$n.summary.json"
  /usr/bin/python3 "$executor" "plans/$n.json" --cad "$cad" --transform "$n.to_cad.json" \
    --json "plans/$n.exec.json" >/dev/null
  report_row "$n" "$R"
fi
