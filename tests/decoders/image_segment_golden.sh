#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Upstream's image_segment golden (tests/nnstreamer_decoder_image_segment): one videotestsrc
# frame through deeplabv3_257_mv_gpu.tflite (here on tensor_filter framework=armnn),
# tensor_decoder mode=image_segment option1=tflite-deeplab, blended over the frame by
# videomixer; the output must equal test_golden.0 byte for byte. (The model finds no object in
# the test pattern, so the mask is all transparent and the colours do not enter the golden.)
# usage: image_segment_golden.sh BUILD_DIR SHARED_DIR   exit 77 when something is missing.
set -euo pipefail
BUILD_DIR=$1
SHARED=$2/models/upstream
MODEL=$SHARED/models/deeplabv3_257_mv_gpu.tflite
GOLDEN=$SHARED/decoder/nnstreamer_decoder_image_segment/test_golden.0
for f in "$MODEL" "$GOLDEN" "$BUILD_DIR/subplugins/filters/libnnstreamer_filter_armnn.so"; do
  [[ -f $f ]] || {
    echo "skipped: $f not found"
    exit 77
  }
done
gst-inspect-1.0 videomixer >/dev/null 2>&1 || {
  echo "skipped: videomixer (gstreamer1.0-plugins-good) missing"
  exit 77
}
# shellcheck source=/dev/null
. "$BUILD_DIR/env.sh"
export GST_REGISTRY=${GST_REGISTRY:-$BUILD_DIR/gst-registry.bin}
out=$(mktemp)
trap 'rm -f "$out"' EXIT
gst-launch-1.0 -q videotestsrc num-buffers=1 ! videoconvert ! videoscale ! \
  video/x-raw,format=RGB,width=257,height=257 ! tee name=t t. ! queue ! mix. \
  t. ! queue ! tensor_converter ! \
  tensor_transform mode=arithmetic option=typecast:float32,div:255.0 ! \
  tensor_filter framework=armnn model="$MODEL" ! \
  tensor_decoder mode=image_segment option1=tflite-deeplab ! mix. \
  videomixer name=mix sink_0::alpha=0.7 sink_1::alpha=0.6 ! filesink location="$out"
cmp "$out" "$GOLDEN"
echo "output equals $GOLDEN"
