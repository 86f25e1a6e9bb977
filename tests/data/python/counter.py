# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script with module-level state: the output is the number of invokes the
# module has seen, so two filters on this script show whether they share the module.
import numpy as np
import nnstreamer_python as nns

count = 0


class CustomFilter(object):
    def getInputDim(self):
        return [nns.TensorShape([1], np.uint8)]

    def getOutputDim(self):
        return [nns.TensorShape([1], np.int64)]

    def invoke(self, inputs):
        global count
        count += 1
        return [np.array([count], dtype=np.int64)]
