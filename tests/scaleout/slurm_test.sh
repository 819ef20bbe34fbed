#!/usr/bin/env bash
# lsds on a real Slurm: starts munged, slurmctld and slurmd on this machine (one node, a
# generated minimal configuration in a temporary folder, no accounting), then
#   1. `lsds submit slurm --shards 4 --submit --wait` renders a 4-task job array and merges it:
#      the merged collection must equal a single `lsds generate` run byte for byte;
#   2. with one task made to fail, the merge must never run (Slurm cancels it: afterok +
#      --kill-on-invalid-dep=yes), no output may appear, and lsds submit must exit non-zero.
# The daemons it started are stopped by PID on every exit. When they cannot start (not
# installed, no permission), the test exits 77, which ctest reports as skipped with the reason.
# Usage: slurm_test.sh LSDS_BINARY SOURCE_DIR
set -uo pipefail
LSDS=$1
SRC=$2
SKIP=77

skip() { echo "SKIPPED: $*"; exit $SKIP; }
fail() { echo "FAILED: $*"; exit 1; }

for tool in munged slurmctld slurmd sbatch scontrol sinfo; do
  command -v "$tool" >/dev/null 2>&1 ||
    skip "$tool is not installed (scripts/install-deps.sh installs slurm-wlm and munge)"
done

T=$(mktemp -d "${TMPDIR:-/tmp}/lsds-slurm.XXXXXX")
chmod 755 "$T"  # munged's socket folder must be searchable
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
  done
  rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 1' INT TERM

# --- munge: a fresh key and a socket of our own ---------------------------------------------
mkdir -p "$T/munge" "$T/state" "$T/spool"
chmod 700 "$T/munge"
head -c 1024 /dev/urandom > "$T/munge/munge.key"
chmod 400 "$T/munge/munge.key"
munged --foreground --force --socket="$T/munge/socket" --key-file="$T/munge/munge.key" \
  --log-file="$T/munge/munged.log" --pid-file="$T/munge/munged.pid" \
  --seed-file="$T/munge/munged.seed" > "$T/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$T/munge/socket" ] && break; sleep 0.1; done
[ -S "$T/munge/socket" ] || skip "munged did not start: $(tail -3 "$T/munged.out")"

# --- slurm.conf: one node, this machine, as the current user -----------------------------------
NODE=$(hostname -s)
USER_NAME=$(id -un)
PORT=$((20000 + RANDOM % 20000))
cat > "$T/slurm.conf" <<CONF
ClusterName=lsdstest
SlurmctldHost=$NODE
SlurmctldPort=$PORT
SlurmdPort=$((PORT + 1))
AuthType=auth/munge
AuthInfo=socket=$T/munge/socket
CredType=cred/munge
SlurmUser=$USER_NAME
SlurmdUser=$USER_NAME
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
NodeName=$NODE CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$T/slurm.conf
export CI=true

slurmctld -D > "$T/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D > "$T/slurmd.out" 2>&1 &
pids+=($!)
state=""
for _ in $(seq 100); do
  state=$(sinfo -h -o %T 2>/dev/null | head -1)
  [ "$state" = "idle" ] && break
  sleep 0.2
done
if [ "$state" != "idle" ]; then
  skip "the Slurm daemons did not start (node state '${state}'):" \
    "$(tail -2 "$T/slurmctld.out" "$T/slurmd.out" "$T/slurmctld.log" "$T/slurmd.log" 2>/dev/null)"
fi
echo "slurm: node $NODE idle (slurmctld port $PORT)"

# --- the run: 12 frames of a small survey -------------------------------------------------------
sed -e 's/res:\[512,512\]/res:[64,48]/' -e 's/x:\[-40,40,6\]/x:[-40,40,4]/' \
  -e 's/y:\[-25,25,4\]/y:[-25,25,3]/' "$SRC/examples/demo_survey.lcap" > "$T/small.lcap"
SCENE="$SRC/examples/uav_survey.lscene"
RUN=(--spp 1 --seed 3)
"$LSDS" generate "$SCENE" "$T/small.lcap" "${RUN[@]}" -q -o "$T/single" ||
  fail "the single run failed"

# 1. The array and the merge equal the single run.
timeout 120 "$LSDS" submit slurm "$SCENE" "$T/small.lcap" "${RUN[@]}" -o "$T/merged" \
  --shards 4 --throttle 4 --cpus-per-task 1 --time 0:05:00 --submit --wait > "$T/submit1.out" 2>&1
rc=$?
cat "$T/submit1.out"
[ $rc -eq 0 ] || fail "lsds submit --wait exited $rc; logs: $(cat "$T"/merged.shards/logs/* 2>/dev/null)"
for i in 0 1 2 3; do
  [ -f "$T/merged.shards/logs/"generate-*_$i.log ] || fail "no log of array task $i"
done
diff -r "$T/single" "$T/merged" > "$T/diff.out" ||
  fail "the merged collection differs from the single run: $(head -5 "$T/diff.out")"
echo "ok: the 4-task array + merge equals the single run byte for byte"

# 2. A failing task: its shard folder is taken by a file, so lsds generate exits 2 in task 2.
mkdir -p "$T/failed.shards"
echo "not a folder" > "$T/failed.shards/shard-2"
timeout 120 "$LSDS" submit slurm "$SCENE" "$T/small.lcap" "${RUN[@]}" -o "$T/failed" \
  --shards 4 --cpus-per-task 1 --submit --wait > "$T/submit2.out" 2>&1
rc=$?
cat "$T/submit2.out"
[ $rc -ne 0 ] || fail "lsds submit --wait exited 0 although task 2 failed"
[ ! -e "$T/failed" ] || fail "an output appeared although task 2 failed"
merge_job=$(sed -n 's/^Submitted batch job \([0-9]*\).*/\1/p' "$T/submit2.out")
[ -n "$merge_job" ] || fail "no merge job id in the output of lsds submit"
merge_state=$(scontrol show job "$merge_job" | grep -o 'JobState=[A-Z]*')
[ "$merge_state" = "JobState=CANCELLED" ] ||
  fail "the merge job $merge_job is $merge_state, expected CANCELLED (never run)"
ls "$T/failed.shards/logs/"merge-* >/dev/null 2>&1 && fail "the merge job ran (it has a log)"
echo "ok: a failed task leaves the merge unrun ($merge_state) and lsds submit exits $rc"
exit 0
