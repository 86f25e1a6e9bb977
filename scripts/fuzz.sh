#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Builds the libFuzzer targets of fuzz/ with clang++ (ASan + UBSan) and runs each of them on a
# generated seed corpus. Exits non-zero when a target finds a crash, leak, UB or broken property
# (the reproducer is kept in $NNS_FUZZ_DIR/artifacts/). See docs/fuzzing.md.
#
# usage: scripts/fuzz.sh [target ...]     smoke run (default: every target): replays the stored
#                                         corpus (fuzz/corpus/, fuzz/regressions/), then fuzzes
#        scripts/fuzz.sh --campaign SECONDS [target ...]
#                                         SECONDS per target, one after the other, under
#                                         nice -n $NNS_FUZZ_NICE (19); afterwards the target's
#                                         corpus is minimized (-merge=1) into fuzz/corpus/<t>/
#                                         (tflite_model: kept in $NNS_FUZZ_DIR, its inputs derive
#                                         from ../shared/models) and its figures go to
#                                         $NNS_FUZZ_DIR/campaign/<t>.txt
# env:   NNS_FUZZ_SECONDS   smoke run: total run time shared by the targets (default 180)
#        NNS_FUZZ_DIR       build folder (default build-fuzz/ beside build/)
#        NNS_JOBS           build jobs (default 2)
#        CXX                clang++ to use (default clang++)
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
DIR=${NNS_FUZZ_DIR:-$ROOT/build-fuzz}
TOTAL=${NNS_FUZZ_SECONDS:-180}
JOBS=${NNS_JOBS:-2}
CLANG=${CXX:-clang++}
[[ $CLANG == *clang++* ]] || CLANG=clang++
ALL=(wire_protobuf wire_flatbuf wire_flexbuf meta_header iio_channel edge_frame mqtt_message
  edge_data tflite_model)
CAMPAIGN=0
if [[ ${1:-} == --campaign ]]; then
  CAMPAIGN=${2:?--campaign needs the seconds per target}
  shift 2
