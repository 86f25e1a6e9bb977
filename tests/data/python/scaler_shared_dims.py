# SPDX-License-Identifier: LGPL-2.1-only
# python3 filter test script as NNStreamer's scaler example writes it: the output shape is built
# from the input shape's own dims list (no copy) and then edited, which must leave the input
# shape alone. Nearest-neighbour scaling of one
# channel:width:height:batch tensor to the size given as custom=WIDTHxHEIGHT (setInputDim API).
import numpy as np
import nnstreamer_python as nns


class CustomFilter(object):
    new_x = 0
    new_y = 0

    def __init__(self, *args):
        if len(args) == 1:
            self.new_x, self.new_y = [int(v) for v in args[0].split('x')]

    def setInputDim(self, input_dims):
        if len(input_dims) != 1:
            return None
        self.input_dims = input_dims
        self.output_dims = [nns.TensorShape(input_dims[0].getDims(),
                                            input_dims[0].getType())]
        dims = self.output_dims[0].getDims()  # the shape's own list: edited in place
        if self.new_x > 0:
            dims[1] = self.new_x
        if self.new_y > 0:
            dims[2] = self.new_y
        return self.output_dims

    def invoke(self, input_array):
        in_dims = self.input_dims[0].getDims()
        out_dims = self.output_dims[0].getDims()
        # numpy shape is the NNStreamer dims reversed: (batch, height, width, channel)
        src = np.reshape(input_array[0], in_dims[::-1])
        ys = (np.arange(out_dims[2]) * in_dims[2]) // out_dims[2]
        xs = (np.arange(out_dims[1]) * in_dims[1]) // out_dims[1]
        out = src[:, ys][:, :, xs]
        return [np.ravel(out)]
