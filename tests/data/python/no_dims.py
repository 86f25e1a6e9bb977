# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script with invoke but neither setInputDim nor getInputDim/getOutputDim.
class CustomFilter(object):
    def getInputDim(self):
        return []

    def invoke(self, input_array):
        return input_array
