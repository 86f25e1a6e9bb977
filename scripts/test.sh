#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Builds (configuring first when needed) and runs the whole test suite with CTest.
# Exits non-zero when the build or any test fails.
#
# usage: scripts/test.sh [extra ctest args, e.g. -R tensor_sink]
# env:   NNS_BUILD_DIR (build), NNS_BUILD_TYPE (Release, first configure only), NNS_JOBS (nproc),
#        NNS_SANITIZE=1  also builds and runs the tests with ASan+UBSan+LeakSanitizer in build-asan/
#                        (default 1 when CI=true, else 0; docs/testing.md),
#        NNS_SANITIZE_FULL=1  the sanitizer tree gets the heavy back ends too (PyTorch, Arm NN,
#                        OpenCV, python3; default: only the light parts, -DNNS_SANITIZE_LIGHT=ON),
#        NNS_ASAN_CTEST_ARGS  ctest arguments of the sanitizer pass only (default: -LE slow|fuzz -E Perf[.];
#                        timing tests cannot hold under ASan),
#        NNS_FORMAT_CHECK=0 skips the clang-format check (a file it would change fails the run).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${NNS_BUILD_DIR:-$ROOT/build}
BUILD_TYPE=${NNS_BUILD_TYPE:-Release}
JOBS=${NNS_JOBS:-$(nproc 2>/dev/null || echo 2)}
CTEST_JOBS=${NNS_CTEST_JOBS:-2}
T0=$(date +%s)
PASSED=0 FAILED=0 SKIPPED=0

say() { printf '[test] %s\n' "$*"; }

# build_tree <dir> <cmake args...>: configure when there is no cache yet, then build.
build_tree() {
  local dir=$1
  shift
  local log_dir=$dir/setup-logs
  mkdir -p "$log_dir"
  if [[ ! -f $dir/CMakeCache.txt ]]; then
    say "configuring ${dir#"$ROOT"/}"
    cmake -S "$ROOT" -B "$dir" "$@" >"$log_dir/cmake-test.log" 2>&1 || {
      tail -n 40 "$log_dir/cmake-test.log" >&2
      say "FAILED: cmake configure of ${dir#"$ROOT"/}"
      exit 1
    }
  fi
  local t0
  t0=$(date +%s)
  if ! cmake --build "$dir" -j"$JOBS" >"$log_dir/build-test.log" 2>&1; then
    grep -E -A5 'error:|Error [0-9]' "$log_dir/build-test.log" | head -n 80 >&2 || true
    say "FAILED: build of ${dir#"$ROOT"/} (log: ${log_dir#"$ROOT"/}/build-test.log)"
    exit 1
  fi
  say "built ${dir#"$ROOT"/} in $(($(date +%s) - t0)) s"
}

# run_ctest <dir> [args]: runs ctest (its summary line is printed), adds up the counts,
# returns ctest's status.
run_ctest() {
  local dir=$1
  shift
  local t0 rc=0 log=$dir/setup-logs/ctest.log
  t0=$(date +%s)
  (cd "$dir" && ctest --output-on-failure -j"$CTEST_JOBS" "$@") 2>&1 | tee "$log" || rc=$?
  local total failed skipped
  total=$(sed -n 's/.* tests failed out of \([0-9]*\).*/\1/p' "$log" | tail -n 1)
  failed=$(sed -n 's/.*, \([0-9]*\) tests failed out of.*/\1/p' "$log" | tail -n 1)
  skipped=$(grep -c '\*\*\*Skipped\|(Disabled)' "$log" || true)
  if [[ -z $total ]]; then
    say "ctest printed no summary (no tests found?)"
    rc=1
  else
    PASSED=$((PASSED + total - failed - skipped))
    FAILED=$((FAILED + failed))
    SKIPPED=$((SKIPPED + skipped))
  fi
  say "ctest in ${dir#"$ROOT"/} took $(($(date +%s) - t0)) s (exit $rc)"
  return $rc
}

