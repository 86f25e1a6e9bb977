#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Image classification with a TensorFlow Lite model: MobileNet v2 1.0 224 quant (uint8, 1001
# classes) through tensor_filter framework=tensorflow-lite; tensor_decoder mode=image_labeling
# gives the label, textoverlay writes it over the photo into build/demo/tflite_classification.png.
#
# usage: examples/tflite_classification/run.sh [picture.png]   (default: the shared orange.png)
# env:   NNS_BUILD_DIR (build), NNS_SHARED_DIR (../shared next to the worktree),
#        NNS_TFLITE_FRAMEWORK (tensor_filter framework=, default tensorflow-lite),
#        NNS_TFLITE_CLS_OUTPUT (the picture written), NNS_SKIP_MISSING=1: exit 77 instead of 1
#        when the model, the picture or a back end that opens the model is unavailable (ctest).
# exit:  0 ok (the label is printed on stdout), 77 skipped, other = failure.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init tflite_classification NNS_SKIP_MISSING
FRAMEWORK=${NNS_TFLITE_FRAMEWORK:-tensorflow-lite}
SHARED=${NNS_SHARED_DIR:-$ROOT/../shared}/models/upstream
MODEL=$SHARED/models/mobilenet_v2_1.0_224_quant.tflite
LABELS=$SHARED/labels/labels.txt # 1001 lines, line 0 "background": the model's own order
PICTURE=${1:-$SHARED/data/orange.png}

[[ -f $BUILD_DIR/env.sh ]] || nns_die 1 "$BUILD_DIR/env.sh missing; build the project first"
for f in "$MODEL" "$LABELS" "$PICTURE"; do
  [[ -f $f ]] || nns_die "$missing" "$f not found"
done
gst-inspect-1.0 textoverlay >/dev/null 2>&1 ||
  nns_die "$missing" "GStreamer element textoverlay missing (Debian gstreamer1.0-x)"
out=${NNS_TFLITE_CLS_OUTPUT:-$BUILD_DIR/demo/tflite_classification.png}
mkdir -p "$(dirname "$out")"

nns_enter_build_env
label_file=$(mktemp)
trap 'rm -f "$label_file"' EXIT
case $PICTURE in
  *.png) dec=pngdec ;;
  *) dec=decodebin ;;
esac
# The model takes uint8 RGB 224x224 (NNStreamer dims 3:224:224:1, quantized with scale 1/128,
# zero point 128: the raw pixels are its input) and gives uint8 scores of the 1001 classes.
nns_launch_tflite \
  filesrc location="$PICTURE" ! $dec ! videoconvert ! imagefreeze num-buffers=1 ! tee name=t \
  t. ! queue ! videoscale ! video/x-raw,format=RGB,width=224,height=224 ! tensor_converter ! \
  tensor_filter framework="$FRAMEWORK" model="$MODEL" ! \
  tensor_decoder mode=image_labeling option1="$LABELS" ! tee name=l \
  l. ! queue ! filesink location="$label_file" \
  l. ! queue ! ov.text_sink \
  t. ! queue ! ov.video_sink \
  textoverlay name=ov font-desc="Sans Bold 28" valignment=top halignment=left \
  ! videoconvert ! pngenc ! filesink location="$out"
label=$(cat "$label_file")
[[ -n $label ]] || nns_die 1 "no label came out of the pipeline"
echo "$label"
echo "label written over the picture into $out" >&2
