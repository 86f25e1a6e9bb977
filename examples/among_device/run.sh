#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Among-device inference in one command, twice:
#  1. TCP: a query server process serving MobileNet v2 (ONNX Runtime, tensor_filter
#     framework=onnxruntime) on 127.0.0.1, and a client pipeline that sends the orange photo to
#     it with tensor_query_client (dest-host/dest-port) and labels the answer;
#  2. HYBRID: a mosquitto broker started here (127.0.0.1, a free port, a temporary config), a
#     query server that announces itself on an MQTT topic, and a client that only knows the
#     broker and the topic: it discovers the server there, then talks TCP to it.
# Prints the label and the query round-trip time (from the client's send to the answer coming
# back) of each.
#
# usage: examples/among_device/run.sh [picture.png]   (default: the shared orange.png)
# env:   NNS_BUILD_DIR (build), NNS_SHARED_DIR (../shared next to the worktree),
#        NNS_SKIP_MISSING=1: exit 77 instead of 1 when the shared models, the picture, the
#        onnxruntime back end or mosquitto is unavailable (not in CI: examples/common.sh nns_ci),
#        NNS_EXPECT_LABEL=orange: exit 1 unless both halves print that label (ctest sets it).
# exit:  0 ok, 77 skipped, other = failure.
set -euo pipefail
# shellcheck source=examples/common.sh
. "$(dirname "${BASH_SOURCE[0]}")/../common.sh"
nns_example_init among_device NNS_SKIP_MISSING
SHARED_DIR=${NNS_SHARED_DIR:-$ROOT/../shared}
SHARED=$SHARED_DIR/models/upstream
MODEL=$SHARED/models/mobilenet_v2_quant.onnx
LABELS=$BUILD_DIR/data/imagenet_labels_1000.txt
PICTURE=${1:-$SHARED/data/orange.png}
EXPECT=${NNS_EXPECT_LABEL:-}

# unavailable <what>: exit $missing (77 = skipped, or 1 in CI) saying what is missing.
unavailable() {
  if ((missing == 77)); then nns_die 77 "skipped: $1"; fi
  nns_die "$missing" "$1"
}

[[ -f $BUILD_DIR/env.sh ]] || nns_die 1 "$BUILD_DIR/env.sh missing; build the project first"
[[ -d $SHARED_DIR/models ]] ||
  unavailable "the shared models folder $SHARED_DIR/models is absent (set NNS_SHARED_DIR)"
for f in "$MODEL" "$PICTURE"; do
  [[ -f $f ]] || unavailable "$f not found"
done
[[ -f $LABELS ]] || nns_die 1 "$LABELS not generated (re-run cmake and build)"
[[ -f $BUILD_DIR/subplugins/filters/libnnstreamer_filter_onnxruntime.so ]] ||
  unavailable "onnxruntime filter back end not built (scripts/deps/onnxruntime.npm)"
[[ -f $BUILD_DIR/subplugins/decoders/libnnstreamer_decoder_image_labeling.so ]] ||
  nns_die 1 "the image_labeling decoder is not built (target nns_decoder_image_labeling)"
MOSQUITTO=
for m in /usr/sbin/mosquitto /usr/bin/mosquitto; do
  if [[ -x $m ]]; then MOSQUITTO=$m && break; fi
done
[[ -n $MOSQUITTO ]] || unavailable "mosquitto is not installed (scripts/deps/mqtt.apt)"

nns_enter_build_env
gst-inspect-1.0 tensor_query_client >/dev/null 2>&1 ||
  nns_die 1 "tensor_query_client is not in $BUILD_DIR/plugin"
