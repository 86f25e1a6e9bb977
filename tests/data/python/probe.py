# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script reporting what invoke sees: inputs 16 uint8 and 4 float32; output 8
# uint64: data address, writeable flag and ndim/length of both inputs, then the id of the thread
# and the number of invokes so far.
import threading
import numpy as np
import nnstreamer_python as nns


class CustomFilter(object):
    def __init__(self, *args):
        self.calls = 0

    def getInputDim(self):
        return [nns.TensorShape([16], np.uint8), nns.TensorShape([4], np.float32)]

    def getOutputDim(self):
        return [nns.TensorShape([8], np.uint64)]

    def invoke(self, inputs):
        self.calls += 1
        a, b = inputs
        out = np.array([a.__array_interface__['data'][0], b.ctypes.data,
                        int(a.flags.writeable), int(b.flags.writeable),
                        a.ndim * 1000 + a.shape[0], b.ndim * 1000 + b.shape[0],
                        threading.get_ident() & 0xffffffff, self.calls], dtype=np.uint64)
        return [out]
