#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# examples/paper/report.py check must fail when a pipeline's outputs differ from its Control's
# (beyond the tolerance), when their lengths differ or when the pipeline wrote nothing, and pass
# when they agree (E4's looser tolerance included).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
PY=/usr/bin/python3
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
write() { # write <file> <values...>
  $PY -c 'import sys, numpy as np; np.array(sys.argv[2:], np.float32).tofile(sys.argv[1])' "$@"
}
expect() { # expect <rc> <text> : runs the check on $d
  local rc=0 out
  out=$($PY "$ROOT/examples/paper/report.py" check "$d") || rc=$?
  [[ $rc == "$1" && $out == *"$2"* ]] || {
    echo "FAIL: expected rc $1 and '$2', got rc $rc: $out"
    exit 1
  }
}
write "$d/control.e1.fast.0.f32" 1 2 3
write "$d/nns.e1.fast.0.f32" 1 2 3
write "$d/control.e4-160.out.1.f32" 1 2 3
write "$d/nns.e4-160.out.1.f32" 1.005 2 3
expect 0 "e4-160.out.1.f32"
write "$d/nns.e1.fast.0.f32" 1 2 3.001
expect 1 "DIFFERENT"
write "$d/nns.e1.fast.0.f32" 1 2
expect 1 "Control has 3 values, pipeline 2"
rm "$d/nns.e1.fast.0.f32"
expect 1 "the pipeline wrote no"
echo "report.py check: all cases as expected"