format_status=0
if [[ ${NNS_FORMAT_CHECK:-1} != 0 && -x $ROOT/scripts/format-check.sh ]]; then
  # The tests still run; the run fails at the end when a file is not clang-formatted.
  "$ROOT/scripts/format-check.sh" --quiet || {
    say "FAILED: clang-format check (fix with scripts/format-check.sh --fix)"
    format_status=1
  }
fi

# failed_names <log>: the names of the tests a ctest log lists as failed, one per line.
failed_names() {
  sed -n '/The following tests FAILED:/,$p' "$1" | sed -n 's/^[[:space:]]*[0-9]* - \(.*\) (.*)$/\1/p'
}

# failure_excerpt <LastTest.log> <test>: what the test printed about its failure (gtest's
# "Failure" blocks, else its last lines), at most 20 lines, indented.
failure_excerpt() {
  awk -v name="$2" '
    /^[0-9]+\/[0-9]+ Testing: / && substr($0, index($0, " Testing: ") + 10) == name { on = 1; n = 0; next }
    on && /^Output:$/ { n = 0; dashes = 1; next }
    dashes { dashes = 0; next }
    on && /^<end of output>/ { on = 0 }
    on { out[n++] = $0 }
    END {
      k = 0
      for (i = 0; i < n && k < 20; i++)
        if (out[i] ~ /Failure$/ || out[i] ~ /FAILED:|Error|error:/) {
          for (j = i; j < n && j < i + 5 && k < 20; j++) { print "    " out[j]; k++ }
          i = j - 1
        }
      if (k == 0) for (i = (n > 10 ? n - 10 : 0); i < n; i++) print "    " out[i]
    }' "$1"
}

