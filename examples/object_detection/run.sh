#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Object detection with a TensorFlow Lite SSD: COCO SSD MobileNet v1 quant, whose graph ends in
# TFLite_Detection_PostProcess, through tensor_filter framework=tensorflow-lite; its four
# outputs are drawn over each photo by tensor_decoder mode=bounding_boxes
# option1=mobilenet-ssd-postprocess into build/demo/object_detection_<photo>.png.
#
# usage: examples/object_detection/run.sh [photo.png ...]
#        (default: the shared orange.png and skimage's astronaut.png)
# env:   NNS_BUILD_DIR (build), NNS_SHARED_DIR (../shared next to the worktree),
#        NNS_TFLITE_FRAMEWORK (tensor_filter framework=, default tensorflow-lite),
#        NNS_DETECT_OUTPUT_DIR (default build/demo), NNS_SKIP_MISSING=1: exit 77 instead of 1
#        when the model, a photo or a back end that opens the model is unavailable (ctest).
# exit:  0 ok (the boxes of each photo are printed), 77 skipped, other = failure.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init object_detection NNS_SKIP_MISSING
FRAMEWORK=${NNS_TFLITE_FRAMEWORK:-tensorflow-lite}
SHARED=${NNS_SHARED_DIR:-$ROOT/../shared}/models
MODEL=$SHARED/tflite/coco_ssd_mobilenet_quant.tflite
LABELMAP=$SHARED/tflite/coco_ssd_mobilenet_quant_labelmap.txt

[[ -f $BUILD_DIR/env.sh ]] || nns_die 1 "$BUILD_DIR/env.sh missing; build the project first"
for f in "$MODEL" "$LABELMAP" "$BUILD_DIR/subplugins/decoders/libnnstreamer_decoder_bounding_boxes.so"; do
  [[ -f $f ]] || nns_die "$missing" "$f not found"
done
photos=("$@")
if ((${#photos[@]} == 0)); then
  photos=("$SHARED/upstream/data/orange.png")
  astronaut=$(nns_fetch_astronaut "") || nns_die "$missing" "astronaut.png unavailable"
  photos+=("$astronaut")
fi
outdir=${NNS_DETECT_OUTPUT_DIR:-$BUILD_DIR/demo}
mkdir -p "$outdir"

nns_enter_build_env
# The model's classes are 0-based COCO ids without the background; the label map starts with
# "???" for the background: drop that line so label c is line c.
labels=$(mktemp)
trap 'rm -f "$labels"' EXIT
tail -n +2 "$LABELMAP" >"$labels"
for photo in "${photos[@]}"; do
  nns_demo_photo "$photo"
  name=$(basename "$photo" .png)
  out=$outdir/object_detection_$name.png
  echo "photo: $photo (${width}x${height})"
  # Input uint8 RGB 300x300 (dims 3:300:300:1); outputs: boxes 4:10:1, classes 10:1,
  # scores 10:1, count 1 (float32). option3 maps them (LOC:CLASS:SCORE:NUM) and keeps scores
  # above 50 %; boxes are computed in 300x300 pixels (option5) and drawn at the photo's size
  # (option4) on a transparent layer that compositor lays over the photo.
  nns_launch_tflite_overlay "$photo" "$out" \
    videoconvert ! videoscale ! video/x-raw,format=RGB,width=300,height=300 ! tensor_converter ! \
    tensor_filter framework="$FRAMEWORK" model="$MODEL" ! \
    tensor_decoder mode=bounding_boxes option1=mobilenet-ssd-postprocess option2="$labels" \
    option3=0:1:2:3,50 option4="$width:$height" option5=300:300 option7=1
  echo "boxes drawn into $out"
done
