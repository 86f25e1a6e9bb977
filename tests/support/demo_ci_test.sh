#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# examples/demo/run_demo.sh may skip (exit 77) locally when an element, model or back end is
# missing, but never in CI (CI=true): there it must fail. Runs the real script against a fake
# build tree whose demo programs exit as told.
set -uo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/build/examples"
: >"$tmp/build/env.sh"
printf 'P3\n1 1\n255\n0 0 0\n' >"$tmp/photo.ppm"
failures=0

# demo_rc <nns-demo exit code> <CI value> -> run_demo.sh's exit code
demo_rc() {
  printf '#!/bin/sh\nexit %s\n' "$1" >"$tmp/build/examples/nns-demo"
  printf '#!/bin/sh\nexit 0\n' >"$tmp/build/examples/nns-face-demo"
  chmod +x "$tmp/build/examples/nns-demo" "$tmp/build/examples/nns-face-demo"
  local rc=0
  env -u CI ${2:+CI=$2} NNS_BUILD_DIR="$tmp/build" NNS_FACE_SKIP_MISSING=1 \
    NNS_DEMO_IMAGE="$tmp/photo.ppm" bash "$ROOT/examples/demo/run_demo.sh" >"$tmp/log" 2>&1 ||
    rc=$?
  echo "$rc"
}

expect() {  # expect <what> <want> <got>
  if [[ $2 == "$3" ]]; then
    echo "ok: $1 -> exit $3"
  else
    echo "FAIL: $1: exit $3, expected $2; output:"
    sed 's/^/  | /' "$tmp/log"
    failures=$((failures + 1))
  fi
}

# An element the demo needs is missing (nns-demo exits 77).
expect "element missing, local" 77 "$(demo_rc 77 '')"
expect "element missing, CI=true" 1 "$(demo_rc 77 true)"
# The face demo's back end is missing (the fake build tree has no onnxruntime back end).
expect "back end missing, local" 0 "$(demo_rc 0 '')"
expect "back end missing, CI=true" 1 "$(demo_rc 0 true)"
((failures == 0))
