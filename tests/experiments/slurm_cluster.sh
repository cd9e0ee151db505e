#!/usr/bin/env bash
# A throwaway single-node Slurm (munged, slurmctld, slurmd from Debian's slurm-wlm and munge) under a directory;
# sourced by test_slurm.sh: `slurm_start DIR` exports SLURM_CONF, `slurm_stop` ends the daemons by PID.
# MaxArraySize is 10, so that a sweep of more than 10 jobs runs several jobs per array task.

SLURM_PIDS=()

# Starts the daemons with every file under DIR (key, sockets, spool, state, logs) and waits, at most 60 s, until
# the node takes jobs. Fails (returns 1, logs on stderr) when a daemon does not come up.
slurm_start() {
  local dir=$1 host cpus mem
  host=$(hostname -s)
  cpus=$(nproc)
  mem=$(awk '/MemTotal/ {print int($2 / 1024) - 512}' /proc/meminfo)
  rm -rf "$dir"; mkdir -p "$dir"/{munge,state,spool,log}
  chmod 700 "$dir/munge"
  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 400 "$dir/munge/munge.key"
  munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" --seed-file="$dir/munge/seed" || return 1
  SLURM_PIDS+=("$(cat "$dir/munge/munged.pid")")
  cat >"$dir/slurm.conf" <<EOF
ClusterName=semlbtest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
SlurmctldPort=$((20000 + RANDOM % 20000))
SlurmdPort=$((40000 + RANDOM % 20000))
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MaxArraySize=10
MinJobAge=600
SchedulerParameters=sched_interval=1
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=FORCE:4
EOF
  export SLURM_CONF=$dir/slurm.conf
  slurmctld -f "$SLURM_CONF" || return 1
  slurmd -f "$SLURM_CONF" || return 1
  local t
  for t in $(seq 1 120); do  # both daemons wrote their PID files and the node is idle
    if [[ -s $dir/slurmctld.pid && -s $dir/slurmd.pid ]] && sinfo -h -o %t 2>/dev/null | grep -qx idle; then
      SLURM_PIDS+=("$(cat "$dir/slurmctld.pid")" "$(cat "$dir/slurmd.pid")")
      return 0
    fi
    sleep 0.5
  done
  echo "slurm did not come up within 60 s" >&2
  [[ -s $dir/slurmctld.pid ]] && SLURM_PIDS+=("$(cat "$dir/slurmctld.pid")")
  [[ -s $dir/slurmd.pid ]] && SLURM_PIDS+=("$(cat "$dir/slurmd.pid")")
  tail -n 20 "$dir"/log/*.log >&2
  return 1
}

# Cancels this cluster's jobs (waiting at most 10 s for them to end, so no task outlives the test), then ends the
# daemons slurm_start started, by PID (slurmd and slurmctld first, munged last), waiting at most 10 s for each.
slurm_stop() {
  local i p
  if [[ ${#SLURM_PIDS[@]} -eq 3 ]]; then
    timeout 10 scancel --me 2>/dev/null || true
    for _ in $(seq 1 50); do [[ -z $(timeout 10 squeue --me -h 2>/dev/null) ]] && break; sleep 0.2; done
  fi
  for ((i = ${#SLURM_PIDS[@]} - 1; i >= 0; i--)); do
    p=${SLURM_PIDS[i]}
    kill "$p" 2>/dev/null || continue
    for _ in $(seq 1 50); do kill -0 "$p" 2>/dev/null || break; sleep 0.2; done
    kill -9 "$p" 2>/dev/null || true
  done
  SLURM_PIDS=()
}
