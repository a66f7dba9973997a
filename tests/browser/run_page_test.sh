#!/usr/bin/env bash
# Checks tests/browser/check_page.py both ways on pages made here: a page showing a picture drawn
# by `untangle render` must pass (with a screenshot of the requested size, and an --eval that
# clicks and one that holds), and so must one with that picture lazy far below the fold; pages
# with a missing image, a missing lazy image below the fold, an image that is not one, a
# console.error, an uncaught exception, an --eval that is false, one that throws and a click whose
# handler throws must fail, each naming its fault. Runs only with UNTANGLE_BROWSER_TEST=1; otherwise exits 77 (ctest: skipped).
#
#   tests/browser/run_page_test.sh UNTANGLE_BINARY
set -euo pipefail

if [[ "${UNTANGLE_BROWSER_TEST:-0}" != "1" ]]; then
  echo "skipped: set UNTANGLE_BROWSER_TEST=1 to run (needs chromium and python3)"
  exit 77
fi
if (($# != 1)); then
  echo "usage: $0 UNTANGLE_BINARY" >&2
  exit 2
fi
untangle="$(realpath "$1")"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
check="$root/tests/browser/check_page.py"
work="$(mktemp -d /tmp/untangle-browser.XXXXXX)"
trap 'rm -rf "$work"' EXIT
cd "$work"

"$untangle" render "$root/testdata/makehuman/male_casualsuit04.obj" \
  --obstacle "$root/testdata/makehuman/male_generic.obj" --contours --size 320x240 -o shirt.png -q
printf 'not a picture\n' > fake.png

page() { # NAME BODY: a page NAME.html with BODY
  printf '<!doctype html>\n<html><head><meta charset="utf-8"><title>%s</title></head>\n<body>\n%s\n</body></html>\n' \
    "$1" "$2" > "$1.html"
}
page good '<h1>untangle render</h1><img src="shirt.png" alt="the garment, its contours in red">'
page missing '<img src="shirt.png"><img src="no_such.png">'
page lazy '<div style="height:30000px"></div><img src="shirt.png" loading="lazy">'
page lazy_missing '<div style="height:30000px"></div><img src="no_such.png" loading="lazy">'
page fake '<img src="shirt.png"><img src="fake.png">'
page console '<img src="shirt.png"><script>console.error("deliberate console error")</script>'
page exception '<script>null.property</script><p>text</p>'
page click "<p id=\"p\" onclick=\"this.textContent = 'clicked'\">text</p><button onclick=\"null.property\">x</button>"

failed=0
fail() {
  echo "FAIL: $*" >&2
  failed=1
}

start=$SECONDS
if python3 "$check" good.html good_shot.png --size 640x480 --eval 'document.images.length === 1' &&
  python3 "$check" lazy.html lazy_shot.png &&
  python3 "$check" click.html click_shot.png --eval "document.getElementById('p').click(), true" \
    --eval "document.getElementById('p').textContent === 'clicked'"; then
  # The screenshot is a PNG of the window size asked for (read from its IHDR chunk).
  size="$(python3 -c '
import struct, sys
data = open(sys.argv[1], "rb").read(24)
assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR", "not a PNG"
print("%dx%d" % struct.unpack(">II", data[16:24]))' good_shot.png)" || size="unreadable"
  [[ "$size" == 640x480 ]] || fail "good.html: screenshot is $size, expected 640x480"
else
  fail "good.html, lazy.html and click.html (clicking the paragraph) should pass"
fi

# NAME WHAT [ARG...]: NAME.html checked with ARGs must fail (exit 1) with a line containing WHAT
# on stderr.
must_fail() {
  local rc=0 name="$1" what="$2"
  shift 2
  python3 "$check" "$name.html" "${name}_shot.png" "$@" 2> "$name.err" || rc=$?
  cat "$name.err" >&2
  if ((rc != 1)); then
    fail "$name.html $*: exit $rc, expected 1"
  elif ! grep -qF -- "$what" "$name.err"; then
    fail "$name.html $*: no line with \"$what\""
  fi
}
must_fail missing "image not decoded (naturalWidth 0): file://$work/no_such.png"
must_fail lazy_missing "image not decoded (naturalWidth 0): file://$work/no_such.png"
must_fail fake "image not decoded (naturalWidth 0): file://$work/fake.png"
must_fail console "console.error: deliberate console error"
must_fail exception "uncaught exception: TypeError"
must_fail good "--eval document.title: is \"good\", not true" --eval document.title
must_fail good "--eval no_such_name: threw ReferenceError" --eval no_such_name
must_fail click "uncaught exception: TypeError" --eval "document.querySelector('button').click(), true"
echo "ten checks of eight pages in $((SECONDS - start)) s"

((failed == 0)) && echo "passed"
exit "$failed"
