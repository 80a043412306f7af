#!/usr/bin/env bash
# Private one-node Slurm cluster on localhost (munged + slurmctld + slurmd), for tests.
# Usage: local_slurm.sh start|stop|env STATE_DIR     (run as root)
#   start: write config, start daemons, wait for the node to be idle, print env line
#   stop:  stop the daemons by their pid files in STATE_DIR (idempotent)
#   env:   print the line to eval so that sbatch/squeue/scontrol use this cluster
set -euo pipefail

usage() { echo "usage: $0 start|stop|env STATE_DIR" >&2; exit 2; }
[[ $# -eq 2 ]] || usage
CMD=$1
DIR=$(realpath -m "$2")
CONF=$DIR/slurm.conf
MUNGE_SOCK=$DIR/munge/munged.sock
HOST=$(hostname -s)
export SLURM_CONF=$CONF

log() { echo "local_slurm: $*" >&2; }

# Report a failed step with the tails of the relevant logs, stop everything, exit 1.
fail() {
  local f
  log "FAILED: $1"; shift
  for f; do [[ -f $f ]] && { log "--- tail of $f ---"; tail -n 20 "$f" >&2; }; done
  do_stop || true
  exit 1
}

# Pid from a pid file, only if that process is still alive and has the expected name.
alive_pid() {
  local pid
  pid=$(cat "$1" 2>/dev/null) || return 1
  [[ $pid =~ ^[0-9]+$ && $(cat "/proc/$pid/comm" 2>/dev/null) == "$2" ]] && running "$pid" && echo "$pid"
}

# True if any given pid is still running (a zombie left for init to reap counts as gone).
running() {
  local p; for p; do [[ $(sed -n 's/.*) \(.\).*/\1/p' "/proc/$p/stat" 2>/dev/null) =~ ^[^ZX]$ ]] && return 0; done; return 1
}

# A TCP port on which nothing answers on 127.0.0.1 (the defaults 6817/6818 are avoided).
# It is drawn below the kernel's ephemeral range, so that no outgoing
# connection can take it between this check and the daemon's bind.
free_port() {
  local p lo
  lo=$(cut -f1 /proc/sys/net/ipv4/ip_local_port_range 2>/dev/null || echo 32768)
  ((lo > 21000)) || lo=32768
  for _ in $(seq 100); do
    p=$((20000 + RANDOM % (lo - 20000)))
    [[ $p == "${1:-}" ]] && continue
    timeout 1 bash -c "exec 3<>/dev/tcp/127.0.0.1/$p" 2>/dev/null || { echo "$p"; return; }
  done
  return 1
}

# Stop all three daemons by pid file: TERM together (each takes 1-2 s), wait up to 5 s, then KILL.
do_stop() {
  local name pidf pid pids=()
  # Cancel leftover jobs first; otherwise their slurmstepd processes outlive slurmd.
  if alive_pid "$DIR/slurmctld.pid" slurmctld >/dev/null; then
    squeue -h -o %A 2>/dev/null | xargs -r scancel 2>/dev/null || true
    for _ in $(seq 20); do [[ -z $(squeue -h -o %A 2>/dev/null) ]] && break; sleep 0.25; done
  fi
  for name in slurmd slurmctld munge/munged; do
    pidf=$DIR/$name.pid
    if pid=$(alive_pid "$pidf" "${name#munge/}"); then kill "$pid" 2>/dev/null && pids+=("$pid"); fi
    rm -f "$pidf"
  done
  for _ in $(seq 50); do running "${pids[@]}" || break; sleep 0.1; done
  for pid in "${pids[@]}"; do running "$pid" && { log "pid $pid ignored TERM, killing"; kill -9 "$pid" || true; }; done
  return 0
}

do_start() {
  [[ $EUID -eq 0 ]] || { log "must run as root"; exit 1; }
  if alive_pid "$DIR/slurmctld.pid" slurmctld >/dev/null; then log "already running in $DIR"; exit 1; fi
  do_stop  # clean up leftovers of a crashed earlier run
  # Fresh private directories (other files in STATE_DIR, e.g. job outputs, are kept).
  rm -rf "$DIR/munge" "$DIR/state" "$DIR/spool" "$DIR/slurmctld.log" "$DIR/slurmd.log"
  mkdir -p "$DIR/munge" "$DIR/state" "$DIR/spool"
  chmod 0755 "$DIR" "$DIR/munge"  # munged rejects group/world-writable dirs

  # munged: private key, socket, pid, log and seed; --force tolerates e.g. /tmp parents.
  dd if=/dev/urandom of="$DIR/munge/munge.key" bs=1024 count=1 status=none && chmod 0400 "$DIR/munge/munge.key"
  munged --force --socket="$MUNGE_SOCK" --key-file="$DIR/munge/munge.key" \
    --pid-file="$DIR/munge/munged.pid" --log-file="$DIR/munge/munged.log" \
    --seed-file="$DIR/munge/munged.seed" </dev/null >>"$DIR/munge/munged.log" 2>&1 \
    || fail "munged did not start" "$DIR/munge/munged.log"
  munge -S "$MUNGE_SOCK" -n | unmunge -S "$MUNGE_SOCK" >/dev/null \
    || fail "munge credential test (munge | unmunge) failed" "$DIR/munge/munged.log"

  # slurm.conf: node size from `slurmd -C`, memory a bit below the real value.
  local hw mem ctld_port slurmd_port
  hw=$(slurmd -C) || fail "'slurmd -C' failed: $hw"
  mem=$(grep -oP 'RealMemory=\K[0-9]+' <<<"$hw") || fail "no RealMemory in 'slurmd -C' output: $hw"
  ctld_port=$(free_port) || fail "no free TCP port found"
  slurmd_port=$(free_port "$ctld_port") || fail "no free TCP port found"
  cat >"$CONF" <<EOF
ClusterName=localtest
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$MUNGE_SOCK
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/slurmctld.pid
SlurmdPidFile=$DIR/slurmd.pid
SlurmctldLogFile=$DIR/slurmctld.log
SlurmdLogFile=$DIR/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
MaxArraySize=1001
SchedulerType=sched/backfill
SchedulerParameters=sched_interval=1,bf_interval=1,sched_min_interval=100000
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
NodeName=$HOST NodeAddr=127.0.0.1 $(grep -oE '(CPUs|Boards|SocketsPerBoard|CoresPerSocket|ThreadsPerCore)=[0-9]+' <<<"$hw" | tr '\n' ' ')RealMemory=$((mem * 9 / 10)) State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF

  # Daemons fork into the background themselves; -c -i: clean start, ignore old state.
  slurmctld -f "$CONF" -c -i </dev/null >>"$DIR/slurmctld.log" 2>&1 \
    || fail "slurmctld did not start" "$DIR/slurmctld.log"
  slurmd -f "$CONF" </dev/null >>"$DIR/slurmd.log" 2>&1 || fail "slurmd did not start" "$DIR/slurmd.log"

  # Wait up to 30 s for the node to be idle; after 2 s (pid files written) a dead daemon fails fast.
  local state="" start=$SECONDS
  while ((SECONDS - start < 30)); do
    state=$(sinfo -h -N -n "$HOST" -o %T 2>/dev/null || true)
    [[ $state == idle ]] && { log "cluster up in $DIR (node $HOST idle)"; do_env; return; }
    if ((SECONDS - start >= 2)); then
      alive_pid "$DIR/munge/munged.pid" munged >/dev/null || fail "munged died" "$DIR/munge/munged.log"
      alive_pid "$DIR/slurmctld.pid" slurmctld >/dev/null || fail "slurmctld died" "$DIR/slurmctld.log"
      alive_pid "$DIR/slurmd.pid" slurmd >/dev/null || fail "slurmd died" "$DIR/slurmd.log"
    fi
    sleep 0.2
  done
  fail "node $HOST not idle after 30 s (sinfo state: '${state:-none}')" "$DIR/slurmctld.log" "$DIR/slurmd.log"
}

do_env() { echo "export SLURM_CONF=$CONF"; }

case $CMD in start) do_start ;; stop) do_stop ;; env) do_env ;; *) usage ;; esac
