# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter for the load/unload leak tests (tests/slow/filter_reload_leak_test.cc): float32
# [1,1024] -> [1,1024] through a 1024x1024 matrix (4 MiB), so that an instance leaked per load
# stands out in the process's memory.
import numpy as np
import nnstreamer_python as nns


class CustomFilter(object):
    def __init__(self, *args):
        self.weights = np.full((1024, 1024), 1.0 / 1024, dtype=np.float32)

    def getInputDim(self):
        return [nns.TensorShape([1024, 1], np.float32)]

    def getOutputDim(self):
        return [nns.TensorShape([1024, 1], np.float32)]

    def invoke(self, inputs):
        x = np.asarray(inputs[0], dtype=np.float32).reshape(1, 1024)
        return [np.ascontiguousarray(x @ self.weights.T)]
