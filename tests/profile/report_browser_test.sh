#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-only
# nns-profile's HTML report in a real headless browser (Debian's chromium): the page loads from
# file:// without any console message other than its own "nns-profile report: N elements" (no
# script error, no blocked load), and its DOM shows every element of the profiled pipeline.
# The same check on a copy of the page with a script error must fail (the check can fail).
# usage: report_browser_test.sh <nns-profile> <plugin dir>
# Exit 77 (skip) when chromium is missing, unless CI=true (then it fails).
set -u
tool=$1
plugin=$2
browser=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$browser" ]; then
  if [ "${CI:-}" = true ]; then
    echo "FAIL: chromium is not installed (scripts/deps/profiler.apt lists it)"
    exit 1
  fi
  echo "SKIP: chromium is not installed (apt-get install chromium)"
  exit 77
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

GST_PLUGIN_PATH=$plugin "$tool" --quiet --html "$dir/report.html" --json "$dir/report.json" \
  "videotestsrc num-buffers=20 ! video/x-raw,format=GRAY8,width=8,height=8 ! \
   identity name=slow sleep-time=1000 ! queue name=q ! tensor_converter name=conv ! \
   fakesink name=sink sync=false" >"$dir/table.txt" 2>"$dir/tool.err" || {
  echo "FAIL: nns-profile failed:"
  cat "$dir/tool.err"
  exit 1
}
names=$(/usr/bin/python3 -c 'import json,sys; print(" ".join(e["name"] for e in json.load(open(sys.argv[1]))["elements"]))' "$dir/report.json")
count=$(echo "$names" | wc -w)
[ "$count" -ge 5 ] || { echo "FAIL: only $count elements in the report: $names"; exit 1; }

# Loads $1 headless; prints the reasons it is not acceptable (nothing when it is).
check_page() {
  local page=$1 profile
  profile=$(mktemp -d "$dir/profile.XXXXXX")
  timeout 20 "$browser" --headless --no-sandbox --disable-gpu --disable-background-networking \
    --disable-component-update --no-first-run --disable-sync --user-data-dir="$profile" \
    --enable-logging=stderr --v=0 --dump-dom "file://$page" >"$dir/dom.html" 2>"$dir/browser.log"
  local rc=$?
  [ $rc -eq 0 ] || echo "chromium exited with $rc"
  grep -F ':CONSOLE' "$dir/browser.log" | grep -vF "\"nns-profile report: $count elements\"" |
    sed 's/^/console: /'
  grep -qF "\"nns-profile report: $count elements\"" "$dir/browser.log" ||
    echo "the page's script did not report $count elements"
  for n in $names; do
    grep -qF "data-name=\"$n\"" "$dir/dom.html" || echo "element $n is not in the DOM"
  done
}

problems=$(check_page "$dir/report.html")
if [ -n "$problems" ]; then
  echo "FAIL: the report does not load cleanly:"
  echo "$problems"
  exit 1
fi
# The check must see a script error when there is one.
sed 's|</body>|<script>notDefinedAnywhere();</script></body>|' "$dir/report.html" >"$dir/broken.html"
problems=$(check_page "$dir/broken.html")
if ! echo "$problems" | grep -q "notDefinedAnywhere"; then
  echo "FAIL: a script error in the page went unnoticed; got: $problems"
  exit 1
fi
echo "PASS: report with $count elements ($names) loads without console errors in $("$browser" --version 2>/dev/null)"
