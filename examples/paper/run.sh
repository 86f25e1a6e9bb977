#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Runs the NNStreamer paper's experiments E1-E4 (docs/paper-experiments.md): each as a pipeline
# of our elements and as a Control loop, over the same recorded inputs and models. Every run is
# its own process (build/examples/nns-paper) and appends one JSON line to results.jsonl; then
# the outputs of pipeline and Control are compared (report.py check) and the plots and tables
# are made (report.py plot).
#
# usage: examples/paper/run.sh [--smoke] [--docs]
#   --smoke  a few frames per experiment, batch runs only (the ctest `paper.smoke`, < 60 s)
#   --docs   copy the figures and tables into docs/paper/ (after a full run)
# env: NNS_BUILD_DIR (build), NNS_PAPER_OUT (build/paper or build/paper-smoke),
#      NNS_PAPER_SKIP_MISSING=1: exit 77 (skipped) when the program, models or ONNX Runtime
#      back end are missing (never in CI),
#      NNS_PAPER_CPUS (default: every online core, e.g. 0-1): the cores both sides are pinned to
#      (taskset -c), NNS_PAPER_ORT_THREADS (1): ONNX Runtime intra-op threads per model, the same
#      for the pipeline's filters and the Control's sessions.
# Every run prints the load average before it starts; the figures only say what pipelining is
# worth on a quiet machine (load average well under 1, no build running): a batch Control that
# gets less than one core (cpu_pct < 100) was squeezed by other jobs (its runq_s shows how long).
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init paper NNS_PAPER_SKIP_MISSING

smoke=0 docs=0
for a in "$@"; do
  case $a in
    --smoke) smoke=1 ;;
    --docs) docs=1 ;;
    *) nns_die 2 "unknown argument $a (usage: run.sh [--smoke] [--docs])" ;;
  esac
done
PY=/usr/bin/python3
HERE=$ROOT/examples/paper
BIN=$BUILD_DIR/examples/nns-paper
MODELS=$BUILD_DIR/examples/paper-models
if ((smoke)); then OUT=${NNS_PAPER_OUT:-$BUILD_DIR/paper-smoke}; else OUT=${NNS_PAPER_OUT:-$BUILD_DIR/paper}; fi
[[ -x $BIN && -f $BUILD_DIR/env.sh ]] ||
  nns_die 1 "$BIN not built; run cmake --build ${BUILD_DIR} --target nns-paper nns_paper_models"
[[ -f $MODELS/paper_models.json ]] ||
  nns_die "$missing" "$MODELS missing: build the target nns_paper_models (needs Debian's python3-torch, python3-onnx)"
[[ -f $BUILD_DIR/subplugins/filters/libnnstreamer_filter_onnxruntime.so ]] ||
  nns_die "$missing" "the onnxruntime back end is not built (scripts/deps/onnxruntime.npm)"
$PY -c "import matplotlib, numpy" 2>/dev/null ||
  nns_die "$missing" "$PY lacks matplotlib/numpy (scripts/deps/paper.apt)"
nns_enter_build_env

# Input lengths: E1 frames, E2 seconds, E3 frames, E4 frames.
if ((smoke)); then lens=(12 2 16 8); else lens=(300 12 300 150); fi
rm -rf "$OUT"
mkdir -p "$OUT/inputs" "$OUT/dumps"
RES=$OUT/results.jsonl
$PY "$HERE/make_inputs.py" "$OUT/inputs" "${lens[@]}"
CPUS=${NNS_PAPER_CPUS:-0-$(($(nproc) - 1))}
ORT_THREADS=${NNS_PAPER_ORT_THREADS:-1}
command -v taskset >/dev/null || nns_die 1 "taskset (util-linux) missing: both sides are pinned with it"
echo "$NNS_TAG: $(nproc) cores, both sides pinned to cores $CPUS, ONNX Runtime intra-op threads" \
  "$ORT_THREADS; load $(cut -d' ' -f1-3 /proc/loadavg); results in $OUT"
busy=$(ps -e -o comm= | grep -c -x -E 'cc1plus|cc1|ld|ld.gold|ld.lld|ninja|make|rustc|clang|clang\+\+' || true)
load1=$(cut -d' ' -f1 /proc/loadavg)
if ((busy > 0)) || awk -v l="$load1" 'BEGIN { exit !(l >= 0.5) }'; then
  echo "$NNS_TAG: WARNING: not a quiet machine (load $load1, $busy compiler/linker processes):" \
    "the CPU each side gets is the scheduler's share, not what pipelining is worth"