work=$(mktemp -d)
server_pid=
broker_pid=
# stop <pid>: SIGINT (gst-launch-1.0 then takes its pipeline to NULL: a HYBRID server clears
# its announcement), SIGKILL after 3 s; reaps it.
stop() {
  kill -INT "$1" 2>/dev/null || return 0
  for _ in $(seq 30); do
    kill -0 "$1" 2>/dev/null || break
    sleep 0.1
  done
  kill -KILL "$1" 2>/dev/null || true
  wait "$1" 2>/dev/null || true
}
# stop_var <variable name>: stops the process whose PID the variable holds and clears it (so a
# PID is never signalled again once reaped).
stop_var() {
  local -n ref=$1
  [[ -z $ref ]] || stop "$ref"
  ref=
}
cleanup() {
  stop_var server_pid # before the broker: a HYBRID server clears its announcement on it
  stop_var broker_pid
  rm -rf "$work"
}
trap cleanup EXIT
free_port() {
  /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
# wait_port <port> <pid> <log> <what>: until 127.0.0.1:<port> accepts (10 s at most).
wait_port() {
  for _ in $(seq 100); do
    (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null && return 0
    kill -0 "$2" 2>/dev/null || { cat "$3" >&2; nns_die 1 "$4 died"; }
    sleep 0.1
  done
  cat "$3" >&2
  nns_die 1 "$4 does not accept connections on 127.0.0.1:$1"
}

# serve <log> <tensor_query_serversrc properties> <tensor_query_serversink properties>: a query
# server process in the background (its PID in $server_pid). Requests are float32 NCHW
# 1x3x224x224 (NNStreamer dims 224:224:3:1), answers the 1000 class scores.
serve() {
  # shellcheck disable=SC2086  # the property lists are split on purpose
  gst-launch-1.0 -q tensor_query_serversrc $2 ! \
    other/tensors,format=static,num_tensors=1,dimensions=224:224:3:1,types=float32,framerate=0/1 ! \
    tensor_filter framework=onnxruntime model="$MODEL" ! \
    tensor_query_serversink $3 >"$1" 2>&1 &
  server_pid=$!
}

# classify <name> <tensor_query_client properties>: the same preprocessing as
# examples/classification, the query, the label; sets $label and $rtt (us, first answer).
classify() {
  local dec=decodebin
  [[ $PICTURE == *.png ]] && dec=pngdec
  # shellcheck disable=SC2086
  GST_DEBUG=tensor_query_client:4 GST_DEBUG_NO_COLOR=1 gst-launch-1.0 -q \
    filesrc location="$PICTURE" ! $dec ! videoconvert ! videoscale ! \
    video/x-raw,format=RGB,width=224,height=224 ! tensor_converter ! \
    tensor_transform mode=arithmetic \
    option=typecast:float32,per-channel:true@0,add:-123.675@0,add:-116.280@1,add:-103.530@2,div:58.3950@0,div:57.1200@1,div:57.3750@2 ! \
    tensor_transform mode=transpose option=1:2:0:3 ! \
    tensor_query_client $2 timeout=10000 ! \
    tensor_decoder mode=image_labeling option1="$LABELS" ! \
    filesink location="$work/$1.label" 2>"$work/$1.client.log" ||
    { cat "$work/$1.client.log" "$work/$1.server.log" >&2; nns_die 1 "$1: the client pipeline failed"; }
  label=$(cat "$work/$1.label")
  [[ -n $label ]] || { cat "$work/$1.client.log" >&2; nns_die 1 "$1: no label came back from the server"; }
  rtt=$(sed -n 's/.*answer 1: round trip \([0-9]*\) us.*/\1/p' "$work/$1.client.log" | head -n 1)
  [[ -n $rtt ]] || nns_die 1 "$1: no round-trip time in the client log"
}

# report <half> <details>: prints the result line; fails when it is not $NNS_EXPECT_LABEL.
report() {
  printf '%-7s label: %s, round trip %s us (%s)\n' "$1:" "$label" "$rtt" "$2"
  [[ -z $EXPECT || $label == "$EXPECT" ]] || nns_die 1 "$1: label '$label', expected '$EXPECT'"
}

# 1. TCP: the client is given the server's address.
port=$(free_port)
serve "$work/tcp.server.log" "host=127.0.0.1 port=$port" ""
wait_port "$port" "$server_pid" "$work/tcp.server.log" "the TCP query server"
classify tcp "host=127.0.0.1 port=0 dest-host=127.0.0.1 dest-port=$port"
report TCP "server 127.0.0.1:$port, MobileNet v2 on ONNX Runtime in the server process"
stop_var server_pid

# 2. HYBRID: a broker of our own, the server announces itself on it, the client discovers it.
broker_port=$(free_port)
cat >"$work/mosquitto.conf" <<EOF
listener $broker_port 127.0.0.1
allow_anonymous true
persistence false
log_dest stderr
log_type error
log_type warning
EOF
"$MOSQUITTO" -c "$work/mosquitto.conf" >"$work/mosquitto.log" 2>&1 &
broker_pid=$!
wait_port "$broker_port" "$broker_pid" "$work/mosquitto.log" "mosquitto"
topic=among_device_$$
port=$(free_port)
serve "$work/hybrid.server.log" \
  "connect-type=HYBRID host=127.0.0.1 port=$port dest-host=127.0.0.1 dest-port=$broker_port topic=$topic" \
  "connect-type=HYBRID"
wait_port "$port" "$server_pid" "$work/hybrid.server.log" "the HYBRID query server"
classify hybrid \
  "connect-type=HYBRID host=127.0.0.1 port=0 dest-host=127.0.0.1 dest-port=$broker_port topic=$topic"
report HYBRID "server found on topic '$topic' through mosquitto 127.0.0.1:$broker_port"
