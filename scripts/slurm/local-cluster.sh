#!/bin/bash
# A single-node Slurm cluster on this machine, for trying submit.sh and for the Slurm test
# (tests/slurm.rs): munged, slurmctld and slurmd with a generated slurm.conf, all their files in
# one directory, no cgroups (proctrack/linuxproc, task/none), no accounting, ports 16817-16818.
# Needs Debian's slurm-wlm and munge and root (the daemons run as root, as SlurmUser).
#
#   scripts/slurm/local-cluster.sh start DIR   # prints the line to export SLURM_CONF
#   scripts/slurm/local-cluster.sh stop DIR
set -euo pipefail
action=${1:-}
dir=${2:-}
if [ -z "$dir" ] || { [ "$action" != start ] && [ "$action" != stop ]; }; then
    sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
fi
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
export SLURM_CONF=$dir/slurm.conf

# Waits up to $2 seconds for the process whose pid file is $1 to end.
wait_gone() {
    local pid
    pid=$(cat "$1" 2>/dev/null) || return 0
    for ((i = 0; i < $2 * 10; i++)); do
        kill -0 "$pid" 2>/dev/null || return 0
        sleep 0.1
    done
    echo "local-cluster.sh: process $pid ($1) still runs; killing it" >&2
    kill -9 "$pid" 2>/dev/null || true
}

stop() {
    if [ -f "$dir/slurmctld.pid" ] || [ -f "$dir/slurmd.pid" ]; then
        scontrol shutdown >/dev/null 2>&1 || true
        wait_gone "$dir/slurmctld.pid" 20
        wait_gone "$dir/slurmd.pid" 20
    fi
    if [ -f "$dir/munged.pid" ]; then
        munged --stop --socket="$dir/munge.sock" >/dev/null 2>&1 || true
        wait_gone "$dir/munged.pid" 10
    fi
    rm -f "$dir"/*.pid
}

if [ "$action" = stop ]; then
    stop
    exit 0
fi

for tool in munged slurmctld slurmd sbatch scontrol sinfo; do
    command -v "$tool" >/dev/null || { echo "local-cluster.sh: $tool not found (apt-get install slurm-wlm munge)" >&2; exit 1; }
done
if [ "$(id -u)" != 0 ]; then
    echo "local-cluster.sh: run as root (the daemons run as root)" >&2
    exit 1
fi
# A cluster left by an earlier run is stopped first.
stop
# munged refuses a socket directory that not everyone may enter, and a key others may read.
chmod 755 "$dir"
mkdir -p "$dir/state" "$dir/spool"
if [ ! -f "$dir/munge.key" ]; then
    head -c 1024 /dev/urandom >"$dir/munge.key"
fi
chmod 600 "$dir/munge.key"
munged --socket="$dir/munge.sock" --key-file="$dir/munge.key" --log-file="$dir/munged.log" \
    --pid-file="$dir/munged.pid" --seed-file="$dir/munged.seed"

host=$(hostname -s)
cpus=$(nproc)
# What the node offers, less 1 GiB for the system (slurmd refuses a node that claims more).
memory=$(awk '/MemTotal/ { m = int($2 / 1024) - 1024; print (m > 256 ? m : 256) }' /proc/meminfo)
cat >"$SLURM_CONF" <<CONF
ClusterName=kairoslocal
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge.sock
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
SlurmctldTimeout=30
SlurmdTimeout=30
# Schedule pending array tasks within a second of a free CPU (the default main loop is 60 s).
SchedulerParameters=sched_interval=1,sched_min_interval=100000
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
slurmctld
slurmd
# The node is ready when sinfo shows it idle (up to 30 s).
for ((i = 0; i < 300; i++)); do
    if sinfo --noheader --states=idle --format=%N 2>/dev/null | grep -q .; then
        echo "export SLURM_CONF=$SLURM_CONF"
        exit 0
    fi
    sleep 0.1
done
echo "local-cluster.sh: the node did not come up in 30 s; the logs are in $dir" >&2
tail -n 20 "$dir/slurmctld.log" "$dir/slurmd.log" >&2 || true
stop
exit 1
