#!/bin/sh
# Whole-process comparison of `untangle check` with the CGAL program doing the same job
# (bench/bench_cgal_check.cpp), run in alternation (one of ours, one of CGAL's, per round) so that
# a change of machine load falls on both alike. Prints, per side, the median and range of the
# wall and CPU (user + system) seconds over the rounds, and the median of the per-round ratios.
#
# Usage: bench/whole_process.sh BUILD_DIR ROUNDS FILE...
#   e.g. bench/whole_process.sh build 11 /tmp/scene/cow.obj /tmp/scene/sheet.obj
# (untangle_bench_detect --write DIR writes the cow and the jittered sheet.)
set -eu
build=$1
rounds=$2
shift 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ours="$build/untangle check --quiet"
cgal="$build/untangle_bench_cgal_check"
# One warm-up of each (page cache, dynamic loader).
$ours "$@" >/dev/null 2>&1 || true
$cgal "$@" >/dev/null 2>&1
i=0
while [ "$i" -lt "$rounds" ]; do
  /usr/bin/time -f "%e %U %S" -a -o "$tmp/ours" $ours "$@" >/dev/null 2>&1 || true
  /usr/bin/time -f "%e %U %S" -a -o "$tmp/cgal" $cgal "$@" >/dev/null 2>&1
  i=$((i + 1))
done
# /usr/bin/time notes a nonzero exit status (check exits 5 when something intersects) on a line
# of its own: only the lines of three numbers are timings.
grep -E '^[0-9.]+ [0-9.]+ [0-9.]+$' "$tmp/ours" >"$tmp/ours.t"
grep -E '^[0-9.]+ [0-9.]+ [0-9.]+$' "$tmp/cgal" >"$tmp/cgal.t"
paste -d ' ' "$tmp/ours.t" "$tmp/cgal.t" | awk '
  function median(a, n,   i, j, t) {
    for (i = 1; i <= n; ++i) for (j = i + 1; j <= n; ++j) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
    return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
  }
  function range(a, n,   i, lo, hi) {
    lo = a[1]; hi = a[1]
    for (i = 2; i <= n; ++i) { if (a[i] < lo) lo = a[i]; if (a[i] > hi) hi = a[i] }
    return sprintf("%.3f to %.3f", lo, hi)
  }
  { ++n; ow[n] = $1; oc[n] = $2 + $3; cw[n] = $4; cc[n] = $5 + $6
    rw[n] = $1 > 0 ? $4 / $1 : 0; rc[n] = oc[n] > 0 ? cc[n] / oc[n] : 0 }
  END {
    printf "rounds %d\n", n
    printf "untangle check: wall median %.3f s (%s), cpu median %.3f s (%s)\n", median(ow, n), range(ow, n), median(oc, n), range(oc, n)
    printf "CGAL program:   wall median %.3f s (%s), cpu median %.3f s (%s)\n", median(cw, n), range(cw, n), median(cc, n), range(cc, n)
    printf "ratio CGAL / untangle per round: wall median %.1f (%s), cpu median %.1f (%s)\n", median(rw, n), range(rw, n), median(rc, n), range(rc, n)
  }'
