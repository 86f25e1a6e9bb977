#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Query load balancing and batching (issue 21) against a real NNStreamer 2.x build, by hand:
# docs/interop.md, "Query load balancing and batching". Not run by CI.
#   scripts/interop/query_lb_batch.sh UPSTREAM_PREFIX [OUR_BUILD_DIR] [WORK_DIR]
# UPSTREAM_PREFIX: NNStreamer + nnstreamer-edge installed as docs/interop.md says
# (lib/gstreamer-1.0, etc/nnstreamer.ini); OUR_BUILD_DIR: this tree's build (default build).
# Needs Debian's mosquitto, ss, /usr/bin/python3 with numpy, onnx and gi (GStreamer bindings),
# and our ONNX Runtime filter. Every pipeline runs in its own process with one implementation's
# plugins and registry; brokers and servers are started here on 127.0.0.1 and stopped by PID.
# Prints PASS/FAIL per check; exits 1 if any failed.
set -u
UP=$(realpath "${1:?usage: $0 UPSTREAM_PREFIX [OUR_BUILD_DIR] [WORK_DIR]}")
OURS=$(realpath "${2:-$(dirname "$0")/../../build}")
W=${3:-$(mktemp -d /tmp/nns-query-interop.XXXXXX)}
mkdir -p "$W"
HELP=$(realpath "$(dirname "$0")/query_lb_batch.py")
SYS_PLUGINS=$(pkg-config --variable=pluginsdir gstreamer-1.0)
FAILED=0
cd "$W" || exit 1
echo "work dir: $W"

