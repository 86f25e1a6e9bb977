#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# The main demo: a real photo through decode -> 224x224 RGB -> tensor_converter ->
# tensor_transform (typecast float32, (x - 127.5) / 127.5) -> filesink + tensor_sink, printing the
# tensor's dims, type, byte count, SHA-256 and value range (examples/demo/demo.cc).
# Then real inference: examples/face_demo/run.sh finds the faces in a photo with BlazeFace
# through tensor_filter framework=onnxruntime and prints their boxes (skimage's astronaut unless
# a photo is given).
#
# usage: examples/demo/run_demo.sh [image.png]
# env:   NNS_BUILD_DIR (build), NNS_DEMO_IMAGE (overrides the photo)
# Photo: the argument, $NNS_DEMO_IMAGE, ../shared/models/upstream/data/orange.png, or else
# skimage's astronaut.png taken from Debian's python3-skimage package (apt-get download, unpacked
# into third_party/demo/, nothing installed).
# exit: 0 ok, 77 skipped (an element the demo needs is not built yet), other = failure.
#       With NNS_FACE_SKIP_MISSING=1 (ctest) a face demo without its model counts as skipped.
#       With CI=true nothing is skipped: a missing element, model or back end is a failure.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init run_demo
DEMO_BIN=$BUILD_DIR/examples/nns-demo

[[ -x $DEMO_BIN && -f $BUILD_DIR/env.sh ]] ||
  nns_die 1 "$DEMO_BIN not built; run scripts/setup.sh (or cmake --build build) first"

image=${1:-${NNS_DEMO_IMAGE:-}}
face_photo=$image
if [[ -z $image ]]; then
  image=$ROOT/../shared/models/upstream/data/orange.png
  [[ -f $image ]] || image=$(nns_fetch_astronaut "no ../shared photo; ")
fi
[[ -f $image ]] || nns_die 1 "image '$image' not found"
image=$(cd "$(dirname "$image")" && pwd)/$(basename "$image")

nns_enter_build_env
# A sanitizer build's plugin cannot be loaded by the (uninstrumented) gst-plugin-scanner helper:
# scan in this process instead, which is instrumented.
if grep -q '^NNS_SANITIZE:BOOL=ON' "$BUILD_DIR/CMakeCache.txt" 2>/dev/null; then
  export GST_REGISTRY_FORK=no
fi
out_dir=$BUILD_DIR/demo
mkdir -p "$out_dir"
out=$out_dir/$(basename "${image%.*}").rgb224.f32
rm -f "$out"
echo "run_demo: image $image"
rc=0
"$DEMO_BIN" --image "$image" --output "$out" || rc=$?
if ((rc == 77)) && nns_ci; then
  nns_die 1 "CI=true: the demo may not be skipped (an element it needs is not built)"
fi
((rc == 0)) || exit $rc

echo
echo "run_demo: face detection with BlazeFace on ONNX Runtime (examples/face_demo/run.sh)"
rc=0
bash "$ROOT/examples/face_demo/run.sh" ${face_photo:+"$face_photo"} || rc=$?
if ((rc == 77)) && nns_ci; then
  nns_die 1 "CI=true: the real inference may not be skipped (see the reason above)"
elif ((rc == 77)); then
  echo "run_demo: face demo skipped (see the reason above)"
  rc=0
elif ((rc == 0)); then
  echo
  echo "run_demo: the same with tensor_decoder mode=bounding_boxes drawing the boxes (examples/face_demo/boxes.sh)"
  bash "$ROOT/examples/face_demo/boxes.sh" ${face_photo:+"$face_photo"} || rc=$?
  if ((rc == 77)) && nns_ci; then
    nns_die 1 "CI=true: the boxes demo may not be skipped (see the reason above)"
  fi
  ((rc != 77)) || rc=0
fi
exit $rc
