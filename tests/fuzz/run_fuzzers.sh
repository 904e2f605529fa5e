#!/usr/bin/env bash
# Runs every fuzz target of BUILD_DIR (made by `./run fuzz`) for SECONDS
# each, two at a time, from its seed corpus (make_seeds.py) and the corpus
# earlier runs grew (BUILD_DIR/fuzz/corpus/<target>, kept between runs).
# Prints one row per target: executions, execs/s, coverage (edges), the
# corpus size and the crashes found; every crash input is saved as
# BUILD_DIR/fuzz/crashes/<target>/crash-* (keep it under
# tests/fuzz-regressions/<target>/ once fixed; a later run moves it to
# BUILD_DIR/fuzz/crashes-earlier/). Appends each run to
# BUILD_DIR/fuzz/runs.jsonl (the time each target was fuzzed in total is
# the sum there). Exit 1 when any target crashed.
#   tests/fuzz/run_fuzzers.sh BUILD_DIR SECONDS [TARGET...]
set -euo pipefail
build="$(cd "${1:?usage: $0 BUILD_DIR SECONDS [TARGET...]}" && pwd)"
seconds="${2:?usage: $0 BUILD_DIR SECONDS [TARGET...]}"
shift 2
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work="$build/fuzz"
mkdir -p "$work"
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(ply obj pcd xyz rawlog mcap tum_depth_list tum_poses camera_json range_model_json regions_json grasps_jsonl plan_json)
fi
/usr/bin/python3 "$here/make_seeds.py" "$work/seeds" "${ICRKIT_DATA:-$here/../../../shared/data}"
# Temporary files of the path readers go to a folder of this run.
export TMPDIR="$work/tmp"
mkdir -p "$TMPDIR"

max_len() {  # as fuzz_targets.cpp sizes them
  case "$1" in
    ply|pcd) echo 262144 ;; obj|xyz|plan_json|mcap) echo 65536 ;; rawlog) echo 2097152 ;;
    camera_json) echo 4096 ;; *) echo 16384 ;;
  esac
}

run_one() {
  local t="$1" log="$work/logs/$1.log"
  mkdir -p "$work/corpus/$t" "$work/crashes/$t" "$work/logs" "$work/crashes-earlier/$t"
  # This run's crashes only: earlier ones move aside.
  find "$work/crashes/$t" -type f -exec mv -t "$work/crashes-earlier/$t/" {} +
  local name="$t"
  case "$t" in *_json|*_jsonl) name=json ;; tum_*) name=tum ;; esac
  local dict=()
  [ -f "$here/dict/$name.dict" ] && dict=(-dict="$here/dict/$name.dict")
  # -malloc_limit_mb: one allocation beyond it is a crash (a header that
  # promises 4e9 vertices must be refused from the file size, never allocated).
  "$build/tests/fuzz/fuzz_$t" "$work/corpus/$t" "$work/seeds/$t" "${dict[@]}" \
    -max_total_time="$seconds" -max_len="$(max_len "$t")" -timeout=20 -rss_limit_mb=2560 -malloc_limit_mb=1024 \
    -artifact_prefix="$work/crashes/$t/" -print_final_stats=1 -close_fd_mask=3 >"$log" 2>&1 || true
}

export -f run_one max_len
export build work here seconds
printf '%s\n' "${targets[@]}" | xargs -P "${ICRKIT_FUZZ_JOBS:-2}" -I{} bash -c 'run_one {}'

status=0
echo "| target | seconds | executions | execs/s | edges (cov) | features | corpus | crashes |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
for t in "${targets[@]}"; do
  log="$work/logs/$t.log"
  execs=$(grep 'stat::number_of_executed_units:' "$log" | awk '{print $2}' | tail -1)
  rate=$(grep 'stat::average_exec_per_sec:' "$log" | awk '{print $2}' | tail -1)
  cov=$(grep -oE '(DONE|pulse|NEW|REDUCE|INITED).* cov: [0-9]+' "$log" | grep -oE 'cov: [0-9]+' | tail -1 | awk '{print $2}')
  ft=$(grep -oE ' ft: [0-9]+' "$log" | tail -1 | awk '{print $2}')
  corpus=$(find "$work/corpus/$t" -type f | wc -l)
  crashes=$(find "$work/crashes/$t" -type f | wc -l)
  [ "$crashes" -gt 0 ] && status=1
  echo "| $t | $seconds | ${execs:-0} | ${rate:-0} | ${cov:-0} | ${ft:-0} | $corpus | $crashes |"
  printf '{"target":"%s","seconds":%s,"executions":%s,"execs_per_s":%s,"edges":%s,"features":%s,"corpus":%s,"crashes":%s,"date":"%s"}\n' \
    "$t" "$seconds" "${execs:-0}" "${rate:-0}" "${cov:-0}" "${ft:-0}" "$corpus" "$crashes" "$(date -u +%FT%TZ)" >>"$work/runs.jsonl"
  if [ "$crashes" -gt 0 ]; then
    echo "  $t: crash inputs in $work/crashes/$t/; the report: $log" >&2
    grep -m3 -E "ERROR: |runtime error|terminate called|==ERROR" "$log" | sed 's/^/    /' >&2 || true
  fi
done
exit $status
