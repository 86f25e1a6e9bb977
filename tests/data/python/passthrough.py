# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script: fixed 3:280:40:1 uint8 in and out, returns its input unchanged
# (NNStreamer's classic passthrough example, written for the getInputDim/getOutputDim API).
import numpy as np
import nnstreamer_python as nns

DIMS = [3, 280, 40, 1]


class CustomFilter(object):
    def __init__(self, *args):
        self.input_dims = [nns.TensorShape(list(DIMS), np.uint8)]
        self.output_dims = [nns.TensorShape(list(DIMS), np.uint8)]

    def getInputDim(self):
        return self.input_dims

    def getOutputDim(self):
        return self.output_dims

    def invoke(self, input_array):
        return input_array
