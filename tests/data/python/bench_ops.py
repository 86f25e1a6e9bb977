# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter benchmark script (backends/filter/python3/python3_invoke_bench.cc): any one
# tensor in, the same shape out. custom= picks what invoke returns:
#   input  the input array itself (the back end copies it: it is the caller's memory)
#   copy   a new array (x.copy()), lent to the host without a copy
#   kept   one array allocated once and returned every time (lent when the host gave it back)
import numpy as np
import nnstreamer_python as nns


class CustomFilter(object):
    def __init__(self, *args):
        self.mode = args[0] if args else 'input'

    def setInputDim(self, dims):
        s = dims[0]
        self.out = np.zeros(int(np.prod(s.getDims())), dtype=s.getType())
        return [nns.TensorShape(list(s.getDims()), s.getType())]

    def invoke(self, inputs):
        if self.mode == 'copy':
            return [inputs[0].copy()]
        if self.mode == 'kept':
            return [self.out]
        return inputs
