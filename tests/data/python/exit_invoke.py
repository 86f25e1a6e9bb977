# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script calling sys.exit() in invoke: must fail the call, not the process.
import sys
import numpy as np
import nnstreamer_python as nns


class CustomFilter(object):
    def getInputDim(self):
        return [nns.TensorShape([4], np.uint8)]

    def getOutputDim(self):
        return [nns.TensorShape([4], np.uint8)]

    def invoke(self, input_array):
        sys.exit(3)
