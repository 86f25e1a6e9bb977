#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Builds the tree (Release unless already configured) and runs every benchmark in build/bench/.
# Results are printed and saved to build/bench-results/<name>.txt.
#
# usage: scripts/bench.sh [name-substring]      e.g. scripts/bench.sh pipeline
#        scripts/bench.sh paper [--docs]        the paper's experiments E1-E4 (examples/paper/run.sh,
#                                               docs/paper-experiments.md), under 10 minutes; both
#                                               sides pinned to $NNS_PAPER_CPUS (every core), the load
#                                               average printed before every run; --docs copies the
#                                               plots and tables.md to docs/paper/ (quiet machine only)
# env:   NNS_BUILD_DIR (build), NNS_JOBS (nproc)
# Benchmarks are timing-sensitive: run them on an otherwise idle machine and compare medians.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${NNS_BUILD_DIR:-$ROOT/build}
JOBS=${NNS_JOBS:-$(nproc 2>/dev/null || echo 2)}
filter=${1:-}

if [[ ! -f $BUILD_DIR/CMakeCache.txt ]]; then
  cmake -S "$ROOT" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
if [[ $filter == paper ]]; then
  cmake --build "$BUILD_DIR" -j"$JOBS" --target nnstreamer nns_filter_onnxruntime \
    nns_decoder_tensor_region nns_decoder_bounding_boxes nns-paper nns_paper_models nns-profile \
    >/dev/null || {
    echo "[bench] build failed: run cmake --build ${BUILD_DIR#"$ROOT"/} for the errors" >&2
    exit 1
  }
  mkdir -p "$BUILD_DIR/bench-results"
  echo "[bench] ===== paper ($(date -u +%FT%TZ), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg))"
  NNS_BUILD_DIR="$BUILD_DIR" bash "$ROOT/examples/paper/run.sh" "${@:2}" 2>&1 |
    tee "$BUILD_DIR/bench-results/paper.txt"
  exit "${PIPESTATUS[0]}"
fi
type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$BUILD_DIR/CMakeCache.txt")
[[ $type == Release ]] || echo "[bench] warning: ${BUILD_DIR#"$ROOT"/} is a '$type' build, not Release"
cmake --build "$BUILD_DIR" -j"$JOBS" >/dev/null || {
  echo "[bench] build failed: run cmake --build ${BUILD_DIR#"$ROOT"/} for the errors" >&2
  exit 1
}
# The benchmarks register the elements in-process; never pick up another plugin build.
export GST_PLUGIN_PATH=
mkdir -p "$BUILD_DIR/bench-results"
shopt -s nullglob
ran=0 failed=0
for b in "$BUILD_DIR"/bench/*_bench; do
  name=$(basename "$b")
  [[ -z $filter || $name == *"$filter"* ]] || continue
  echo "[bench] ===== $name ($(date -u +%FT%TZ), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg))"
  if "$b" 2>&1 | tee "$BUILD_DIR/bench-results/$name.txt"; then ran=$((ran + 1)); else
    echo "[bench] $name FAILED" >&2
    failed=$((failed + 1))
  fi
done
# The Python package's Single.invoke overhead (python/bench/bench_single.py), when it is built.
if [[ -f $BUILD_DIR/python/nnstreamer/__init__.py && ( -z $filter || python_single == *"$filter"* ) ]]; then
  echo "[bench] ===== python_single ($(date -u +%FT%TZ), load $(cut -d' ' -f1-3 /proc/loadavg))"
  if PYTHONPATH="$BUILD_DIR/python" NNSTREAMER_CONF="$BUILD_DIR/nnstreamer.ini" \
    /usr/bin/python3 "$ROOT/python/bench/bench_single.py" "$BUILD_DIR" 2>&1 |
    tee "$BUILD_DIR/bench-results/python_single.txt"; then ran=$((ran + 1)); else
    echo "[bench] python_single FAILED" >&2
    failed=$((failed + 1))
  fi
fi
# The figures with targets, gathered from every result file of this run.
if ((ran)); then
  echo "[bench] ===== summary (targets: pipeline/direct >= 0.97, mux/demux <= 2 us per buffer, query_serve served/in-process >= 0.9)"
  for b in "$BUILD_DIR"/bench/*_bench; do
    name=$(basename "$b")
    [[ -z $filter || $name == *"$filter"* ]] || continue
    f=$BUILD_DIR/bench-results/$name.txt
    [[ -f $f ]] || continue
    grep -E 'ratio|tensor_mux:|tensor_demux:|sync-mode=|speed-up' "$f" | sed "s/^/[$name] /" || true
  done
fi
((ran + failed)) || echo "[bench] no benchmark matched '${filter}' in ${BUILD_DIR#"$ROOT"/}/bench"
echo "[bench] $ran benchmark(s) ran, $failed failed; results in ${BUILD_DIR#"$ROOT"/}/bench-results/"
((failed == 0))
