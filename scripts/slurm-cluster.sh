#!/usr/bin/env bash
# A single-node Slurm cluster on loopback, to try `wiredem-server --executor
# slurm` on one machine and to test it (tests/slurm). Debian's packages
# (slurmctld, slurmd, slurm-client, munge; installed when missing), no init
# system: the script starts munged as user munge, then slurmctld and
# `slurmd -N localhost`, all with their state, spool, sockets and logs in one
# directory.
#
#   scripts/slurm-cluster.sh start    # prints the SLURM_CONF line to export
#   scripts/slurm-cluster.sh status
#   scripts/slurm-cluster.sh stop     # cancels every job, then stops the daemons
#
# Environment:
#   WIREDEM_SLURM_DIR   the cluster's directory (default ${TMPDIR:-/tmp}/wiredem-slurm)
#   WIREDEM_SLURM_PORT  slurmctld's port; slurmd takes the next (default 6817)
#
# Every command is idempotent: start on a running cluster says so and does
# nothing, stop on a stopped one neither. The daemons listen on 127.0.0.1
# only (CommunicationParameters=NoCtldInAddrAny,NoInAddrAny). Needs root:
# munged runs as user munge and slurmd must be able to run jobs as their user.
#
# Container-friendly choices: process tracking by the process tree
# (proctrack/linuxproc) and no task binding (task/none), so no cgroup is
# needed; no accounting database (sacct has nothing: wiredem-server follows
# jobs with squeue/scontrol and the files of the job directory).
set -euo pipefail

dir=${WIREDEM_SLURM_DIR:-${TMPDIR:-/tmp}/wiredem-slurm}
port=${WIREDEM_SLURM_PORT:-6817}
conf=$dir/etc/slurm.conf
export SLURM_CONF=$conf

die() { echo "slurm-cluster.sh: $*" >&2; exit 1; }

usage() { echo "usage: $0 start|stop|status" >&2; exit 2; }

# The pid in FILE, if that process is alive and is the daemon NAME (a stale
# pid file must not make the script signal whatever took its number).
alive_pid() { # file name
  local pid
  [[ -s $1 ]] || return 1
  pid=$(<"$1")
  [[ $pid =~ ^[0-9]+$ ]] && kill -0 "$pid" 2>/dev/null && [[ $(cat "/proc/$pid/comm" 2>/dev/null) == "$2"* ]] \
    && echo "$pid"
}

