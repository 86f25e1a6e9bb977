# shellcheck shell=bash
# SPDX-License-Identifier: LGPL-2.1-only
# Shared by the example scripts (sourced, after `set -euo pipefail`):
#   . "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
#   nns_example_init <tag> [skip-variable]
# sets ROOT (the worktree), BUILD_DIR ($NNS_BUILD_DIR or build/), NNS_TAG (message prefix) and
# `missing` (exit code for an unavailable model/photo/back end: 1, or 77 when the named
# variable, e.g. NNS_SKIP_MISSING, is set: ctest counts 77 as skipped). In CI (CI=true in the
# environment, as .ci/run sets it) nothing may be skipped: `missing` stays 1 (see nns_ci).

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

# shellcheck disable=SC2034  # globals for the calling script
nns_example_init() {
  NNS_TAG=$1
  BUILD_DIR=${NNS_BUILD_DIR:-$ROOT/build}
  missing=1
  if [[ -n ${2:-} && -n ${!2:-} ]] && ! nns_ci; then missing=77; fi
}

# nns_ci: true in CI (CI=true), where a demo whose model, photo, back end or element is missing
# must fail instead of being skipped (scripts/setup.sh provides all of them there).
nns_ci() {
  [[ ${CI:-} == true ]]
}

# nns_die <exit code> <message>: "<tag>: <message>" on stderr, then exit.
nns_die() {
  echo "$NNS_TAG: $2" >&2
  exit "$1"
}

# nns_require_ort_app <binary> <model>: the example application is built (exit 1 if not), its
# npm model is fetched and the onnxruntime filter back end is built (exit $missing if not).
nns_require_ort_app() {
  local bin=$1 model=$2
  local ort=$BUILD_DIR/subplugins/filters/libnnstreamer_filter_onnxruntime.so
  [[ -x $bin && -f $BUILD_DIR/env.sh ]] ||
    nns_die 1 "$bin not built; run scripts/setup.sh (or cmake --build build) first"
  [[ -f $model ]] ||
    nns_die "$missing" "$model missing; run scripts/setup.sh (it fetches scripts/deps/models.npm)"
  [[ -f $ort ]] ||
    nns_die "$missing" "$ort not built (ONNX Runtime missing? scripts/deps/onnxruntime.npm)"
}

# The build tree's environment (GST_PLUGIN_PATH, NNSTREAMER_CONF, ...) and a registry cache of
# this build tree's own, so other checkouts' plugins never mix in.
nns_enter_build_env() {
  # shellcheck source=/dev/null
  . "$BUILD_DIR/env.sh"
  export GST_REGISTRY=${GST_REGISTRY:-$BUILD_DIR/gst-registry.bin}
}

# nns_fetch_astronaut [why]: prints the path of skimage's astronaut.png, extracted once from
# Debian's python3-skimage package into third_party/demo/ (apt-get download + dpkg -x, nothing
# installed). `why` prefixes the progress message. Returns 1 when the download fails.
nns_fetch_astronaut() {
  local dir=$ROOT/third_party/demo png=$ROOT/third_party/demo/astronaut.png
  if [[ ! -f $png ]]; then
    echo "$NNS_TAG: ${1:-}extracting astronaut.png from Debian's python3-skimage" >&2
    local tmp
    tmp=$(mktemp -d)
    (cd "$tmp" && apt-get download python3-skimage >/dev/null 2>&1) || {
      rm -rf "$tmp"
      echo "$NNS_TAG: 'apt-get download python3-skimage' failed (run apt-get update?)" >&2
      return 1
    }
    dpkg -x "$tmp"/python3-skimage_*.deb "$tmp/x"
    mkdir -p "$dir"
    cp "$(find "$tmp/x" -path '*skimage/data/astronaut.png' | head -n 1)" "$png"
    rm -rf "$tmp"
  fi
  echo "$png"
}

# nns_launch_tflite <gst-launch arguments...>: runs gst-launch-1.0 -q; when it fails because no
# tensor_filter back end could open the .tflite model ("could not open model": before the TFLite
# engine is built, framework=tensorflow-lite falls back to armnn, which cannot parse every
# model), exits $missing (77 skipped locally, 1 in CI); any other failure exits 1. stdout passes
# through; stderr is shown after the run.
nns_launch_tflite() {
  local log rc=0
  log=$(mktemp)
  gst-launch-1.0 -q "$@" 2>"$log" || rc=$?
  cat "$log" >&2
  if ((rc != 0)); then
    if grep -q "could not open model" "$log"; then
      rm -f "$log"
      nns_die "$missing" "no tensor_filter back end opens the model (TFLite back end not built?)"
    fi
    rm -f "$log"
    nns_die 1 "gst-launch-1.0 failed (exit $rc)"
  fi
  rm -f "$log"
}

# nns_png_size <file.png>: prints "WIDTH HEIGHT" of a PNG file (from its IHDR); exits 1 with a
# message when the file is not a PNG.
nns_png_size() {
  [[ $(head -c 8 "$1" | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a ]] ||
    nns_die 1 "'$1' is not a PNG file"
  od -An -tu1 -j16 -N8 "$1" |
    awk '{print $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8}'
}

# nns_demo_photo [photo]: sets `photo` (the argument, or skimage's astronaut.png) and `width`,
# `height` (from its PNG header); exits $missing when the photo is unavailable.
# shellcheck disable=SC2034  # globals for the calling script
nns_demo_photo() {
  photo=${1:-}
  [[ -n $photo ]] || photo=$(nns_fetch_astronaut "") || nns_die "$missing" "astronaut.png unavailable"
  [[ -f $photo ]] || nns_die "$missing" "photo '$photo' not found"
  read -r width height < <(nns_png_size "$photo")
}

# nns_launch_tflite_overlay <photo.png> <out.png> <model branch...>: one frame of the photo
# through the model branch (gst-launch elements from the RGBA photo to a decoder giving an RGBA
# layer of the photo's size), the layer laid over the photo by compositor, written as PNG.
# Further gst-launch branches (e.g. from a tee named in the model branch) may follow in the
# array nns_overlay_extra. Run through nns_launch_tflite (exit $missing when no back end opens
# the model).
nns_launch_tflite_overlay() {
  local photo=$1 out=$2
  shift 2
  nns_launch_tflite \
    filesrc location="$photo" ! pngdec ! videoconvert ! video/x-raw,format=RGBA ! \
    imagefreeze num-buffers=1 ! tee name=t \
    t. ! queue ! mix.sink_0 \
    t. ! queue ! "$@" ! mix.sink_1 \
    compositor name=mix sink_1::zorder=1 ! videoconvert ! pngenc ! filesink location="$out" \
    "${nns_overlay_extra[@]}"
}
nns_overlay_extra=()