FLAKY=()
# rerun_failed <dir>: runs the tests that failed in <dir>'s last ctest run once more. A test that
# passes the second time is reported as flaky by name at the end of the output (not hidden; see
# docs/testing.md "Re-runs"); one that fails again fails the run. Returns non-zero at once when
# the log names no failed test (ctest itself failed: nothing to re-run).
rerun_failed() {
  local dir=$1 log=$1/setup-logs/ctest.log name first again
  mapfile -t first < <(failed_names "$log")
  ((${#first[@]})) || return 1
  cp "$log" "$log.first"
  cp "$dir/Testing/Temporary/LastTest.log" "$dir/setup-logs/LastTest.log.first" 2>/dev/null || true
  FAILED=$((FAILED - ${#first[@]}))
  say "${#first[@]} test(s) failed in ${dir#"$ROOT"/} (log kept in ${log#"$ROOT"/}.first);" \
    "running them once more"
  local rc=0
  run_ctest "$dir" --rerun-failed || rc=$?
  mapfile -t again < <(failed_names "$log")
  for name in "${first[@]}"; do
    printf '%s\n' "${again[@]}" | grep -qxF -- "$name" || FLAKY+=("$dir|$name")
  done
  return $rc
}

build_tree "$BUILD_DIR" -DCMAKE_BUILD_TYPE="$BUILD_TYPE"
status=$format_status
run_ctest "$BUILD_DIR" "$@" || rerun_failed "$BUILD_DIR" || status=1
# The Python package's pytest summary (python_api.pytest, tests/python-api.cmake).
py_summary=$(grep -E '^[0-9]+ (passed|failed|skipped|error).* in [0-9.]+s' \
  "$BUILD_DIR/Testing/Temporary/LastTest.log" 2>/dev/null | tail -n 1 || true)
[[ -z $py_summary ]] || say "pytest (python/tests): $py_summary"

if [[ -z ${NNS_SANITIZE:-} ]]; then
  if [[ ${CI:-} == true ]]; then NNS_SANITIZE=1; else NNS_SANITIZE=0; fi
fi
if [[ $NNS_SANITIZE == 1 ]]; then
  ASAN_DIR=${NNS_ASAN_BUILD_DIR:-$ROOT/build-asan}
  SUPP=$ROOT/scripts/sanitizers
  light=ON
  [[ ${NNS_SANITIZE_FULL:-0} == 1 ]] && light=OFF
  say "sanitizer pass (ASan+UBSan+LSan, light parts only: $light) in ${ASAN_DIR#"$ROOT"/}"
  # Leaks are checked (LSan at exit of every test process); suppressions: scripts/sanitizers/*.supp.
  # G_SLICE=always-malloc: GLib's slice magazines would otherwise hide leaked GstBuffers/events.
  # fast_unwind_on_malloc=0: GLib/GStreamer have no frame pointers; without it leak stacks stop
  # at g_malloc and neither the reports nor the suppressions can name the caller.
  # Exported before the build: gtest_discover_tests runs the test binaries at build time.
  # use_tls=0: LeakSanitizer (GCC 12) misreads the dynamic TLS of dlopen'ed libraries on glibc
  # 2.36 and its tracer crashes (wire_pipeline_test, "Tracer caught signal 11"); TLS is then not a
  # root, so GLib's per-thread data is suppressed by name in lsan.supp.
  export G_SLICE=always-malloc G_DEBUG=gc-friendly
  export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:detect_odr_violation=0:fast_unwind_on_malloc=0:suppressions=$SUPP/asan.supp}
  export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$SUPP/lsan.supp:print_suppressions=0:use_tls=0}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1:suppressions=$SUPP/ubsan.supp}
  # -O1 -g1: about half the compile time of -O2 -g, still file:line in the reports.
  build_tree "$ASAN_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNNS_SANITIZE=ON \
    -DNNS_SANITIZE_LIGHT=$light -DNNS_BUILD_BENCH=OFF \
    -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1"
  asan_args=(-LE 'slow|fuzz' -E 'Perf[.]')
  # shellcheck disable=SC2206
  [[ -n ${NNS_ASAN_CTEST_ARGS+x} ]] && asan_args=($NNS_ASAN_CTEST_ARGS)
  if ! run_ctest "$ASAN_DIR" "${asan_args[@]}" "$@"; then
    # A sanitizer report (an ASan error, a leak, UBSan's "runtime error:") fails the run at once:
    # a finding is not flaky. Other failures run once more, as in the Release pass: a test that
    # measures time or crosses processes, or LeakSanitizer's stop-the-world tracer crashing at
    # process exit ("Tracer caught signal 11 ... LeakSanitizer has encountered a fatal error"),
    # a fault of the sanitizer (docs/testing.md).
    if grep -q 'ERROR: AddressSanitizer\|ERROR: LeakSanitizer: detected\|runtime error:' \
      "$ASAN_DIR/setup-logs/ctest.log"; then
      status=1
    else
      rerun_failed "$ASAN_DIR" || status=1
    fi
  fi
fi

# The names come last so that the tail of a CI log says which tests failed or were flaky.
for entry in "${FLAKY[@]}"; do
  dir=${entry%%|*} name=${entry#*|}
  say "FLAKY (failed, then passed when re-run): ${dir#"$ROOT"/}: $name"
  failure_excerpt "$dir/setup-logs/LastTest.log.first" "$name" || true
done
if ((status)); then
  for dir in "$BUILD_DIR" "${ASAN_DIR:-/nonexistent}"; do
    [[ -f $dir/setup-logs/ctest.log ]] || continue
    failed_names "$dir/setup-logs/ctest.log" | while read -r name; do
      say "FAILED in ${dir#"$ROOT"/}: $name"
      failure_excerpt "$dir/Testing/Temporary/LastTest.log" "$name" || true
    done
  done
fi
if ((status)); then say "FAILED after $(($(date +%s) - T0)) s"; else say "all tests passed in $(($(date +%s) - T0)) s"; fi
# Plain closing line (counts over every ctest run above).
echo "tests: $PASSED passed, $FAILED failed, $SKIPPED skipped"
exit $status
