# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script: one uint8 tensor of 8 in, two uint8 tensors of 4 out; the first
# custom argument picks what invoke returns. Failing cases fail on the first invoke only and then
# behave like 'copy', to check that a failure leaves nothing behind.
import numpy as np
import nnstreamer_python as nns

KEPT = np.arange(4, dtype=np.uint8)  # a module-level array returned by the 'kept' case


def kept_address():
    return KEPT.__array_interface__['data'][0]


class CustomFilter(object):
    def __init__(self, *args):
        self.mode = args[0] if args else 'copy'
        self.calls = 0

    def getInputDim(self):
        return [nns.TensorShape([8], np.uint8)]

    def getOutputDim(self):
        return [nns.TensorShape([4], np.uint8), nns.TensorShape([4], np.uint8)]

    def invoke(self, inputs):
        x = inputs[0]
        seq = np.arange(16, dtype=np.uint8)
        mode = self.mode
        self.calls += 1
        failing = ('raise', 'not_array', 'not_list', 'none', 'count', 'second_bad', 'short',
                   'int8', 'big_endian')
        if mode in failing and self.calls > 1:
            mode = 'copy'
        if mode == 'raise':
            raise KeyError('raise case')
        if mode == 'alias':
            return [x[:4], x[4:]]
        if mode == 'reshaped_alias':
            return [x.reshape(2, 4)[0], x.reshape(2, 4)[1]]
        if mode == 'strided':
            return [seq[:8:2], seq[7::-2]]
        if mode == 'same':
            return [seq[:4]] * 2
        if mode == 'kept':
            return [KEPT, x[4:] + 0]
        if mode == '2d':
            return [seq[:4].reshape(2, 2), seq[4:8].reshape(1, 4)]
        if mode == 'not_array':
            return [x[:4].tobytes(), x[4:].copy()]
        if mode == 'not_list':
            return (x[:4].copy(), x[4:].copy())
        if mode == 'none':
            return None
        if mode == 'count':
            return [x[:4].copy()]
        if mode == 'second_bad':
            return [x[:4].copy(), x[4:].astype(np.int32)]
        if mode == 'short':
            return [x[:4].copy(), x[4:7].copy()]
        if mode == 'int8':
            return [x[:4].copy(), x[4:].view(np.int8).copy()]
        if mode == 'big_endian':
            return [x[:4].copy(), x[4:].astype('>u1').copy()]
        return [x[:4].copy(), x[4:].copy()]
