#!/usr/bin/env bash
# A throw-away one-node Slurm cluster on localhost (Debian's munge and slurm-wlm), for tests.
#
#   source scripts/dev/slurm_local_cluster.sh DIR    # starts munged, slurmctld, slurmd under DIR
#   ... sbatch / squeue (SLURM_CONF is exported) ...
#   slurm_local_stop                              # stops exactly the daemons started here, by pid
#
# Needs root (slurmd runs jobs as the submitting user). Fails loudly when a package is missing:
# a test built on it must not pass by skipping. Ports are chosen per run so that two runs on one
# machine do not meet.

slurm_local_fail() {
  echo "slurm_local_cluster: FAILED: $*" >&2
  return 1
}

slurm_local_stop() {
  local pid
  for pid in ${SLURM_LOCAL_PIDS:-}; do
    kill "$pid" 2>/dev/null || true
  done
  for pid in ${SLURM_LOCAL_PIDS:-}; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  SLURM_LOCAL_PIDS=""
}

slurm_local_start() {
  local dir=$1
  local tool
  for tool in munged slurmctld slurmd sbatch squeue sinfo scontrol; do
    command -v "$tool" >/dev/null ||
      PATH="$PATH:/usr/sbin" command -v "$tool" >/dev/null ||
      slurm_local_fail "'$tool' not found: install munge and slurm-wlm (scripts/setup.sh does)" || return 1
  done
  [[ $(id -u) -eq 0 ]] || { slurm_local_fail "must run as root (slurmd starts jobs as their user)"; return 1; }
  export PATH="$PATH:/usr/sbin"
  mkdir -p "$dir"/{munge,state,spool,log}
  dir=$(cd "$dir" && pwd)
  chmod 711 "$dir/munge"
  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 400 "$dir/munge/munge.key"
  local socket="$dir/munge/munge.socket"
  munged --foreground --force --key-file="$dir/munge/munge.key" --socket="$socket" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" \
    --seed-file="$dir/munge/munged.seed" >"$dir/log/munged.out" 2>&1 &
  SLURM_LOCAL_PIDS="$!"
  for _ in $(seq 50); do [[ -S $socket ]] && break; sleep 0.1; done
  [[ -S $socket ]] || { slurm_local_fail "munged did not start (see $dir/log/munged.log)"; return 1; }

  local base=$((20000 + RANDOM % 20000))
  local cpus mem
  cpus=$(nproc)
  mem=$(awk '/MemTotal/ {print int($2 / 1024 / 2)}' /proc/meminfo)
  cat >"$dir/slurm.conf" <<CONF
ClusterName=graftnavlocal
SlurmctldHost=localhost
SlurmctldPort=$base
SlurmdPort=$((base + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=local Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$dir/slurm.conf"
  slurmctld -D -i -f "$SLURM_CONF" >"$dir/log/slurmctld.out" 2>&1 &
  SLURM_LOCAL_PIDS="$SLURM_LOCAL_PIDS $!"
  slurmd -D -N localhost -f "$SLURM_CONF" >"$dir/log/slurmd.out" 2>&1 &
  SLURM_LOCAL_PIDS="$SLURM_LOCAL_PIDS $!"
  local state=""
  for _ in $(seq 100); do
    state=$(sinfo -h -n localhost -o '%t' 2>/dev/null || true)
    [[ $state == idle* ]] && break
    sleep 0.2
  done
  [[ $state == idle* ]] || {
    slurm_local_fail "node not idle after 20 s (state '$state'); logs in $dir/log"
    tail -n 20 "$dir"/log/*.log "$dir"/log/*.out >&2
    return 1
  }
  echo "slurm_local_cluster: munged, slurmctld, slurmd up (pids $SLURM_LOCAL_PIDS), SLURM_CONF=$SLURM_CONF" >&2
}