install_packages() {
  local missing=()
  command -v munged >/dev/null || missing+=(munge)
  command -v slurmctld >/dev/null || missing+=(slurmctld)
  command -v slurmd >/dev/null || missing+=(slurmd)
  command -v sbatch >/dev/null || missing+=(slurm-client)
  ((${#missing[@]} == 0)) && return 0
  echo "slurm-cluster.sh: installing ${missing[*]}" >&2
  command -v apt-get >/dev/null || die "missing ${missing[*]} and no apt-get to install them (Debian packages slurmctld slurmd slurm-client munge)"
  DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}" >&2 \
    || { apt-get update >&2 && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}" >&2; } \
    || die "cannot install ${missing[*]}"
}

write_config() {
  mkdir -p "$dir"/{etc,state,spool,log,munge}
  chmod 0755 "$dir" "$dir/etc"
  # munged refuses a socket directory others may write or not enter, and a key
  # others may read.
  chown munge:munge "$dir/munge"
  chmod 0755 "$dir/munge"  # clients reach the socket; the key stays 0400
  if [[ ! -s $dir/munge/munge.key ]]; then
    head -c 128 /dev/urandom > "$dir/munge/munge.key"
    chown munge:munge "$dir/munge/munge.key"
    chmod 0400 "$dir/munge/munge.key"
  fi
  # The node as slurmd sees it (CPUs, sockets, cores, memory), named localhost.
  local node cpus memory
  node=$(slurmd -C | head -n 1) || die "slurmd -C failed"
  node=${node/NodeName=* CPUs=/NodeName=localhost NodeAddr=127.0.0.1 CPUs=}
  cpus=$(sed -n 's/.* CPUs=\([0-9]*\).*/\1/p' <<<"$node")
  memory=$(sed -n 's/.* RealMemory=\([0-9]*\).*/\1/p' <<<"$node")
  [[ -n $cpus && -n $memory ]] || die "cannot read the node's CPUs and memory from slurmd -C: $node"
  cat > "$conf" <<EOF
# Written by scripts/slurm-cluster.sh: a single-node cluster on loopback.
ClusterName=wiredem-local
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
DefMemPerCPU=$((memory / cpus / 2))
MailProg=/bin/true
ReturnToService=2
SlurmdTimeout=60
$node
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
}

start() {
  [[ $(id -u) == 0 ]] || die "needs root (munged runs as user munge; slurmd runs jobs as their user)"
  install_packages
  if alive_pid "$dir/slurmctld.pid" slurmctld >/dev/null && alive_pid "$dir/slurmd.pid" slurmd >/dev/null; then
    echo "slurm-cluster.sh: already running in $dir" >&2
    echo "export SLURM_CONF=$conf"
    return 0
  fi
  write_config
  if ! alive_pid "$dir/munge/munged.pid" munged >/dev/null; then
    runuser -u munge -- munged --socket="$dir/munge/munge.socket" --key-file="$dir/munge/munge.key" \
      --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/munged.seed" \
      || die "munged did not start: $(tail -n 3 "$dir/munge/munged.log" 2>/dev/null)"
  fi
  alive_pid "$dir/slurmctld.pid" slurmctld >/dev/null || slurmctld -c -f "$conf" \
    || die "slurmctld did not start: $(tail -n 5 "$dir/log/slurmctld.log" 2>/dev/null)"
  alive_pid "$dir/slurmd.pid" slurmd >/dev/null || slurmd -N localhost -f "$conf" \
    || die "slurmd did not start: $(tail -n 5 "$dir/log/slurmd.log" 2>/dev/null)"
  # Ready when the node takes jobs.
  local state=""
  for _ in $(seq 1 100); do
    state=$(sinfo --noheader --nodes=localhost --format=%t 2>/dev/null || true)
    [[ $state == idle* || $state == mix* || $state == alloc* ]] && break
    sleep 0.2
  done
  if [[ $state != idle* && $state != mix* && $state != alloc* ]]; then
    die "the node did not come up (state '${state:-none}'): $(tail -n 5 "$dir/log/slurmd.log" "$dir/log/slurmctld.log" 2>/dev/null)"
  fi
  echo "slurm-cluster.sh: running in $dir (slurmctld 127.0.0.1:$port, node localhost $state)" >&2
  echo "export SLURM_CONF=$conf"
}

stop_daemon() { # name pidfile
  local pid
  pid=$(alive_pid "$2" "$1") || return 0
  kill "$pid" 2>/dev/null || true
  for _ in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || return 0; sleep 0.1; done
  echo "slurm-cluster.sh: $1 did not stop on SIGTERM, killing it" >&2
  kill -9 "$pid" 2>/dev/null || true
}

stop() {
  if alive_pid "$dir/slurmctld.pid" slurmctld >/dev/null; then
    scancel --full --quiet --partition=debug 2>/dev/null || scancel --quiet --user=root 2>/dev/null || true
    # Jobs end as their steps are signalled; give them a moment to leave.
    for _ in $(seq 1 50); do
      [[ -z $(squeue --noheader --format=%i 2>/dev/null) ]] && break
      sleep 0.1
    done
  fi
  stop_daemon slurmd "$dir/slurmd.pid"
  stop_daemon slurmctld "$dir/slurmctld.pid"
  stop_daemon munged "$dir/munge/munged.pid"
  echo "slurm-cluster.sh: stopped" >&2
}

status() {
  local up=0
  for d in munged:munge/munged.pid slurmctld:slurmctld.pid slurmd:slurmd.pid; do
    if pid=$(alive_pid "$dir/${d#*:}" "${d%%:*}"); then echo "${d%%:*}: running (pid $pid)"; else echo "${d%%:*}: stopped"; up=1; fi
  done
  if ((up == 0)); then
    echo "export SLURM_CONF=$conf"
    sinfo --nodes=localhost
    squeue
  fi
  return $up
}

case ${1:-} in
  start) start ;;
  stop) stop ;;
  status) status ;;
  *) usage ;;
esac
