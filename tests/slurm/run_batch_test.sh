#!/usr/bin/env bash
# Issue 22 §5: `untangle batch --emit slurm` on a one-node Slurm cluster on loopback gives the
# summary a local batch gives. Four jobs (the shipped MakeHuman garment on its body, each moved
# along x by 0.25 k, so that every job's files differ) are run by a local `untangle batch` into
# local/, and emitted with `--emit slurm` into slurm/; tests/slurm/run_array_test.sh submits
# slurm/batch.sbatch (its own #SBATCH --array) and waits, then gather.sbatch is submitted as
# submit.sh does (--dependency=afterany on the array) and waited for. slurm/summary.json must equal
# local/summary.json without the times and the resumed flags (the only keys that differ between
# two runs, man page BATCH), and every written mesh must be the same bytes. Afterwards no process
# may mention the cluster's folder (run_array_test.sh stops the daemons by their PIDs).
# Runs only with UNTANGLE_SLURM_TEST=1; otherwise exits 77 (ctest: skipped).
#
#   tests/slurm/run_batch_test.sh UNTANGLE_BINARY
set -euo pipefail

if [[ "${UNTANGLE_SLURM_TEST:-0}" != "1" ]]; then
  echo "skipped: set UNTANGLE_SLURM_TEST=1 to run (needs root, munge and slurm-wlm)"
  exit 77
fi
if (($# != 1)); then
  echo "usage: $0 UNTANGLE_BINARY" >&2
  exit 2
fi
untangle="$(realpath "$1")"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
work="$(mktemp -d /tmp/untangle-slurm-batch.XXXXXX)"
trap 'rm -rf "$work"' EXIT

# Jobs that end clean: the shipped MakeHuman garment on its body. (A task whose job ends distorted
# or unresolved exits 0 as well, man page BATCH, Scale-out; only a failed job fails its task, which
# sbatch --wait would report.)
data="$here/../../testdata/makehuman"
mkdir "$work/in" "$work/local" "$work/slurm"
for k in 0 1 2 3; do
  mkdir "$work/in/job-$k"
  awk -v shift="0.$((25 * k))" '$1 == "v" { printf "v %.6f %s %s\n", $2 + shift, $3, $4; next } { print }' \
    "$data/male_casualsuit04.obj" > "$work/in/job-$k/movable_0.obj"
  awk -v shift="0.$((25 * k))" '$1 == "v" { printf "v %.6f %s %s\n", $2 + shift, $3, $4; next } { print }' \
    "$data/male_generic.obj" > "$work/in/job-$k/obstacle_0.obj"
done
start=$SECONDS
"$untangle" batch "$work/in" --output-dir "$work/local" --jobs 2 -q
echo "local batch done in $((SECONDS - start)) s"
"$untangle" batch "$work/in" --output-dir "$work/slurm" --jobs 2 --emit slurm

# Run by run_array_test.sh after the array ended, with the cluster's SLURM_CONF.
cat > "$work/check.sh" <<'CHECK'
#!/usr/bin/env bash
set -euo pipefail
work="$1"
start=$SECONDS
if ! timeout 300 sbatch --wait --dependency="afterany:$UNTANGLE_SLURM_JOB_ID" "$work/slurm/gather.sbatch"; then
  cat "$work"/slurm/slurm-gather-*.out >&2 2> /dev/null || true
  echo "error: gather.sbatch failed or timed out" >&2
  exit 1
fi
echo "gather job done in $((SECONDS - start)) s"
python3 - "$work/local" "$work/slurm" <<'PY'
import difflib, json, pathlib, sys

def without_times(summary):
    for part in [summary["totals"]] + summary["jobs"]:
        part.pop("time_ms")
        part.pop("resumed")
    return summary

local, slurm = (pathlib.Path(p) for p in sys.argv[1:])
a, b = (without_times(json.loads((d / "summary.json").read_text())) for d in (local, slurm))
failed = False
# Not two empty summaries: the four jobs, each fixed intersection-free (clean, or distorted: beyond
# fix's default quality bounds, as these generated scenes end).
finished = a["totals"]["clean"] + a["totals"]["distorted"]
if a["totals"]["jobs"] != 4 or finished != 4 or a["exit_code"] not in (0, 6):
    print(f"error: the local batch should have four intersection-free jobs: {a['totals']}", file=sys.stderr)
    failed = True
if a != b:
    lines = [json.dumps(s, indent=1, sort_keys=True).splitlines() for s in (a, b)]
    sys.stderr.writelines(l + "\n" for l in difflib.unified_diff(*lines, "local", "slurm", lineterm=""))
    print("error: the Slurm batch's summary.json differs from the local batch's", file=sys.stderr)
    failed = True
outputs = [p for job in a["jobs"] for p in job["outputs"]]
for p in outputs:
    if (local / p).read_bytes() != (slurm / p).read_bytes():
        print(f"error: {p} differs between the local and the Slurm batch", file=sys.stderr)
        failed = True
if not failed:
    print(f"summary.json equal (times aside), {len(outputs)} meshes equal")
sys.exit(1 if failed else 0)
PY
CHECK

rc=0
bash "$here/run_array_test.sh" "$work/slurm/batch.sbatch" bash "$work/check.sh" "$work" |
  tee "$work/run.out" || rc=$?
# run_array_test.sh printed its cluster's folder (SLURM_CONF=DIR/cluster/slurm.conf); every daemon
# it started names that folder on its command line (-f, --socket).
cluster="$(sed -n 's|.*(SLURM_CONF=\(.*\)/slurm.conf)$|\1|p' "$work/run.out")"
[[ -n "$cluster" ]] || { echo "FAIL: run_array_test.sh printed no SLURM_CONF" >&2; exit 1; }
left="$(ps -eo pid=,args= | grep -F -- "$cluster" | grep -v -F grep || true)"
if [[ -n "$left" ]]; then
  echo "FAIL: processes of the cluster in $cluster are still running:" >&2
  echo "$left" >&2
  exit 1
fi
echo "no daemon of $cluster left"
((rc == 0)) && echo "passed"
exit "$rc"
