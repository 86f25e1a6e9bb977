# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script whose getOutputDim returns the malformed value named by custom=.
import numpy as np
import nnstreamer_python as nns


class FakeShape(object):
    def getDims(self):
        return "3:4"

    def getType(self):
        return np.uint8


class CustomFilter(object):
    def __init__(self, *args):
        self.case = args[0]

    def getInputDim(self):
        return [nns.TensorShape([4], np.uint8)]

    def getOutputDim(self):
        c = self.case
        if c == 'none':
            return None
        if c == 'empty':
            return []
        if c == 'int':
            return [4]
        if c == 'negative':
            return [nns.TensorShape([3, -1], np.uint8)]
        if c == 'fraction':
            return [nns.TensorShape([3, 2.5], np.uint8)]
        if c == 'float_ok':
            return [nns.TensorShape([3.0, 2], np.uint8)]
        if c == 'complex':
            return [nns.TensorShape([4], np.complex64)]
        if c == 'object':
            return [nns.TensorShape([4], object)]
        if c == 'zero_inside':
            return [nns.TensorShape([3, 0, 2], np.uint8)]
        if c == 'trailing_zero':
            return [nns.TensorShape([3, 2, 0, 0], np.uint8)]
        if c == 'huge':
            return [nns.TensorShape([2 ** 33], np.uint8)]
        if c == 'string_dims':
            return [FakeShape()]
        if c == 'raise':
            raise IndexError('getOutputDim broke')
        return [nns.TensorShape([4], np.uint8)]

    def invoke(self, inputs):
        return inputs
