#!/usr/bin/env bash
# Stops the daemons scripts/slurm/start.sh DIR started, and only those: the PIDs in DIR/pid/*.pid,
# each only while it still runs the program it was started as. SIGTERM, a bounded wait, then
# SIGKILL. Exits non-zero if any of them is still running at the end.
set -uo pipefail

if (($# != 1)); then
  echo "usage: $0 DIR" >&2
  exit 2
fi
dir="$1"
# A reader of this script's output that goes away (| head) must not end it halfway, daemons left.
trap '' PIPE
timeout_s="${UNTANGLE_SLURM_STOP_TIMEOUT:-20}"

# Is PID alive (a zombie has ended: only its parent, here init, has yet to reap it) and still the
# program NAME (not a recycled PID)?
runs() {
  local state_comm
  state_comm="$(ps -o stat=,comm= -p "$1" 2> /dev/null)" || return 1
  [[ "$state_comm" != Z* && "${state_comm##* }" == "$2" ]]
}

# Jobs still queued or running (a test that timed out) are cancelled first: their slurmstepd
# processes would outlive slurmd. Bounded; a cluster that no longer answers is skipped.
if [[ -e "$dir/slurm.conf" ]] && command -v scancel > /dev/null; then
  export SLURM_CONF="$dir/slurm.conf"
  if timeout 10 squeue -h > /dev/null 2>&1; then
    timeout 10 scancel --user="$(id -un)" 2> /dev/null
    deadline=$((SECONDS + timeout_s))
    while [[ -n "$(timeout 10 squeue -h 2> /dev/null)" ]] && ((SECONDS < deadline)); do sleep 0.5; done
  fi
fi

status=0
# slurmd first (it reports to slurmctld), munged last (both authenticate through it).
for name in slurmd slurmctld munged; do
  pidfile="$dir/pid/$name.pid"
  [[ -s "$pidfile" ]] || continue
  pid="$(tr -dc 0-9 < "$pidfile")"
  if [[ -z "$pid" ]] || ! runs "$pid" "$name"; then
    rm -f "$pidfile"
    continue
  fi
  kill -TERM "$pid" 2> /dev/null
  deadline=$((SECONDS + timeout_s))
  while runs "$pid" "$name" && ((SECONDS < deadline)); do sleep 0.2; done
  if runs "$pid" "$name"; then
    echo "stop: $name ($pid) ignored SIGTERM for ${timeout_s} s; sending SIGKILL" >&2
    kill -KILL "$pid" 2> /dev/null
    deadline=$((SECONDS + 5))
    while runs "$pid" "$name" && ((SECONDS < deadline)); do sleep 0.2; done
  fi
  if runs "$pid" "$name"; then
    echo "stop: $name ($pid) is still running" >&2
    status=1
  else
    rm -f "$pidfile"
  fi
done
exit "$status"