fi
TARGETS=("${@:-${ALL[@]}}")
[[ $# -gt 0 ]] || TARGETS=("${ALL[@]}")

say() { printf '[fuzz] %s\n' "$*"; }

command -v "$CLANG" >/dev/null || { say "clang++ not found"; exit 2; }
mkdir -p "$DIR"
if [[ ! -f $DIR/CMakeCache.txt ]]; then
  cmake -S "$ROOT/fuzz" -B "$DIR" -DCMAKE_CXX_COMPILER="$CLANG" -DCMAKE_BUILD_TYPE=None \
    >"$DIR/configure.log" 2>&1 || { tail -n 30 "$DIR/configure.log"; exit 1; }
fi
cmake --build "$DIR" -j"$JOBS" >"$DIR/build.log" 2>&1 || {
  grep -E -A5 'error' "$DIR/build.log" | head -n 60
  say "build failed (log: $DIR/build.log)"
  exit 1
}

# Seeds: regenerated every run (cheap), kept apart from what the fuzzer adds.
rm -rf "$DIR/seeds"
"$DIR/nns_fuzz_corpus" "$DIR/seeds" >/dev/null
# tflite_model: the small real models of ../shared/models when present (never copied into git).
mkdir -p "$DIR/seeds/tflite_model"
for f in "$ROOT"/../shared/models/upstream/models/{add,simple_32_in_32_out}.tflite \
  "$ROOT"/../shared/models/tflite/{hello_world_float,hello_world_int8,micro_speech_quantized}.tflite; do
  if [[ -f $f ]]; then cp "$f" "$DIR/seeds/tflite_model/"; fi
done
# Regression inputs of fixed bugs (tiny, in git) and the stored corpus of the last campaign
# (minimized, in git): every run replays them first, so a fixed finding that comes back fails.
for t in "${ALL[@]}"; do
  for d in "$ROOT/fuzz/regressions/$t" "$ROOT/fuzz/corpus/$t"; do
    if [[ -d $d ]]; then cp "$d"/* "$DIR/seeds/$t/" 2>/dev/null || true; fi
  done
done
mkdir -p "$DIR/artifacts"

# libFuzzer's closing figures: "<executions> <cov> <ft> <corpus>" of a log.
figures() {
  local execs cov ft corp
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$1" | tail -n 1)
  cov=$(grep -oE ' cov: [0-9]+' "$1" | tail -n 1 | tr -dc 0-9)
  ft=$(grep -oE ' ft: [0-9]+' "$1" | tail -n 1 | tr -dc 0-9)
  corp=$(grep -oE ' corp: [0-9]+' "$1" | tail -n 1 | tr -dc 0-9)
  echo "${execs:-?} ${cov:-?} ${ft:-?} ${corp:-?}"
}

if ((CAMPAIGN)); then
  status=0
  mkdir -p "$DIR/campaign"
  for t in "${TARGETS[@]}"; do
    exe=$DIR/fuzz_$t
    [[ -x $exe ]] || { say "unknown target $t"; status=1; continue; }
    work=$DIR/campaign/$t
    mkdir -p "$work"
    say "$t: campaign of ${CAMPAIGN}s (nice ${NNS_FUZZ_NICE:-19}), load: $(cut -d' ' -f1-3 /proc/loadavg)"
    t0=$(date +%s)
    rc=0
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
      nice -n "${NNS_FUZZ_NICE:-19}" "$exe" "$work" "$DIR/seeds/$t" -max_total_time="$CAMPAIGN" \
      -rss_limit_mb=1024 -max_len=65536 -timeout=10 -print_final_stats=1 \
      -artifact_prefix="$DIR/artifacts/$t-" >"$DIR/campaign/$t.log" 2>&1 || rc=$?
    read -r execs cov ft corp < <(figures "$DIR/campaign/$t.log")
    # Minimize what the campaign has (its corpus, the seeds) into the stored corpus.
    rm -rf "$work.min" && mkdir -p "$work.min"
    nice -n "${NNS_FUZZ_NICE:-19}" "$exe" -merge=1 "$work.min" "$work" "$DIR/seeds/$t" \
      -max_len=65536 -timeout=10 -rss_limit_mb=1024 >"$DIR/campaign/$t.merge.log" 2>&1 || true
    # tflite_model's inputs are (mutated) real models of ../shared/models: never into git.
    store=$ROOT/fuzz/corpus/$t
    [[ $t == tflite_model ]] && store=$DIR/campaign/$t.stored
    rm -rf "$store" && mkdir -p "$store"
    cp "$work.min"/* "$store/" 2>/dev/null || true
    n=$(find "$store" -type f | wc -l)
    kb=$(du -sk --apparent-size "$store" | cut -f1)
    line="$t: $(($(date +%s) - t0))s, exit $rc, $execs executions, cov $cov, ft $ft, corpus $corp -> $n files ($kb KiB) stored in ${store#"$ROOT"/}, load: $(cut -d' ' -f1-3 /proc/loadavg)"
    echo "$line" | tee "$DIR/campaign/$t.txt" | sed 's/^/[fuzz] /'
    if ((rc)); then
      tail -n 40 "$DIR/campaign/$t.log"
      say "FINDING in $t (reproducer in $DIR/artifacts/, log $DIR/campaign/$t.log)"
      status=1
    fi
  done
  exit $status
fi

per=$((TOTAL / ${#TARGETS[@]}))
((per >= 1)) || per=1
status=0
for t in "${TARGETS[@]}"; do
  exe=$DIR/fuzz_$t
  [[ -x $exe ]] || { say "unknown target $t"; status=1; continue; }
  mkdir -p "$DIR/corpus/$t"
  say "$t: ${per}s"
  # -rss_limit_mb: the decoders must not need more than a few hundred MB for any input.
  if ! ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "$exe" "$DIR/corpus/$t" "$DIR/seeds/$t" -max_total_time="$per" -rss_limit_mb=1024 \
    -max_len=65536 -timeout=10 -print_final_stats=1 -artifact_prefix="$DIR/artifacts/$t-" \
    >"$DIR/$t.log" 2>&1; then
    tail -n 40 "$DIR/$t.log"
    say "FAILED: $t (reproducer in $DIR/artifacts/, log $DIR/$t.log)"
    status=1
  else
    grep -E '^stat::number_of_executed_units|^#[0-9]+.*DONE' "$DIR/$t.log" | tail -n 2 |
      sed "s/^/[fuzz] $t: /"
  fi
done
exit $status
