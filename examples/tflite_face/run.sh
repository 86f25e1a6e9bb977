#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Face detection with MediaPipe's own TensorFlow Lite BlazeFace (face_detection_short_range,
# fp16 weights expanded by DEQUANTIZE) through tensor_filter framework=tensorflow-lite;
# tensor_decoder mode=bounding_boxes option1=mp-palm-detection decodes its 896 anchors and draws
# the box over the photo into build/demo/tflite_face.png. Same network as
# examples/face_demo (the ONNX conversion): the box must match that demo's.
#
# usage: examples/tflite_face/run.sh [photo.png]   (default: skimage's astronaut.png)
# env:   NNS_BUILD_DIR (build), NNS_SHARED_DIR (../shared next to the worktree),
#        NNS_TFLITE_FRAMEWORK (tensor_filter framework=, default tensorflow-lite),
#        NNS_TFLITE_FACE_OUTPUT (the picture written), NNS_SKIP_MISSING=1: exit 77 instead of 1
#        when the model, the photo or a back end that opens the model is unavailable (ctest).
# exit:  0 ok (the boxes are printed), 77 skipped, other = failure.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init tflite_face NNS_SKIP_MISSING
FRAMEWORK=${NNS_TFLITE_FRAMEWORK:-tensorflow-lite}
MODEL=${NNS_SHARED_DIR:-$ROOT/../shared}/models/tflite/face_detection_short_range.tflite

[[ -f $BUILD_DIR/env.sh ]] || nns_die 1 "$BUILD_DIR/env.sh missing; build the project first"
for f in "$MODEL" "$BUILD_DIR/subplugins/decoders/libnnstreamer_decoder_bounding_boxes.so"; do
  [[ -f $f ]] || nns_die "$missing" "$f not found"
done
nns_demo_photo "${1:-}"
out=${NNS_TFLITE_FACE_OUTPUT:-$BUILD_DIR/demo/tflite_face.png}
mkdir -p "$(dirname "$out")"

nns_enter_build_env
echo "photo: $photo (${width}x${height})"
# Input float32 RGB 128x128 in [-1,1] (dims 3:128:128:1). Outputs: regressors 16:896:1 (box
# centre x, y, size w, h, then 6 keypoints, in input pixels from the anchor centres) and
# classificators 1:896:1 (logits). option3: score threshold 0.5, MediaPipe's 4-layer anchors
# (strides 8,16,16,16, fixed size), `xy/` = MediaPipe's x,y,w,h order; option5: model input.
nns_launch_tflite_overlay "$photo" "$out" \
  videoconvert ! videoscale ! video/x-raw,format=RGB,width=128,height=128 ! tensor_converter ! \
  tensor_transform mode=arithmetic option=typecast:float32,div:127.5,add:-1 ! \
  tensor_filter framework="$FRAMEWORK" model="$MODEL" ! \
  tensor_decoder mode=bounding_boxes option1=mp-palm-detection \
  option3=xy/0.5:4:1.0:1.0:0.5:0.5:8:16:16:16 option4="$width:$height" option5=128:128 option7=1
echo "boxes drawn into $out"
