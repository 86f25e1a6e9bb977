# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script with two inputs and two outputs: the element-wise sum and product of
# two float32 2:2 tensors.
import numpy as np
import nnstreamer_python as nns


class CustomFilter(object):
    def getInputDim(self):
        return [nns.TensorShape([2, 2], np.float32), nns.TensorShape([2, 2], 'float32')]

    def getOutputDim(self):
        return [nns.TensorShape([2, 2], np.float32), nns.TensorShape([2, 2], np.dtype('f4'))]

    def invoke(self, inputs):
        a, b = inputs
        return [a + b, a * b]
