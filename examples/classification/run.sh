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
LABELS=$SHARED/labels/labels.txt
PICTURE=${1:-$SHARED/data/orange.png}

[[ -f $BUILD_DIR/env.sh ]] || {
  echo "classification: $BUILD_DIR/env.sh missing; build the project first" >&2
  exit 1
}
for f in "$MODEL" "$LABELS" "$PICTURE"; do
  [[ -f $f ]] || {
    echo "classification: $f not found" >&2
    exit $missing
  }
done
[[ -f $BUILD_DIR/subplugins/filters/libnnstreamer_filter_onnxruntime.so ]] || {
  echo "classification: onnxruntime filter back end not built (scripts/deps/onnxruntime.npm)" >&2
  exit $missing
}

# shellcheck source=/dev/null
. "$BUILD_DIR/env.sh"
export GST_REGISTRY=${GST_REGISTRY:-$BUILD_DIR/gst-registry.bin}
out=$(mktemp)
trap 'rm -f "$out"' EXIT
# The model takes float32 NCHW 1:3:224:224 in [-1, 1] (NNStreamer dims 224:224:3:1): the
# converter gives 3:224:224:1 (RGB interleaved), transpose moves the channels outwards.
case $PICTURE in
  *.png) dec=pngdec ;;
  *) dec=decodebin ;;
esac
gst-launch-1.0 -q filesrc location="$PICTURE" ! $dec ! videoconvert ! videoscale ! \
  video/x-raw,format=RGB,width=224,height=224 ! tensor_converter ! \
  tensor_transform mode=transpose option=1:2:0:3 ! \
  tensor_transform mode=arithmetic option=typecast:float32,div:127.5,add:-1 ! \
  tensor_filter framework=onnxruntime model="$MODEL" ! \
  tensor_decoder mode=image_labeling option1="$LABELS" ! \
  filesink location="$out"
label=$(cat "$out")
[[ -n $label ]] || {
  echo "classification: no label came out of the pipeline" >&2
  exit 1
}
echo "$label"
