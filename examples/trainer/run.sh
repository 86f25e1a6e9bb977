#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# On-device training demo: scikit-learn's handwritten digits (load_digits, 1797 8x8 images) in a
# data repository, streamed by datareposrc into tensor_trainer (framework=pytorch) which trains
# an MLP and saves it; then tensor_filter framework=pytorch runs the saved model on 300
# held-apart digits and the accuracy is printed. A second training run starts from the saved
# model (model-load-path), as personalisation on a device would. examples/trainer/README.md.
#
# usage: examples/trainer/run.sh [epochs (10)]
# env:   NNS_BUILD_DIR (build), NNS_TRAINER_SKIP_MISSING=1: exit 77 instead of 1 when the
#        PyTorch back end/trainer or python3-sklearn is missing (ctest; never under CI=true).
# exit: 0 ok (accuracy >= 0.9 and the second run starts from the first), 77 skipped, else failure.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init trainer NNS_TRAINER_SKIP_MISSING
epochs=${1:-10}
[[ -f $BUILD_DIR/env.sh ]] || nns_die 1 "$BUILD_DIR not built; run scripts/setup.sh first"
for f in trainers/libnnstreamer_trainer_pytorch.so filters/libnnstreamer_filter_pytorch.so; do
  [[ -f $BUILD_DIR/subplugins/$f ]] ||
    nns_die "$missing" "$BUILD_DIR/subplugins/$f is not built (Debian libtorch-dev)"
done
/usr/bin/python3 -c 'import sklearn, torch' 2>/dev/null ||
  nns_die "$missing" "/usr/bin/python3 lacks sklearn or torch (python3-sklearn, python3-torch)"
nns_enter_build_env

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
/usr/bin/python3 "$ROOT/examples/trainer/make_digits.py" "$work"
train() {  # train <epochs> <save> [load]
  gst-launch-1.0 -q datareposrc location=train.dat json=train.json epochs="$1" is-shuffle=false ! \
    tensor_trainer framework=pytorch model-config=config.json model-save-path="$2" \
    ${3:+model-load-path="$3"} num-inputs=1 num-labels=1 num-training-samples=1200 \
    num-validation-samples=297 epochs="$1" ! filesink location="$2.stats"
}
evaluate() {  # evaluate <model> -> prints the accuracy on the 300 test digits
  gst-launch-1.0 -q datareposrc location=test.dat json=test.json is-shuffle=false ! \
    tensor_filter framework=pytorch model="$1" input=64:1 inputtype=float32 ! \
    filesink location="$1.pred"
  /usr/bin/python3 -c 'import sys, numpy as np
p = np.fromfile(sys.argv[1], np.float32).reshape(-1, 10)
y = np.fromfile("test_labels.u8", np.uint8)
print("%.4f" % (p.argmax(1) == y).mean() if len(p) == len(y) else "0")' "$1.pred"
}
first_loss() {  # training loss of the first epoch in a stats file
  /usr/bin/python3 -c 'import sys, numpy as np
print("%.6f" % np.fromfile(sys.argv[1], np.float64).reshape(-1, 4)[1][0])' "$1"
}
start=$(date +%s%N)
train "$epochs" digits.pt
ms=$((($(date +%s%N) - start) / 1000000))
acc=$(evaluate digits.pt)
echo "trainer: $epochs epochs of 1200 training + 297 validation digits in $ms ms;" \
  "first-epoch training loss $(first_loss digits.pt.stats)"
echo "trainer: accuracy of the saved model on 300 held-apart digits: $acc"
train 2 digits2.pt digits.pt
acc2=$(evaluate digits2.pt)
echo "trainer: continued from digits.pt for 2 epochs: first-epoch training loss" \
  "$(first_loss digits2.pt.stats), accuracy $acc2"
/usr/bin/python3 -c 'import sys
acc, acc2, l1, l2 = map(float, sys.argv[1:])
ok = acc >= 0.9 and acc2 >= 0.9 and l2 < l1
sys.exit(0 if ok else "trainer: accuracy below 0.9 or the second run did not start from the first")' \
  "$acc" "$acc2" "$(first_loss digits.pt.stats)" "$(first_loss digits2.pt.stats)"
