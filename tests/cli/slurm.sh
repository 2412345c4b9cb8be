#!/usr/bin/env bash
# `prism batch --shard` under a real Slurm: starts a single-node cluster on localhost (munged,
# slurmctld, slurmd; Debian's slurm-wlm and munge), submits the shipped
# docs/examples/prism-batch.sbatch as a 3-task array over a small job file, and checks that
# every job's output exists, the three per-shard reports list every job as rendered, and the
# outputs are bit-identical to one plain `prism batch` of the same file.
# Everything the cluster writes (its configuration, state, logs, PID files, munge's socket)
# lives in a temporary folder, so nothing under /etc or /var is touched and a cluster already
# running on the machine is left alone; the daemons this test started are stopped by their PID
# files on any exit. Needs root (the daemons run as root, munged as munge).
# Exits 77 (skipped) only when the tools are not installed or it is not root; a cluster that
# is installed but does not start is a failure, with the daemons' logs printed.
# Usage: slurm.sh PRISM SOURCE_DIR
source "$(dirname "$0")/lib/common.bash" "$@"
set -eo pipefail

for tool in slurmctld slurmd sbatch sinfo squeue munged; do
  command -v "$tool" >/dev/null || PATH=$PATH:/usr/sbin
  command -v "$tool" >/dev/null || { echo "SKIP: $tool is not installed (scripts/setup.sh installs slurm-wlm and munge)"; exit 77; }
done
[[ $(id -u) -eq 0 ]] || { echo "SKIP: a test cluster needs root"; exit 77; }
PRISM=$(realpath "$PRISM")
SBATCH_SCRIPT="$SRC/docs/examples/prism-batch.sbatch"

# munged runs as the munge user, which cannot enter the 0700 $TMP: its folder is a separate
# one it owns, which it also insists must not be writable by others.
MUNGE_DIR=$(mktemp -d /tmp/prism-munge.XXXXXX)
C="$TMP/cluster"
mkdir -p "$C/state" "$C/spool" "$TMP/work"
chown munge:munge "$MUNGE_DIR"
chmod 0755 "$MUNGE_DIR"

cleanup() {
  local status=$? file pid
  # The daemons this test started, by their PID files; slurmd first, so that it does not
  # outlive its controller and keep retrying.
  for file in "$C/slurmd.pid" "$C/slurmctld.pid" "$MUNGE_DIR/munged.pid"; do
    [[ -s $file ]] || continue
    pid=$(cat "$file")
    kill "$pid" 2>/dev/null || continue
    for ((i = 0; i < 100; i++)); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -0 "$pid" 2>/dev/null && kill -9 "$pid" 2>/dev/null
  done
  rm -rf "$TMP" "$MUNGE_DIR"
  exit "$status"
}
trap cleanup EXIT

logs() {
  local log
  for log in "$MUNGE_DIR/munged.log" "$C/slurmctld.log" "$C/slurmd.log" "$TMP"/work/prism-batch-*.out; do
    [[ -e $log ]] || continue
    echo "----- $log (last 40 lines)"
    tail -n 40 "$log"
  done
}
# die MESSAGE: a failure the rest cannot go on from; prints the logs and exits.
die() {
  echo "FAIL: $*"
  logs
  exit 1
}

# seconds_since NANOSECONDS: the seconds from `date +%s%N` then to now, to 0.1 s.
seconds_since() {
  local tenths=$((($(date +%s%N) - $1) / 100000000))
  echo "$((tenths / 10)).$((tenths % 10))"
}

# cred_expire (below) is also how long a requeued job waits before it may start again: 120 s
# by default, 10 here so that the requeue check is quick.
# Two free TCP ports for slurmctld and slurmd, so that a cluster already on the default
# 6817 and 6818 is not disturbed.
read -r CTLD_PORT SLURMD_PORT < <(/usr/bin/python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*(x.getsockname()[1] for x in s))')

runuser -u munge -- munged --socket="$MUNGE_DIR/munge.socket" --pid-file="$MUNGE_DIR/munged.pid" \
  --log-file="$MUNGE_DIR/munged.log" --seed-file="$MUNGE_DIR/munged.seed" ||
  die "munged did not start"

export SLURM_CONF="$C/slurm.conf"
cat >"$SLURM_CONF" <<EOF
ClusterName=prismtest
SlurmctldHost=localhost
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$MUNGE_DIR/munge.socket,cred_expire=10
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
StateSaveLocation=$C/state
SlurmdSpoolDir=$C/spool
SlurmctldPidFile=$C/slurmctld.pid
SlurmdPidFile=$C/slurmd.pid
SlurmctldLogFile=$C/slurmctld.log
SlurmdLogFile=$C/slurmd.log
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
NodeName=localhost CPUs=$(nproc) State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF

