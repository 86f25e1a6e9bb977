# SPDX-License-Identifier: LGPL-2.1-only
"""The python3 filter back end loaded into a host program that is itself Python.

Run by ctest as
`<python> python3_host_test.py <libnnstreamer_filter_python3.so> <scripts> <X.Y built for>`.
With the Python the back end was built for, it must reuse this interpreter (no second
Py_Initialize, no finalize), take the GIL properly whether the caller released it (ctypes
CFUNCTYPE) or holds it (PYFUNCTYPE), from the main thread and from other threads, and find
nnstreamer_python without PYTHONPATH. With another Python version, open must fail cleanly.
"""
import ctypes as C
import os
import signal
import sys
import threading

SO, SCRIPTS, BUILT_FOR = sys.argv[1], sys.argv[2], sys.argv[3]
OTHER_VERSION = "%d.%d" % sys.version_info[:2] != BUILT_FOR

# The back end must find nnstreamer_python by itself: drop any build/python from the path.
sys.path[:] = [p for p in sys.path if not os.path.isfile(os.path.join(p, "nnstreamer_python.py"))]
assert "nnstreamer_python" not in sys.modules

if not OTHER_VERSION:
    import numpy as np  # noqa: E402


class TensorDesc(C.Structure):
    _fields_ = [("name", C.c_char * 256), ("type", C.c_uint32), ("dims", C.c_uint32 * 16)]


class TensorsDesc(C.Structure):
    _fields_ = [("num_tensors", C.c_uint32), ("format", C.c_uint32),
                ("tensors", TensorDesc * 256)]


class Props(C.Structure):
    _fields_ = [("framework", C.c_char_p), ("model_files", C.POINTER(C.c_char_p)),
                ("num_models", C.c_uint32), ("input", C.POINTER(TensorsDesc)),
                ("output", C.POINTER(TensorsDesc)), ("custom", C.c_char_p),
                ("accelerator", C.c_char_p), ("input_layout", C.c_void_p),
                ("output_layout", C.c_void_p), ("invoke_dynamic", C.c_int),
                ("num_threads", C.c_int)]


class Mem(C.Structure):
    _fields_ = [("data", C.c_void_p), ("size", C.c_size_t)]


ERR = (C.c_char_p, C.c_size_t)
OPEN = (C.c_int, C.POINTER(Props), C.POINTER(C.c_void_p)) + ERR
INFO = (C.c_int, C.c_void_p, C.POINTER(TensorsDesc), C.POINTER(TensorsDesc)) + ERR
INVOKE = (C.c_int, C.c_void_p, C.POINTER(Mem), C.c_uint32, C.POINTER(Mem), C.c_uint32) + ERR


class Backend(C.Structure):
    _fields_ = [("api_version", C.c_uint32), ("name", C.c_char_p), ("flags", C.c_uint32),
                ("extensions", C.c_void_p), ("open", C.CFUNCTYPE(*OPEN)),
                ("close", C.CFUNCTYPE(None, C.c_void_p)), ("get_model_info", C.CFUNCTYPE(*INFO)),
                ("set_input_info", C.c_void_p), ("invoke", C.CFUNCTYPE(*INVOKE)),
                ("free_output", C.CFUNCTYPE(None, C.c_void_p, C.c_void_p)),
                ("invoke_dynamic", C.c_void_p), ("reload", C.c_void_p),
                ("handle_event", C.c_void_p), ("check_accelerator", C.c_void_p)]


lib = C.CDLL(SO)  # RTLD_LOCAL, as a GStreamer host loads sub-plugins
lib.nns_filter_backend_entry.restype = C.POINTER(Backend)
be = lib.nns_filter_backend_entry().contents
# The same invoke, called with the GIL held (PYFUNCTYPE) instead of released (CFUNCTYPE).
invoke_gil_held = C.PYFUNCTYPE(*INVOKE)(C.cast(be.invoke, C.c_void_p).value)

passed = failed = 0


