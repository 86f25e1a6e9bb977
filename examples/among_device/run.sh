#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Among-device inference over TCP in one command: a query server process serving MobileNet v2
# (ONNX Runtime, tensor_filter framework=onnxruntime) on 127.0.0.1, and a client pipeline that
# sends the orange photo to it with tensor_query_client and labels the answer. Prints the label
# and the query round-trip time (from the client's send to the answer coming back).
#
# usage: examples/among_device/run.sh [picture.png]   (default: the shared orange.png)
# env:   NNS_BUILD_DIR (build), NNS_SHARED_DIR (../shared next to the worktree),
#        NNS_SKIP_MISSING=1: exit 77 instead of 1 when the model, picture or the onnxruntime
#        back end is unavailable (not in CI: examples/common.sh nns_ci).
# exit:  0 ok, 77 skipped, other = failure.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init among_device NNS_SKIP_MISSING
SHARED=${NNS_SHARED_DIR:-$ROOT/../shared}/models/upstream
MODEL=$SHARED/models/mobilenet_v2_quant.onnx
LABELS=$BUILD_DIR/data/imagenet_labels_1000.txt
PICTURE=${1:-$SHARED/data/orange.png}

[[ -f $BUILD_DIR/env.sh ]] || nns_die 1 "$BUILD_DIR/env.sh missing; build the project first"
for f in "$MODEL" "$PICTURE"; do
  [[ -f $f ]] || nns_die $missing "$f not found"
done
[[ -f $LABELS ]] || nns_die 1 "$LABELS not generated (re-run cmake and build)"
[[ -f $BUILD_DIR/subplugins/filters/libnnstreamer_filter_onnxruntime.so ]] ||
  nns_die $missing "onnxruntime filter back end not built (scripts/deps/onnxruntime.npm)"

nns_enter_build_env
gst-inspect-1.0 tensor_query_client >/dev/null 2>&1 ||
  nns_die 1 "tensor_query_client is not in $BUILD_DIR/plugin"
work=$(mktemp -d)
server_pid=
cleanup() {
  if [[ -n $server_pid ]]; then kill "$server_pid" 2>/dev/null || true; wait "$server_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
port=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')

# The server: requests are float32 NCHW 1x3x224x224 (NNStreamer dims 224:224:3:1), answers
# the 1000 class scores.
gst-launch-1.0 -q tensor_query_serversrc host=127.0.0.1 port="$port" ! \
  other/tensors,format=static,num_tensors=1,dimensions=224:224:3:1,types=float32,framerate=0/1 ! \
  tensor_filter framework=onnxruntime model="$MODEL" ! \
  tensor_query_serversink >"$work/server.log" 2>&1 &
server_pid=$!
for _ in $(seq 100); do
  (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null && break
  kill -0 "$server_pid" 2>/dev/null || { cat "$work/server.log" >&2; nns_die 1 "server died"; }
  sleep 0.1
done

# The client: the same preprocessing as examples/classification, then the query.
case $PICTURE in
  *.png) dec=pngdec ;;
  *) dec=decodebin ;;
esac
GST_DEBUG=tensor_query_client:4 GST_DEBUG_NO_COLOR=1 gst-launch-1.0 -q \
  filesrc location="$PICTURE" ! $dec ! videoconvert ! videoscale ! \
  video/x-raw,format=RGB,width=224,height=224 ! tensor_converter ! \
  tensor_transform mode=arithmetic \
  option=typecast:float32,per-channel:true@0,add:-123.675@0,add:-116.280@1,add:-103.530@2,div:58.3950@0,div:57.1200@1,div:57.3750@2 ! \
  tensor_transform mode=transpose option=1:2:0:3 ! \
  tensor_query_client host=127.0.0.1 port=0 dest-host=127.0.0.1 dest-port="$port" timeout=10000 ! \
  tensor_decoder mode=image_labeling option1="$LABELS" ! \
  filesink location="$work/label.txt" 2>"$work/client.log" ||
  { cat "$work/client.log" "$work/server.log" >&2; nns_die 1 "the client pipeline failed"; }
label=$(cat "$work/label.txt")
[[ -n $label ]] || nns_die 1 "no label came back from the server"
rtt=$(sed -n 's/.*answer 1: round trip \([0-9]*\) us.*/\1/p' "$work/client.log" | head -n 1)
[[ -n $rtt ]] || nns_die 1 "no round-trip time in the client log"
echo "label: $label"
echo "round trip: $rtt us (send to answer, MobileNet v2 on ONNX Runtime in the server process)"
