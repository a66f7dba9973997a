#!/usr/bin/env bash
# Issue 23: `untangle batch` on three generated scenes and a job whose input is not a mesh, then
# tests/browser/check_page.py on OUT/summary.html in headless Chromium: the page loads with no
# console error or failed load, every thumbnail is decoded (naturalWidth > 0), there is one per
# finished job and none (not a broken <img>) in the failed job's row, and a click on the status
# header sorts the rows failed first, a second click the other way round. Runs only with
# UNTANGLE_BROWSER_TEST=1; otherwise exits 77 (ctest: skipped).
#
#   tests/browser/run_summary_test.sh UNTANGLE_BINARY GEN_SCENES_BINARY [SHOT.png]
# SHOT.png (default: in the temporary folder, removed) keeps the screenshot of the sorted page.
set -euo pipefail

if [[ "${UNTANGLE_BROWSER_TEST:-0}" != "1" ]]; then
  echo "skipped: set UNTANGLE_BROWSER_TEST=1 to run (needs chromium and python3)"
  exit 77
fi
if (($# < 2 || $# > 3)); then
  echo "usage: $0 UNTANGLE_BINARY GEN_SCENES_BINARY [SHOT.png]" >&2
  exit 2
fi
untangle="$(realpath "$1")"
gen_scenes="$(realpath "$2")"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
work="$(mktemp -d /tmp/untangle-browser.XXXXXX)"
trap 'rm -rf "$work"' EXIT
shot="$(realpath -m "${3:-$work/summary.png}")"
cd "$work"

# Jobs in id order: folded_sheet, garbled (failed: unreadable input), sheet_through_sphere,
# sheets_corner. The failed job is not first, so that sorting by status has rows to move.
"$gen_scenes" scenes 2> /dev/null
mkdir in out
for scene in folded_sheet sheet_through_sphere sheets_corner; do mv "scenes/$scene" in/; done
mkdir in/garbled
printf 'v 1 2\n' > in/garbled/movable_0.obj
rc=0
"$untangle" batch "$work/in" --output-dir out --jobs 2 -q || rc=$?
# fix exits 3 on an unreadable input, and the batch's status is its worst job's.
if ((rc != 3)); then
  echo "FAIL: untangle batch exited $rc, expected 3 (the garbled job's)" >&2
  exit 1
fi

# The status cells' classes, top to bottom, e.g. "distorted,failed,distorted,distorted" (the three
# generated scenes end intersection-free but beyond fix's default quality bounds).
statuses="Array.from(document.querySelectorAll('tbody tr'), r => r.cells[1].className).join()"
expect() { # JS VALUE: an --eval that is true when JS is VALUE, and otherwise shows what JS was
  printf '(v => v === %s || v)(%s)' "$2" "$1"
}
start=$SECONDS
python3 "$root/tests/browser/check_page.py" out/summary.html "$shot" \
  --eval "$(expect "$statuses" "'distorted,failed,distorted,distorted'")" \
  --eval "$(expect "document.images.length" 3)" \
  --eval "$(expect "Array.from(document.images, i => i.closest('tr').cells[0].textContent).join()" \
    "'folded_sheet,sheet_through_sphere,sheets_corner'")" \
  --eval "$(expect "document.querySelector('td.failed').closest('tr').cells[7].innerHTML" "''")" \
  --eval "document.querySelectorAll('th')[1].click(), true" \
  --eval "$(expect "$statuses" "'failed,distorted,distorted,distorted'")" \
  --eval "$(expect "document.querySelector('tbody tr').cells[0].textContent" "'garbled'")" \
  --eval "document.querySelectorAll('th')[1].click(), true" \
  --eval "$(expect "$statuses" "'distorted,distorted,distorted,failed'")"
echo "summary.html checked in $((SECONDS - start)) s; screenshot $shot"
echo "passed"