def check(cond, what):
    global passed, failed
    if cond:
        passed += 1
    else:
        failed += 1
        print("FAILED:", what)


def open_script(name, custom=None):
    path = os.path.join(SCRIPTS, name).encode()
    models = (C.c_char_p * 1)(path)
    none = TensorsDesc()
    p = Props(framework=b"python3", model_files=models, num_models=1, input=C.pointer(none),
              output=C.pointer(none), custom=custom)
    priv = C.c_void_p()
    err = C.create_string_buffer(4096)
    rc = be.open(C.byref(p), C.byref(priv), err, len(err))
    return rc, priv, err.value.decode()


def run(priv, data, invoke=None):
    ins = (Mem * 1)(Mem(data.ctypes.data, data.nbytes))
    outs = (Mem * 1)()
    err = C.create_string_buffer(4096)
    rc = (invoke or be.invoke)(priv, ins, 1, outs, 1, err, len(err))
    if rc != 0:
        return rc, None, err.value.decode()
    out = bytes(C.string_at(outs[0].data, outs[0].size))
    be.free_output(priv, outs[0].data)
    return rc, out, ""


if OTHER_VERSION:
    rc, priv, err = open_script("passthrough.py")
    check(rc != 0 and not priv.value, "open fails under another Python version")
    want = "built for Python %s, but the program runs Python %d.%d." % ((BUILT_FOR,) +
                                                                     sys.version_info[:2])
    check(want in err, "version mismatch message: " + err)
    print("%d passed, %d failed" % (passed, failed))
    sys.exit(1 if failed else 0)

sigint_before = signal.getsignal(signal.SIGINT)
rc, priv, err = open_script("passthrough.py")
check(rc == 0, "open passthrough.py: " + err)

# One interpreter: the script runs in ours, and nnstreamer_python was found without PYTHONPATH.
check("passthrough" in sys.modules and hasattr(sys.modules["passthrough"], "CustomFilter"),
      "the script module is in the host interpreter's sys.modules")
import nnstreamer_python  # noqa: E402
check(sys.modules["passthrough"].nns is nnstreamer_python, "same nnstreamer_python module")
check(signal.getsignal(signal.SIGINT) is sigint_before, "SIGINT handler untouched")

info_in, info_out = TensorsDesc(), TensorsDesc()
err = C.create_string_buffer(256)
check(be.get_model_info(priv, C.byref(info_in), C.byref(info_out), err, 256) == 0, "model info")
check(list(info_in.tensors[0].dims[:5]) == [3, 280, 40, 1, 0], "passthrough dims")

data = (np.arange(3 * 280 * 40) % 251).astype(np.uint8)
rc, out, err = run(priv, data)
check(rc == 0 and out == data.tobytes(), "invoke with the GIL released (CFUNCTYPE): " + err)
rc, out, err = run(priv, data, invoke_gil_held)
check(rc == 0 and out == data.tobytes(), "invoke with the GIL held (PYFUNCTYPE): " + err)

results = []


def worker(held):
    for _ in range(20):
        results.append(run(priv, data, invoke_gil_held if held else None)[1] == data.tobytes())


threads = [threading.Thread(target=worker, args=(h,)) for h in (False, True, False)]
for t in threads:
    t.start()
for t in threads:
    t.join()
check(len(results) == 60 and all(results), "invokes from three Python threads")

be.close(priv)

# Errors come back as text; the host interpreter keeps no pending exception.
rc, priv, err = open_script("bad_syntax.py")
check(rc != 0 and "SyntaxError" in err and "bad_syntax.py" in err, "syntax error text: " + err)
check(sys.exc_info()[0] is None, "no exception left pending in the host")
rc, priv, err = open_script("exit_invoke.py")
check(rc == 0, "open exit_invoke.py")
rc, out, err = run(priv, np.zeros(4, np.uint8))
check(rc != 0 and "SystemExit: 3" in err, "sys.exit() in invoke is an error, not an exit: " + err)
be.close(priv)

print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
