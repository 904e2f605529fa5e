#!/usr/bin/env bash
# Submits a sharded `icrkit paper` study to Slurm: the job array of
# paper-array.sbatch (one shard per task) and merge.sbatch, which starts only
# once every task has succeeded (--dependency=afterok). See docs/scaling.md.
#   scripts/slurm/submit-study.sh [--shards N] [--sbatch OPTION]... STUDY [icrkit paper options...]
#     --shards N       number of shards = array tasks (default 9)
#     --sbatch OPTION  one more sbatch option for both jobs (repeatable), e.g.
#                      --sbatch --partition=big --sbatch --cpus-per-task=8
#   STUDY            study folder (made absolute; created; logs in STUDY/logs);
#                    the shards go to STUDY/shard-<i>, the merged run to STUDY/merged
#   paper options    passed to every shard (default: none, the paper's whole study)
# Prints "<array job id> <merge job id>" on stdout. ICRKIT (the icrkit command,
# default icrkit on PATH) and the rest of the environment reach the jobs.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
usage() { sed -n '5,14s/^# \{0,1\}//p' "$0" >&2; exit 2; }

shards=9
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --shards) [ $# -ge 2 ] || usage; shards="$2"; shift 2 ;;
    --sbatch) [ $# -ge 2 ] || usage; extra+=("$2"); shift 2 ;;
    -h|--help) usage ;;
    *) break ;;
  esac
done
[ $# -ge 1 ] || usage
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || { echo "submit-study: --shards must be a positive integer, not '$shards'" >&2; exit 2; }
study="$(realpath -m "$1")"
shift
mkdir -p "$study/logs"

array_id=$(sbatch --parsable --array="0-$((shards - 1))" --export=ALL,ICRKIT_SHARDS="$shards" \
  --output="$study/logs/paper-%A_%a.out" "${extra[@]}" "$here/paper-array.sbatch" "$study" "$@")
array_id="${array_id%%;*}"  # --parsable prints "id" or "id;cluster"
merge_id=$(sbatch --parsable --dependency="afterok:$array_id" --kill-on-invalid-dep=yes \
  --output="$study/logs/merge-%j.out" "${extra[@]}" "$here/merge.sbatch" "$study")
merge_id="${merge_id%%;*}"
echo "submit-study: array job $array_id ($shards shards of icrkit paper), merge job $merge_id -> $study/merged" >&2
echo "$array_id $merge_id"