# Background calls exec, so $! is the process itself (its PID is what gets killed).
_run() { if [ "$BASHPID" != "$$" ]; then exec "$@"; else "$@"; fi; }
_env() {  # $1 plugin dir, $2 registry, $3 conf, $4 sub-plugin root, $5 LD_LIBRARY_PATH, then the command
  local p=$1 r=$2 c=$3 s=$4 l=$5
  shift 5
  _run env -i PATH=/usr/bin:/bin HOME="$HOME" GST_PLUGIN_SYSTEM_PATH="$SYS_PLUGINS" GST_PLUGIN_PATH="$p" \
    GST_REGISTRY="$r" NNSTREAMER_CONF="$c" NNSTREAMER_FILTERS="$s/filters" \
    NNSTREAMER_DECODERS="$s/decoders" NNSTREAMER_CONVERTERS="$s/converters" \
    NNSTREAMER_TRAINERS="$s/trainers" LD_LIBRARY_PATH="$l" GST_DEBUG=1 "$@"
}
up() { _env "$UP/lib/gstreamer-1.0" "$W/reg-up.bin" "$UP/etc/nnstreamer.ini" "$UP/lib/nnstreamer" "$UP/lib" "$@"; }
ours() { _env "$OURS/plugin" "$W/reg-ours.bin" "$OURS/nnstreamer.ini" "$OURS/subplugins" "$OURS/lib" "$@"; }
freeport() { /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
wait_port() {
  local i
  for i in $(seq 150); do ss -ltnH "sport = :$1" | grep -q LISTEN && return 0; sleep 0.1; done
  echo "FAIL port $1 not listening"
  FAILED=1
}
wait_or_kill() {  # PID, seconds[, its log: then not a failure, only a note]
  local i
  for i in $(seq $(($2 * 10))); do kill -0 "$1" 2>/dev/null || { wait "$1"; return; }; sleep 0.1; done
  if [ -n "${3:-}" ]; then echo "note: pid $1 did not stop within $2 s: $(grep -o 'Caught SIG[A-Z]*' "$3" | head -1) ($3)"; else echo "FAIL pid $1 still running after $2 s: killed"; FAILED=1; fi
  kill -KILL "$1"
  wait "$1" 2>/dev/null
}
check() { "$@" || FAILED=1; }
tcaps() { echo "other/tensors,format=static,num_tensors=1,dimensions=(string)$1,types=$2,framerate=0/1"; }

/usr/bin/python3 "$HELP" gen "$W" || exit 1
BROKER_PORT=$(freeport)
printf 'listener %s 127.0.0.1\nallow_anonymous true\n' "$BROKER_PORT" >mosq.conf
/usr/sbin/mosquitto -c mosq.conf >mosq.log 2>&1 &
BROKER_PID=$!
sleep 0.5

# (a) Four upstream clients (200 frames each) at once -> our server at max-batch N.
# $1 tag, $2 N, $3 batch-timeout, $4 model|add, $5 TCP|HYBRID
to_ours() {
  local tag=$1 n=$2 bt=$3 kind=$4 ct=$5 P hy="" hys="" body conv ext fs c pids=()
  P=$(freeport)
  [ "$ct" = HYBRID ] && hy="connect-type=HYBRID dest-host=127.0.0.1 dest-port=$BROKER_PORT topic=a$tag" && hys="connect-type=HYBRID"
  if [ "$kind" = model ]; then  # capsfilters on both sides: upstream clients need fixed answer caps
    body="$(tcaps 8:"$n" float32) ! tensor_filter framework=onnxruntime model=$W/dyn.onnx input=8:$n inputtype=float32 ! $(tcaps 4:"$n" float32)"
    conv="tensor_converter input-dim=8:1 input-type=float32" ext=f32 fs=32
  else
    body="$(tcaps 3:8:6:"$n" uint8) ! tensor_transform mode=arithmetic option=add:1 ! $(tcaps 3:8:6:"$n" uint8)"
    conv="tensor_converter input-dim=3:8:6:1 input-type=uint8" ext=u8 fs=144
  fi
  ours /usr/bin/python3 "$HELP" run "tensor_query_serversrc name=c host=127.0.0.1 port=$P $hy max-batch=$n batch-timeout=$bt ! $body ! tensor_query_serversink $hys" 600 >"srv-$tag.log" 2>&1 &
  local SP=$!
  wait_port "$P"
  local dst="dest-host=127.0.0.1 dest-port=$P"
  [ "$ct" = HYBRID ] && dst="connect-type=HYBRID dest-host=127.0.0.1 dest-port=$BROKER_PORT topic=a$tag"
  for c in 0 1 2 3; do
    up gst-launch-1.0 -q filesrc location="in$c.$ext" blocksize=$fs ! application/octet-stream ! $conv ! \
      tensor_query_client $dst host=127.0.0.1 port=0 timeout=5000 ! filesink location="out-$tag-$c.$ext" >"cli-$tag-$c.log" 2>&1 &
    pids+=($!)
  done
  for c in "${pids[@]}"; do wait_or_kill "$c" 60; done
  kill -TERM "$SP"
  wait "$SP"
  echo "== (a) $tag: 4 upstream clients -> ours, max-batch=$n batch-timeout=$bt, $kind, $ct"
  grep -E '^(STATS|WARNING|ERROR)' "srv-$tag.log"
  for c in 0 1 2 3; do
    if [ "$kind" = model ]; then
      check /usr/bin/python3 "$HELP" model "$W" "in$c.f32" "out-$tag-$c.f32"
    else
      check /usr/bin/python3 "$HELP" add "in$c.u8" "out-$tag-$c.u8" 144 1
    fi
  done
}
same_as() { local c; for c in 0 1 2 3; do check /usr/bin/python3 "$HELP" same "out-$1-$c.$3" "out-$2-$c.$3"; done; }
to_ours tcp1 1 0 model TCP
to_ours tcp4 4 20000 model TCP
same_as tcp1 tcp4 f32
to_ours tcp4t0 4 0 model TCP
same_as tcp1 tcp4t0 f32
to_ours hy4 4 20000 model HYBRID
same_as tcp1 hy4 f32
to_ours tcpadd4 4 20000 add TCP
to_ours hyadd4 4 20000 add HYBRID

# (b, c) Our load-balancing client (200 frames) over servers "up:K" (NNStreamer, id=K) or
# "ours:K" (batching, max-batch=4), each answering input + K.
# $1 tag, $2 HYBRID|LIST, $3 policy, $4 index of the server killed (SIGKILL at 1.2 s) or none,
# $5 resend-on-failover, $6... servers. SRV_SLEEP (us per request, servers), SLEEP (us per
# input, client).
start_server() {  # $1 spec, $2 mode, $3 topic; sets SPID SPORT
  local kind=${1%%:*} k=${1##*:} P hy="" hys=""
  P=$(freeport)
  [ "$2" = HYBRID ] && hy="connect-type=HYBRID dest-host=127.0.0.1 dest-port=$BROKER_PORT topic=$3" && hys="connect-type=HYBRID"
  local delay="identity sleep-time=${SRV_SLEEP:-0}"
  if [ "$kind" = up ]; then  # distinct ids: NNStreamer announces on edge/inference/device-<id>/<topic>/
    up gst-launch-1.0 tensor_query_serversrc id="$k" host=127.0.0.1 port="$P" $hy ! "$(tcaps 3:8:6:1 uint8)" ! $delay ! \
      tensor_transform mode=arithmetic option=add:"$k" ! "$(tcaps 3:8:6:1 uint8)" ! tensor_query_serversink id="$k" $hys >"srv-$TAG-$1.log" 2>&1 &
  else
    ours /usr/bin/python3 "$HELP" run "tensor_query_serversrc name=c host=127.0.0.1 port=$P $hy max-batch=4 batch-timeout=5000 ! $(tcaps 3:8:6:4 uint8) ! $delay ! tensor_transform mode=arithmetic option=add:$k ! $(tcaps 3:8:6:4 uint8) ! tensor_query_serversink $hys" 600 >"srv-$TAG-$1.log" 2>&1 &
  fi
  SPID=$! SPORT=$P
  wait_port "$P"
}
balance() {
  TAG=$1
  local mode=$2 pol=$3 kill=$4 resend=$5 i dst
  shift 5
  local specs=("$@") pids=() ports=() ks=()
  for i in "${!specs[@]}"; do
    start_server "${specs[$i]}" "$mode" "b$TAG"
    pids+=("$SPID") ports+=("$SPORT") ks+=("${specs[$i]##*:}")
  done
  sleep 1
  if [ "$mode" = HYBRID ]; then
    dst="connect-type=HYBRID dest-host=127.0.0.1 dest-port=$BROKER_PORT topic=b$TAG"
  else
    dst="dest-host=$(printf '127.0.0.1:%s,' "${ports[@]}" | sed 's/,$//')"
  fi
  ours /usr/bin/python3 "$HELP" run "filesrc location=in0.u8 blocksize=144 ! application/octet-stream ! tensor_converter input-dim=3:8:6:1 input-type=uint8 ! identity sleep-time=${SLEEP:-10000} ! tensor_query_client name=c $dst host=127.0.0.1 port=0 timeout=5000 max-request=8 load-balance=$pol resend-on-failover=$resend ! filesink location=out-$TAG.u8" 120 >"cli-$TAG.log" 2>&1 &
  local CP=$!
  [ "$kill" != none ] && sleep 1.2 && kill -KILL "${pids[$kill]}"
  wait_or_kill "$CP" 120
  for i in "${!pids[@]}"; do
    [ "$kill" = "$i" ] && { wait "${pids[$i]}" 2>/dev/null; continue; }
    case ${specs[$i]} in
      # NNStreamer's HYBRID server sometimes crashes when stopped, with its own clients too
      # (docs/interop.md); gst-launch then waits for a debugger.
      up:*) kill -INT "${pids[$i]}" && wait_or_kill "${pids[$i]}" 10 "srv-$TAG-${specs[$i]}.log" ;;
      *) kill -TERM "${pids[$i]}" && wait_or_kill "${pids[$i]}" 10 ;;
    esac
  done
  echo "== (b/c) $TAG: $mode load-balance=$pol resend-on-failover=$resend servers ${specs[*]} killed=$kill"
  grep -E '^(END|STATS|WARNING|ERROR)' "cli-$TAG.log" | sed 's/latency-[a-z]*-us=(double)[0-9.]*, *//g'
  for i in "${!specs[@]}"; do grep -E '^STATS' "srv-$TAG-${specs[$i]}.log" | sed "s/^/${specs[$i]}: /"; done
  # Missing answers: none with resend-on-failover, else as many as the client counted lost.
  local lost=0
  [ "$resend" = false ] && lost=$(grep -o 'lost=(guint64)[0-9]*' "cli-$TAG.log" | head -1 | grep -o '[0-9]*$')
  LOST=${lost:-0} check /usr/bin/python3 "$HELP" add in0.u8 "out-$TAG.u8" 144 "${ks[@]}"
}
balance hy-rr HYBRID round-robin none true up:1 up:2
balance hy-lo HYBRID least-outstanding none true up:1 up:2
balance list-rr LIST round-robin none true up:1 up:2
balance list-lo LIST least-outstanding none true up:1 up:2
SRV_SLEEP=20000 SLEEP=5000 balance hy-rr-kill HYBRID round-robin 0 true up:1 up:2
SRV_SLEEP=20000 SLEEP=5000 balance list-lo-kill LIST least-outstanding 1 true up:1 up:2
SRV_SLEEP=20000 SLEEP=5000 balance hy-rr-kill-noresend HYBRID round-robin 0 false up:1 up:2
balance mix-hy-rr HYBRID round-robin none true up:1 ours:2
balance mix-list-lo LIST least-outstanding none true up:1 ours:2
SRV_SLEEP=20000 SLEEP=5000 balance mix-hy-rr-killup HYBRID round-robin 0 true up:1 ours:2
SRV_SLEEP=20000 SLEEP=5000 balance mix-list-rr-killours LIST round-robin 1 true up:1 ours:2

kill "$BROKER_PID"
wait "$BROKER_PID" 2>/dev/null
[ $FAILED = 0 ] && echo "all checks passed" || echo "SOME CHECKS FAILED"
exit $FAILED
