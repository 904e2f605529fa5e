#!/usr/bin/env bash
# End-to-end on a real Slurm: brings up a single-node cluster on this machine
# (Debian slurm-wlm and munge; configuration, keys, state and logs in a temp
# folder; its own munged, slurmctld and slurmd on free ports), submits the job
# array and the dependent merge job of docs/scaling.md with
# scripts/slurm/submit-study.sh for a short `icrkit paper` (two datasets, 6
# views, 3 grasps per finger count, 3 shards), and checks the merged folder
# equals the unsharded run byte for byte. Exits 77 (skipped) with a one-line
# reason when Slurm or munge is missing or cannot start; stops every daemon it
# started on exit. ICRKIT_SLURM_KEEP=1 keeps the temp folder (logs) for a look;
# ICRKIT_SLURM_WAIT (default 120) is how long the study may take, in seconds.
set -uo pipefail
source "$(dirname "$0")/cli_common.sh"
icrkit="${ICRKIT:?set ICRKIT to the icrkit binary}"
case "$icrkit" in  # the jobs run in another folder: an absolute path
  */*) icrkit="$(cd "$(dirname "$icrkit")" && pwd)/$(basename "$icrkit")" ;;
  *) icrkit="$(command -v "$icrkit")" || { echo "FAIL: $ICRKIT not found" >&2; exit 1; } ;;
esac
export PATH="$PATH:/usr/sbin:/sbin"
# Run from inside a Slurm job or with sbatch defaults set, the client commands
# would take those for ours: only our SLURM_CONF (set below) counts.
unset $(compgen -e | grep -E '^(SLURM|SBATCH|SQUEUE|SINFO|SCONTROL|SCANCEL|SALLOC|SRUN)_') 2>/dev/null

skip() { echo "slurm_study: SKIPPED: $*" >&2; exit 77; }

# ---- Can a cluster start here at all? ---------------------------------------
for c in slurmctld slurmd sbatch squeue sinfo scontrol scancel munged munge; do
  command -v "$c" >/dev/null 2>&1 ||
    skip "'$c' not found: install Debian slurm-wlm and munge (scripts/install-deps.sh does, as root)"
done
[ "$(id -u)" -eq 0 ] || skip "starting slurmctld and slurmd needs root (running as $(id -un))"

# ---- Clean-up: cancel the jobs, stop the daemons, remove the folder ---------
started=()   # pids of the slurm daemons this test started
# pids_in_work: processes other than this script with their working directory or
# an open file inside $work: our daemons, their slurmstepd (which detach into
# sessions of their own) and the jobs, whatever their name.
pids_in_work() {
  local p link
  for p in /proc/[0-9]*; do
    case "${p#/proc/}" in "$$" | "$BASHPID") continue ;; esac
    for link in "$p/cwd" "$p"/fd/*; do
      case "$(readlink "$link" 2>/dev/null)" in "$work" | "$work"/*) echo "${p#/proc/}"; break ;; esac
    done
  done
}
cleanup() {
  local pid i left deadline
  if [ ${#started[@]} -gt 0 ]; then
    # Cancel while slurmd still runs, so that the steps end cleanly (up to 15 s).
    timeout 10 scancel --quiet --user=root >/dev/null 2>&1
    deadline=$((SECONDS + 15))
    while [ "$SECONDS" -lt "$deadline" ] && [ -n "$(timeout 3 squeue -h -o %i 2>/dev/null)" ]; do
      sleep 0.5
    done
    for pid in "${started[@]}"; do kill -TERM "$pid" 2>/dev/null; done
    for ((i = 0; i < 50; i++)); do  # up to 10 s
      left=0
      for pid in "${started[@]}"; do kill -0 "$pid" 2>/dev/null && left=1; done
      [ "$left" -eq 0 ] && break
      sleep 0.2
    done
    for pid in "${started[@]}"; do kill -KILL "$pid" 2>/dev/null; done
  fi
  if [ -n "${munge_socket:-}" ] && [ -S "$munge_socket" ]; then
    timeout 10 munged --stop --socket="$munge_socket" >/dev/null 2>&1
  fi
  # Anything left (a stuck munged or slurmstepd, a job): by pid, SIGKILL (slurmstepd ignores SIGTERM).
  pids_in_work | xargs -r kill -KILL 2>/dev/null
  if [ "${ICRKIT_SLURM_KEEP:-0}" = 1 ]; then echo "slurm_study: kept $work" >&2; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

chmod 755 "$work"  # munged wants every directory above its socket searchable by all
mkdir -p "$work/munge" "$work/slurm/state" "$work/slurm/spool" || exit 1

# first_error LOG: the log's first error line (but the notes of a fresh state
# folder and the PMIx plugins Debian's Slurm fails to load), to name why a
# daemon did not come up.
first_error() {
  grep -iE 'error|fatal' "$1" 2>/dev/null | grep -vE 'state file|NOTE: Trying backup|pmix|MPI:' | head -n 1 | cut -c1-200
}

# ---- munge: a fresh key and our own munged on our own socket ------------------
munge_socket="$work/munge/munge.socket"
(umask 077 && head -c 1024 /dev/urandom >"$work/munge/munge.key") || exit 1
chmod 400 "$work/munge/munge.key"
munged --socket="$munge_socket" --key-file="$work/munge/munge.key" --log-file="$work/munge/munged.log" \
  --pid-file="$work/munge/munged.pid" --seed-file="$work/munge/munged.seed" >/dev/null 2>&1 ||
  skip "munged did not start: $(first_error "$work/munge/munged.log")"
munge -n --socket="$munge_socket" | unmunge --socket="$munge_socket" >/dev/null 2>&1 ||
  skip "munge credentials do not round-trip through our munged"

# ---- slurm.conf: this host as the controller and the only node ------------------
host="$(hostname -s)"
read -r ctld_port slurmd_port < <(py "
import random, socket
ports = []
while len(ports) < 2:
    p = random.randint(20000, 29999)
    s = socket.socket()
    try:
        s.bind(('', p)); ports.append(p)
    except OSError:
        pass
    finally:
        s.close()
print(*ports)")
node_line="$(slurmd -C 2>/dev/null | grep '^NodeName=')" || skip "slurmd -C could not describe this machine"
export SLURM_CONF="$work/slurm/slurm.conf"
cat >"$SLURM_CONF" <<EOF
ClusterName=icrkittest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$munge_socket
StateSaveLocation=$work/slurm/state
SlurmdSpoolDir=$work/slurm/spool
SlurmctldPidFile=$work/slurm/slurmctld.pid
SlurmdPidFile=$work/slurm/slurmd.pid
SlurmctldLogFile=$work/slurm/slurmctld.log
SlurmdLogFile=$work/slurm/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
PlugStackConfig=$work/slurm/plugstack.conf
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
MailProg=/bin/true
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MinJobAge=600
KillWait=5
$node_line NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=icrkit Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
: >"$work/slurm/plugstack.conf"
# No cgroups are used (proctrack/linuxproc, task/none), but slurmd 22.05 still
# loads a cgroup plugin at start; without systemd's D-Bus (containers) cgroup/v2
# then builds its hierarchy itself. This file also keeps /etc/slurm/cgroup.conf out.
printf 'CgroupPlugin=autodetect\nIgnoreSystemdOnFailure=yes\n' >"$work/slurm/cgroup.conf"

# ---- slurmctld and slurmd in the foreground, each in a session of its own -----
setsid slurmctld -D -f "$SLURM_CONF" >"$work/slurm/slurmctld.out" 2>&1 &
started+=($!)
setsid slurmd -D -f "$SLURM_CONF" >"$work/slurm/slurmd.out" 2>&1 &
started+=($!)

state=""
deadline=$((SECONDS + 60))
while [ "$SECONDS" -lt "$deadline" ]; do
  kill -0 "${started[0]}" 2>/dev/null ||
    skip "slurmctld exited: $(first_error "$work/slurm/slurmctld.out")"
  kill -0 "${started[1]}" 2>/dev/null ||
    skip "slurmd exited: $(first_error "$work/slurm/slurmd.out")"
  state="$(timeout 5 sinfo -h -N -n "$host" -o %t 2>/dev/null | head -n 1)"
  [ "$state" = idle ] && break
  sleep 0.5
done
[ "$state" = idle ] ||
  skip "node $host not idle within 60 s (state '${state:-none}'): $(first_error "$work/slurm/slurmd.log")"

# ---- The study: the scripts of docs/scaling.md on this cluster -----------------
small=(--datasets cup_sr4000_A,wooden_toy_2_sr4000_A --views 6 --grasps 3 --no-preselection --quiet)
ids="$(cd "$work" && ICRKIT="$icrkit" "$root/scripts/slurm/submit-study.sh" --shards 3 \
  --sbatch --cpus-per-task=1 --sbatch --mem=1G --sbatch --time=00:10:00 \
  "$work/study" "${small[@]}" 2>"$work/err")" || { echo "FAIL: submit-study.sh: $(cat "$work/err")" >&2; exit 1; }
read -r array_id merge_id <<<"$ids"
[[ "$array_id" =~ ^[0-9]+$ && "$merge_id" =~ ^[0-9]+$ ]] || { echo "FAIL: submit-study.sh printed '$ids'" >&2; exit 1; }

# job_field JOB FIELD: a field of `scontrol show job` (jobs stay listed MinJobAge = 600 s after they end).
job_field() { timeout 5 scontrol show job -o "$1" 2>/dev/null | grep -o "\b$2=[^ ]*" | head -n 1 | cut -d= -f2-; }
job_state() { job_field "$1" JobState; }
# wait_job JOB SECONDS: the job's final state, or nothing if it has not ended in time.
wait_job() {
  local s end=$((SECONDS + $2))
  while [ "$SECONDS" -lt "$end" ]; do
    s="$(job_state "$1")"
    case "$s" in
      COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY | BOOT_FAIL | DEADLINE | PREEMPTED)
        echo "$s"; return ;;
    esac
    sleep 0.5
  done
}
wait_s="${ICRKIT_SLURM_WAIT:-120}"
merge_state="$(wait_job "$merge_id" "$wait_s")"
if [ "$merge_state" != COMPLETED ]; then
  fail "merge job $merge_id ${merge_state:+ended as $merge_state}${merge_state:-not done within $wait_s s} (array job $array_id)"
  timeout 5 squeue -h --states=all -o '%i %j %T %r' >&2
  for f in "$work/study/logs/"*; do echo "== $f" >&2; tail -n 20 "$f" >&2; done
  echo "== slurmctld.log" >&2; tail -n 20 "$work/slurm/slurmctld.log" >&2
  exit 1
fi
merge_start="$(job_field "$merge_id" StartTime)"
for t in 0 1 2; do
  s="$(job_state "${array_id}_$t")"
  [ "$s" = COMPLETED ] || fail "array task ${array_id}_$t ended as '${s:-unknown}'"
  [ -s "$work/study/shard-$t/run.json" ] || fail "array task $t did not write study/shard-$t"
  py "import json; r = json.load(open('$work/study/shard-$t/run.json'))['shard']; assert r == {'index': $t, 'count': 3}, r" ||
    fail "study/shard-$t is not shard $t/3"
  # afterok: the merge starts only once every task has ended (times to the second).
  end="$(job_field "${array_id}_$t" EndTime)"
  [[ ! "$merge_start" < "$end" ]] || fail "the merge job started ($merge_start) before array task $t ended ($end)"
done
[ ! -e "$work/study/shard-0/datasets/wooden_toy_2_sr4000_A" ] || fail "shard 0 made a dataset outside its block"

# ---- The same study unsharded, here: the merged folder must equal it -----------
expect_exit 0 "$icrkit" paper "${small[@]}" -o "$work/full"
merged="$work/study/merged"
for f in table1.md table1.csv table1.json table1.svg table1.png eligibility.json grasps.jsonl \
         fig8_4fingers.svg fig8_4fingers.png fig8_4fingers.json fig8_5fingers.svg fig8_5fingers.png fig8_5fingers.json \
         conservative.json conservative.md conservative.svg; do
  [ -s "$work/full/$f" ] || { fail "the unsharded run did not write $f"; continue; }
  cmp -s "$work/full/$f" "$merged/$f" || fail "merged Slurm shards differ from the unsharded run in $f"
done
# run.json: identical but for the list of merged shard folders.
py "
import json
full = json.load(open('$work/full/run.json'))
merged = json.load(open('$merged/run.json'))
assert merged.pop('merged_from') == ['$work/study/shard-0', '$work/study/shard-1', '$work/study/shard-2'], 'merged_from'
assert full == merged, 'run.json differs'
" || fail "merged run.json differs from the unsharded one beyond merged_from"
# The renders: the same files, identical (each shard renders the first
# evaluated grasps of its block; the merge keeps those an unsharded run renders).
[ "$(ls "$work/full/renders")" = "$(ls "$merged/renders")" ] ||
  fail "merged renders differ from the unsharded run's: $(ls "$merged/renders" | tr '\n' ' ')"
for f in "$work/full/renders/"*.png; do
  cmp -s "$f" "$merged/renders/$(basename "$f")" || fail "merged render $(basename "$f") differs or is missing"
done

# The docs' recovery of one failed task: an array of task 1 alone, ICRKIT_SHARDS
# giving the shard count, --reuse; the shard is the same as before.
cp "$work/study/shard-1/grasps.jsonl" "$work/shard1_grasps.jsonl"
rerun_id="$(cd "$work" && ICRKIT="$icrkit" ICRKIT_SHARDS=3 sbatch --parsable --array=1 --cpus-per-task=1 --mem=1G \
  --time=00:10:00 --output="$work/study/logs/rerun-%A_%a.out" "$root/scripts/slurm/paper-array.sbatch" \
  "$work/study" "${small[@]}" --reuse 2>"$work/err")" || fail "sbatch of the re-run: $(cat "$work/err")"
rerun_id="${rerun_id%%;*}"
if [ -n "$rerun_id" ]; then
  s="$(wait_job "$rerun_id" 45)"
  [ "$s" = COMPLETED ] || fail "the re-run of task 1 (job $rerun_id) ended as '${s:-not done within 45 s}'"
  py "import json; r = json.load(open('$work/study/shard-1/run.json'))['shard']; assert r == {'index': 1, 'count': 3}, r" ||
    fail "the re-run of task 1 is not shard 1/3"
  cmp -s "$work/shard1_grasps.jsonl" "$work/study/shard-1/grasps.jsonl" || fail "the re-run of task 1 changed its records"
fi

[ "$failures" -eq 0 ] && echo "slurm_study: all checks passed (array job $array_id, merge job $merge_id)" >&2
exit $((failures > 0))
