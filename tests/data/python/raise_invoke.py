# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script whose invoke raises (through a helper, to get a two-frame traceback).
import numpy as np
import nnstreamer_python as nns


def check_input(arr):
    raise ValueError("input rejected by raise_invoke.py: %d elements" % arr.size)


class CustomFilter(object):
    def getInputDim(self):
        return [nns.TensorShape([4], np.float32)]

    def getOutputDim(self):
        return [nns.TensorShape([4], np.float32)]

    def invoke(self, input_array):
        check_input(input_array[0])
        return input_array
