#!/usr/bin/env bash
# Installs what is missing, builds (scripts/setup.sh) and runs the whole test suite, then builds the
# ASan + UBSan preset (build-asan/) and runs the suite again under the sanitizers.
# UNTANGLE_SKIP_SANITIZE=1 skips the sanitizer build and run. Exits non-zero if either suite
# fails; the last line printed is the combined "N passed, N failed, N skipped".
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

logs="$(mktemp -d)"
trap 'rm -rf "$logs"' EXIT

status=0
total_passed=0
total_failed=0
total_skipped=0
summaries=()

heading() {
  echo
  echo "==== $* ===="
}

# Runs ctest with the given arguments, keeps its output in $logs/$1.log and adds its counts to the
# totals. A ctest run that prints no summary (crash, no tests found) counts as one failure. ctest
# counts a skipped test (GTEST_SKIP, or a test behind a flag that exits 77) in its "passed"
# percentage; here it counts as skipped, from ctest's list of tests that did not run.
run_suite() {
  local name="$1"
  shift
  local rc=0
  ctest "$@" 2>&1 | tee "$logs/$name.log" || rc=$?
  local line
  line="$(grep -E '[0-9]+ tests? failed out of [0-9]+' "$logs/$name.log" | tail -n 1 || true)"
  if [[ "$line" =~ ([0-9]+)\ tests?\ failed\ out\ of\ ([0-9]+) ]]; then
    local failed="${BASH_REMATCH[1]}" ran="${BASH_REMATCH[2]}" skipped
    skipped="$(grep -cE '^[[:space:]]+[0-9]+ - .+ \(Skipped\)$' "$logs/$name.log" || true)"
    total_passed=$((total_passed + ran - failed - skipped))
    total_failed=$((total_failed + failed))
    total_skipped=$((total_skipped + skipped))
    summaries+=("$name: $((ran - failed - skipped)) passed, $failed failed, $skipped skipped")
    if ((failed > 0)); then rc=1; fi
  else
    total_failed=$((total_failed + 1))
    summaries+=("$name: no ctest summary (ctest exit status $rc)")
    rc=1
  fi
  if ((rc != 0)); then status=1; fi
}

heading "set-up and Release build (scripts/setup.sh, build/)"
bash scripts/setup.sh

heading "test suite: Release (build/)"
start=$SECONDS
run_suite release --preset release
echo "release suite: $((SECONDS - start)) s"

if [[ "${UNTANGLE_SKIP_SANITIZE:-0}" == "1" ]]; then
  heading "test suite: ASan + UBSan skipped (UNTANGLE_SKIP_SANITIZE=1)"
  summaries+=("asan: skipped (UNTANGLE_SKIP_SANITIZE=1)")
else
  heading "ASan + UBSan build (preset asan, build-asan/)"
  start=$SECONDS
  if cmake --preset asan && cmake --build --preset asan -j"$(nproc)"; then
    echo "asan build: $((SECONDS - start)) s"
    heading "test suite: ASan + UBSan (build-asan/)"
    # The environment of the asan test preset sets ASAN_OPTIONS and UBSAN_OPTIONS; set here too so
    # that the CLI processes the tests start see them whatever ctest does.
    export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    # Debian's assimp 5.2 leaks what an importer allocated when it throws on a corrupt file (STL,
    # glTF, LWO, ... in the hostile-input tests); leaks in our own code are still reported.
    printf 'leak:libassimp.so\n' > "$logs/lsan.supp"
    export LSAN_OPTIONS="suppressions=$logs/lsan.supp:print_suppressions=0"
    start=$SECONDS
    run_suite asan --preset asan
    echo "asan suite: $((SECONDS - start)) s"
  else
    echo "error: the ASan + UBSan build failed (see above)" >&2
    summaries+=("asan: build failed")
    total_failed=$((total_failed + 1))
    status=1
  fi
fi

heading "summary"
for line in "${summaries[@]}"; do echo "$line"; done
echo "$total_passed passed, $total_failed failed, $total_skipped skipped"
exit "$status"
