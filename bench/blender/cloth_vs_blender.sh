#!/usr/bin/env bash
# untangle simulate against Blender's cloth on the same example scene (issue 19, "Speed"): a
# benchmark behind a flag, never run by CI (docs/CONTRIBUTING.md, "Benchmarks behind flags").
#
#   bench/blender/cloth_vs_blender.sh NAME FRAMES      # NAME: spikes, cow, fitting, ball or box
#
# 1. `untangle simulate --example NAME --frames 1` writes the scene's start meshes into
#    OUT/start (a cloth mesh is one that also has a frame file, <stem>_0001.obj).
# 2. Blender (`blender -b --factory-startup -t BLENDER_THREADS`) runs cloth_blender.py on them:
#    a Cloth modifier with self-collision on each cloth, a Collision modifier on each obstacle,
#    FRAMES frames timed one by one; the last frame's cloth is written to OUT/blender in the
#    original vertex order.
# 3. `untangle simulate --example NAME --frames FRAMES --threads 1` (only the last frame written).
# 4. `untangle check` judges both tools' last frames the same way (cloth movable, obstacles
#    --obstacle): crossings with a cloth mesh in them (an obstacle's crossings with itself, like
#    the cow's tail through its rump, are left out) and cloth vertices inside an obstacle.
# Then one table row per tool: median and total ms per frame, crossings and inside vertices at
# the end. The two runs are one after the other, never at the same time.
#
# Environment: UNTANGLE (default build/untangle of this checkout), BLENDER (default blender),
# OUT (default /tmp/cloth_vs_blender/NAME-FRAMES, emptied first), BLENDER_THREADS (default 1,
# like untangle's --threads 1), BLENDER_ARGS (more options for cloth_blender.py, e.g.
# "--quality 8 --collision-quality 4"), SKIP_UNTANGLE=1 (Blender's row only).
# Exit status 0 when both runs finished (whatever they left), 2 on a usage error, 1 otherwise.
set -euo pipefail

