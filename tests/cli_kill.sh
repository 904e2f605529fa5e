#!/usr/bin/env bash
# Killed mid-run, nothing half-written (issue 37): `reconstruct`,
# `evaluate`, `paper` and `plan` are interrupted (SIGINT, SIGKILL) at
# several moments of a run; every output file then present must be
# complete (it parses as its format, its summary's record matches it), and
# rerunning the same command (with --reuse where it exists) must finish the
# work with the same results as an uninterrupted run.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"
icrkit="${ICRKIT:?set ICRKIT to the icrkit binary}"

# check_outputs DIR LABEL: every file under DIR parses as its extension says.
check_outputs() {
  local dir="$1" label="$2"
  [ -d "$dir" ] || return 0
  PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 - "$dir" "$label" "$icrkit" <<'PY' || fail "$2: incomplete outputs"
import json, os, subprocess, sys
root, label, icrkit = sys.argv[1:4]
bad = []
for folder, _, files in os.walk(root):
    for name in files:
        path = os.path.join(folder, name)
        ext = name.rsplit(".", 1)[-1] if "." in name else ""
        data = open(path, "rb").read()
        try:
            if ".tmp." in name:
                continue  # a temporary of the killed run: never under a final name
            if ext == "json":
                json.loads(data)
            elif ext == "jsonl":
                for line in data.decode().splitlines():
                    json.loads(line)
            elif ext in ("ply", "obj"):
                r = subprocess.run([icrkit, "info", path, "--quiet"], capture_output=True)
                if r.returncode != 0:
                    raise ValueError(r.stderr.decode().strip())
            elif ext == "png":
                if not (data.startswith(b"\x89PNG") and data.rstrip(b"\x00").endswith(b"IEND\xaeB`\x82")):
                    raise ValueError("PNG without its end chunk")
            elif ext == "svg":
                if not data.rstrip().endswith(b"</svg>"):
                    raise ValueError("SVG without its end tag")
            elif ext in ("md", "csv", "txt"):
                if data and not data.endswith(b"\n"):
                    raise ValueError("text file ends mid-line")
            elif ext == "rawlog":
                if len(data) == 0:
                    raise ValueError("empty rawlog")
        except Exception as e:
            bad.append(f"{path}: {e}")
for b in bad:
    print(f"{label}: {b}", file=sys.stderr)
sys.exit(1 if bad else 0)
PY
}

# interrupt SIGNAL SECONDS DIR CMD...: runs CMD, sends SIGNAL after SECONDS
# (if it is still running), waits, checks DIR.
interrupt() {
  local signal="$1" after="$2" dir="$3"; shift 3
  "$@" >/dev/null 2>&1 &
  local pid=$!
  sleep "$after"
  kill -s "$signal" "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
  check_outputs "$dir" "$(basename "$dir") after SIG$signal at ${after}s"
}

# timed CMD...: runs CMD to completion, prints its wall time in seconds.
timed() {
  local start end
  start=$(date +%s.%N)
  "$@" >/dev/null 2>"$work/timed.err" || { fail "'$*' failed: $(cat "$work/timed.err")"; echo 1; return; }
  end=$(date +%s.%N)
  py "print($end - $start)"
}

# same_file A B LABEL: byte-identical outputs.
same_file() { cmp -s "$1" "$2" || fail "$3: $(basename "$1") differs from the uninterrupted run's"; }

"$icrkit" simulate --object cup --sensor sr4000 --views 8 --seed 3 -o "$work/sim" --quiet >/dev/null ||
  { echo "FAIL: simulate" >&2; exit 1; }
rawlog="$work/sim/scans.rawlog"

# reconstruct: no --reuse; the rerun replaces whatever the killed run left.
T=$(timed "$icrkit" reconstruct "$rawlog" -o "$work/rec_ref" --quiet)
for signal in INT KILL; do
  for fraction in 0.3 0.7; do
    at=$(py "print(round($T * $fraction, 2))")
    d="$work/rec_${signal}_$fraction"
    interrupt "$signal" "$at" "$d" "$icrkit" reconstruct "$rawlog" -o "$d" --quiet
    expect_exit 0 "$icrkit" reconstruct "$rawlog" -o "$d" --quiet
    for f in cloud.ply raw.ply filtered.ply poses.txt; do same_file "$d/$f" "$work/rec_ref/$f" "reconstruct $signal $fraction"; done
  done
done

# evaluate on the reconstruction.
eval_args=(--cad "$work/sim/object.ply" --raw "$work/rec_ref/raw.ply" --filtered "$work/rec_ref/filtered.ply"
  --name cup --fingers 4 --grasps 12 --renders 1 --plan-top 2 --quiet)
T=$(timed "$icrkit" evaluate "${eval_args[@]}" -o "$work/ev_ref")
for signal in INT KILL; do
  for fraction in 0.3 0.7; do
    at=$(py "print(round($T * $fraction, 2))")
    d="$work/ev_${signal}_$fraction"
    interrupt "$signal" "$at" "$d" "$icrkit" evaluate "${eval_args[@]}" -o "$d"
    expect_exit 0 "$icrkit" evaluate "${eval_args[@]}" -o "$d"
    for f in grasps.jsonl table1.csv; do same_file "$d/$f" "$work/ev_ref/$f" "evaluate $signal $fraction"; done
  done
done

# paper: simulate, reconstruct and evaluate one small dataset; --reuse on the rerun.
paper_args=(--datasets cup_sr4000_A --views 6 --fingers 4 --grasps 8 --renders 0 --plan-top 0 --quiet)
T=$(timed "$icrkit" paper "${paper_args[@]}" -o "$work/paper_ref")
for signal in INT KILL; do
  for fraction in 0.2 0.5 0.8; do
    at=$(py "print(round($T * $fraction, 2))")
    d="$work/paper_${signal}_$fraction"
    interrupt "$signal" "$at" "$d" "$icrkit" paper "${paper_args[@]}" -o "$d"
    expect_exit 0 "$icrkit" paper "${paper_args[@]}" --reuse -o "$d"
    for f in grasps.jsonl table1.csv; do same_file "$d/$f" "$work/paper_ref/$f" "paper $signal $fraction"; done
  done
done

# plan on the filtered mesh.
plan_args=("$work/rec_ref/filtered.ply" --fingers 3 --top 3 --renders 1 --quiet)
mkdir -p "$work/plan_ref"
T=$(timed "$icrkit" plan "${plan_args[@]}" -o "$work/plan_ref/plan.json")
for signal in INT KILL; do
  for fraction in 0.3 0.7; do
    at=$(py "print(round($T * $fraction, 2))")
    d="$work/plan_${signal}_$fraction"
    mkdir -p "$d"
    interrupt "$signal" "$at" "$d" "$icrkit" plan "${plan_args[@]}" -o "$d/plan.json"
    expect_exit 0 "$icrkit" plan "${plan_args[@]}" -o "$d/plan.json"
    same_file "$d/plan.json" "$work/plan_ref/plan.json" "plan $signal $fraction"
  done
done

[ "$failures" -eq 0 ] || { echo "$failures failure(s)" >&2; exit 1; }
echo "cli_kill: all checks passed"
