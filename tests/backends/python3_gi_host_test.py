# SPDX-License-Identifier: LGPL-2.1-only
"""tensor_filter framework=python3 inside a PyGObject application (the host is Python).

NNStreamer's python3 sub-plugin crashed in this setting (Py_IsInitialized assertion, issue 4523).
Here the back end must run the script in the application's own interpreter, with streaming threads
taking the GIL while the main thread waits in GStreamer, and find nnstreamer_python without
PYTHONPATH. Run by ctest (tests/python3.cmake) as
`/usr/bin/python3 python3_gi_host_test.py <scripts folder>`; exits 77 (skipped) without PyGObject
or tensor_filter.
"""
import os
import sys
import threading

SCRIPTS = sys.argv[1]
sys.path[:] = [p for p in sys.path if not os.path.isfile(os.path.join(p, "nnstreamer_python.py"))]

try:
    import gi
    gi.require_version("Gst", "1.0")
    from gi.repository import Gst
except (ImportError, ValueError) as e:
    print("skipped: PyGObject/Gst typelib missing (%s)" % e)
    sys.exit(77)

Gst.init(None)
if Gst.ElementFactory.find("tensor_filter") is None:
    print("skipped: no tensor_filter element (GST_PLUGIN_PATH=%s)" % os.environ.get("GST_PLUGIN_PATH"))
    sys.exit(77)

passed = failed = 0


def check(cond, what):
    global passed, failed
    if cond:
        passed += 1
    else:
        failed += 1
        print("FAILED:", what)


FRAMES = 5
pipeline = Gst.parse_launch(
    "videotestsrc num-buffers=%d pattern=ball ! video/x-raw,format=RGB,width=280,height=40,"
    "framerate=30/1 ! tensor_converter ! tee name=t ! queue ! tensor_filter framework=python3 "
    "model=%s ! fakesink name=filtered signal-handoffs=true enable-last-sample=false t. ! queue ! "
    "fakesink name=direct signal-handoffs=true enable-last-sample=false"
    % (FRAMES, os.path.join(SCRIPTS, "passthrough.py")))
got = {"filtered": [], "direct": []}
threads = set()


# fakesink handoffs rather than appsink: PyGObject 3.42 leaks the samples of
# appsink.emit("pull-sample"), which would keep the filter's output buffers (and so the filter
# instance) alive after the pipeline stops.
def on_handoff(sink, buf, pad, name):
    got[name].append(buf.extract_dup(0, buf.get_size()))
    threads.add(threading.get_ident())


for name in got:
    pipeline.get_by_name(name).connect("handoff", on_handoff, name)

pipeline.set_state(Gst.State.PLAYING)
msg = pipeline.get_bus().timed_pop_filtered(20 * Gst.SECOND,
                                            Gst.MessageType.EOS | Gst.MessageType.ERROR)
check(msg is not None and msg.type == Gst.MessageType.EOS,
      "pipeline reaches EOS: %s" % (msg.parse_error() if msg and msg.type == Gst.MessageType.ERROR
                                    else msg))
pipeline.set_state(Gst.State.NULL)
pipeline = None

check(len(got["filtered"]) == FRAMES, "%d filtered frames" % len(got["filtered"]))
check(got["filtered"] == got["direct"], "passthrough output equals its input")
check(threading.main_thread().ident not in threads, "frames came from streaming threads")
# The script ran in this interpreter (one interpreter per process) and found nnstreamer_python.
check("passthrough" not in sys.modules, "the script module is unloaded when the filter closes")
check("nnstreamer_python" in sys.modules, "nnstreamer_python was imported into this interpreter")

# A broken script: a bus error with the Python message, and the application keeps running.
pipeline = Gst.parse_launch(
    "videotestsrc num-buffers=1 ! video/x-raw,format=RGB,width=8,height=8 ! tensor_converter ! "
    "tensor_filter framework=python3 model=%s ! fakesink"
    % os.path.join(SCRIPTS, "bad_syntax.py"))
pipeline.set_state(Gst.State.PLAYING)
msg = pipeline.get_bus().timed_pop_filtered(20 * Gst.SECOND,
                                            Gst.MessageType.EOS | Gst.MessageType.ERROR)
text = ""
if msg is not None and msg.type == Gst.MessageType.ERROR:
    err, dbg = msg.parse_error()
    text = "%s | %s" % (err.message, dbg)
check("SyntaxError" in text and "bad_syntax.py" in text, "syntax error on the bus: " + text)
pipeline.set_state(Gst.State.NULL)

print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
