#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
# Helpers of scripts/interop/query_lb_batch.sh (docs/interop.md, "Query load balancing and
# batching"). Not run by CI.
#   gen DIR                      inputs and the Y = X W + B ONNX model (free batch) into DIR
#   run DESC SECONDS             run a pipeline (in the calling environment) to EOS, an error,
#                                SIGTERM or SECONDS; print bus warnings/errors and the `stats`
#                                of the element named "c"
#   add IN OUT FRAMESIZE K...    every answer is its input + k (uint8), k one of K, in input
#                                order; with LOST=n in the environment n inputs may be missing
#   model DIR IN OUT             float32 answers equal X W + B (|err| <= 1e-5), one per input
#   same A B                     byte-identical files
import os
import signal
import sys

import numpy as np


def gen(d):
    import onnx
    from onnx import TensorProto, helper, numpy_helper
    rng = np.random.default_rng(21)
    w = rng.uniform(-1, 1, (8, 4)).astype(np.float32)
    b = rng.uniform(-1, 1, (4,)).astype(np.float32)
    x = helper.make_tensor_value_info("X", TensorProto.FLOAT, ["N", 8])
    y = helper.make_tensor_value_info("Y", TensorProto.FLOAT, ["N", 4])
    g = helper.make_graph([helper.make_node("MatMul", ["X", "W"], ["XW"]),
                           helper.make_node("Add", ["XW", "B"], ["Y"])], "dyn", [x], [y],
                          [numpy_helper.from_array(w, "W"), numpy_helper.from_array(b, "B")])
    m = helper.make_model(g, opset_imports=[helper.make_opsetid("", 13)])
    m.ir_version = 7
    onnx.checker.check_model(m)
    onnx.save(m, d + "/dyn.onnx")
    w.tofile(d + "/W.raw")
    b.tofile(d + "/B.raw")
    for c in range(4):
        rng.uniform(-4, 4, (200, 8)).astype(np.float32).tofile("%s/in%d.f32" % (d, c))
        rng.integers(0, 250, (200, 144), dtype=np.uint8).tofile("%s/in%d.u8" % (d, c))


def run(desc, limit):
    import gi
    gi.require_version("Gst", "1.0")
    from gi.repository import Gst
    Gst.init(None)
    stop = []
    signal.signal(signal.SIGTERM, lambda *a: stop.append(1))
    p = Gst.parse_launch(desc)
    p.set_state(Gst.State.PLAYING)
    bus, end, t = p.get_bus(), "TIMEOUT", 0.0
    kinds = Gst.MessageType.EOS | Gst.MessageType.ERROR | Gst.MessageType.WARNING
    while t < limit and not stop:
        m = bus.timed_pop_filtered(100 * Gst.MSECOND, kinds)
        t += 0.1
        if m is None:
            continue
        if m.type == Gst.MessageType.WARNING:
            print("WARNING:", m.src.get_name(), m.parse_warning()[0].message, flush=True)
            continue
        if m.type == Gst.MessageType.ERROR:
            print("ERROR:", m.src.get_name(), m.parse_error()[0].message, flush=True)
        end = "EOS" if m.type == Gst.MessageType.EOS else "ERROR"
        break
    print("END:", "TERM" if stop else end, flush=True)
    c = p.get_by_name("c")
    if c is not None and c.find_property("stats"):
        print("STATS:", c.get_property("stats").to_string().replace("\\", ""), flush=True)
    p.set_state(Gst.State.NULL)


def check_add(inp, out, fs, ks):
    i = np.fromfile(inp, np.uint8).reshape(-1, fs).astype(np.int32)
    o = np.fromfile(out, np.uint8).reshape(-1, fs).astype(np.int32)
    allowed = int(os.environ.get("LOST", "0"))
    counts, j, missing = {k: 0 for k in ks}, 0, 0
    for n, frame in enumerate(o):
        while j < len(i):
            d = frame - i[j]
            if d.min() == d.max() and int(d[0]) in counts:
                break
            j, missing = j + 1, missing + 1
        if j == len(i):
            print("FAIL answer %d matches no remaining input" % n)
            return 1
        counts[int(d[0])] += 1
        j += 1
    missing += len(i) - j
    ok = missing == allowed
    print("%s inputs %d answers %d (missing %d, expected %d), answers per k %s" %
          ("PASS" if ok else "FAIL", len(i), len(o), missing, allowed, counts))
    return 0 if ok else 1


def check_model(d, inp, out):
    x = np.fromfile(inp, np.float32).reshape(-1, 8)
    y = np.fromfile(out, np.float32).reshape(-1, 4)
    w = np.fromfile(d + "/W.raw", np.float32).reshape(8, 4)
    b = np.fromfile(d + "/B.raw", np.float32)
    n = min(len(x), len(y))
    err = float(np.abs(y[:n] - (x[:n].astype(np.float64) @ w + b)).max()) if n else -1.0
    ok = len(y) == len(x) and 0 <= err <= 1e-5
    print("%s inputs %d answers %d max |err| %.3g" % ("PASS" if ok else "FAIL", len(x), len(y), err))
    return 0 if ok else 1


def same(a, b):
    x, y = open(a, "rb").read(), open(b, "rb").read()
    print(("PASS identical, %d bytes" % len(x)) if x == y else
          ("FAIL differ: %d vs %d bytes" % (len(x), len(y))))
    return 0 if x == y else 1


if __name__ == "__main__":
    cmd, a = sys.argv[1], sys.argv[2:]
    if cmd == "gen":
        gen(a[0])
    elif cmd == "run":
        run(a[0], float(a[1]))
    elif cmd == "add":
        sys.exit(check_add(a[0], a[1], int(a[2]), [int(k) for k in a[3:]]))
    elif cmd == "model":
        sys.exit(check_model(a[0], a[1], a[2]))
    elif cmd == "same":
        sys.exit(same(a[0], a[1]))
    else:
        sys.exit("unknown command " + cmd)
