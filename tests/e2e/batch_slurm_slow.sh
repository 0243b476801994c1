#!/usr/bin/env bash
# jnd batch --slurm against a real Slurm (issue 14): Debian's munged, slurmctld
# and slurmd, configured here as a one-node cluster on loopback (ports picked
# free, state in a temporary folder), started and stopped by this test. The
# 4-asset manifest (one row malformed) goes through a job array of 2 tasks
# and the merge job that depends on it (afterok); its summary must equal a
# local run's. Skips, with the reason, only where Slurm cannot start.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
cd "$T" || exit 1
for c in munged slurmctld slurmd sbatch squeue scontrol sinfo; do
  command -v "$c" >/dev/null 2>&1 || skip "$c is not installed (scripts/install-deps.sh installs munge, slurmctld, slurmd, slurm-client)"
done
[ "$(id -u)" -eq 0 ] || skip "slurmd runs jobs as their user and must start as root; this test is not root"

# ---- a one-node cluster on loopback ----
D=$(mktemp -d /tmp/jnd-slurm.XXXXXX) # short: the munge socket's path has a length limit
chmod 755 "$D"
mkdir -p "$D/state" "$D/spool"
stop_cluster() {
  SLURM_CONF=$D/slurm.conf timeout 10 scontrol shutdown >/dev/null 2>&1
  for f in slurmd slurmctld munged; do
    [ -s "$D/$f.pid" ] || continue
    local p; p=$(cat "$D/$f.pid")
    kill -TERM "$p" 2>/dev/null
    for _ in $(seq 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$p" 2>/dev/null
  done
  rm -rf "$D"
}
trap stop_cluster EXIT
read -r P1 P2 < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
dd if=/dev/urandom of="$D/munge.key" bs=1024 count=1 status=none && chmod 400 "$D/munge.key"
cat >"$D/slurm.conf" <<EOF
ClusterName=jndtest
SlurmctldHost=localhost(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$P1
SlurmdPort=$P2
AuthType=auth/munge
AuthInfo=socket=$D/munge.sock
CredType=cred/munge
StateSaveLocation=$D/state
SlurmdSpoolDir=$D/spool
SlurmctldPidFile=$D/slurmctld.pid
SlurmdPidFile=$D/slurmd.pid
SlurmctldLogFile=$D/slurmctld.log
SlurmdLogFile=$D/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
MpiDefault=none
ReturnToService=2
NodeName=jndnode NodeAddr=127.0.0.1 CPUs=2 RealMemory=2048 State=UNKNOWN
PartitionName=jnd Nodes=jndnode Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$D/slurm.conf
munged --socket="$D/munge.sock" --key-file="$D/munge.key" --pid-file="$D/munged.pid" \
  --log-file="$D/munged.log" --seed-file="$D/munged.seed" --force ||
  skip "munged does not start here: $(tail -3 "$D/munged.log" 2>/dev/null | tr '\n' ' ')"
slurmctld -f "$D/slurm.conf" || skip "slurmctld does not start here: $(tail -3 "$D/slurmctld.log" 2>/dev/null | tr '\n' ' ')"
slurmd -f "$D/slurm.conf" -N jndnode || skip "slurmd does not start here: $(tail -3 "$D/slurmd.log" 2>/dev/null | tr '\n' ' ')"
up=""
for _ in $(seq 150); do
  state=$(sinfo -h -n jndnode -o %t 2>/dev/null)
  [ "$state" = "idle" ] && up=1 && break
  sleep 0.2
done
[ -n "$up" ] || skip "the Slurm node did not come up (state '${state:-none}'): $(tail -2 "$D/slurmd.log" | tr '\n' ' ')"
ok "a one-node Slurm runs on loopback (ports $P1, $P2)"

# ---- the manifest, locally ----
"$JND" example -o pairs --size 96x64 >/dev/null 2>&1
TINY="--views 2 --size 64x64 --map-size 64"
cat >assets.csv <<EOF
id,asset,command,options
box,builtin,texres,$TINY --samples 1 --anisotropy 1 --no-matrix
pair,pairs/reference.png,diff,pairs/test.png --display phone
broken,builtin,texres,"--views 'two"
set,builtin,pca,--material builtin $TINY --no-bc
EOF
expect_exit 0 "the local run" "$JND" batch assets.csv -o local --quiet
"$JND" batch merge local --no-timings --quiet

# ---- the scripts ----
SL=(--slurm --shards 2 --array-limit 2 --cpus-per-task 1 --mem 700M --time 10:00)
expect_exit 0 "--dry-run prints the scripts" "$JND" batch assets.csv -o viaslurm "${SL[@]}" --dry-run
check "the array: one task per shard, at most 2 at once, resources and time from the flags" bash -c "
  grep -qx '#SBATCH --array=0-1%2' '$T/out.txt' && grep -qx '#SBATCH --cpus-per-task=1' '$T/out.txt' &&
  grep -qx '#SBATCH --mem=700M' '$T/out.txt' && grep -qx '#SBATCH --time=10:00' '$T/out.txt' &&
  grep -q -- '--shard \"\$SLURM_ARRAY_TASK_ID/2\"' '$T/out.txt'"
check "the merge job depends on the array (afterok) and writes the report" bash -c "
  grep -q -- '--dependency=afterok:ARRAY_ID' '$T/out.txt' && grep -q ' batch merge ' '$T/out.txt' && grep -q ' report ' '$T/out.txt'"
check "--dry-run submits nothing and writes nothing" test ! -e viaslurm
expect_exit 2 "a bad --time" "$JND" batch assets.csv -o x --slurm --time 'soon;rm -rf /'
check "a bad --time: one line" one_line_error

# ---- submitted to the real scheduler ----
expect_exit 0 "submitted with sbatch" "$JND" batch assets.csv -o viaslurm "${SL[@]}"
read -r ARRAY MERGE <"$T/out.txt"
check "sbatch gave two job ids" test -n "${ARRAY:-}" -a -n "${MERGE:-}"
done_=""
for _ in $(seq 900); do
  left=$(squeue -h -j "$ARRAY,$MERGE" -o '%i %t %r' 2>/dev/null)
  [ -z "$left" ] && done_=1 && break
  if echo "$left" | grep -q DependencyNeverSatisfied; then break; fi
  sleep 0.2
done
check "the array and the merge job ran to the end" test -n "$done_"
[ -n "$done_" ] || { echo "squeue: $left"; tail -5 "$D/slurmctld.log"; cat viaslurm/_batch/slurm/*.log 2>/dev/null | tail -20; }
check "the merge job completed" bash -c "scontrol show job '$MERGE' | grep -q 'JobState=COMPLETED'"
check "two array tasks each ran their shard" bash -c "
  grep -q '^jnd batch: 1/2 box (texres) ok' viaslurm/_batch/slurm/shard-0.log &&
  grep -q '^jnd batch: 2/2 set (pca) ok' viaslurm/_batch/slurm/shard-1.log"
check "the merge job wrote the summary and the report" test -s viaslurm/summary.json -a -s viaslurm/report/index.html
"$JND" batch merge viaslurm --no-timings --quiet
check "the merged summary through Slurm equals the local run's (json)" cmp viaslurm/summary.json local/summary.json
check "the merged summary through Slurm equals the local run's (csv)" cmp viaslurm/summary.csv local/summary.csv
check "the summary has the malformed row's error" grep -q "^broken,4,.*,failed,,assets.csv:4: options: a ' is not closed" viaslurm/summary.csv

# ---- a rerun through Slurm recomputes nothing ----
stamp() { stat -c '%i %Y' viaslurm/box/texres.json viaslurm/set/pca.json viaslurm/_batch/records/*.json; }
before=$(stamp)
expect_exit 0 "resubmitted" "$JND" batch assets.csv -o viaslurm "${SL[@]}" --quiet
read -r ARRAY MERGE <"$T/out.txt"
for _ in $(seq 900); do [ -z "$(squeue -h -j "$ARRAY,$MERGE" 2>/dev/null)" ] && break; sleep 0.2; done
check "the second array skipped every complete asset" bash -c "[ \$(cat viaslurm/_batch/slurm/shard-*.log | grep -c 'complete, skipped') -eq 3 ]"
check "and touched no output" test "$before" = "$(stamp)"
finish
