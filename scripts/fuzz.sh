#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Builds the libFuzzer targets of fuzz/ with clang++ (ASan + UBSan) and runs each of them on a
# generated seed corpus. Exits non-zero when a target finds a crash, leak, UB or broken property
# (the reproducer is kept in $NNS_FUZZ_DIR/artifacts/). See docs/fuzzing.md.
#
# usage: scripts/fuzz.sh [target ...]     (default: every target)
# env:   NNS_FUZZ_SECONDS   total run time shared by the targets (default 180)
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
# Regression inputs of fixed bugs (tiny, in git).
for t in "${ALL[@]}"; do
  if [[ -d $ROOT/fuzz/regressions/$t ]]; then
    cp "$ROOT/fuzz/regressions/$t"/* "$DIR/seeds/$t/" 2>/dev/null || true
  fi
done

per=$((TOTAL / ${#TARGETS[@]}))
((per >= 1)) || per=1
mkdir -p "$DIR/artifacts"
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
