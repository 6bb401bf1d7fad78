#!/usr/bin/env bash
# A throwaway single-node Slurm cluster under one folder, for tests and trying `photoncl batch
# slurm` on one machine: munged, slurmctld and slurmd started by hand (no systemd), every file
# (slurm.conf, munge key and socket, state, spool, logs, pid files) under DIR, nothing read from
# or written to /etc/slurm, /etc/munge or /run/munge. Runs as root or as any user (the daemons
# run as the caller).
#
#   scripts/slurm_cluster.sh start DIR   write the config, start the daemons, wait for the node
#   scripts/slurm_cluster.sh stop DIR    cancel jobs, stop each daemon by its pid file, wait
#   scripts/slurm_cluster.sh env DIR     print `export SLURM_CONF=...` for sbatch/squeue/sinfo
#
# DIR: no blanks (slurm.conf paths cannot hold them), and every folder above it open to all for
# execute (munged checks the path to its socket; `mktemp -d` makes 0700: chmod 755 it).
#
# Configuration choices (Debian 12, Slurm 22.05): proctrack/linuxproc, task/none and
# jobacct_gather/none need no cgroups (a container or a CI machine without systemd has no
# delegated cgroup tree); select/cons_tres with CR_Core, so array tasks share the node by cores;
# the node line is `slurmd -C`'s own (CPUs, sockets, cores, threads, memory: a mismatch drains
# the node); sched/builtin with a 1 s poll, so a job starts within a second or two of its
# dependency; ports picked free at start.
set -euo pipefail

usage() { echo "usage: $0 start|stop|env DIR" >&2; exit 2; }
[ $# -eq 2 ] || usage
action=$1
dir=$2

for tool in munged slurmctld slurmd sinfo scontrol; do
  command -v "$tool" >/dev/null || { echo "slurm_cluster: $tool not found (scripts/setup.sh installs slurm-wlm and munge)" >&2; exit 3; }
done

conf() { echo "$dir/etc/slurm.conf"; }

free_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

# Pid of a daemon from its pid file, when that process still runs.
running_pid() {
  local file=$1 pid
  [ -s "$file" ] || return 1
  pid=$(cat "$file")
  kill -0 "$pid" 2>/dev/null || return 1
  echo "$pid"
}

dump_logs() {
  for log in "$dir"/log/*.log; do
    [ -f "$log" ] || continue
    echo "---- $log (last 30 lines)" >&2
    tail -n 30 "$log" >&2
  done
}

start() {
  mkdir -p "$dir"
  dir=$(cd "$dir" && pwd)
  case $dir in
    *[[:space:]]*) echo "slurm_cluster: '$dir': expected a folder without blanks (slurm.conf cannot hold them)" >&2; exit 2 ;;
  esac
  mkdir -p "$dir/etc" "$dir/munge" "$dir/socket" "$dir/state" "$dir/spool" "$dir/log" "$dir/run"
  # munged wants its key private and the folders up to its socket open to all for execute
  # (mktemp -d makes 0700) and writable by no one else.
  chmod 755 "$dir" "$dir/socket"
  chmod 700 "$dir/munge" "$dir/log"
  local user node ctld_port slurmd_port node_line
  user=$(id -un)
  node=$(hostname -s)

  # Munge: its own key, socket, pid, seed and log under DIR.
  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 400 "$dir/munge/munge.key"
  munged --key-file="$dir/munge/munge.key" --socket="$dir/socket/munge.socket" \
         --pid-file="$dir/run/munged.pid" --seed-file="$dir/munge/munged.seed" \
         --log-file="$dir/log/munged.log"

  ctld_port=$(free_port)
  slurmd_port=$(free_port)
  while [ "$slurmd_port" = "$ctld_port" ]; do slurmd_port=$(free_port); done
  # slurmd -C reports this machine's layout; the node name is `hostname -s`.
  node_line=$(slurmd -C | head -n 1 | sed "s/^NodeName=[^ ]*/NodeName=$node/")

  : > "$dir/etc/plugstack.conf"
  cat > "$(conf)" <<EOF
# Written by scripts/slurm_cluster.sh: a single-node cluster under $dir
ClusterName=photoncl-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/socket/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
PlugStackConfig=$dir/etc/plugstack.conf
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=1
ReturnToService=2
SlurmctldTimeout=10
SlurmdTimeout=10
InactiveLimit=0
KillWait=5
MinJobAge=300
MailProg=/bin/true
SlurmctldDebug=info
SlurmdDebug=info
$node_line NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF

  export SLURM_CONF
  SLURM_CONF=$(conf)
  slurmctld -f "$(conf)"
  slurmd -f "$(conf)"

  # Ready when the node reports idle (a freshly registered node says idle within a second or two).
  local state=""
  for _ in $(seq 1 100); do
    state=$(sinfo -h -n "$node" -o '%t' 2>/dev/null | head -n 1 || true)
    [ "$state" = "idle" ] && break
    sleep 0.2
  done
  if [ "$state" != "idle" ]; then
    echo "slurm_cluster: node $node is '${state:-unreachable}' after 20 s, not idle" >&2
    dump_logs
    exit 1
  fi
  echo "slurm_cluster: node $node idle (slurmctld $(cat "$dir/run/slurmctld.pid"), slurmd $(cat "$dir/run/slurmd.pid"), munged $(cat "$dir/run/munged.pid")); export SLURM_CONF=$(conf)" >&2
}

stop() {
  [ -d "$dir" ] || return 0
  dir=$(cd "$dir" && pwd)
  # Jobs first, so their slurmstepd processes end while slurmd still runs.
  if [ -f "$(conf)" ] && running_pid "$dir/run/slurmctld.pid" >/dev/null; then
    SLURM_CONF=$(conf) scancel --full --quiet -u "$(id -un)" 2>/dev/null || true
  fi
  # The Slurm daemons together, then munged, which they use while they shut down.
  terminate slurmd slurmctld
  terminate munged
}

# SIGTERM to each named daemon by its pid file; SIGKILL to any still running after 5 s.
terminate() {
  local name pid pids=()
  for name in "$@"; do
    pid=$(running_pid "$dir/run/$name.pid") || continue
    kill -TERM "$pid" 2>/dev/null || true
    pids+=("$name:$pid")
  done
  for entry in ${pids[@]+"${pids[@]}"}; do
    name=${entry%%:*}
    pid=${entry##*:}
    for _ in $(seq 1 50); do
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.1
    done
    if kill -0 "$pid" 2>/dev/null; then
      echo "slurm_cluster: $name ($pid) still runs after 5 s: SIGKILL" >&2
      kill -KILL "$pid" 2>/dev/null || true
    fi
  done
}

case $action in
  start) start ;;
  stop) stop ;;
  env) echo "export SLURM_CONF=$(cd "$dir" && pwd)/etc/slurm.conf" ;;
  *) usage ;;
esac