fi

# run <exp> <mode> <config> [nns-paper options...]
run() {
  local exp=$1 mode=$2 config=$3
  shift 3
  echo "$NNS_TAG: $exp $mode ${config:--} $* (load $(cut -d' ' -f1-3 /proc/loadavg))" >&2
  taskset -c "$CPUS" "$BIN" --exp "$exp" --mode "$mode" --config "$config" --models "$MODELS" \
    --inputs "$OUT/inputs" --out "$RES" --ort-threads "$ORT_THREADS" "$@" >/dev/null ||
    nns_die 1 "$exp $mode $config failed"
}
both() {
  local exp=$1 config=$2
  shift 2
  for mode in control nns; do run "$exp" "$mode" "$config" "$@"; done
}

# 1. Agreement: batch runs with output dumps (every frame through every model).
for mode in control nns; do
  d="$OUT/dumps/$mode"
  run e1 "$mode" fast,mid,slow --dump "$d.e1" --rate 30
  run e2 "$mode" "" --dump "$d.e2"
  run e3 "$mode" "" --dump "$d.e3"
  run e4 "$mode" 160 --dump "$d.e4-160"
  run e4 "$mode" 320 --dump "$d.e4-320"
done
$PY "$HERE/report.py" check "$OUT/dumps" || nns_die 1 "pipeline and Control outputs differ"

# 2. Measurements (full mode): batch runs three times (the report takes the median), live runs
#    at 30 fps once.
if ((!smoke)); then
  for c in fast mid slow fast,mid mid,slow fast,slow fast,mid,slow; do
    both e1 "$c" --live --frames 240
  done
  for _ in 1 2 3; do both e1 fast,mid,slow --frames 100; done
  both e2 "" --live
  for _ in 1 2 3; do both e2 ""; done
  for _ in 1 2 3; do both e3 ""; done
  both e3 "" --live --rate 5 --frames 25
  for s in 160 320; do
    for _ in 1 2 3; do both e4 $s; done
    both e4 $s --live
  done
fi

# 3. Where the pipelines spend their time: separate runs under the nnsprofile tracer
#    (docs/profiler.md), reported by nns-profile (text table, HTML, JSON) and report.py.
#    Kept apart from the measurements above so the tracer's own cost does not enter them.
profile() {
  local tag=$1
  shift
  mkdir -p "$OUT/profile"
  echo "$NNS_TAG: profile $tag" >&2
  GST_TRACERS="nnsprofile(file=$OUT/profile/$tag.trace.json,interval=0)" \
    taskset -c "$CPUS" "$BIN" --mode nns --models "$MODELS" --inputs "$OUT/inputs" \
    --ort-threads "$ORT_THREADS" "$@" >/dev/null ||
    nns_die 1 "profiled run $tag failed"
  "$BUILD_DIR/tools/nns-profile" --from "$OUT/profile/$tag.trace.json" \
    --html "$OUT/profile/$tag.html" --json "$OUT/profile/$tag.json" \
    >"$OUT/profile/$tag.txt" 2>/dev/null || nns_die 1 "nns-profile failed on $tag"
}
if [[ -x $BUILD_DIR/tools/nns-profile ]]; then
  profile e3 --exp e3
  if ((!smoke)); then
    profile e1 --exp e1 --config fast,mid,slow --frames 100
    profile e2 --exp e2
    profile e4-320 --exp e4 --config 320
  fi
else
  echo "$NNS_TAG: $BUILD_DIR/tools/nns-profile not built: no per-element profile" >&2
fi

$PY "$HERE/report.py" plot "$RES" "$OUT" || nns_die 1 "report.py plot failed"
if ((docs)); then
  mkdir -p "$ROOT/docs/paper"
  cp "$OUT"/e[1-4].png "$OUT/tables.md" "$ROOT/docs/paper/"
  for f in "$OUT"/profile/*.txt; do
    [[ -f $f ]] && sed "s|$OUT/||g" "$f" >"$ROOT/docs/paper/$(basename "$f")"
  done
  echo "$NNS_TAG: figures and tables copied to docs/paper/"
fi
echo "$NNS_TAG: done: $(wc -l <"$RES") runs, figures $OUT/e1.png .. e4.png, tables $OUT/tables.md"
