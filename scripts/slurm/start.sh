#!/usr/bin/env bash
# Starts a private one-node Slurm cluster on 127.0.0.1 whose every file lives under DIR: a munged
# with its own key and socket, slurmctld and slurmd from the config scripts/slurm/slurm.conf.in.
# Waits (bounded) until the node is idle, then prints the environment to use it (eval "$(...)").
# scripts/slurm/stop.sh DIR stops exactly the daemons this started. Needs root, munge, slurm-wlm.
set -euo pipefail

if (($# != 1)); then
  echo "usage: $0 DIR   (a new or empty folder for the cluster's state, logs and pid files)" >&2
  exit 2
fi
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
mkdir -p "$1"
dir="$(cd "$1" && pwd)"
timeout_s="${UNTANGLE_SLURM_START_TIMEOUT:-60}"

for tool in munged munge unmunge slurmctld slurmd sinfo python3; do
  if ! command -v "$tool" > /dev/null; then
    echo "error: $tool not found; install munge and slurm-wlm (UNTANGLE_WITH_SLURM=1 bash scripts/setup.sh)" >&2
    exit 3
  fi
done
if [[ -e "$dir/slurm.conf" || -e "$dir/pid/munged.pid" ]]; then
  echo "error: $dir holds a cluster's files: one may be running there (scripts/slurm/stop.sh $dir first)" >&2
  exit 2
fi

# On any failure below, stop what was started so that no daemon is left behind.
fail() {
  echo "error: $*" >&2
  for log in "$dir"/log/*.log; do
    [[ -e "$log" ]] && { echo "--- last lines of $log" >&2; tail -n 15 "$log" >&2; }
  done
  bash "$here/stop.sh" "$dir" >&2 || true
  exit 1
}

# Waits up to $timeout_s seconds for the command to succeed.
wait_for() {
  local what="$1"
  shift
  local deadline=$((SECONDS + timeout_s))
  until "$@" > /dev/null 2>&1; do
    ((SECONDS < deadline)) || fail "timed out after ${timeout_s} s waiting for $what"
    sleep 0.2
  done
}

# munged wants its key private and its socket's folders searchable by all (clients of any user).
up="$dir"
while up="$(dirname "$up")" && [[ "$up" != / ]]; do
  if (((8#$(stat -c %a "$up") & 1) == 0)); then
    echo "error: $up is not searchable by all (chmod o+x), which munged requires for its socket" >&2
    exit 2
  fi
done
mkdir -p "$dir"/{munge,run,state,spool,pid,log}
chmod 755 "$dir" "$dir/run"
chmod 700 "$dir/munge"

# munged: its own key, socket, pid, seed and log, nothing in /etc/munge or /run/munge.
socket="$dir/run/munge.socket"
mungekey --create --keyfile="$dir/munge/munge.key"
munged --socket="$socket" --key-file="$dir/munge/munge.key" --pid-file="$dir/pid/munged.pid" \
  --log-file="$dir/log/munged.log" --seed-file="$dir/munge/munged.seed" ||
  fail "munged did not start"
wait_for "munged to answer on $socket" \
  bash -c 'munge -n --socket="$1" | unmunge --socket="$1"' _ "$socket"

# Two free ports on loopback, so that clusters of concurrent runs do not collide.
read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')

host="$(hostname -s)"
node_line="$(slurmd -C | head -n 1)"
[[ "$node_line" == NodeName=* ]] || fail "slurmd -C printed no node line: $node_line"
sed -e "s|@DIR@|$dir|g" -e "s|@HOST@|$host|g" -e "s|@CTLD_PORT@|$ctld_port|g" \
  -e "s|@SLURMD_PORT@|$slurmd_port|g" -e "s|@NODE_LINE@|$node_line|g" \
  "$here/slurm.conf.in" > "$dir/slurm.conf"
export SLURM_CONF="$dir/slurm.conf"

slurmctld -c -f "$SLURM_CONF" || fail "slurmctld did not start"
wait_for "slurmctld's pid file" test -s "$dir/pid/slurmctld.pid"
slurmd -f "$SLURM_CONF" || fail "slurmd did not start"
wait_for "slurmd's pid file" test -s "$dir/pid/slurmd.pid"
wait_for "node $host to be idle" \
  bash -c '[[ "$(sinfo -h -N -n "$1" -o %t)" == idle ]]' _ "$host"

echo "export SLURM_CONF=$SLURM_CONF"
echo "export UNTANGLE_MUNGE_SOCKET=$socket"
