# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script for invoke-dynamic: with invoke-dynamic the inputs arrive shaped
# (numpy order) and the returned arrays' shapes and dtypes define the output of each frame.
# Outputs: the first input transposed and doubled (same dtype), and an int32 vector with the
# input's numpy shape. custom=bad_type or custom=empty return an invalid first output.
import numpy as np


class CustomFilter(object):
    def __init__(self, *args):
        self.case = args[0] if args else ''

    def setInputDim(self, input_dims):
        return input_dims

    def invoke(self, inputs):
        x = inputs[0]
        if self.case == 'bad_type':
            return [np.array(['text'])]
        if self.case == 'empty':
            return [np.zeros((0, 3), np.float32)]
        return [(x * 2).T, np.array(x.shape, dtype=np.int32)]
