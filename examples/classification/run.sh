#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Image classification with gst-launch-1.0: MobileNet v2 (ONNX, through tensor_filter
# framework=onnxruntime) on a picture, tensor_decoder mode=image_labeling prints the label.
#
# usage: examples/classification/run.sh [picture.png]   (default: the shared orange.png)
# env:   NNS_BUILD_DIR (build), NNS_SHARED_DIR (../shared next to the worktree),
#        NNS_SKIP_MISSING=1: exit 77 instead of 1 when the model, picture or the onnxruntime
#        back end is unavailable (ctest).
# exit:  0 ok (the label is printed on stdout), 77 skipped, other = failure.
set -euo pipefail
missing=1
[[ -z ${NNS_SKIP_MISSING:-} ]] || missing=77
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BUILD_DIR=${NNS_BUILD_DIR:-$ROOT/build}
SHARED=${NNS_SHARED_DIR:-$ROOT/../shared}/models/upstream
MODEL=$SHARED/models/mobilenet_v2_quant.onnx
# The 1000 ImageNet labels (no background line): made by the build from $SHARED/labels/labels.txt.
LABELS=$BUILD_DIR/data/imagenet_labels_1000.txt
PICTURE=${1:-$SHARED/data/orange.png}

[[ -f $BUILD_DIR/env.sh ]] || {
  echo "classification: $BUILD_DIR/env.sh missing; build the project first" >&2
  exit 1
}
for f in "$MODEL" "$PICTURE"; do
  [[ -f $f ]] || {
    echo "classification: $f not found" >&2
    exit $missing
  }
done
[[ -f $LABELS ]] || {
  echo "classification: $LABELS not generated (cmake makes it when $SHARED/labels/labels.txt" \
    "exists; re-run cmake and build)" >&2
  exit 1
}
[[ -f $BUILD_DIR/subplugins/filters/libnnstreamer_filter_onnxruntime.so ]] || {
  echo "classification: onnxruntime filter back end not built (scripts/deps/onnxruntime.npm)" >&2
  exit $missing
}

# shellcheck source=/dev/null
. "$BUILD_DIR/env.sh"
export GST_REGISTRY=${GST_REGISTRY:-$BUILD_DIR/gst-registry.bin}
out=$(mktemp)
trap 'rm -f "$out"' EXIT
# The model (a PyTorch export) takes float32 NCHW 1x3x224x224 (NNStreamer dims 224:224:3:1)
# with torchvision's ImageNet normalisation (x / 255 - mean) / std per channel, mean 0.485,
# 0.456, 0.406, std 0.229, 0.224, 0.225, written as (x - 255 mean) / (255 std). The converter
# gives 3:224:224:1 (RGB interleaved): per-channel arithmetic on dim 0, then transpose moves the
# channels outwards.
case $PICTURE in
  *.png) dec=pngdec ;;
  *) dec=decodebin ;;
esac
gst-launch-1.0 -q filesrc location="$PICTURE" ! $dec ! videoconvert ! videoscale ! \
  video/x-raw,format=RGB,width=224,height=224 ! tensor_converter ! \
  tensor_transform mode=arithmetic \
  option=typecast:float32,per-channel:true@0,add:-123.675@0,add:-116.280@1,add:-103.530@2,div:58.3950@0,div:57.1200@1,div:57.3750@2 ! \
  tensor_transform mode=transpose option=1:2:0:3 ! \
  tensor_filter framework=onnxruntime model="$MODEL" ! \
  tensor_decoder mode=image_labeling option1="$LABELS" ! \
  filesink location="$out"
label=$(cat "$out")
[[ -n $label ]] || {
  echo "classification: no label came out of the pipeline" >&2
  exit 1
}
echo "$label"
