# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script: accepts any input (setInputDim) and returns it unchanged; with the
# custom argument 'double' numeric outputs are the inputs times two.
import numpy as np
import nnstreamer_python as nns


class CustomFilter(object):
    def __init__(self, *args):
        self.double = 'double' in args

    def setInputDim(self, input_dims):
        self.dims = [nns.TensorShape(list(s.getDims()), s.getType()) for s in input_dims]
        return self.dims

    def invoke(self, inputs):
        if self.double:
            return [x * 2 for x in inputs]
        return inputs
