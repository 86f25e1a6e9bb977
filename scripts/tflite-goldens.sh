#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-only
# Remakes the TensorFlow Lite golden outputs of tests/data/tflite (README.md there) with
# TensorFlow Lite itself: the WebAssembly build in npm's @tensorflow/tfjs-tflite, installed into
# a temporary folder (needs node and npm; not part of the build or of CI: the goldens are
# committed). Run from anywhere; needs ../shared/models/{tflite,upstream} and /usr/bin/python3
# with numpy and flatbuffers.
#   scripts/tflite-goldens.sh [shared models/tflite dir]
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
models=${1:-${NNS_SHARED_DIR:-$src/../shared}/models/tflite}
upstream=$models/../upstream
out=$src/tests/data/tflite
tools=$src/tests/tools
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

(cd "$tmp" && npm init -y >/dev/null &&
  npm install --prefer-offline --silent @tensorflow/tfjs-tflite@0.0.1-alpha.10 @tensorflow/tfjs-core@4.9.0 >/dev/null)
tfl=$tmp/node_modules/@tensorflow/tfjs-tflite
run() { node "$tools/tflite_reference.js" "$tfl" "$@" 2> >(grep -v '^INFO:' >&2); }

rgb=$out/astronaut_192x192.rgb
# Palm detection: RGB / 255 as float32.
/usr/bin/python3 -c "import numpy as n,sys; (n.fromfile(sys.argv[1],n.uint8).astype(n.float32)/n.float32(255)).tofile(sys.argv[2])" \
  "$rgb" "$tmp/palm_in.raw"
run "$models/palm_detection_lite.tflite" "$out/palm_astronaut" "$tmp/palm_in.raw"

# BlazeFace short range: the centre 128x128 of the photo, RGB / 127.5 - 1 as float32.
/usr/bin/python3 -c "import numpy as n,sys; x=n.fromfile(sys.argv[1],n.uint8).reshape(192,192,3)[32:160,32:160]; (x.astype(n.float32)/n.float32(127.5)-n.float32(1)).tofile(sys.argv[2])" \
  "$rgb" "$tmp/face_in.raw"
run "$models/face_detection_short_range.tflite" "$out/blazeface_astronaut_crop" "$tmp/face_in.raw"

# MoveNet: keypoints on the photo; and tensor 201 (the FPN's conv2d_2 output, after 28 of the
# 157 operators) on the photo with the bytes that make a rounding tie in the input scaling
# moved by one (tflite_reference_test.cc, movenet_tie_free).
run "$models/movenet_single_pose_lightning_ptq.tflite" "$out/movenet_astronaut" "$rgb"
/usr/bin/python3 "$tools/tflite_patch.py" output "$models/movenet_single_pose_lightning_ptq.tflite" \
  "$tmp/movenet_t201.tflite" 201
/usr/bin/python3 - "$rgb" "$tmp/tie_free.rgb" <<'PY'
import sys, numpy as n
x = n.fromfile(sys.argv[1], n.uint8)
ties = set(range(32, 47, 2)) | set(range(176, 191, 2)) | {255}
y = x.copy()
for v in ties:
    y[x == v] = v - 1 if v == 255 else v + 1
y.tofile(sys.argv[2])
PY
run "$tmp/movenet_t201.tflite" "$out/movenet_tie_free_t201" "$tmp/tie_free.rgb"
# MoveNet's input scaling (tensor 178, after CAST, QUANTIZE, SUB, MUL, SUB) on every byte value:
# an input whose bytes count 0..255 over and over; the first 256 outputs are kept.
/usr/bin/python3 "$tools/tflite_patch.py" output "$models/movenet_single_pose_lightning_ptq.tflite" \
  "$tmp/movenet_t178.tflite" 178
/usr/bin/python3 -c "import numpy as n,sys; (n.arange(192*192*3)%256).astype(n.uint8).tofile(sys.argv[1])" "$tmp/ramp.raw"
run "$tmp/movenet_t178.tflite" "$tmp/movenet_ramp_t178" "$tmp/ramp.raw"
head -c 256 "$tmp/movenet_ramp_t178.0.raw" >"$out/movenet_ramp_t178.raw"

# person_detect: TFLite refuses its 1-D biases quantized along axis 3; the copy says axis 0.
/usr/bin/python3 "$tools/tflite_patch.py" unaxis-bias "$models/person_detect.tflite" "$tmp/pd.tflite"
for f in person no_person; do
  run "$tmp/pd.tflite" "$out/person_detect_$f" "$models/data/${f}_96x96_int8.raw"
done

# MobileNet v2 quant on upstream's orange.raw (224x224 RGB uint8): the 1001 uint8 scores.
run "$upstream/models/mobilenet_v2_1.0_224_quant.tflite" "$out/mobilenet_v2_quant_orange" \
  "$upstream/data/orange.raw"

# DeepLab v3 and the COCO SSD on orange.raw scaled by nearest neighbour (source index
# i * 224 / size, rounded down; tflite_reference_test.cc, orange_nearest, does the same):
# DeepLab's input as float32 (x - 127.5) / 127.5, and only its class map kept (uint8 argmax of
# the 21 scores per pixel, first maximum); the SSD's four outputs after
# TFLite_Detection_PostProcess as they are.
/usr/bin/python3 - "$upstream/data/orange.raw" "$tmp" <<'PY'
import sys, numpy as n
x = n.fromfile(sys.argv[1], n.uint8).reshape(224, 224, 3)
def nearest(size):
    i = n.arange(size) * 224 // size
    return x[i][:, i]
((nearest(257).astype(n.float32) - n.float32(127.5)) / n.float32(127.5)).tofile(sys.argv[2] + "/deeplab_in.raw")
nearest(300).tofile(sys.argv[2] + "/ssd_in.raw")
PY
run "$upstream/models/deeplabv3_257_mv_gpu.tflite" "$tmp/deeplab" "$tmp/deeplab_in.raw"
/usr/bin/python3 -c "import numpy as n,sys; n.fromfile(sys.argv[1],n.float32).reshape(257*257,21).argmax(1).astype(n.uint8).tofile(sys.argv[2])" \
  "$tmp/deeplab.0.raw" "$out/deeplab_orange257_classes.u8"
run "$models/coco_ssd_mobilenet_quant.tflite" "$out/ssd_orange300" "$tmp/ssd_in.raw"
ls -l "$out"
