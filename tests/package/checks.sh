#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-only
# Runs INSIDE the Debian 12 test root, after `apt-get install ./*.deb`, with no environment
# variable but PATH and HOME (install_test.sh starts it with env -i). Checks the installed
# packages as a user uses them: no build tree, no NNSTREAMER_* or GST_PLUGIN_PATH.
# Inputs: /tmp/nns-models (models, pictures, labels), /tmp/nns-check (this folder).
# Prints one "check <name>: ok|FAILED|skipped (...)" line per check; exits 1 when one failed.
set -u
M=/tmp/nns-models
C=/tmp/nns-check
O=/tmp/nns-out
rm -rf "$O" && mkdir -p "$O"
FILTERS=$(ls -d /usr/lib/*/nnstreamer/filters 2>/dev/null | head -n 1)
failed=0

ok() { echo "check $1: ok${2:+ ($2)}"; }
bad() {
  echo "check $1: FAILED ($2)"
  failed=1
}
skipped() { echo "check $1: skipped ($2)"; }
have_filter() { [ -e "$FILTERS/libnnstreamer_filter_$1.so" ]; }
# run <name> <log> <command...>: runs it with its output in <log>; prints the log on failure.
run() {
  local name=$1 log=$O/$2.log
  shift 2
  local rc=0
  "$@" >"$log" 2>&1 || rc=$?
  if [ $rc != 0 ]; then
    bad "$name" "exit $rc: $*"
    sed 's/^/    /' "$log" | tail -n 20
    return 1
  fi
}
# argmax <file> [od type: u1 (default) or f4]: index of the largest value.
argmax() { od -An -v -t"${2:-u1}" "$1" | tr -s ' ' '\n' | grep -v '^$' | awk 'NR==1||$1+0>m{m=$1+0;i=NR-1} END{print i}'; }
# values <file>: the uint8 values, space-separated; inverted <file>: 255 - each of them.
values() { od -An -v -tu1 "$1" | tr -s ' ' '\n' | grep -v '^$' | awk '{printf "%d ", $1}'; }
inverted() { od -An -v -tu1 "$1" | tr -s ' ' '\n' | grep -v '^$' | awk '{printf "%d ", 255-$1}'; }
# invert_check <name> <framework> <model>: the filter must output 255 - the 28x28 digit.
invert_check() {
  if run "$1" "$1" gst-launch-1.0 -q $LENET_SRC ! tensor_filter framework=$2 model=$3 ! \
    filesink location=$O/$1.bin; then
    [ "$(inverted "$M/9.raw")" = "$(values "$O/$1.bin")" ] && ok "$1" "${4:-255 - input, exactly}" ||
      bad "$1" "the filter's output is not 255 - input"
  fi
}

# 1. The plugin is found through GStreamer's own plugin folder.
if run gst-inspect inspect gst-inspect-1.0 tensor_converter; then ok gst-inspect "tensor_converter"; fi

# 2. One pipeline per installed back end, on real models.
LENET_SRC="filesrc location=$M/9.raw ! application/octet-stream ! tensor_converter input-dim=1:28:28:1 input-type=uint8"
if have_filter pytorch; then
  if run pytorch pytorch gst-launch-1.0 -q $LENET_SRC ! tensor_filter framework=pytorch \
    model=$M/pytorch_lenet5.pt input=1:28:28:1 inputtype=uint8 output=10:1 outputtype=uint8 ! \
    filesink location=$O/lenet.bin; then
    c=$(argmax "$O/lenet.bin")
    [ "$c" = 9 ] && ok pytorch "LeNet: digit 9" || bad pytorch "LeNet says $c for the 9"
  fi
else skipped pytorch "nnstreamer-cpp-pytorch not installed"; fi

if have_filter onnxruntime; then
  if run onnxruntime onnxruntime gst-launch-1.0 -q filesrc location=$M/orange.png ! pngdec ! \
    videoconvert ! video/x-raw,format=RGB,width=224,height=224 ! tensor_converter ! \
    tensor_transform mode=arithmetic option=typecast:float32,per-channel:true@0,add:-123.675@0,add:-116.280@1,add:-103.530@2,div:58.3950@0,div:57.1200@1,div:57.3750@2 ! \
    tensor_transform mode=transpose option=1:2:0:3 ! \
    tensor_filter framework=onnxruntime model=$M/mobilenet_v2_quant.onnx ! \
    tensor_decoder mode=image_labeling option1=$M/imagenet_labels_1000.txt ! \
    filesink location=$O/onnx-label.txt; then
    l=$(cat "$O/onnx-label.txt")
    [ "$l" = orange ] && ok onnxruntime "MobileNet v2: orange" || bad onnxruntime "MobileNet v2 says '$l'"
  fi
else skipped onnxruntime "nnstreamer-cpp-onnxruntime not installed"; fi

# .tflite: whichever back end claims it (tensorflow2-lite, else Arm NN; /etc/nnstreamer.ini).
if have_filter tensorflow2-lite || have_filter armnn; then
  if run tflite tflite gst-launch-1.0 -q filesrc location=$M/orange.raw blocksize=-1 ! application/octet-stream ! \
    tensor_converter input-dim=3:224:224:1 input-type=uint8 ! \
    tensor_filter framework=tensorflow-lite model=$M/mobilenet_v2_1.0_224_quant.tflite ! \
    tensor_decoder mode=image_labeling option1=$M/labels.txt ! filesink location=$O/tflite-label.txt; then
    l=$(cat "$O/tflite-label.txt")
    [ "$l" = orange ] && ok tflite "MobileNet v2 .tflite: orange" || bad tflite "MobileNet v2 .tflite says '$l'"
  fi
else skipped tflite "no back end for .tflite installed"; fi

if have_filter opencv; then
  if run opencv opencv gst-launch-1.0 -q $LENET_SRC ! tensor_transform mode=arithmetic \
    option=typecast:float32,add:-127.5,div:127.5 ! tensor_filter framework=opencv \
    model=$M/lenet_deploy.prototxt,$M/lenet_iter_9000.caffemodel ! filesink location=$O/opencv.bin; then
    c=$(argmax "$O/opencv.bin" f4)
    [ "$c" = 9 ] && ok opencv "Caffe LeNet: digit 9" || bad opencv "Caffe LeNet says $c for the 9"
  fi
else skipped opencv "nnstreamer-cpp-opencv not installed"; fi
if have_filter lua; then invert_check lua lua "$C/invert.lua"; else skipped lua "nnstreamer-cpp-lua not installed"; fi
if have_filter python3; then invert_check python3-filter python3 "$C/invert.py"; else
  skipped python3-filter "nnstreamer-cpp-python3 not installed"; fi

# The transports' plugins load (their libraries resolve) when installed.
for e in mqttsink:libgstmqtt tensor_src_grpc:libnnstreamer-grpc tensor_ros_sink:libnnstreamer_ros; do
  if ls /usr/lib/*/gstreamer-1.0/${e#*:}.so >/dev/null 2>&1; then
    run "plugin-${e%%:*}" "inspect-${e%%:*}" gst-inspect-1.0 "${e%%:*}" && ok "plugin-${e%%:*}" "${e#*:}.so"
  fi
done

# 3. A custom filter built with pkg-config against the -dev package.
if run custom-filter cc-custom sh -c "cc -O2 -Wall -Werror -shared -fPIC -o $O/libinvert.so $C/invert_filter.c \$(pkg-config --cflags --libs nnstreamer)"; then
  invert_check custom-filter custom "$O/libinvert.so" "pkg-config nnstreamer $(pkg-config --modversion nnstreamer): 255 - input"
fi

# 4. A C program on the ML API (single-shot, LeNet on PyTorch).
if have_filter pytorch; then
  if run ml-api cc-mlapi sh -c "cc -O2 -Wall -Werror -o $O/ml_api_check $C/ml_api_check.c \$(pkg-config --cflags --libs capi-ml-inference)" &&
    run ml-api mlapi "$O/ml_api_check" "$M/pytorch_lenet5.pt" "$M/9.raw"; then
    grep -qx 'class 9' "$O/mlapi.log" && ok ml-api "ml_single_invoke: LeNet says 9" ||
      bad ml-api "$(cat "$O/mlapi.log")"
  fi
else skipped ml-api "needs nnstreamer-cpp-pytorch"; fi

# 5. The Python module, running a model.
if [ -d /usr/lib/python3/dist-packages/nnstreamer ] && have_filter onnxruntime; then
  if run python3 python python3 -c "
import numpy as np, nnstreamer
x = np.fromfile('$M/orange.raw', np.uint8).reshape(224, 224, 3).astype(np.float32)
x = (x - np.array([123.675, 116.28, 103.53], np.float32)) / np.array([58.395, 57.12, 57.375], np.float32)
with nnstreamer.Single('$M/mobilenet_v2_quant.onnx', 'onnxruntime') as m:
    (s,) = m.invoke(np.ascontiguousarray(x.transpose(2, 0, 1)[None]))
print('class', int(np.argmax(s)))
"; then
    grep -qx 'class 950' "$O/python.log" && ok python3 "import nnstreamer: orange (950)" ||
      bad python3 "$(tail -n 3 "$O/python.log")"
  fi
else skipped python3 "needs python3-nnstreamer and nnstreamer-cpp-onnxruntime"; fi

# 6. nns-profile runs a pipeline.
if command -v nns-profile >/dev/null; then
  if run nns-profile profile sh -c "cd $O && nns-profile 'videotestsrc num-buffers=10 ! video/x-raw,width=32,height=32 ! tensor_converter ! fakesink'"; then
    ok nns-profile
  fi
fi
exit $failed
