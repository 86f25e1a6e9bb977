#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Semantic segmentation with gst-launch-1.0: DeepLab v3 (deeplabv3_257_mv_gpu.tflite, PASCAL VOC
# classes) through tensor_filter framework=armnn (CpuRef), tensor_decoder mode=image_segment
# paints the classes, compositor lays the mask over the photo, pngenc writes the result.
#
# usage: examples/segmentation/run.sh [photo.png]
# env:   NNS_BUILD_DIR (build), NNS_SHARED_DIR (../shared next to the worktree),
#        NNS_SEG_OUTPUT (build/demo/segmentation.png),
#        NNS_SEG_MASK: also write the decoder's raw RGBA mask (257x257) to this file,
#        NNS_SKIP_MISSING=1: exit 77 instead of 1 when the model, photo or armnn back end is
#        unavailable (ctest).
# Photo: the argument (PNG), or skimage's astronaut.png from Debian's python3-skimage package
# (apt-get download + dpkg -x into third_party/demo/, nothing installed).
# exit:  0 ok, 77 skipped, other = failure.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init segmentation NNS_SKIP_MISSING
SHARED=${NNS_SHARED_DIR:-$ROOT/../shared}/models/upstream
MODEL=$SHARED/models/deeplabv3_257_mv_gpu.tflite

[[ -f $BUILD_DIR/env.sh ]] || nns_die 1 "$BUILD_DIR/env.sh missing; build the project first"
[[ -f $MODEL ]] || nns_die $missing "$MODEL not found"
[[ -f $BUILD_DIR/subplugins/filters/libnnstreamer_filter_armnn.so ]] ||
  nns_die $missing "armnn filter back end not built (scripts/deps/armnn.apt)"

photo=${1:-}
[[ -n $photo ]] || photo=$(nns_fetch_astronaut "") || exit $missing
[[ -f $photo ]] || nns_die 1 "photo '$photo' not found"
# Width and height from the PNG header (IHDR, big-endian, bytes 16..23).
[[ $(head -c 8 "$photo" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] ||
  nns_die 1 "'$photo' is not a PNG file"
read -r width height < <(od -An -tu1 -j16 -N8 "$photo" |
  awk '{print $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8}')
out=${NNS_SEG_OUTPUT:-$BUILD_DIR/demo/segmentation.png}
mkdir -p "$(dirname "$out")"
mask_branch=()
if [[ -n ${NNS_SEG_MASK:-} ]]; then
  mask_branch=(m. ! queue ! filesink location="$NNS_SEG_MASK")
fi

nns_enter_build_env
# The model takes float32 1:257:257:3 in [-1, 1] and gives 21 class scores per pixel.
start=$(date +%s.%N)
gst-launch-1.0 -q filesrc location="$photo" ! pngdec ! imagefreeze num-buffers=1 ! videoconvert ! tee name=t \
  t. ! queue ! videoscale ! video/x-raw,format=RGB,width=257,height=257 ! tensor_converter ! \
  tensor_transform mode=arithmetic option=typecast:float32,div:127.5,add:-1 ! \
  tensor_filter framework=armnn model="$MODEL" ! \
  tensor_decoder mode=image_segment option1=tflite-deeplab ! tee name=m \
  m. ! queue ! mix.sink_1 \
  t. ! queue ! mix.sink_0 \
  compositor name=mix sink_0::zorder=0 sink_1::zorder=1 sink_1::alpha=0.6 sink_1::width="$width" sink_1::height="$height" ! \
  videoconvert ! pngenc ! filesink location="$out" \
  "${mask_branch[@]}"
end=$(date +%s.%N)
echo "photo: $photo (${width}x${height}), pipeline $(awk -v a="$start" -v b="$end" \
  'BEGIN{printf "%.1f", b-a}') s"
echo "segmentation drawn into $out"