if [[ $# -ne 2 || ! "$2" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: $0 spikes|cow|fitting|ball|box FRAMES" >&2
  exit 2
fi
name=$1
frames=$2
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
untangle=${UNTANGLE:-$root/build/untangle}
blender=${BLENDER:-blender}
out=${OUT:-/tmp/cloth_vs_blender/$name-$frames}
threads=${BLENDER_THREADS:-1}
if [[ ! -x "$untangle" ]]; then
  echo "error: $untangle is not built (cmake --preset release && cmake --build build)" >&2
  exit 1
fi
if ! command -v "$blender" > /dev/null; then
  echo "error: $blender not found (UNTANGLE_WITH_BLENDER=1 bash scripts/setup.sh installs it)" >&2
  exit 1
fi

rm -rf "$out"
mkdir -p "$out"
echo "machine: $(nproc) cores, $(uptime | sed 's/.*load/load/')" | tee "$out/machine.txt"

# 1. The start meshes.
"$untangle" simulate --example "$name" --output-dir "$out/start" --frames 1 --threads 1 -q \
  > /dev/null || true  # a first frame that is not clean still wrote the start
cloth=() obstacles=()
for f in "$out"/start/*.obj; do
  stem=$(basename "$f" .obj)
  [[ "$stem" =~ _[0-9]{4}$ ]] && continue
  if [[ -e "$out/start/${stem}_0001.obj" ]]; then cloth+=("$f"); else obstacles+=("$f"); fi
done
if [[ ${#cloth[@]} -eq 0 ]]; then
  echo "error: the example '$name' wrote no cloth into $out/start" >&2
  exit 1
fi
echo "cloth: ${cloth[*]##*/}; obstacles: ${obstacles[*]##*/}"

# 2. Blender.
args=(--frames "$frames" --out "$out/blender")
for f in "${cloth[@]}"; do args+=(--cloth "$f"); done
for f in "${obstacles[@]}"; do args+=(--obstacle "$f"); done
# shellcheck disable=SC2206  # BLENDER_ARGS is split on purpose
args+=(${BLENDER_ARGS:-})
blender_start=$EPOCHREALTIME
"$blender" -b --factory-startup -t "$threads" --python "$here/cloth_blender.py" -- "${args[@]}" \
  > "$out/blender.log" 2>&1 || { tail -20 "$out/blender.log" >&2; exit 1; }
blender_wall=$(python3 -c "print($EPOCHREALTIME - $blender_start)")
judge() {  # judge DIR STEMSUFFIX: untangle check on the cloth files of DIR, obstacles from start
  local dir=$1 suffix=$2 files=() obst=()
  for f in "${cloth[@]}"; do files+=("$dir/$(basename "$f" .obj)$suffix.obj"); done
  for f in "${obstacles[@]}"; do obst+=(--obstacle "$f"); done
  "$untangle" check "${files[@]}" "${obst[@]}" --threads 1 -q --report "$dir/check.json" \
    --overwrite || true  # exit 5 is a result here, not a failure
}
judge "$out/blender" ""

# 3. untangle.
untangle_status=finished
if [[ "${SKIP_UNTANGLE:-0}" != "1" ]]; then
  untangle_start=$EPOCHREALTIME
  "$untangle" simulate --example "$name" --output-dir "$out/untangle" --frames "$frames" \
    --save-every "$frames" --threads 1 --report "$out/untangle/report.json" -q \
    || untangle_status="exit $?"
  untangle_wall=$(python3 -c "print($EPOCHREALTIME - $untangle_start)")
  judge "$out/untangle" "_$(printf %04d "$frames")"
fi

# 4. The table.
python3 - "$out" "$frames" "${blender_wall}" "${untangle_wall:-}" "$untangle_status" <<'EOF'
import json, os, statistics, sys
out, frames, blender_wall, untangle_wall, untangle_status = sys.argv[1:6]
def judged(d):
    """Crossings with a cloth mesh in them, and cloth vertices inside an obstacle. `check` also
    counts an obstacle's crossings with itself (the cow's tail passes through its rump: 84
    crossings that no cloth can change); those are the contours without a movable mesh."""
    r = json.load(open(os.path.join(d, "check.json")))
    roles = [m["role"] for m in r["meshes"]]
    own = sum(c["crossings"] for c in r["contours"]
              if all(roles[m] != "movable" for m in c["meshes"]))
    if sum(c["crossings"] for c in r["contours"]) != r["before"]["crossings"]:
        sys.exit("cloth_vs_blender: check.json's contours do not hold every crossing")
    judged.obstacles_own = own
    return r["before"]["crossings"] - own, r["before"]["inside_vertices"]
rows = []
t = json.load(open(os.path.join(out, "blender", "blender_timing.json")))
c, i = judged(os.path.join(out, "blender"))
s = t["settings"]
rows.append(("blender %s (-t %s)" % (s["blender"], os.environ.get("BLENDER_THREADS", "1")),
             statistics.median(t["frame_ms"]), sum(t["frame_ms"]), float(blender_wall), c, i,
             "quality %d, collision quality %d, time_scale %.3f" %
             (s["quality"], s["collision_quality"], s["time_scale"])))
r_path = os.path.join(out, "untangle", "report.json")
if untangle_wall and os.path.exists(r_path):
    r = json.load(open(r_path))
    per = [sum(f["timing_ms"].values()) for f in r["frames"]]
    c, i = judged(os.path.join(out, "untangle"))
    last = r["frames"][-1]
    rows.append(("untangle simulate (--threads 1)", statistics.median(per), sum(per),
                 float(untangle_wall), c, i,
                 "status %s (%s); last frame: report's written_crossings %s, max_stretch %.2f, "
                 "frames with crossings %s, overstretched %s" %
                 (r["status"], untangle_status, last.get("written_crossings"),
                  last["max_stretch"], r["frames_with_crossings"], r["frames_overstretched"])))
print()
print("crossings: those with a cloth mesh in them, by untangle check; the obstacles' own "
      "crossings with themselves (%d) left out" % judged.obstacles_own)
print("| tool | frames | ms/frame median | ms total | wall s | crossings at the end | inside vertices | notes |")
print("|---|---|---|---|---|---|---|---|")
for name, med, tot, wall, c, i, note in rows:
    print("| %s | %s | %.0f | %.0f | %.2f | %d | %d | %s |" % (name, frames, med, tot, wall, c, i, note))
EOF
