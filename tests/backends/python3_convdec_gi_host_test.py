# SPDX-License-Identifier: LGPL-2.1-only
"""tensor_decoder mode=python3 and tensor_converter mode=custom-script:<file.py> inside a
PyGObject application (the host is Python).

The sub-plugins must use the application's interpreter, take the GIL on streaming threads while
the main thread waits in GStreamer, and find nnstreamer_python without PYTHONPATH. Run by ctest
(tests/python3_convdec.cmake) as `/usr/bin/python3 python3_convdec_gi_host_test.py <scripts>`;
exits 77 (skipped) without PyGObject or the elements.
"""
import gc
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
for element in ("tensor_converter", "tensor_decoder"):
    if Gst.ElementFactory.find(element) is None:
        print("skipped: no %s element (GST_PLUGIN_PATH=%s)"
              % (element, os.environ.get("GST_PLUGIN_PATH")))
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
    "framerate=30/1 ! tensor_converter ! tee name=t ! queue ! tensor_decoder mode=python3 "
    "option1=%s ! tensor_converter mode=custom-script:%s ! fakesink name=round "
    "signal-handoffs=true enable-last-sample=false t. ! queue ! "
    "fakesink name=direct signal-handoffs=true enable-last-sample=false"
    % (FRAMES, os.path.join(SCRIPTS, "dec_concat.py"), os.path.join(SCRIPTS, "conv_view.py")))
got = {"round": [], "direct": []}
threads = set()


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
pipeline = msg = None  # the EOS message refers to the pipeline too
gc.collect()

check(len(got["round"]) == FRAMES, "%d round-trip frames" % len(got["round"]))
check(got["round"] == got["direct"], "decoder + converter reproduce the tensors")
check(threading.main_thread().ident not in threads, "frames came from streaming threads")
check("dec_concat" not in sys.modules and "conv_view" not in sys.modules,
      "the script modules are unloaded when the elements go: %s"
      % [m for m in ("dec_concat", "conv_view") if m in sys.modules])
check("nnstreamer_python" in sys.modules, "nnstreamer_python was imported into this interpreter")

# A raising script: a bus error with the Python message, and the application keeps running.
pipeline = Gst.parse_launch(
    "videotestsrc num-buffers=1 ! video/x-raw,format=RGB,width=8,height=8 ! tensor_converter ! "
    "tensor_decoder mode=python3 option1=%s ! fakesink" % os.path.join(SCRIPTS, "dec_caps_raise.py"))
pipeline.set_state(Gst.State.PLAYING)
msg = pipeline.get_bus().timed_pop_filtered(20 * Gst.SECOND,
                                            Gst.MessageType.EOS | Gst.MessageType.ERROR)
text = ""
if msg is not None and msg.type == Gst.MessageType.ERROR:
    err, dbg = msg.parse_error()
    text = "%s | %s" % (err.message, dbg)
check("LookupError: no caps for you" in text and "dec_caps_raise.py" in text,
      "getOutCaps exception on the bus: " + text)
pipeline.set_state(Gst.State.NULL)

print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
