# SPDX-License-Identifier: LGPL-2.1-only
# tensor_filter framework=python3 in the package test (checks.sh): out = 255 - in, 28x28 uint8.
import numpy as np
import nnstreamer_python as nns


class CustomFilter:
    def __init__(self, *args):
        self.shape = nns.TensorShape([1, 28, 28, 1], np.uint8)

    def getInputDim(self):
        return [self.shape]

    def getOutputDim(self):
        return [self.shape]

    def invoke(self, inputs):
        return [(255 - inputs[0]).astype(np.uint8)]
