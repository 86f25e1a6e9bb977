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
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
BUILD_DIR=${NNS_BUILD_DIR:-$ROOT/build}
DEMO_BIN=$BUILD_DIR/examples/nns-demo

[[ -x $DEMO_BIN && -f $BUILD_DIR/env.sh ]] || {
  echo "run_demo: $DEMO_BIN not built; run scripts/setup.sh (or cmake --build build) first" >&2
  exit 1
}

fetch_debian_photo() {
  local dir=$ROOT/third_party/demo png=$ROOT/third_party/demo/astronaut.png
  if [[ ! -f $png ]]; then
    echo "run_demo: no ../shared photo; extracting astronaut.png from Debian's python3-skimage" >&2
    local tmp
    tmp=$(mktemp -d)
    (cd "$tmp" && apt-get download python3-skimage >/dev/null 2>&1) || {
      rm -rf "$tmp"
      echo "run_demo: 'apt-get download python3-skimage' failed (run apt-get update?)" >&2
      return 1
    }
    dpkg -x "$tmp"/python3-skimage_*.deb "$tmp/x"
    mkdir -p "$dir"
    cp "$(find "$tmp/x" -path '*skimage/data/astronaut.png' | head -n 1)" "$png"
    rm -rf "$tmp"
  fi
  echo "$png"
}

image=${1:-${NNS_DEMO_IMAGE:-}}
face_photo=$image
if [[ -z $image ]]; then
  image=$ROOT/../shared/models/upstream/data/orange.png
  [[ -f $image ]] || image=$(fetch_debian_photo)
fi
[[ -f $image ]] || {
  echo "run_demo: image '$image' not found" >&2
  exit 1
}
image=$(cd "$(dirname "$image")" && pwd)/$(basename "$image")

# shellcheck source=/dev/null
. "$BUILD_DIR/env.sh"
# A registry cache of this build tree's own, so other checkouts' plugins never mix in.
export GST_REGISTRY=${GST_REGISTRY:-$BUILD_DIR/gst-registry.bin}
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
"$DEMO_BIN" --image "$image" --output "$out" || exit $?

echo
echo "run_demo: face detection with BlazeFace on ONNX Runtime (examples/face_demo/run.sh)"
rc=0
bash "$ROOT/examples/face_demo/run.sh" ${face_photo:+"$face_photo"} || rc=$?
if ((rc == 77)); then
  echo "run_demo: face demo skipped (see the reason above)"
  rc=0
elif ((rc == 0)); then
  echo
  echo "run_demo: the same with tensor_decoder mode=bounding_boxes drawing the boxes (examples/face_demo/boxes.sh)"
  bash "$ROOT/examples/face_demo/boxes.sh" ${face_photo:+"$face_photo"} || rc=$?
  ((rc != 77)) || rc=0
fi
exit $rc
