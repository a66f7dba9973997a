#!/usr/bin/env bash
# Starts the one-node loopback cluster of scripts/slurm/, submits an array job with sbatch --wait,
# checks what its tasks wrote, and stops the daemons it started (also on failure or interrupt).
# Runs only with UNTANGLE_SLURM_TEST=1; otherwise exits 77, which ctest reports as skipped.
#
#   tests/slurm/run_array_test.sh                  array 0-4 of a script writing one file a task
#   tests/slurm/run_array_test.sh SCRIPT [CHECK...] SCRIPT as it is (its own #SBATCH lines), then
#                                                   CHECK, whose exit status decides
# The work folder is $UNTANGLE_SLURM_WORK (exported to the job and CHECK); the job runs there.
# CHECK also gets the submitted job's id in $UNTANGLE_SLURM_JOB_ID (for a --dependency on it).
set -euo pipefail

if [[ "${UNTANGLE_SLURM_TEST:-0}" != "1" ]]; then
  echo "skipped: set UNTANGLE_SLURM_TEST=1 to run (needs root, munge and slurm-wlm)"
  exit 77
fi
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
job_timeout="${UNTANGLE_SLURM_JOB_TIMEOUT:-300}"

run="$(mktemp -d /tmp/untangle-slurm.XXXXXX)"
chmod 755 "$run" # munged wants every folder above its socket searchable by all
cleanup() {
  bash "$root/scripts/slurm/stop.sh" "$run/cluster" || echo "error: a daemon did not stop" >&2
  rm -rf "$run"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

start=$SECONDS
env="$(bash "$root/scripts/slurm/start.sh" "$run/cluster")" || exit 1
eval "$env"
echo "cluster up in $((SECONDS - start)) s (SLURM_CONF=$SLURM_CONF)"
export UNTANGLE_SLURM_WORK="$run/work"
mkdir -p "$UNTANGLE_SLURM_WORK"

submit() {
  start=$SECONDS
  # --wait: sbatch returns when every task ended, non-zero when any failed.
  if ! timeout "$job_timeout" sbatch --wait --chdir="$UNTANGLE_SLURM_WORK" \
    --output="$UNTANGLE_SLURM_WORK/slurm-%A_%a.out" "$@" > "$run/sbatch.out"; then
    cat "$run/sbatch.out" "$UNTANGLE_SLURM_WORK"/slurm-*.out >&2 2> /dev/null || true
    echo "error: sbatch $* failed or timed out after $job_timeout s" >&2
    exit 1
  fi
  cat "$run/sbatch.out"
  echo "array job done in $((SECONDS - start)) s"
  UNTANGLE_SLURM_JOB_ID="$(sed -n 's/^Submitted batch job \([0-9]*\)$/\1/p' "$run/sbatch.out")"
  [[ -n "$UNTANGLE_SLURM_JOB_ID" ]] || { echo "error: no job id in sbatch's output" >&2; exit 1; }
  export UNTANGLE_SLURM_JOB_ID
}

if (($# > 0)); then
  script="$(realpath "$1")"
  shift
  submit "$script"
  if (($# > 0)); then "$@"; fi
  echo "passed"
  exit 0
fi

# The default job: five tasks, each writes its array index and the job id Slurm gave it.
cat > "$run/tasks.sh" <<'JOB'
#!/bin/bash
printf '%s %s\n' "$SLURM_ARRAY_TASK_ID" "$SLURM_ARRAY_JOB_ID" > "task_$SLURM_ARRAY_TASK_ID.txt"
JOB
submit --array=0-4 "$run/tasks.sh"
job_id="$UNTANGLE_SLURM_JOB_ID"

failed=0
for i in 0 1 2 3 4; do
  file="$UNTANGLE_SLURM_WORK/task_$i.txt"
  if [[ "$(cat "$file" 2> /dev/null)" != "$i $job_id" ]]; then
    echo "error: $file should hold \"$i $job_id\", holds \"$(cat "$file" 2> /dev/null)\"" >&2
    failed=1
  fi
done
count="$(find "$UNTANGLE_SLURM_WORK" -name 'task_*.txt' | wc -l)"
if ((count != 5)); then
  echo "error: $count task files, expected 5 (array 0-4)" >&2
  failed=1
fi
((failed == 0)) && echo "passed: 5 tasks of job $job_id wrote their files"
exit "$failed"
