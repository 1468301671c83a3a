#!/usr/bin/env bash
# A private single-node SLURM cluster on this machine, for the sharded-run test
# (tests/slurm/sharded-study.sh) and for trying a job array before a real cluster. Everything
# lives under DIR: the configuration (DIR/slurm.conf), a generated munge key and munged's
# socket, the controller's state and the node's spool, the daemons' logs and pid files. Nothing
# under /etc or /run is touched, so the machine's own SLURM or munge (if any) is left alone.
#
#   bash tests/slurm/single-node.sh start DIR   # prints "export SLURM_CONF=DIR/slurm.conf"
#   bash tests/slurm/single-node.sh stop DIR
#
# Needs Debian's packages slurmctld, slurmd, slurm-client and munge (install-deps.sh installs
# them) and root: slurmd starts the jobs as the submitting user. The node is declared with this
# machine's host name and CPU count (`slurmd -C`), without systemd or cgroups
# (proctrack/linuxproc, task/none, no accounting), which is what a container allows.
# `start` waits until the node is idle (at most 60 s) or fails naming the daemon's log.
set -euo pipefail

usage() { echo "usage: $0 start|stop DIR" >&2; exit 2; }
[ $# -eq 2 ] || usage
action=$1
dir=$(realpath -m "$2")

stop() {
  for pidfile in "$dir/slurmd.pid" "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
    [ -f "$pidfile" ] || continue
    pid=$(cat "$pidfile")
    if kill "$pid" 2>/dev/null; then
      for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
      kill -9 "$pid" 2>/dev/null || true
    fi
    rm -f "$pidfile"
  done
}

fail() {  # fail WHAT LOG: the reason and the log's tail, then stop what started
  echo "single-node.sh: $1" >&2
  [ -f "$2" ] && { echo "--- last lines of $2:" >&2; tail -n 20 "$2" >&2; }
  stop
  exit 1
}

case $action in
  stop) stop; exit 0 ;;
  start) ;;
  *) usage ;;
esac

[ "$(id -u)" -eq 0 ] || { echo "single-node.sh: must run as root (slurmd starts jobs as their user)" >&2; exit 1; }
for tool in munged slurmctld slurmd sbatch sinfo; do
  command -v "$tool" >/dev/null || {
    echo "single-node.sh: $tool not found: install Debian's slurmctld, slurmd, slurm-client and munge (bash install-deps.sh)" >&2
    exit 1
  }
done

mkdir -p "$dir/munge" "$dir/state" "$dir/spool"
chmod 700 "$dir/munge"
# munged checks that its key is private and its directories are not writable by others.
dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$dir/munge/munge.key"
socket="$dir/munge/munge.socket"
munged --force --key-file="$dir/munge/munge.key" --socket="$socket" \
  --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" \
  --seed-file="$dir/munge/munged.seed" ||
  fail "munged did not start" "$dir/munge/munged.log"

host=$(hostname -s)
cpus=$(nproc)
memory=$(slurmd -C | sed -n 's/.*RealMemory=\([0-9]*\).*/\1/p')
cat > "$dir/slurm.conf" <<CONF
ClusterName=lgvi-single-node
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
SlurmctldPort=$(( 20000 + RANDOM % 20000 ))
SlurmdPort=$(( 40000 + RANDOM % 20000 ))
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
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SchedulerParameters=sched_min_interval=100000
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
NodeName=$host CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=single Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$dir/slurm.conf"

slurmctld -f "$SLURM_CONF" || fail "slurmctld did not start" "$dir/slurmctld.log"
slurmd -f "$SLURM_CONF" || fail "slurmd did not start" "$dir/slurmd.log"
state=
for _ in $(seq 120); do
  state=$(sinfo -h -n "$host" -o %T 2>/dev/null || true)
  [ "$state" = idle ] && break
  sleep 0.5
done
[ "$state" = idle ] || fail "the node $host is not idle after 60 s (state: '${state:-no answer}')" "$dir/slurmd.log"
echo "export SLURM_CONF=$SLURM_CONF"