started=$(date +%s%N)
slurmctld -f "$SLURM_CONF" || die "slurmctld did not start"
slurmd -f "$SLURM_CONF" -N localhost || die "slurmd did not start"
# The node registers within seconds; 60 s is for a loaded machine.
for ((i = 0; i < 120; i++)); do
  state=$(sinfo -h -n localhost -o %T 2>/dev/null || true)
  [[ $state == idle ]] && break
  sleep 0.5
done
[[ $state == idle ]] || die "the node is '${state:-not listed}' after 60 s, not idle: $(sinfo 2>&1)"
echo "ok: single-node cluster up in $(seconds_since "$started") s (ports $CTLD_PORT, $SLURMD_PORT)"

# 9 renders over the three shipped scenes, cheap enough for 3 tasks of 1 thread each.
W="$TMP/work"
mkdir -p "$W/slurm" "$W/plain"
jobfile() {
  cat <<EOF
{
  "version": 1,
  "defaults": {"res": "64x48"},
  "jobs": [
    {"name": "w", "scene": "$SRC/scenes/whitted.gltf", "integrator": ["phong", "shadow", "whitted"],
     "spp": 2, "output": "$1/{job}-{scene}-{integrator}-{spp}.exr"},
    {"name": "s", "scene": "$SRC/scenes/spheres.gltf", "integrator": ["phong", "whitted"],
     "spp": [1, 4], "output": "$1/{job}-{scene}-{integrator}-{spp}.exr"},
    {"name": "f", "scene": "$SRC/scenes/furnace.gltf", "integrator": "shadow",
     "spp": [2, 4], "output": "$1/{job}-{scene}-{integrator}-{spp}.exr"}
  ]
}
EOF
}
jobfile "$W/slurm" >"$W/slurm.json"
jobfile "$W/plain" >"$W/plain.json"
"$PRISM" batch "$W/slurm.json" --dry-run >"$W/dry" || die "dry run: $(cat "$W/dry")"
mapfile -t expected < <(sed -n 's/.*  -> \(.*\)  \[.*\]$/\1/p' "$W/dry")
[[ ${#expected[@]} -eq 9 ]] || die "the job file expands into ${#expected[@]} renders, expected 9"
for k in 0 1 2; do
  "$PRISM" batch "$W/slurm.json" --dry-run --shard "$k/3" | sed -n 's/.*  -> .*\/\(.*\)  \[.*\]$/\1/p' |
    tr '\n' ' ' >"$W/plan-$k"
  echo "shard $k/3 plans: $(cat "$W/plan-$k")"
done

# The shipped script as a user submits it, with PRISM and JOBS from the environment (sbatch
# exports the submitting environment by default) and one CPU a task so that two tasks run
# at once on a 2-core node. --wait returns when every task has ended, with the highest exit
# code of them; timeout bounds a cluster that never schedules them.
submitted=$(date +%s%N)
PRISM="$PRISM" JOBS="$W/slurm.json" timeout 300 sbatch --wait --array=0-2 --cpus-per-task=1 \
  --chdir="$W" --output="$W/prism-batch-%A_%a.out" --time=10 "$SBATCH_SCRIPT" >"$W/sbatch.out" 2>&1 ||
  die "sbatch --wait exited $?: $(cat "$W/sbatch.out")"
took=$(seconds_since "$submitted")
echo "ok: $(head -1 "$W/sbatch.out"); the array of 3 ended in $took s"
for out in "$W"/prism-batch-*.out; do
  echo "----- $(basename "$out")"
  cat "$out"
done

# Every job's output, once, and nothing left half-written.
for path in "${expected[@]}"; do
  [[ -s $path ]] || fail "missing output $path"
done
[[ $(find "$W/slurm" -name '*.exr' | wc -l) -eq 9 ]] || fail "$(find "$W/slurm" -name '*.exr' | wc -l) EXRs, expected 9"
find "$W/slurm" -name '*.tmp*' -o -name '*.checkpoint' | grep -q . && fail "left over: $(find "$W/slurm" -name '*.tmp*' -o -name '*.checkpoint')"
# Three reports, each of its own shard, every job rendered, together each output once.
/usr/bin/python3 - "$W/slurm" "${expected[@]}" <<'EOF' || fail "the shard reports are not what was planned"
import json, sys
folder, expected = sys.argv[1], sorted(sys.argv[2:])
seen = []
for k in range(3):
    report = json.load(open(f"{folder}/batch-report-{k}-of-3.json"))
    assert report["shard"] == f"{k}/3", report["shard"]
    for job in report["jobs"]:
        assert job["status"] == "rendered", (k, job["output"], job["status"], job["error"])
        seen.append(job["output"])
    names = " ".join(j["output"].rsplit("/", 1)[-1] for j in report["jobs"])
    print(f"shard {k}/3: {len(report['jobs'])} rendered in {report['wall_seconds']:.2f} s: {names}")
assert sorted(seen) == expected, (sorted(seen), expected)
EOF

# The same file rendered by one plain `prism batch`: the same pixels, bit for bit.
"$PRISM" batch "$W/plain.json" --threads 2 --quiet || fail "plain prism batch exited $?"
dump() { oiiotool "$1" --dumpdata 2>&1 | sed 1d; }
same=0
for path in "${expected[@]}"; do
  plain="$W/plain/$(basename "$path")"
  max=$("$PRISM" diff "$path" "$plain" --metric max) || { fail "prism diff $path $plain failed"; continue; }
  [[ $max == 0 ]] || { fail "$(basename "$path"): max difference $max from the plain batch"; continue; }
  cmp -s <(dump "$path") <(dump "$plain") || { fail "$(basename "$path"): pixels differ from the plain batch"; continue; }
  same=$((same + 1))
done
echo "ok: $same of ${#expected[@]} outputs bit-identical to the plain batch"

# What the time limit does: Slurm's --signal=B:USR1 (sent here at once with scancel) reaches the
# script, which passes it to prism; prism saves a checkpoint and stops (138), the script
# requeues its task, and the task's second run resumes the job from the checkpoint: the same
# pixels as one uninterrupted render.
mkdir -p "$W/requeue"
# Long enough (several seconds on one core) that checkpoints every second are written before it
# ends, now that a process starts in milliseconds.
LONG_SPP=1024
cat >"$W/requeue.json" <<EOF
{"version": 1, "jobs": [{"name": "long", "scene": "$SRC/scenes/spheres.gltf", "res": "160x90",
  "spp": $LONG_SPP, "output": "$W/requeue/long.exr"}]}
EOF
PRISM="$PRISM" JOBS="$W/requeue.json" sbatch --parsable --array=0-0 --cpus-per-task=1 --chdir="$W" \
  --output="$W/requeue-%A_%a.out" --time=10 "$SBATCH_SCRIPT" --checkpoint-interval 1 >"$W/requeue.id" 2>&1 ||
  die "sbatch of the requeue test: $(cat "$W/requeue.id")"
job=$(cut -d';' -f1 "$W/requeue.id")
for ((i = 0; i < 600; i++)); do
  [[ -e $W/requeue/long.exr.checkpoint ]] && break
  sleep 0.1
done
[[ -e $W/requeue/long.exr.checkpoint ]] || die "the requeue test wrote no checkpoint in 60 s"
requeue_started=$(date +%s%N)
scancel --batch --signal=USR1 "${job}_0" || fail "scancel --signal=USR1 ${job}_0"
# Requeued, it waits for the node to be released and runs again; bounded at 180 s.
for ((i = 0; i < 360; i++)); do
  [[ -e $W/requeue/long.exr ]] && ! squeue -h -j "$job" 2>/dev/null | grep -q . && break
  sleep 0.5
done
echo "requeue: from SIGUSR1 to the finished output $(seconds_since "$requeue_started") s"
log=$(cat "$W/requeue-${job}_0.out" 2>/dev/null || true)
echo "----- requeue-${job}_0.out"
echo "$log"
grep -q "^prism: stopped by SIGUSR1: no job half-written, the running one saved a checkpoint" <<<"$log" ||
  fail "SIGUSR1 did not stop prism with a checkpoint"
grep -q "^prism-batch: checkpoint saved; requeueing ${job}_0$" <<<"$log" || fail "the task did not requeue itself"
grep -q "restart 1$" <<<"$log" || fail "the task did not run a second time"
resumed=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["jobs"][0]["resumed_samples"])' \
  "$W/requeue/batch-report.json" 2>/dev/null || echo 0)
((resumed > 0 && resumed < LONG_SPP)) || fail "the requeued task did not resume from the checkpoint (resumed_samples $resumed)"
echo "requeue: the second run resumed at $resumed of $LONG_SPP spp"
if [[ -e $W/requeue/long.exr ]]; then
  "$PRISM" render "$SRC/scenes/spheres.gltf" -o "$W/long-plain.exr" --res 160x90 --spp "$LONG_SPP" --quiet ||
    fail "uninterrupted render of the requeue job"
  max=$("$PRISM" diff "$W/requeue/long.exr" "$W/long-plain.exr" --metric max) || max="failed"
  if [[ $max == 0 ]] && cmp -s <(dump "$W/requeue/long.exr") <(dump "$W/long-plain.exr"); then
    echo "ok: stopped by SIGUSR1, requeued, resumed: the same pixels as an uninterrupted render"
  else
    fail "the requeued render differs from an uninterrupted one (max $max)"
  fi
else
  fail "the requeued task did not write its output within 180 s: $(squeue -j "$job" 2>&1)"
fi

((failures == 0)) || logs
echo "$failures failed"
[[ $failures -eq 0 ]]
