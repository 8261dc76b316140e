#!/usr/bin/env bash
# A series rendered by a real Slurm job array (docs/scale-out.md): this script starts a one-node
# Slurm cluster of its own (munged, slurmctld, slurmd in the foreground, on ports of its own, in a
# directory of its own), submits `sbatch --array=0-2 --wait` whose tasks each run
# `atmoglobe render --time-series` with no --shard (the shard comes from Slurm's variables), and
# checks that the three tasks wrote the series' 7 frames exactly once, each equal byte for byte to
# the frame of the whole series rendered in one process. Where Slurm cannot start (not installed,
# not permitted), it says why and checks the shards with the variables set by hand instead.
#
# Usage: SlurmShards.sh ATMOGLOBE OUTDIR
set -euo pipefail
cli="$1"
out="$2"
rm -rf "$out"
mkdir -p "$out/whole" "$out/slurm" "$out/cluster/state" "$out/cluster/spool"
"$cli" synth --grid --grid-size 30,30,8,4 -o "$out/series.nc" >/dev/null 2>&1
common=(render --grid "$out/series.nc" --time-series --time-substeps 2 --grid-step 2000 --no-map
        --camera 34.4,-97.6,8e5,0,-60,0 --size 48x27)
env -u SLURM_ARRAY_TASK_ID -u SLURM_ARRAY_TASK_COUNT -u SLURM_ARRAY_TASK_MIN \
  "$cli" "${common[@]}" -o "$out/whole/s.png" >/dev/null 2>&1

# Compares the frames in $out/slurm with the whole series: the same 7 names, the same bytes.
check() {
  local whole shards
  whole=$(cd "$out/whole" && ls)
  shards=$(cd "$out/slurm" && ls)
  if [ "$whole" != "$shards" ]; then
    echo "FAIL: the shards wrote [$(echo $shards)], the whole series is [$(echo $whole)]"
    exit 1
  fi
  for f in $whole; do
    cmp -s "$out/whole/$f" "$out/slurm/$f" || { echo "FAIL: $f differs from the whole series' frame"; exit 1; }
  done
  echo "$(echo "$whole" | wc -w) frames, each written once by the shards and equal to the whole series"
}

by_hand() {
  echo "Slurm cannot start here: $1; the shards are checked with Slurm's variables set by hand"
  for id in 0 1 2; do
    SLURM_ARRAY_TASK_ID=$id SLURM_ARRAY_TASK_COUNT=3 SLURM_ARRAY_TASK_MIN=0 \
      "$cli" "${common[@]}" -o "$out/slurm/s.png" >/dev/null 2>&1
  done
  check
  exit 0
}

missing=""
for p in munged mungekey slurmctld slurmd sbatch sinfo scontrol; do
  command -v "$p" >/dev/null 2>&1 || missing="$missing $p"
done
[ -z "$missing" ] || by_hand "not installed:$missing (Debian slurm-wlm, munge)"

c="$out/cluster"
user=$(id -un)
node=$(hostname -s)
base=$(( 20000 + ($$ % 20000) ))
cat > "$c/slurm.conf" <<EOF
ClusterName=atmoglobe-test
SlurmctldHost=$node
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$c/munge.socket
CryptoType=crypto/munge
StateSaveLocation=$c/state
SlurmdSpoolDir=$c/spool
SlurmctldPidFile=$c/slurmctld.pid
SlurmdPidFile=$c/slurmd.pid
SlurmctldPort=$base
SlurmdPort=$((base + 1))
SlurmctldLogFile=$c/slurmctld.log
SlurmdLogFile=$c/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=$node CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$c/slurm.conf"
pids=()
cleanup() {
  scontrol shutdown >/dev/null 2>&1 || true
  for p in "${pids[@]}"; do kill "$p" >/dev/null 2>&1 || true; done
  [ -f "$c/munged.pid" ] && kill "$(cat "$c/munged.pid")" >/dev/null 2>&1 || true
}
trap cleanup EXIT

mungekey -c -f -k "$c/munge.key" >/dev/null 2>&1 && chmod 600 "$c/munge.key" || by_hand "mungekey failed"
munged --force --key-file="$c/munge.key" --socket="$c/munge.socket" --pid-file="$c/munged.pid" \
  --log-file="$c/munged.log" --seed-file="$c/munge.seed" >/dev/null 2>&1 || by_hand "munged did not start ($(tail -1 "$c/munged.log" 2>/dev/null))"
slurmctld -D >"$c/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D >"$c/slurmd.out" 2>&1 &
pids+=($!)
ready=""
for _ in $(seq 1 60); do
  if sinfo -h -o %T 2>/dev/null | grep -q idle; then ready=1; break; fi
  sleep 0.5
done
[ -n "$ready" ] || by_hand "the node did not come up within 30 s ($(tail -1 "$c/slurmd.log" 2>/dev/null))"
echo "one-node Slurm cluster up: $(sinfo -h -o '%P %D %T %N' | head -1); $(slurmd -V)"

cat > "$c/job.sh" <<EOF
#!/bin/sh
# No --shard: each task's shard comes from SLURM_ARRAY_TASK_ID / _COUNT / _MIN.
exec "$cli" ${common[@]} -o "$out/slurm/s.png"
EOF
chmod +x "$c/job.sh"
timeout 300 sbatch --array=0-2 --wait -o "$c/task_%a.out" "$c/job.sh" ||
  { echo "FAIL: the job array failed"; tail -n 5 "$c"/task_*.out "$c/slurmd.log"; exit 1; }
for t in 0 1 2; do
  grep -h "shard $t/3 (SLURM_ARRAY_TASK_ID/COUNT)" "$c/task_$t.out" || { echo "FAIL: task $t rendered no shard of its own"; cat "$c/task_$t.out"; exit 1; }
done
check
