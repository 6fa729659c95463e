#!/bin/bash
# Starts a real single-node Slurm (munged, slurmctld and slurmd on this machine, in a private
# folder, on private ports), submits packaging/slurm/atelier-array.sbatch as a 3-task array over
# a small manifest, waits, checks every job's outputs and the merged summary, and stops Slurm.
# Skips (exit 77) with the reason when Slurm or munge is not installed or cannot start.
#
#   packaging/slurm/slurm_array_test.sh ATELIER_CLI SOURCE_DIR
set -uo pipefail

cli=$(readlink -f "$1")
src=$(readlink -f "$2")
skip() { echo "SKIP: $*"; exit 77; }
fail() { echo "FAIL: $*"; exit 1; }

for tool in munged slurmctld slurmd sbatch squeue sacct scontrol; do
    command -v "$tool" >/dev/null 2>&1 ||
        skip "$tool not found (Debian: apt-get install slurm-wlm munge)"
done
[ "$(id -u)" -eq 0 ] || skip "starting slurmd needs root"

work=$(mktemp -d /tmp/atelier-slurm.XXXXXX)
chmod 755 "$work"
cleanup() {
    [ -f "$work/slurmd.pid" ] && kill "$(cat "$work/slurmd.pid")" 2>/dev/null
    [ -f "$work/slurmctld.pid" ] && kill "$(cat "$work/slurmctld.pid")" 2>/dev/null
    [ -f "$work/munged.pid" ] && kill "$(cat "$work/munged.pid")" 2>/dev/null
    sleep 1
    rm -rf "$work"
}
trap cleanup EXIT

# munge: its own key, socket and state in $work.
mkdir -p "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
munged --force --socket="$work/munge/munge.sock" --key-file="$work/munge/munge.key" \
    --pid-file="$work/munged.pid" --log-file="$work/munge/munged.log" \
    --seed-file="$work/munge/munged.seed" ||
    skip "munged did not start: $(tail -2 "$work/munge/munged.log" 2>/dev/null)"

host=$(hostname -s)
cpus=$(nproc)
ctld_port=$((20000 + RANDOM % 20000))
mkdir -p "$work/state" "$work/spool"
cat >"$work/slurm.conf" <<CONF
ClusterName=ateliertest
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$ctld_port
SlurmdPort=$((ctld_port + 1))
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$work/munge/munge.sock
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
slurmctld || skip "slurmctld did not start: $(tail -3 "$work/slurmctld.log" 2>/dev/null)"
slurmd || skip "slurmd did not start: $(tail -3 "$work/slurmd.log" 2>/dev/null)"

# Wait for the node to be idle.
for _ in $(seq 60); do
    state=$(sinfo -h -n "$host" -o %t 2>/dev/null)
    [ "$state" = "idle" ] && break
    sleep 1
done
[ "$state" = "idle" ] ||
    skip "the Slurm node did not come up (state '$state'): $(tail -3 "$work/slurmd.log")"

# A small manifest: 3 jobs, one per task; each a coarse skirt drape with one picture.
mkdir -p "$work/out"
cat >"$work/manifest.json" <<JSON
{"format": "atelier-batch", "version": 1,
 "defaults": {"particle_distance_mm": 40, "time_limit_s": 0.4, "views": ["front"],
              "size": [96, 96], "threads": 1},
 "matrix": {"projects": ["$src/assets/garments/skirt.atelier"],
            "fabrics": ["cotton", "denim", "silk"]}}
JSON
chmod -R a+rwX "$work"
job=$(ATELIER_CLI="$cli" sbatch --parsable --array=0-2 --cpus-per-task=1 \
    --chdir="$work" --output="$work/task-%a.log" \
    "$src/packaging/slurm/atelier-array.sbatch" "$work/manifest.json" "$work/out") ||
    fail "sbatch failed"
echo "submitted array job $job"
for _ in $(seq 600); do
    [ -z "$(squeue -h -j "$job" 2>/dev/null)" ] && break
    sleep 1
done
[ -z "$(squeue -h -j "$job" 2>/dev/null)" ] || fail "the array did not finish in 10 minutes"
for task in 0 1 2; do
    echo "--- task $task"
    cat "$work/task-$task.log" 2>/dev/null
done

status=0
for fabric in cotton denim silk; do
    name="skirt-$fabric"
    for file in job.json "$name.obj" "$name.body.obj" "$name.report.json" "$name-front.png"; do
        [ -s "$work/out/$name/$file" ] || { echo "missing: $name/$file"; status=1; }
    done
    grep -q '"status": "done"' "$work/out/$name/job.json" 2>/dev/null ||
        { echo "$name: not done"; status=1; }
done
"$cli" batch-summary "$work/out" --manifest "$work/manifest.json" || status=1
grep -q '"done": 3' "$work/out/summary.json" || { echo "summary: not 3 done"; status=1; }
[ $status -eq 0 ] || fail "outputs incomplete"
echo "PASS: 3-task Slurm array draped 3 jobs; summary merged"
