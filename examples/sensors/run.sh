#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Multi-sensor demo in the manner of the NNStreamer paper's E2: two (fake) Linux IIO sensors at
# different rates -- a 3-axis accelerometer at 100 Hz and a light sensor at 10 Hz -- read by
# tensor_src_iio, the accelerometer windowed by tensor_aggregator (10 samples), both combined by
# tensor_mux and fed to a small recurrent model (GRU) on PyTorch. The sensors are sysfs trees
# made by make_sensors.py in a temp folder, with files standing in for the character devices, so
# the demo runs without hardware; it checks the model's outputs against torch run directly on
# the same sensor values and prints them (examples/sensors/README.md).
#
# usage: examples/sensors/run.sh [windows (5)]
# env:   NNS_BUILD_DIR (build), NNS_SENSORS_SKIP_MISSING=1: exit 77 instead of 1 when the PyTorch
#        back end or python3-torch is unavailable (ctest; never under CI=true).
# exit: 0 ok (outputs match), 77 skipped, other = failure.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init sensors NNS_SENSORS_SKIP_MISSING
windows=${1:-5}
[[ -f $BUILD_DIR/env.sh ]] || nns_die 1 "$BUILD_DIR not built; run scripts/setup.sh first"
[[ -f $BUILD_DIR/subplugins/filters/libnnstreamer_filter_pytorch.so ]] ||
  nns_die "$missing" "the PyTorch back end is not built (Debian libtorch-dev)"
/usr/bin/python3 -c 'import torch, numpy' 2>/dev/null ||
  nns_die "$missing" "/usr/bin/python3 lacks torch/numpy (python3-torch, python3-numpy)"
nns_enter_build_env

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 "$ROOT/examples/sensors/make_sensors.py" "$work" "$windows" >/dev/null
iio="iio-base-dir=$work/sys dev-dir=$work/dev"
start=$(date +%s%N)
gst-launch-1.0 -q \
  tensor_src_iio device=e2_accel $iio channels=all buffer-capacity=1 ! \
  tensor_aggregator frames-in=1 frames-out=10 frames-dim=1 ! mux.sink_0 \
  tensor_src_iio device=e2_light $iio channels=all ! mux.sink_1 \
  tensor_mux name=mux sync-mode=nosync ! \
  tensor_filter framework=pytorch model="$work/e2_gru.pt" input=3:10,1:1 \
  inputtype=float32,float32 ! filesink location="$work/out.f32"
ms=$((($(date +%s%N) - start) / 1000000))
/usr/bin/python3 - "$work" "$windows" "$ms" <<'PY'
import sys
import numpy as np
work, windows, ms = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
out = np.fromfile(work + "/out.f32", np.float32)
ref = np.fromfile(work + "/reference.f32", np.float32)
if out.size != ref.size:
    sys.exit("sensors: got %d scores, expected %d (%d windows x 2)" % (out.size, ref.size, windows))
err = float(np.abs(out - ref).max())
for w in range(windows):
    print("window %d (accel 10 x 3 @ 100 Hz + light @ 10 Hz): scores %s" %
          (w, np.array2string(out[2 * w:2 * w + 2], precision=4)))
print("sensors: %d windows in %d ms, max |pipeline - torch| = %.3g" % (windows, ms, err))
sys.exit(0 if err <= 1e-5 else "sensors: outputs differ from torch's")
PY
