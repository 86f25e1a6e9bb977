# SPDX-License-Identifier: LGPL-2.1-only
"""nnstreamer-cpp's ML API for Python.

    import numpy as np, nnstreamer
    with nnstreamer.Single("mobilenet_v2.onnx", "onnxruntime") as model:
        scores, = model.invoke(np.zeros((1, 3, 224, 224), np.float32))

    with nnstreamer.Pipeline("videotestsrc num-buffers=3 ! tensor_converter ! "
                             "tensor_sink name=out") as pipe:
        pipe.on_sink("out", lambda arrays, info: print(arrays[0].shape))
        pipe.start()

Single wraps ml_single_* (libnnstreamer-single), Pipeline ml_pipeline_* (libcapi-nnstreamer;
pipelines load the nnstreamer GStreamer plugin: GST_PLUGIN_PATH, see build/env.sh). Errors raise nnstreamer.Error (a
RuntimeError) whose message is the library's ml_error() text and whose .code is the
ml_error_e value (nnstreamer.ERROR_*). Shapes are numpy's (outermost first): NNStreamer's
dimension 3:224:224:1 is the shape (1, 224, 224, 3).
"""
import atexit as _atexit

from ._nnstreamer import (  # noqa: F401
    ERROR_INVALID_PARAMETER,
    ERROR_IO_ERROR,
    ERROR_NONE,
    ERROR_NOT_SUPPORTED,
    ERROR_OUT_OF_MEMORY,
    ERROR_PERMISSION_DENIED,
    ERROR_STREAMS_PIPE,
    ERROR_TIMED_OUT,
    ERROR_TRY_AGAIN,
    ERROR_UNKNOWN,
    Element,
    ElementProperties,
    Error,
    Pipeline,
    Single,
    State,
    Switch,
    TensorInfo,
    Valve,
    _close_all_pipelines,
    ml_api_version,
)

# Pipelines still open at exit are destroyed while Python can still run their callbacks.
_atexit.register(_close_all_pipelines)

__all__ = [
    "Element",
    "ElementProperties",
    "Error",
    "Pipeline",
    "Single",
    "State",
    "Switch",
    "TensorInfo",
    "Valve",
    "ml_api_version",
]
