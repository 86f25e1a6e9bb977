#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Pose estimation with a TensorFlow Lite model: MoveNet SinglePose Lightning (int8 PTQ) through
# tensor_filter framework=tensorflow-lite; tensor_decoder mode=pose_estimation option4=keypoints
# draws its 17 keypoints and the skeleton over the photo into build/demo/pose.png.
#
# usage: examples/pose/run.sh [photo.png]   (default: skimage's astronaut.png)
# env:   NNS_BUILD_DIR (build), NNS_SHARED_DIR (../shared next to the worktree),
#        NNS_TFLITE_FRAMEWORK (tensor_filter framework=, default tensorflow-lite),
#        NNS_POSE_OUTPUT (the picture written), NNS_POSE_LAYER (also write the decoder's RGBA
#        layer there, raw, photo-sized: examples/pose/check_pose.py reads it),
#        NNS_SKIP_MISSING=1: exit 77 instead of 1 when the model, the photo or a back end that
#        opens the model is unavailable (ctest).
# exit:  0 ok, 77 skipped, other = failure.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init pose NNS_SKIP_MISSING
FRAMEWORK=${NNS_TFLITE_FRAMEWORK:-tensorflow-lite}
MODEL=${NNS_SHARED_DIR:-$ROOT/../shared}/models/tflite/movenet_single_pose_lightning_ptq.tflite

[[ -f $BUILD_DIR/env.sh ]] || nns_die 1 "$BUILD_DIR/env.sh missing; build the project first"
for f in "$MODEL" "$BUILD_DIR/subplugins/decoders/libnnstreamer_decoder_pose_estimation.so"; do
  [[ -f $f ]] || nns_die "$missing" "$f not found"
done
nns_demo_photo "${1:-}"
out=${NNS_POSE_OUTPUT:-$BUILD_DIR/demo/pose.png}
mkdir -p "$(dirname "$out")"
if [[ -n ${NNS_POSE_LAYER:-} ]]; then
  nns_overlay_extra=(l. ! queue ! filesink location="$NNS_POSE_LAYER")
fi

nns_enter_build_env
echo "photo: $photo (${width}x${height})"
# Input: raw uint8 RGB 192x192 (dims 3:192:192:1; the model casts it itself). Output float32
# 3:17:1:1 = (y, x, score) per keypoint, normalized: option4=keypoints places them on the
# photo-sized layer (option1); keypoints scoring >= 0.3 (option5, the threshold of TF's MoveNet
# examples) are drawn, with the 17-point COCO skeleton.
nns_launch_tflite_overlay "$photo" "$out" \
  videoconvert ! videoscale ! video/x-raw,format=RGB,width=192,height=192 ! tensor_converter ! \
  tensor_filter framework="$FRAMEWORK" model="$MODEL" ! \
  tensor_decoder mode=pose_estimation option1="$width:$height" option4=keypoints option5=0.3 ! \
  tee name=l l. ! queue
echo "keypoints drawn into $out"
