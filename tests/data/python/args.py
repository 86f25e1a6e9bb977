# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script: the output has one uint8 per constructor argument (custom= split on
# spaces), holding each argument's length.
import numpy as np
import nnstreamer_python as nns


class CustomFilter(object):
    def __init__(self, *args):
        self.args = args

    def getInputDim(self):
        return [nns.TensorShape([1], np.uint8)]

    def getOutputDim(self):
        return [nns.TensorShape([max(1, len(self.args))], np.uint8)]

    def invoke(self, inputs):
        return [np.array([len(a) for a in self.args] or [0], dtype=np.uint8)]
